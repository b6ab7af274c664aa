//! The structural configuration of a model: everything that changes the equations' form
//! (modes per section, contacts per overlap, force flow, clearance law, fixed or moving
//! positions, drive). Physical values (lengths, masses, stiffnesses) stay parameters. The
//! generator (`telescopic-codegen`) generates a model per [`ModelConfig`]; the runtime finds
//! a scene's model by [`configuration_key`]; both speak these words, defined only here.

pub use crate::model::params::ForceFlow;
use crate::model::params::{Drive, ModelParams};
use crate::shape::MAX_MODES;
use serde::{Deserialize, Serialize};
use std::fmt;

/// Whether telescopic positions move.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize, PartialOrd, Ord)]
#[serde(rename_all = "kebab-case")]
pub enum Positions {
    /// Constant `a_k`: contact vectors are computed once per scene.
    Fixed,
    /// `a_k(t)`: contact vectors and their rates are evaluated per call.
    Moving,
}

/// How the vehicle is driven.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize, PartialOrd, Ord)]
#[serde(rename_all = "kebab-case")]
pub enum DriveKind {
    /// A force `F(t)`.
    Force,
    /// A prescribed position `s(t)`.
    Motion,
}

/// One model configuration, as listed in `generated/models.toml`.
#[derive(Debug, Clone, PartialEq, Eq, Hash, Serialize, Deserialize, PartialOrd, Ord)]
#[serde(deny_unknown_fields)]
pub struct ModelConfig {
    /// Modes per section `N_k`, from the bottom up (the length is the number of sections).
    pub modes: Vec<usize>,
    /// Contact points per overlap `n_c`.
    pub contacts: usize,
    /// Axial force flow.
    pub force_flow: ForceFlow,
    /// True: the dead-zone law with clearance `l_S > 0`; false: the linear law (`l_S = 0`).
    pub clearance: bool,
    /// Fixed or moving telescopic positions.
    pub positions: Positions,
    /// Force or prescribed-motion drive.
    pub drive: DriveKind,
}

impl ModelConfig {
    /// Number of sections.
    pub fn sections(&self) -> usize {
        self.modes.len()
    }

    /// Number of generalized coordinates.
    pub fn dof(&self) -> usize {
        self.modes.iter().sum()
    }

    /// Number of contact points.
    pub fn contact_count(&self) -> usize {
        (self.sections() - 1) * self.contacts
    }

    /// Index of the first coordinate of section `k` (1-based).
    pub fn offset(&self, k: usize) -> usize {
        self.modes[..k - 1].iter().sum()
    }

    /// A stable identifier, also the emitted module's name, e.g.
    /// `s2_m5x5_c3_cable_linear_fixed_force`.
    pub fn key(&self) -> String {
        let modes: Vec<String> = self.modes.iter().map(|m| m.to_string()).collect();
        format!(
            "s{}_m{}_c{}_{}_{}_{}_{}",
            self.sections(),
            modes.join("x"),
            self.contacts,
            match self.force_flow {
                ForceFlow::Cable => "cable",
                ForceFlow::External => "external",
                ForceFlow::None => "noflow",
            },
            if self.clearance {
                "clearance"
            } else {
                "linear"
            },
            self.positions.word(),
            self.drive.word()
        )
    }

    /// Checks the rules of a configuration.
    ///
    /// # Errors
    /// A message naming the broken rule.
    pub fn validate(&self) -> Result<(), String> {
        if self.modes.is_empty() {
            return Err("modes: at least one section".into());
        }
        if let Some(m) = self.modes.iter().find(|m| !(1..=MAX_MODES).contains(*m)) {
            return Err(format!("modes: each in 1..={MAX_MODES} (got {m})"));
        }
        if self.sections() > 1 && self.contacts < 2 {
            return Err(format!(
                "contacts: at least 2 per overlap (got {})",
                self.contacts
            ));
        }
        if self.sections() == 1 && self.positions == Positions::Moving {
            return Err("positions: a single section has no telescopic position to move".into());
        }
        Ok(())
    }
}

impl fmt::Display for ModelConfig {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "modes = {:?}, contacts = {}, force_flow = {:?}, clearance = {}, positions = {:?}, drive = {:?}",
            self.modes, self.contacts, self.force_flow, self.clearance, self.positions, self.drive
        )
    }
}

impl ModelConfig {
    /// The configuration of a set of parameters.
    pub fn of(params: &ModelParams) -> Self {
        ModelConfig {
            modes: params.modes(),
            contacts: params.contact_points,
            force_flow: params.force_flow,
            clearance: params.contact.clearance > 0.0,
            positions: if params.positions.iter().all(|p| p.is_constant()) {
                Positions::Fixed
            } else {
                Positions::Moving
            },
            drive: match params.drive {
                Drive::Force(_) => DriveKind::Force,
                Drive::Motion(_) => DriveKind::Motion,
            },
        }
    }

    /// The `[[model]]` entry of a models file that generates this configuration.
    pub fn models_toml_entry(&self) -> String {
        format!(
            "[[model]]\nmodes = {:?}\ncontacts = {}\nforce_flow = \"{}\"\nclearance = {}\n\
             positions = \"{}\"\ndrive = \"{}\"\n",
            self.modes,
            self.contacts,
            self.force_flow.word(),
            self.clearance,
            self.positions.word(),
            self.drive.word(),
        )
    }
}

impl ForceFlow {
    /// The name in a models file and a scene (`cable`, `external`, `none`).
    pub fn word(self) -> &'static str {
        match self {
            ForceFlow::Cable => "cable",
            ForceFlow::External => "external",
            ForceFlow::None => "none",
        }
    }
}

impl Positions {
    /// The name in a models file and a key (`fixed`, `moving`).
    pub fn word(self) -> &'static str {
        match self {
            Positions::Fixed => "fixed",
            Positions::Moving => "moving",
        }
    }
}

impl DriveKind {
    /// The name in a models file and a key (`force`, `motion`).
    pub fn word(self) -> &'static str {
        match self {
            DriveKind::Force => "force",
            DriveKind::Motion => "motion",
        }
    }
}

/// The configuration key of these parameters, as the generator names its module, e.g.
/// `s2_m5x5_c3_cable_linear_fixed_force`.
///
/// ```
/// # let scene = telescopic_runtime::Scene::load("../scenes/test-rig.toml".as_ref(), &[]).unwrap();
/// assert_eq!(
///     telescopic_runtime::configuration_key(&scene.params),
///     "s2_m5x5_c3_cable_linear_fixed_force"
/// );
/// ```
pub fn configuration_key(params: &ModelParams) -> String {
    ModelConfig::of(params).key()
}

/// The `[[model]]` entry of a models file that generates a model for these parameters.
pub fn models_toml_entry(params: &ModelParams) -> String {
    ModelConfig::of(params).models_toml_entry()
}
