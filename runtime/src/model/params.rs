//! Physical parameters of one model, in SI units, as the scene gives them (validated).

use crate::contact::ContactLaw;
use crate::profile::Profile;
use serde::{Deserialize, Serialize};

pub use telescopic_config::ForceFlow;

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
    /// ([`crate::shape::spline`]): cubic B-splines with knots at its contact stations.
    #[serde(rename = "modes+static")]
    ModesAndStatic,
}

/// The contact tables' tolerance on `g` for the static correction shapes (relative).
pub const SPLINE_TABLE_TOLERANCE: f64 = 1e-9;

impl Basis {
    /// The contact tables' tolerances on `g` and its rate (relative) for this basis: the
    /// splines are C2 at their knots, so a contact point crossing one makes `g` only C2 in
    /// time; 1e-9 of `g` is a contact force error of about 1e-9 c |g| |z| (a millinewton on
    /// the shipped scenes), far below the model's truncation.
    pub fn table_tolerances(self) -> (f64, f64) {
        match self {
            Basis::Modes => (
                crate::contact::table::G_TOLERANCE,
                crate::contact::table::GD_TOLERANCE,
            ),
            Basis::ModesAndStatic => (SPLINE_TABLE_TOLERANCE, 1e3 * SPLINE_TABLE_TOLERANCE),
        }
    }

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
    pub damping: StructuralDamping,
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
                    Basis::ModesAndStatic => correction_knots(self, k).len() + 2,
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

/// The structural damping of a model.
#[derive(Debug, Clone, PartialEq, Default)]
pub enum StructuralDamping {
    /// No structural damping (the default).
    #[default]
    None,
    /// Modal damping ratios (1) of the closed-contact modes at `positions`.
    Modal {
        /// The `i`-th value for mode `f_{i+1}` of `telescopic modes` at `positions`; modes
        /// beyond the list take its last value; contact modes take none.
        ratios: Vec<f64>,
        /// The telescopic positions `a_2..a_n` (m) of the modes (the scene's start).
        positions: Vec<f64>,
    },
    /// Rayleigh damping `alpha M + beta K`: `alpha` (1/s), `beta` (s).
    Rayleigh {
        /// Mass-proportional coefficient (1/s).
        alpha: f64,
        /// Stiffness-proportional coefficient (s).
        beta: f64,
    },
}

impl StructuralDamping {
    /// True when there is no structural damping.
    pub fn is_none(&self) -> bool {
        match self {
            StructuralDamping::None => true,
            StructuralDamping::Modal { ratios, .. } => ratios.iter().all(|&z| z == 0.0),
            StructuralDamping::Rayleigh { alpha, beta } => *alpha == 0.0 && *beta == 0.0,
        }
    }

    /// The modal ratio of mode `index` (0-based, ascending frequency), for
    /// [`StructuralDamping::Modal`]; 0 otherwise.
    pub fn modal_ratio(&self, index: usize) -> f64 {
        match self {
            StructuralDamping::Modal { ratios, .. } if !ratios.is_empty() => {
                ratios[index.min(ratios.len() - 1)]
            }
            _ => 0.0,
        }
    }

    /// A short description for run summaries and tables.
    pub fn describe(&self) -> String {
        match self {
            _ if self.is_none() => "none".into(),
            StructuralDamping::Modal { ratios, positions } => {
                let at = if positions.is_empty() {
                    String::new()
                } else {
                    format!(" (closed-contact modes at a = {positions:?} m)")
                };
                if ratios.len() == 1 {
                    format!("modal, zeta = {}{at}", ratios[0])
                } else {
                    format!("modal, zeta = {ratios:?} by mode{at}")
                }
            }
            StructuralDamping::Rayleigh { alpha, beta } => {
                format!("Rayleigh, alpha = {alpha} 1/s, beta = {beta} s")
            }
            StructuralDamping::None => unreachable!("handled by is_none"),
        }
    }
}

/// Knots spread evenly over the range of a moving contact station (both ends included): the
/// splines then hold the station's force wherever it is to within a knot spacing.
pub const MOVING_STATION_KNOTS: usize = 4;

/// The interior knots of section `k` (1-based): every contact station on it strictly inside
/// `(0, l_k)`; a station that moves with its telescopic position gets
/// [`MOVING_STATION_KNOTS`] over the range it travels.
pub fn correction_knots(params: &ModelParams, k: usize) -> Vec<f64> {
    let n = params.sections.len();
    let l = params.sections[k - 1].length;
    let fractions: Vec<f64> = (0..params.contact_points)
        .map(|j| j as f64 / (params.contact_points - 1).max(1) as f64)
        .collect();
    let mut stations: Vec<(f64, f64)> = Vec::new();
    // as the inner section of overlap k: x_in = s (l_{k-1} - a_k)
    if k >= 2 {
        let (lo, hi) = travel(&params.positions[k - 2]);
        let outer = params.sections[k - 2].length;
        stations.extend(
            fractions
                .iter()
                .map(|s| (s * (outer - hi), s * (outer - lo))),
        );
    }
    // as the outer section of overlap k + 1: x_out = a + s (l_k - a), increasing in a
    if k < n {
        let (lo, hi) = travel(&params.positions[k - 1]);
        stations.extend(
            fractions
                .iter()
                .map(|s| (lo + s * (l - lo), hi + s * (l - hi))),
        );
    }
    let mut knots: Vec<f64> = stations
        .iter()
        .flat_map(|&(a, b)| {
            let count = if b > a { MOVING_STATION_KNOTS } else { 1 };
            (0..count).map(move |i| a + (b - a) * i as f64 / (count - 1).max(1) as f64)
        })
        .filter(|&x| x > 1e-9 * l && x < l * (1.0 - 1e-9))
        .collect();
    knots.sort_by(f64::total_cmp);
    knots.dedup_by(|a, b| (*a - *b).abs() <= 1e-6 * l);
    knots
}

/// The smallest and largest value a telescopic position takes (m).
fn travel(position: &Profile) -> (f64, f64) {
    let times = position.breakpoints();
    match (
        times.iter().copied().reduce(f64::min),
        times.iter().copied().reduce(f64::max),
    ) {
        (Some(first), Some(last)) => position.range(first - 1.0, last + 1.0),
        _ => (position.value(0.0), position.value(0.0)),
    }
}
