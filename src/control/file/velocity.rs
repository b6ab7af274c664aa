//! The velocity-feedback file: its layout, its checks and what it tells a run.

use crate::control::law::strain::STRAIN_RATE_SENSORS;
use crate::{Error, OptionName, Result};
use serde::{Deserialize, Serialize};
use telescopic_runtime::{Drive, ModelParams, Scene, configuration_key};

/// The `format` of a velocity-feedback file.
pub const VELOCITY_FEEDBACK_FORMAT: &str = "telescopic velocity feedback";

/// The layout version this build writes and reads.
pub const VELOCITY_FEEDBACK_VERSION: u32 = 3;

/// A designed velocity-servo feedback: what `plan` writes beside a plan that uses feedback,
/// and `simulate --controller` reads.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct VelocityFeedback {
    /// `telescopic velocity feedback`.
    pub format: String,
    /// Layout version of the file.
    pub version: u32,
    /// The tool that wrote it.
    pub generator: String,
    /// The scene designed for.
    pub scene: String,
    /// Its configuration key (a scene of another configuration is refused).
    pub configuration: String,
    /// Controller rate (Hz).
    pub rate_hz: f64,
    /// The measured outputs: `vehicle` and `kappa_1_0`.
    pub sensors: Vec<String>,
    /// Their measurement noise (standard deviation, m and 1/m).
    pub noise: Vec<f64>,
    /// Seed of the simulated measurement noise.
    pub seed: u64,
    /// The first mode's damping ratio with the loop closed (the design's knob; the
    /// structure's own is about zero, so it is the damping the law adds).
    pub added_damping: f64,
    /// The vehicle's two closed-loop poles, real, in units of the first mode's angular
    /// frequency (their sizes: `s = -p omega_1`).
    pub vehicle_poles_per_mode: [f64; 2],
    /// The damping ratio of the observer's oscillatory pair.
    pub observer_damping: f64,
    /// The observer pair's natural frequency in units of the first mode's.
    pub observer_frequency_per_mode: f64,
    /// The observer's real pole (its estimate of the curvature at rest), in units of the
    /// first mode's angular frequency.
    pub observer_bias_pole_per_mode: f64,
    /// Bound of the velocity correction (m/s).
    pub velocity_limit_m_per_s: f64,
    /// Bound of the correction's acceleration (m/s^2).
    pub acceleration_limit_m_per_s2: f64,
    /// The scheduled position (`a_k`), if the positions move.
    pub schedule_parameter: Option<String>,
    /// The design points per load the law is scheduled on, ordered by the load; one table
    /// is used whatever the load.
    pub tables: Vec<VelocityTable>,
}

/// The design points at one load.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct VelocityTable {
    /// The load designed for (kg).
    pub load_kg: f64,
    /// The design points, ordered by the scheduled position (the same positions in every
    /// table).
    pub points: Vec<VelocityPoint>,
}

/// The law at one design point.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct VelocityPoint {
    /// Telescopic positions `a_2..a_n` (m).
    pub positions: Vec<f64>,
    /// The first elastic mode's frequency with the vehicle held (Hz).
    pub first_mode_hz: f64,
    /// `tip_rel` per `kappa_1_0` in that mode (m^2).
    pub tip_per_curvature_m2: f64,
    /// `c`: `kappa_1_0` at rest under a unit vehicle acceleration, vehicle held (1/m per
    /// m/s^2).
    pub curvature_per_acceleration: f64,
}

/// The rule a load the law is told keeps (kg): `Err` with the rule broken.
pub(crate) fn check_weighed_load(load_kg: f64) -> std::result::Result<(), String> {
    match load_kg.is_finite() && load_kg >= 0.0 {
        true => Ok(()),
        false => Err(format!(
            "must be a finite mass of 0 kg or more (got {load_kg})"
        )),
    }
}

pub(crate) fn field(name: &str, rule: impl std::fmt::Display) -> Error {
    Error::input(format!("velocity feedback `{name}`"), rule)
}

