//! Bending moments and stresses at stations along the sections, from the Galerkin series:
//! `M_k(x) = EI_k w_k''(x)` (N m), `sigma_k(x) = M_k(x) / W_k` (Pa) with the section modulus
//! `W_k` of the scene (`sections.section_modulus`, or `2 I / h` from `sections.height`).
//!
//! A station is `k:x`: section `k` (1-based, bottom up) at `x` metres from its own foot. Its
//! columns are `moment_k_x` (N m) and, when the scene gives `W`, `stress_k_x` (Pa); a positive
//! moment bends the section with positive curvature `w''`. docs/model.md section 7 says how well
//! the series resolves the moment where contact forces act (the foot of section 1, the
//! overlap ends): the moment is a second derivative of a truncated series.
//!
//! ```
//! use telescopic::stress::Station;
//! let stations = Station::parse_list("1:0,1:0.675,2:0.2")?;
//! assert_eq!(stations[1], Station { section: 1, x: 0.675 });
//! assert_eq!(stations[1].moment_name(), "moment_1_0.675");
//! # Ok::<(), telescopic::Error>(())
//! ```

use crate::simulation::Trajectory;
use crate::{Error, Result};
use telescopic_runtime::Scene;
use telescopic_runtime::sensors::curvature_row;

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
                        "SimulationOptions::stations",
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

    /// The label `k_x` of the columns (`x` as given, shortest form).
    fn label(&self) -> String {
        format!("{}_{}", self.section, self.x)
    }

    /// The moment column's name, `moment_k_x`.
    pub fn moment_name(&self) -> String {
        format!("moment_{}", self.label())
    }

    /// The stress column's name, `stress_k_x`.
    pub fn stress_name(&self) -> String {
        format!("stress_{}", self.label())
    }
}

/// The stations of a run as rows over the coordinates: `moment = row . z`, allocation-free
/// per sample.
#[derive(Debug, Clone, PartialEq)]
pub struct StationRows {
    stations: Vec<Station>,
    /// `EI_k w_k''(x)` per unit of each coordinate (N m per coordinate unit).
    rows: Vec<Vec<f64>>,
    /// `W_k` (m^3) of each station's section, when the scene gives them.
    moduli: Option<Vec<f64>>,
}

impl StationRows {
    /// The rows of `stations` on `scene`'s sections.
    ///
    /// # Errors
    /// [`Error::Option`] naming `--stations` for a section that does not exist or a distance
    /// outside `[0, l_k]`.
    pub fn new(scene: &Scene, stations: &[Station]) -> Result<Self> {
        let sections = &scene.params.sections;
        for s in stations {
            if !(1..=sections.len()).contains(&s.section) {
                return Err(Error::option(
                    "SimulationOptions::stations",
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
                    "SimulationOptions::stations",
                    format!(
                        "x = {} m is outside section {} (from its foot, 0 ..= {l} m)",
                        s.x, s.section
                    ),
                ));
            }
        }
        let rows = stations
            .iter()
            .map(|s| {
                let ei = sections[s.section - 1].bending_stiffness;
                curvature_row(&scene.params, s.section, s.x)
                    .into_iter()
                    .map(|v| ei * v)
                    .collect()
            })
            .collect();
        let moduli = scene
            .section_moduli()
            .map(|w| stations.iter().map(|s| w[s.section - 1]).collect());
        Ok(StationRows {
            stations: stations.to_vec(),
            rows,
            moduli,
        })
    }

    /// True without stations.
    pub fn is_empty(&self) -> bool {
        self.stations.is_empty()
    }

    /// True when stresses come with the moments (the scene gives section moduli).
    pub fn has_stresses(&self) -> bool {
        self.moduli.is_some() && !self.is_empty()
    }

    /// The column names: every `moment_k_x`, then every `stress_k_x` when known.
    pub fn names(&self) -> Vec<String> {
        let mut names: Vec<String> = self.stations.iter().map(Station::moment_name).collect();
        if self.moduli.is_some() {
            names.extend(self.stations.iter().map(Station::stress_name));
        }
        names
    }

    /// The values at coordinates `z` into `out` (in the order of [`StationRows::names`]).
    pub fn values(&self, z: &[f64], out: &mut [f64]) {
        let n = self.rows.len();
        for (i, row) in self.rows.iter().enumerate() {
            out[i] = row.iter().zip(z).map(|(a, b)| a * b).sum();
        }
        if let Some(w) = &self.moduli {
            for i in 0..n {
                out[n + i] = out[i] / w[i];
            }
        }
    }

    /// The moment (N m) at station `i` for coordinates `z`.
    pub fn moment(&self, i: usize, z: &[f64]) -> f64 {
        self.rows[i].iter().zip(z).map(|(a, b)| a * b).sum()
    }
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
        for (c, name) in trajectory.names.iter().enumerate() {
            let Some(label) = name.strip_prefix("stress_") else {
                continue;
            };
            let station = Station::parse_list(&label.replacen('_', ":", 1))
                .ok()?
                .pop()?;
            for row in &trajectory.rows {
                let v = row[c + 1];
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
