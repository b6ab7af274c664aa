//! Bending moments and stresses at stations along the sections: `M_k(x)` (N m) by force
//! summation ([`StationRows`]), `sigma_k(x) = M_k(x) / W_k` (Pa) with the section modulus
//! `W_k` of the scene (`sections.section_modulus`, or `2 I / h` from `sections.height`).
//!
//! A station is `k:x`: section `k` (1-based, bottom up) at `x` metres from its own foot. Its
//! columns are `moment_k_x` (N m) and, when the scene gives `W`, `stress_k_x` (Pa); a positive
//! moment bends the section with positive curvature `w''`. docs/numerics.md says how well
//! the moments converge with the number of modes, against the finite-element beams.
//!
//! ```
//! use telescopic::run::stress::Station;
//! let stations = Station::parse_list("1:0,1:0.675,2:0.2")?;
//! assert_eq!(stations[1], Station { section: 1, x: 0.675 });
//! assert_eq!(stations[1].moment_name(), "moment_1_0.675");
//! # Ok::<(), telescopic::Error>(())
//! ```

use crate::OptionName;
use crate::run::{Column, Trajectory};
use crate::{Error, Result};
use telescopic_runtime::nalgebra::DVector;
use telescopic_runtime::{Model, Output, Scene};

/// Where a moment is evaluated.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Station {
    /// Section `k` (1-based, bottom up).
    pub section: usize,
    /// Distance from the section's foot (m).
    pub x: f64,
}

impl Station {
    /// Parses `k:x[,k:x...]` (`x` in metres from section `k`'s foot).
    ///
    /// # Errors
    /// [`Error::Option`] naming `--stations` and the entry that does not parse.
    pub fn parse_list(text: &str) -> Result<Vec<Station>> {
        text.split(',')
            .map(str::trim)
            .filter(|s| !s.is_empty())
            .map(|entry| {
                let bad = || {
                    Error::option(
                        OptionName::Stations,
                        format!(
                            "'{entry}' is not SECTION:X (a section number from 1 and a \
                             distance in metres from that section's foot, e.g. 1:0.5)"
                        ),
                    )
                };
                let (k, x) = entry.split_once(':').ok_or_else(bad)?;
                let section = k.trim().parse::<usize>().map_err(|_| bad())?;
                let x = x.trim().parse::<f64>().map_err(|_| bad())?;
                Ok(Station { section, x })
            })
            .collect()
    }

    /// The moment column's name, `moment_k_x` (`x` as given, shortest form).
    pub fn moment_name(&self) -> String {
        self.moment().to_string()
    }

    /// The moment here (N m).
    pub fn moment(&self) -> Output {
        Output::Moment {
            section: self.section,
            x: self.x,
        }
    }

    /// The bending stress at the outer fibre here (Pa).
    pub fn stress(&self) -> Output {
        Output::Stress {
            section: self.section,
            x: self.x,
        }
    }
}

/// The stations of a run as rows over the coordinates, their rates and accelerations, and
/// the contact forces' arms: allocation-free per sample.
///
/// A station's moment is found by **force summation** (the mode-acceleration method): the
/// equilibrium of the part of the section above the station under its inertia, the contact
/// forces on it and its axial prestress,
///
/// ```text
/// M_k(x) = sum_c s_c f_c (x_c - x)_+  -  int_x^l (xi - x) rhoA a(xi) dxi  -  [k = n] m_L (l - x) a(l)
///          + int_x^l P_k(xi) w_k'(xi) dxi
/// ```
///
/// with `a` the acceleration field (plus the structural damping force over the mass, `M^-1
/// D_s z'`, the distributed load whose generalized forces it is), `f_c` the contact forces at
/// their stations `x_c` (`s_c = +1` on the outer section, `-1` on the inner one). It equals
/// `EI w''` for the exact solution, but accelerations and forces converge as fast as the
/// displacements, while the curvature of a truncated series converges slowest exactly where
/// contact forces act (docs/numerics.md measures both against the finite-element beams).
#[derive(Debug, Clone, PartialEq)]
pub struct StationRows {
    stations: Vec<Station>,
    /// Per station: the row over `z` (prestress, N m per coordinate unit).
    displacement: Vec<Vec<f64>>,
    /// Per station: the row over `z'` (structural damping's share).
    rate: Vec<Vec<f64>>,
    /// Per station: the row over `z''` (inertia).
    acceleration: Vec<Vec<f64>>,
    /// The contact points: overlap, fraction along it.
    contacts: Vec<(usize, f64)>,
    /// Section lengths (m) and telescopic positions, for the contact forces' arms.
    lengths: Vec<f64>,
    positions: Vec<telescopic_runtime::Profile>,
    /// `W_k` (m^3) of each station's section, when the scene gives them.
    moduli: Option<Vec<f64>>,
}