impl VelocityFeedback {
    /// The file (JSON).
    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(self).expect("plain data") + "\n"
    }

    /// Whether `text` says it is a velocity-feedback file (its `format` field), whatever
    /// its version or contents.
    pub fn is_feedback_file(text: &str) -> bool {
        serde_json::from_str::<serde_json::Value>(text)
            .is_ok_and(|head| feedback_format(&head) == Some(VELOCITY_FEEDBACK_FORMAT))
    }

    /// Reads a velocity-feedback file: its format and version first.
    ///
    /// # Errors
    /// [`Error::Input`] naming what is malformed.
    pub fn from_json(text: &str) -> Result<Self> {
        let malformed = |e: serde_json::Error| Error::input("velocity feedback", e);
        crate::io::unique_keys::check_unique_keys(text)
            .map_err(|e| Error::input("velocity feedback", e))?;
        let head: serde_json::Value = serde_json::from_str(text).map_err(malformed)?;
        if feedback_format(&head) != Some(VELOCITY_FEEDBACK_FORMAT) {
            return Err(Error::input(
                "velocity feedback",
                format!("`format` is not \"{VELOCITY_FEEDBACK_FORMAT}\""),
            ));
        }
        let version = head.get("version").and_then(|v| v.as_u64());
        if version != Some(u64::from(VELOCITY_FEEDBACK_VERSION)) {
            return Err(Error::input(
                "velocity feedback",
                format!(
                    "layout version {}, but this build reads version \
                     {VELOCITY_FEEDBACK_VERSION}; plan again with this build",
                    version.map_or("none".to_string(), |v| v.to_string())
                ),
            ));
        }
        serde_json::from_value(head).map_err(malformed)
    }

    /// In a few words, e.g. `velocity feedback (zeta 0.30) from vehicle, kappa_1_0 at 1000 Hz,
    /// scheduled on the load 10 to 30 kg`.
    pub fn describe(&self) -> String {
        let loads = self.loads();
        let scheduled = match loads[..] {
            [first, .., last] => format!(", scheduled on the load {first} to {last} kg"),
            _ => String::new(),
        };
        format!(
            "velocity feedback (zeta {:.2}) from {} at {} Hz{scheduled}",
            self.added_damping,
            self.sensors.join(", "),
            self.rate_hz
        )
    }

    /// The loads of the tables (kg), ascending.
    pub fn loads(&self) -> Vec<f64> {
        self.tables.iter().map(|t| t.load_kg).collect()
    }

    /// Checks that the file fits `scene`: the configuration, a prescribed motion, the sensors
    /// the law reads, finite bounded settings and one position per telescopic position at
    /// every point.
    ///
    /// # Errors
    /// [`Error::Input`] naming the field and the rule; [`Error::Option`] for a scene without
    /// a prescribed motion.
    pub fn check_fits(&self, scene: &Scene) -> Result<()> {
        let params = &scene.params;
        if !matches!(params.drive, Drive::Motion(_)) {
            return Err(Error::option(
                OptionName::Controller,
                "velocity feedback corrects a prescribed motion; the scene's drive is a force",
            ));
        }
        let key = configuration_key(params);
        if key != self.configuration {
            return Err(field(
                "configuration",
                format!(
                    "designed for configuration {} (scene {}), the scene is {key}",
                    self.configuration, self.scene
                ),
            ));
        }
        if self.sensors != STRAIN_RATE_SENSORS || self.noise.len() != self.sensors.len() {
            return Err(field(
                "sensors",
                "must be [\"vehicle\", \"kappa_1_0\"] with one noise each",
            ));
        }
        // a standard deviation of 1 m on the vehicle or 1 1/m on a curvature (a beam bent
        // to a 1 m radius) is no measurement; NaN commands follow from larger ones
        for (i, (v, unit)) in self.noise.iter().zip(["m", "1/m"]).enumerate() {
            if !(v.is_finite() && (0.0..=1.0).contains(v)) {
                return Err(field(
                    &format!("noise[{i}]"),
                    format!("must be 0 to 1 {unit} (got {v})"),
                ));
            }
        }
        crate::control::law::sampled::check_rate(self.rate_hz).map_err(|_| {
            field(
                "rate_hz",
                format!("must be 1 to 1e6 Hz (got {})", self.rate_hz),
            )
        })?;
        for (name, v, high) in [
            ("added_damping", self.added_damping, 2.0),
            (
                "vehicle_poles_per_mode[0]",
                self.vehicle_poles_per_mode[0],
                100.0,
            ),
            (
                "vehicle_poles_per_mode[1]",
                self.vehicle_poles_per_mode[1],
                100.0,
            ),
            ("observer_damping", self.observer_damping, 2.0),
            (
                "observer_frequency_per_mode",
                self.observer_frequency_per_mode,
                100.0,
            ),
            (
                "observer_bias_pole_per_mode",
                self.observer_bias_pole_per_mode,
                100.0,
            ),
            ("velocity_limit_m_per_s", self.velocity_limit_m_per_s, 1e3),
            (
                "acceleration_limit_m_per_s2",
                self.acceleration_limit_m_per_s2,
                1e4,
            ),
        ] {
            if !(v.is_finite() && v > 0.0 && v <= high) {
                return Err(field(
                    name,
                    format!("must be > 0 and at most {high} (got {v})"),
                ));
            }
        }
        self.check_tables(params)
    }

    /// The tables: one or more, at finite positive ascending loads, each with the same
    /// scheduled positions.
    fn check_tables(&self, params: &ModelParams) -> Result<()> {
        let Some(first) = self.tables.first() else {
            return Err(field(
                "tables",
                "must hold at least one table of design points",
            ));
        };
        let scheduled = self.scheduled_index();
        let names_a_position = scheduled.is_some_and(|i| i < params.positions.len());
        if (self.schedule_parameter.is_some() || first.points.len() > 1) && !names_a_position {
            return Err(field(
                "schedule_parameter",
                "must name a telescopic position of the scene (a_2, ...), as it must when there \
                 are several points",
            ));
        }
        for (t, table) in self.tables.iter().enumerate() {
            let m = table.load_kg;
            if !(m.is_finite() && m > 0.0 && m <= 1e9) {
                return Err(field(
                    &format!("tables[{t}].load_kg"),
                    format!("must be > 0 and at most 1e9 kg (got {m})"),
                ));
            }
            if t > 0 && m <= self.tables[t - 1].load_kg {
                return Err(field("tables", "must ascend strictly along load_kg"));
            }
            check_points(&format!("tables[{t}].points"), &table.points, params)?;
            if let Some(i) = scheduled
                && table
                    .points
                    .windows(2)
                    .any(|w| w[1].positions[i] < w[0].positions[i])
            {
                return Err(field(
                    &format!("tables[{t}].points"),
                    "must ascend along the scheduled position",
                ));
            }
            let at = |points: &[VelocityPoint]| -> Vec<f64> {
                points
                    .iter()
                    .map(|p| scheduled.map_or(0.0, |i| p.positions[i]))
                    .collect()
            };
            if at(&table.points) != at(&first.points) {
                return Err(field(
                    &format!("tables[{t}].points"),
                    "must be at the scheduled positions of tables[0], one for one",
                ));
            }
        }
        Ok(())
    }

    /// Each design point's scheduled position (m): zeros when nothing is scheduled.
    pub(crate) fn scheduled_positions(&self) -> Vec<f64> {
        let points = self.tables.first().map_or(&[][..], |t| &t.points[..]);
        match self.scheduled_index() {
            Some(i) => points.iter().map(|p| p.positions[i]).collect(),
            None => vec![0.0; points.len()],
        }
    }

    /// Index (among `a_2..`) of the scheduled position.
    pub(crate) fn scheduled_index(&self) -> Option<usize> {
        self.schedule_parameter
            .as_deref()
            .and_then(|s| s.strip_prefix("a_"))
            .and_then(|k| k.parse::<usize>().ok())
            .and_then(|k| k.checked_sub(2))
    }
}

