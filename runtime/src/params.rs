//! Physical parameters of one model, in SI units, as the scene gives them (validated).

use crate::contact::ContactLaw;
use crate::profile::Profile;
use serde::{Deserialize, Serialize};

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

/// The functions that discretize the sections (docs/model.md section 4).
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize, Default,
)]
pub enum Basis {
    /// The paper's shape functions: `N_k` modes per section.
    #[default]
    #[serde(rename = "modes")]
    Modes,
    /// The paper's modes plus each section's static correction shapes
    /// ([`crate::spline`]): cubic B-splines with knots at its contact stations.
    #[serde(rename = "modes+static")]
    ModesAndStatic,
}

impl Basis {
    /// The scene file's word for it.
    pub fn word(self) -> &'static str {
        match self {
            Basis::Modes => "modes",
            Basis::ModesAndStatic => "modes+static",
        }
    }
}

/// One Euler-Bernoulli section.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SectionParams {
    /// Length `l_k` (m).
    pub length: f64,
    /// Mass per length `rhoA_k` (kg/m).
    pub mass_per_length: f64,
    /// Bending stiffness `EI_k` (N m^2).
    pub bending_stiffness: f64,
    /// Number of shape functions `N_k`.
    pub modes: usize,
}

/// How the vehicle is driven.
#[derive(Debug, Clone, PartialEq)]
pub enum Drive {
    /// A force `F(t)` (N) on the vehicle.
    Force(Profile),
    /// A prescribed vehicle position `s(t)` (m); the force becomes a reaction (an output).
    Motion(Profile),
}

/// Everything a model needs: geometry, materials, masses, gravity, contacts, telescopic
/// positions and drive.
#[derive(Debug, Clone, PartialEq)]
pub struct ModelParams {
    /// Sections from the bottom (k = 1, on the vehicle) up.
    pub sections: Vec<SectionParams>,
    /// Vehicle mass `m_T` (kg), a point mass at the foot of section 1.
    pub vehicle_mass: f64,
    /// Load mass `m_L` (kg), a point mass at the top of section n.
    pub load_mass: f64,
    /// Gravitational acceleration `g` (m/s^2).
    pub gravity: f64,
    /// Axial force flow.
    pub force_flow: ForceFlow,
    /// Contact points per overlap `n_c`.
    pub contact_points: usize,
    /// The contact law (`c`, `d`, `l_S`).
    pub contact: ContactLaw,
    /// Telescopic positions `a_k(t)` (m), `k = 2..n` (index 0 is `a_2`).
    pub positions: Vec<Profile>,
    /// The drive.
    pub drive: Drive,
    /// Structural damping of the sections (none by default).
    pub damping: crate::damping::StructuralDamping,
    /// The functions that discretize the sections.
    pub basis: Basis,
}

impl ModelParams {
    /// The valid range `[min, max]` (m) of the telescopic position `a_k`, `k = 2..n` (index 0
    /// is `a_2`): its overlap `l_{k-1} - a_k` stays in `[0, min(l_{k-1}, l_k)]`.
    pub fn position_range(&self, index: usize) -> (f64, f64) {
        let (below, above) = (self.sections[index].length, self.sections[index + 1].length);
        (below - below.min(above), below)
    }

    /// The profile of the drive: `F(t)` (N) or `s(t)` (m).
    pub fn drive_profile(&self) -> &Profile {
        match &self.drive {
            Drive::Force(p) | Drive::Motion(p) => p,
        }
    }

    /// Number of sections `n`.
    pub fn section_count(&self) -> usize {
        self.sections.len()
    }

    /// Modes per section.
    pub fn modes(&self) -> Vec<usize> {
        self.sections.iter().map(|s| s.modes).collect()
    }

    /// Coordinates per section: its modes, and its static correction shapes for
    /// [`Basis::ModesAndStatic`].
    pub fn coordinates(&self) -> Vec<usize> {
        (1..=self.sections.len())
            .map(|k| {
                let extra = match self.basis {
                    Basis::Modes => 0,
                    Basis::ModesAndStatic => crate::spline::correction_knots(self, k).len() + 2,
                };
                self.sections[k - 1].modes + extra
            })
            .collect()
    }

    /// Total mass: sections, vehicle and load (kg).
    pub fn total_mass(&self) -> f64 {
        self.vehicle_mass
            + self.load_mass
            + self
                .sections
                .iter()
                .map(|s| s.mass_per_length * s.length)
                .sum::<f64>()
    }

    /// Axial compressive force `P_k(x) = p0 + p1 x` of section `k` (1-based) as `(p0, p1)`
    /// in N and N/m.
    pub fn prestress(&self, k: usize) -> (f64, f64) {
        let n = self.sections.len();
        let s = &self.sections[k - 1];
        let g = self.gravity;
        let above = match self.force_flow {
            ForceFlow::None => return (0.0, 0.0),
            ForceFlow::Cable => {
                self.sections[k..]
                    .iter()
                    .map(|u| u.mass_per_length * u.length)
                    .sum::<f64>()
                    + self.load_mass
            }
            ForceFlow::External => {
                if k == n {
                    self.load_mass
                } else {
                    0.0
                }
            }
        };
        (
            g * (s.mass_per_length * s.length + above),
            -g * s.mass_per_length,
        )
    }
}
