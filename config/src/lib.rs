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
//!     static_knots: None,
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

/// The interior knots of each section's static correction shapes, as fractions `x / l_k` of
/// its length (ascending, strictly inside `(0, 1)`), from the bottom up: the basis
/// `modes+static` (cubic B-splines on these knots, orthogonalized against the modes). Compared
/// bit for bit: a scene's knots are computed from its contact stations the same way each time.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(transparent)]
pub struct StaticKnots(pub Vec<Vec<f64>>);

impl StaticKnots {
    fn bits(&self) -> impl Iterator<Item = u64> + '_ {
        // a section's end marker (not a knot's bits: those lie in (0, 1)) keeps sections apart
        self.0
            .iter()
            .flat_map(|k| k.iter().map(|x| x.to_bits()).chain([u64::MAX]))
    }

    /// Number of correction shapes of section `k` (1-based): its knots and two more.
    pub fn shapes(&self, k: usize) -> usize {
        self.0[k - 1].len() + 2
    }

    /// A short stable digest of the knots (FNV-1a over their bits), for the key.
    fn digest(&self) -> u32 {
        let mut h: u64 = 0xcbf2_9ce4_8422_2325;
        for b in self.bits() {
            for byte in b.to_le_bytes() {
                h = (h ^ u64::from(byte)).wrapping_mul(0x0000_0100_0000_01b3);
            }
        }
        (h ^ (h >> 32)) as u32
    }
}

impl Eq for StaticKnots {}

impl std::hash::Hash for StaticKnots {
    fn hash<H: std::hash::Hasher>(&self, state: &mut H) {
        self.bits().for_each(|b| b.hash(state));
    }
}

impl PartialOrd for StaticKnots {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for StaticKnots {
    fn cmp(&self, other: &Self) -> std::cmp::Ordering {
        self.bits().cmp(other.bits())
    }
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
    /// The static correction shapes' knots (basis `modes+static`); `None`: the paper's modes.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub static_knots: Option<StaticKnots>,
}

impl ModelConfig {
    /// Number of sections.
    pub fn sections(&self) -> usize {
        self.modes.len()
    }

    /// Number of generalized coordinates.
    pub fn dof(&self) -> usize {
        (1..=self.sections()).map(|k| self.coordinates(k)).sum()
    }

    /// Coordinates of section `k` (1-based): its modes and its correction shapes.
    pub fn coordinates(&self, k: usize) -> usize {
        self.modes[k - 1] + self.static_knots.as_ref().map_or(0, |s| s.shapes(k))
    }

    /// Number of contact points.
    pub fn contact_count(&self) -> usize {
        (self.sections() - 1) * self.contacts
    }

    /// Index of the first coordinate of section `k` (1-based).
    pub fn offset(&self, k: usize) -> usize {
        (1..k).map(|j| self.coordinates(j)).sum()
    }

    /// A stable identifier, also the emitted module's name, e.g.
    /// `s2_m5x5_c3_cable_linear_fixed_force`.
    pub fn key(&self) -> String {
        let modes: Vec<String> = self.modes.iter().map(|m| m.to_string()).collect();
        let basis = match &self.static_knots {
            None => String::new(),
            Some(knots) => format!("_static{:08x}", knots.digest()),
        };
        format!(
            "s{}_m{}{basis}_c{}_{}_{}_{}_{}",
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
        if let Some(StaticKnots(knots)) = &self.static_knots {
            if knots.len() != self.sections() {
                return Err(format!(
                    "static_knots: one list per section ({} sections, got {})",
                    self.sections(),
                    knots.len()
                ));
            }
            for (k, list) in knots.iter().enumerate() {
                let inside = list.iter().all(|x| *x > 0.0 && *x < 1.0);
                if !inside || list.windows(2).any(|w| w[0] >= w[1]) {
                    return Err(format!(
                        "static_knots: section {}'s fractions ascending and strictly inside \
                         (0, 1) (got {list:?})",
                        k + 1
                    ));
                }
            }
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
        )?;
        match &self.static_knots {
            None => Ok(()),
            Some(StaticKnots(knots)) => write!(f, ", static_knots = {knots:?}"),
        }
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
        ) + &match &self.static_knots {
            None => String::new(),
            // `{:?}` writes the shortest decimal that reads back to the same bits
            Some(StaticKnots(knots)) => format!("static_knots = {knots:?}\n"),
        }
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
            static_knots: None,
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
    fn static_knots_read_back_bit_for_bit_and_name_the_key() {
        let knots = StaticKnots(vec![vec![0.1 + 0.2, 0.7], vec![1.0 / 3.0]]);
        let config = ModelConfig {
            modes: vec![6, 6],
            contacts: 2,
            force_flow: ForceFlow::Cable,
            clearance: false,
            positions: Positions::Moving,
            drive: DriveKind::Force,
            static_knots: Some(knots.clone()),
        };
        #[derive(Deserialize)]
        struct File {
            model: Vec<ModelConfig>,
        }
        let file: File = toml::from_str(&config.models_toml_entry()).unwrap();
        assert_eq!(file.model, std::slice::from_ref(&config));
        // two corrections more than knots per section, after the modes
        assert_eq!(
            (config.coordinates(1), config.dof(), config.offset(2)),
            (10, 19, 10)
        );
        let plain = ModelConfig {
            static_knots: None,
            ..config.clone()
        };
        let moved = ModelConfig {
            static_knots: Some(StaticKnots(vec![vec![0.3, 0.7], vec![1.0 / 3.0]])),
            ..config.clone()
        };
        // 0.1 + 0.2 is not 0.3: knots one rounding apart are other models
        assert!(config.key().starts_with("s2_m6x6_static"));
        assert_ne!(config.key(), moved.key());
        assert_ne!(config.key(), plain.key());
        assert_eq!(plain.key(), "s2_m6x6_c2_cable_linear_moving_force");
        assert!(config.validate().is_ok());
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
            static_knots: None,
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
            (
                ModelConfig {
                    static_knots: Some(StaticKnots(vec![vec![0.5]])),
                    ..base.clone()
                },
                "one list per section",
            ),
            (
                ModelConfig {
                    static_knots: Some(StaticKnots(vec![vec![0.5, 0.4], vec![0.2]])),
                    ..base.clone()
                },
                "section 1's fractions ascending",
            ),
            (
                ModelConfig {
                    static_knots: Some(StaticKnots(vec![vec![0.5], vec![1.0]])),
                    ..base.clone()
                },
                "section 2's fractions ascending and strictly inside",
            ),
        ] {
            let e = config.validate().unwrap_err();
            assert!(e.contains(rule), "{e}");
        }
    }
}