/// The design points `points` (named `name` in errors): one or more, positions of the scene's
/// count, finite gains.
fn check_points(name: &str, points: &[VelocityPoint], params: &ModelParams) -> Result<()> {
    if points.is_empty() {
        return Err(field(name, "must hold at least one design point"));
    }
    for (j, p) in points.iter().enumerate() {
        if p.positions.len() != params.positions.len() || p.positions.iter().any(|a| !a.is_finite())
        {
            return Err(field(
                &format!("{name}[{j}].positions"),
                format!("must be {} finite positions", params.positions.len()),
            ));
        }
        for (what, v, high) in [
            ("tip_per_curvature_m2", p.tip_per_curvature_m2, 1e4),
            (
                "curvature_per_acceleration",
                p.curvature_per_acceleration,
                1.0,
            ),
        ] {
            if !(v.is_finite() && v.abs() <= high) {
                return Err(field(
                    &format!("{name}[{j}].{what}"),
                    format!("must be finite, at most {high:e} in size (got {v})"),
                ));
            }
        }
        let f = p.first_mode_hz;
        if !(f.is_finite() && f > 0.0 && f <= 1e4) {
            return Err(field(
                &format!("{name}[{j}].first_mode_hz"),
                format!("must be > 0 and at most 1e4 Hz (got {f})"),
            ));
        }
        // the base's acceleration bends the tip against it: Gamma = -r c w^2 > 0, and the
        // law divides by it (both are finite here, checked above)
        if p.tip_per_curvature_m2 * p.curvature_per_acceleration >= 0.0 {
            return Err(field(
                &format!("{name}[{j}].curvature_per_acceleration"),
                format!(
                    "must be of the opposite sign to tip_per_curvature_m2 and not zero \
                     (got {} and {})",
                    p.curvature_per_acceleration, p.tip_per_curvature_m2
                ),
            ));
        }
    }
    Ok(())
}

/// The `format` field of a JSON file's head.
fn feedback_format(head: &serde_json::Value) -> Option<&str> {
    head.get("format").and_then(|f| f.as_str())
}
