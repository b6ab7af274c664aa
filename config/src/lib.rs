//! The structural configuration of a telescopic-beam model: everything that changes the
//! equations' form (modes per section, contacts per overlap, force flow, clearance law, fixed
//! or moving positions, drive). Physical values (lengths, masses, stiffnesses) stay
//! parameters. The generator (`telescopic-codegen`) generates a model per [`ModelConfig`]; the
//! runtime (`telescopic-runtime`) finds a scene's model by its key; both speak these words,
//! defined only here, and the generator needs nothing else of the runtime.
//!
//! ```
//! use telescopic_config::{DriveKind, ForceFlow, ModelConfig, Positions};
//! let config = ModelConfig {
//!     modes: vec![5, 5],
//!     contacts: 3,
//!     force_flow: ForceFlow::Cable,
//!     clearance: false,
//!     positions: Positions::Fixed,
//!     drive: DriveKind::Force,
//! };
//! assert_eq!(config.key(), "s2_m5x5_c3_cable_linear_fixed_force");
//! assert!(config.validate().is_ok());
//! ```

use serde::{Deserialize, Serialize};
use std::fmt;

/// Highest mode index per section that the project supports (roots are computed for any
/// index, but the scene schema limits modes to this).
pub const MAX_MODES: usize = 30;

/// How gravity loads the sections axially (docs/model.md section 2).
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize, Default,
)]
#[serde(rename_all = "kebab-case")]
pub enum ForceFlow {
    /// Each section stands on its foot and carries the sections above (the paper's eq. 3):
    /// `P_k(x) = g (rhoA_k (l_k - x) + sum_{j>k} rhoA_j l_j + m_L)`.
    #[default]
    Cable,
    /// The upper sections are carried by an external system:
    /// `P_k(x) = g (rhoA_k (l_k - x) + [k = n] m_L)`.
    External,
    /// No axial prestress (`P_k = 0`).
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_models_file_entry_reads_back_as_its_configuration() {
        let config = ModelConfig {
            modes: vec![4, 3, 2],
            contacts: 2,
            force_flow: ForceFlow::External,
            clearance: true,
            positions: Positions::Moving,
            drive: DriveKind::Motion,
        };
        #[derive(Deserialize)]
        struct File {
            model: Vec<ModelConfig>,
        }
        let file: File = toml::from_str(&config.models_toml_entry()).unwrap();
        assert_eq!(file.model, std::slice::from_ref(&config));
        assert_eq!(
            config.key(),
            "s3_m4x3x2_c2_external_clearance_moving_motion"
        );
    }

    #[test]
    fn configurations_breaking_a_rule_are_refused_naming_it() {
        let base = ModelConfig {
            modes: vec![5, 5],
            contacts: 3,
            force_flow: ForceFlow::Cable,
            clearance: false,
            positions: Positions::Fixed,
            drive: DriveKind::Force,
        };
        for (config, rule) in [
            (
                ModelConfig {
                    modes: vec![],
                    ..base.clone()
                },
                "at least one section",
            ),
            (
                ModelConfig {
                    modes: vec![5, 31],
                    ..base.clone()
                },
                "each in 1..=30",
            ),
            (
                ModelConfig {
                    contacts: 1,
                    ..base.clone()
                },
                "at least 2 per overlap",
            ),
            (
                ModelConfig {
                    modes: vec![5],
                    positions: Positions::Moving,
                    ..base.clone()
                },
                "no telescopic position to move",
            ),
        ] {
            let e = config.validate().unwrap_err();
            assert!(e.contains(rule), "{e}");
        }
    }
}