impl StationRows {
    /// The rows of `stations` on `scene`'s sections for the coordinates of `model`.
    ///
    /// # Errors
    /// [`Error::Option`] naming `--stations` for a section that does not exist or a distance
    /// outside `[0, l_k]`.
    pub fn new(scene: &Scene, model: &dyn Model, stations: &[Station]) -> Result<Self> {
        check_stations(scene, stations)?;
        let params = &scene.params;
        let inverse_mass_damping = model.damping_matrix().map(|d| {
            let m = model
                .mass_matrix()
                .clone()
                .cholesky()
                .expect("the model's mass is positive definite");
            (d.clone(), m)
        });
        let mut displacement = Vec::with_capacity(stations.len());
        let mut rate = Vec::with_capacity(stations.len());
        let mut acceleration = Vec::with_capacity(stations.len());
        for s in stations {
            let (z_row, a_row) = equilibrium_rows(model, s);
            // D_s M^-1 a_row: the damping force's share, over z'
            let r_row = match &inverse_mass_damping {
                Some((d, m)) => (d * m.solve(&DVector::from_column_slice(&a_row)))
                    .as_slice()
                    .to_vec(),
                None => vec![0.0; a_row.len()],
            };
            displacement.push(z_row);
            rate.push(r_row);
            acceleration.push(a_row);
        }
        let layout = model.layout();
        let moduli = scene
            .section_moduli()
            .map(|w| stations.iter().map(|s| w[s.section - 1]).collect());
        Ok(StationRows {
            stations: stations.to_vec(),
            displacement,
            rate,
            acceleration,
            contacts: layout.contacts().map(|c| (c.overlap, c.fraction)).collect(),
            lengths: params.sections.iter().map(|s| s.length).collect(),
            positions: params.positions.clone(),
            moduli,
        })
    }

    /// No stations.
    pub fn none() -> Self {
        StationRows {
            stations: Vec::new(),
            displacement: Vec::new(),
            rate: Vec::new(),
            acceleration: Vec::new(),
            contacts: Vec::new(),
            lengths: Vec::new(),
            positions: Vec::new(),
            moduli: None,
        }
    }

    /// True without stations.
    pub fn is_empty(&self) -> bool {
        self.stations.is_empty()
    }

    /// How many stations.
    pub fn len(&self) -> usize {
        self.stations.len()
    }

    /// True when stresses come with the moments (the scene gives section moduli).
    pub fn has_stresses(&self) -> bool {
        self.moduli.is_some() && !self.is_empty()
    }

    /// The columns: every `moment_k_x`, then every `stress_k_x` when known.
    pub fn columns(&self) -> Vec<Column> {
        let moments = self.stations.iter().map(Station::moment);
        let stresses = self.stations.iter().map(Station::stress);
        let mut columns: Vec<Column> = moments.map(Column::Output).collect();
        if self.moduli.is_some() {
            columns.extend(stresses.map(Column::Output));
        }
        columns
    }

    /// The values at time `t` (s), state `y = [z, z']` with derivative `ydot = [z', z'']`
    /// and contact forces `forces` (N, the model's `f_k_j` in order) into `out` (in the order
    /// of [`StationRows::columns`]). `dof` is the number of coordinates of `y`: a controller or
    /// observer may carry its own after the plant's.
    pub fn values(
        &self,
        t: f64,
        dof: usize,
        (y, ydot): (&[f64], &[f64]),
        forces: &[f64],
        out: &mut [f64],
    ) {
        let n = self.stations.len();
        for (i, o) in out[..n].iter_mut().enumerate() {
            *o = self.moment(i, t, dof, (y, ydot), forces);
        }
        if let Some(w) = &self.moduli {
            for i in 0..n {
                out[n + i] = out[i] / w[i];
            }
        }
    }

    /// The moment (N m) at station `i`, as [`StationRows::values`] has it.
    pub fn moment(
        &self,
        i: usize,
        t: f64,
        dof: usize,
        (y, ydot): (&[f64], &[f64]),
        forces: &[f64],
    ) -> f64 {
        let dot = |row: &[f64], v: &[f64]| row.iter().zip(v).map(|(a, b)| a * b).sum::<f64>();
        let station = self.stations[i];
        let mut m = dot(&self.displacement[i], y)
            + dot(&self.rate[i], &y[dof..])
            + dot(&self.acceleration[i], &ydot[dof..]);
        for (&(k, s), &f) in self.contacts.iter().zip(forces) {
            let a = self.positions[k - 2].value(t);
            let overlap = self.lengths[k - 2] - a;
            // +f on the outer section k - 1 at a + s o, -f on the inner section k at s o
            if station.section == k - 1 {
                m += f * (a + s * overlap - station.x).max(0.0);
            } else if station.section == k {
                m -= f * (s * overlap - station.x).max(0.0);
            }
        }
        m
    }
}

