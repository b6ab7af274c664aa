//! The structural configuration a model is generated for: everything that changes the
//! equations' form. Physical values (lengths, masses, stiffnesses) stay parameters.

use serde::{Deserialize, Serialize};
use std::fmt;

/// Maximum modes per section (the runtime's limit).
pub const MAX_MODES: usize = 30;

/// Axial prestress from gravity (docs/model.md section 2).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize, PartialOrd, Ord)]
#[serde(rename_all = "kebab-case")]
pub enum ForceFlow {
    /// Each section carries those above it.
    Cable,
    /// Upper sections carried by an external system.
    External,
    /// No prestress terms.
    None,
}

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

/// `generated/models.toml`: `[[model]]` tables.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ModelList {
    /// The configurations to generate.
    pub model: Vec<ModelConfig>,
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
            match self.positions {
                Positions::Fixed => "fixed",
                Positions::Moving => "moving",
            },
            match self.drive {
                DriveKind::Force => "force",
                DriveKind::Motion => "motion",
            }
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