/// Points per piece and pieces of the composite Gauss rule on `[x, l]` for the station rows:
/// the coordinate functions are smooth, or cubic between spline knots, so 64 pieces of 8
/// points leave an error far below the moments' own.
const STATION_RULE: (usize, usize) = (8, 64);

/// The rows over `z` (prestress, `int_x^l P psi'`) and over the acceleration (`-int_x^l (xi - x)
/// rhoA psi - [k = n] m_L (l - x) psi(l)`) of station `s` on `model`'s coordinates.
fn equilibrium_rows(model: &dyn Model, s: &Station) -> (Vec<f64>, Vec<f64>) {
    let params = model.params();
    let k = s.section;
    let sec = &params.sections[k - 1];
    let (p0, p1) = params.prestress(k);
    let l = sec.length;
    let dof = model.dof();
    let (mut z_row, mut a_row) = (vec![0.0; dof], vec![0.0; dof]);
    let (points, pieces) = STATION_RULE;
    let piece = telescopic_runtime::model::quadrature::SectionQuadrature::with_points(
        (l - s.x) / pieces as f64,
        points,
    );
    for p in 0..pieces {
        let start = s.x + (l - s.x) * p as f64 / pieces as f64;
        for (&u, &w) in piece.nodes.iter().zip(&piece.weights) {
            let xi = start + u;
            let value = model.shape_row(k, xi, 0);
            let slope = model.shape_row(k, xi, 1);
            let prestress = w * (p0 + p1 * xi);
            let inertia = w * sec.mass_per_length * (xi - s.x);
            for j in 0..dof {
                z_row[j] += prestress * slope[j];
                a_row[j] -= inertia * value[j];
            }
        }
    }
    if k == params.sections.len() && params.load_mass > 0.0 {
        for (a, v) in a_row.iter_mut().zip(model.shape_row(k, l, 0)) {
            *a -= params.load_mass * (l - s.x) * v;
        }
    }
    (z_row, a_row)
}

/// Refuses stations on sections that do not exist, outside their section, or given twice
/// (their columns would share a name).
fn check_stations(scene: &Scene, stations: &[Station]) -> Result<()> {
    let sections = &scene.params.sections;
    for (k, s) in stations.iter().enumerate() {
        if stations[..k]
            .iter()
            .any(|o| o.section == s.section && o.x == s.x)
        {
            return Err(Error::option(
                OptionName::Stations,
                format!("{}:{} is given twice", s.section, s.x),
            ));
        }
        if !(1..=sections.len()).contains(&s.section) {
            return Err(Error::option(
                OptionName::Stations,
                format!(
                    "section {} does not exist: the scene has sections 1..={}",
                    s.section,
                    sections.len()
                ),
            ));
        }
        let l = sections[s.section - 1].length;
        if !(s.x.is_finite() && (0.0..=l).contains(&s.x)) {
            return Err(Error::option(
                OptionName::Stations,
                format!(
                    "x = {} m is outside section {} (from its foot, 0 ..= {l} m)",
                    s.x, s.section
                ),
            ));
        }
    }
    Ok(())
}

/// The largest stress magnitude of a run over its stations.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StressEnvelope {
    /// `max |sigma|` (Pa).
    pub max_abs_stress: f64,
    /// Its signed value (Pa).
    pub stress: f64,
    /// Where: section `k` and distance from its foot (m).
    pub station: Station,
    /// When (s).
    pub t: f64,
}

impl StressEnvelope {
    /// The envelope of `trajectory`'s `stress_k_x` columns; `None` without them.
    pub fn of(trajectory: &Trajectory) -> Option<StressEnvelope> {
        let mut best: Option<StressEnvelope> = None;
        for (c, output) in trajectory.outputs() {
            let Output::Stress { section, x } = output else {
                continue;
            };
            let station = Station { section, x };
            for row in &trajectory.rows {
                let v = row[c];
                if best.is_none_or(|b| v.abs() > b.max_abs_stress) {
                    best = Some(StressEnvelope {
                        max_abs_stress: v.abs(),
                        stress: v,
                        station,
                        t: row[0],
                    });
                }
            }
        }
        best
    }

    /// One line for the run summary.
    pub fn describe(&self) -> String {
        format!(
            "stress envelope: max |stress| {:.4} MPa ({:+.4} MPa) at section {}, x = {} m, \
             t = {} s",
            self.max_abs_stress * 1e-6,
            self.stress * 1e-6,
            self.station.section,
            self.station.x,
            self.t
        )
    }
}
