//! What a fit found: the fitted values with their standard deviations and correlations,
//! each sensor's noise, offset and residual, the model it ran, the fitted scene, and the
//! record beside the fitted run for the figure; a validation's per-sensor prediction error.

use super::model_size::FitModel;
use super::noise::NoiseSource;
use super::offsets::{Offsets, offset_of};
use super::problem::FitProblem;
use super::start::StartFit;
use super::uncertainty::uncertainty;
use crate::Result;
use crate::run::{Column, Trajectory};
use std::fmt::Write as _;
use telescopic_runtime::{Output, RunStats, Scene};

/// One fitted value.
#[derive(Debug, Clone, PartialEq)]
pub struct FittedValue {
    /// The scene key.
    pub key: String,
    /// Its SI unit.
    pub unit: &'static str,
    /// The scene's value, where the fit started.
    pub start: f64,
    /// The fitted value.
    pub value: f64,
    /// Its standard deviation (its unit); `None` when it ended on a bound.
    pub std: Option<f64>,
    /// The bounds it was kept in.
    pub bounds: (f64, f64),
}

/// One sensor's part of a fit.
#[derive(Debug, Clone, PartialEq)]
pub struct SensorFit {
    /// The sensor.
    pub output: Output,
    /// Its noise (its unit) and where that figure comes from.
    pub noise: (f64, NoiseSource),
    /// The fitted offset (record minus model; 0 with [`Offsets::Zero`]).
    pub offset: f64,
    /// RMS of the residual at the optimum in the fit's window (its unit).
    pub rms_residual: f64,
    /// The model's truncation estimate for it (its unit), if known.
    pub model_error: Option<f64>,
}

/// How well a run predicts one sensor of a record.
#[derive(Debug, Clone, PartialEq)]
pub struct SensorPrediction {
    /// The sensor.
    pub output: Output,
    /// Its peak: the largest deviation from its mean (its unit).
    pub peak: f64,
    /// Largest error of the prediction (its offset removed as in the fit) (its unit).
    pub max_error: f64,
    /// RMS error (its unit).
    pub rms_error: f64,
}

impl SensorPrediction {
    /// The prediction `p` of record samples `y`.
    pub fn of(output: Output, y: &[f64], p: &[f64], offsets: Offsets) -> Self {
        let offset = offset_of(p, y, offsets);
        let mean = y.iter().sum::<f64>() / y.len() as f64;
        let errors: Vec<f64> = p.iter().zip(y).map(|(p, y)| p - y - offset).collect();
        SensorPrediction {
            output,
            peak: y.iter().map(|y| (y - mean).abs()).fold(0.0, f64::max),
            max_error: errors.iter().map(|e| e.abs()).fold(0.0, f64::max),
            rms_error: rms(&errors),
        }
    }

    /// The largest error relative to the peak.
    pub fn relative(&self) -> f64 {
        self.max_error / self.peak
    }
}

/// A finished fit.
#[derive(Debug, Clone)]
pub struct Identification {
    /// The scene with the fitted values (the scene as given otherwise).
    pub scene: Scene,
    /// The fitted values.
    pub values: Vec<FittedValue>,
    /// The correlation matrix of the values inside their bounds ([`Self::correlated`]).
    pub correlation: Vec<Vec<f64>>,
    /// The keys of the correlation's rows.
    pub correlated: Vec<String>,
    /// Values on a bound the record does not see at all, held there for the others'
    /// deviations (which then do not include their uncertainty).
    pub held: Vec<String>,
    /// The weighted residual's variance per degree of freedom (1: noise and model right).
    pub variance_factor: f64,
    /// The widening of the standard deviations' variance for correlated residuals.
    pub correlation_factor: f64,
    /// Each sensor.
    pub sensors: Vec<SensorFit>,
    /// The model the fit ran.
    pub model: FitModel,
    /// Which part of the record was fitted, and why.
    pub window: String,
    /// What was fitted of a record that starts in motion; `None`: it started at rest.
    pub start: Option<StartFit>,
    /// The recorded drive force's noise (N), where it shows ([`super::noise::force_noise`]).
    pub force_noise: Option<f64>,
    /// Runs of the model the fit made.
    pub runs: usize,
    /// Why the optimizer stopped.
    pub termination: String,
    /// Wall time of the whole fit (s).
    pub wall_s: f64,
    /// The record's sensors.
    pub measured: Trajectory,
    /// The fitted model's sensors, their offsets applied: drawn over `measured`.
    pub fitted: Trajectory,
}

/// A residual RMS above this many noise deviations is a misfit the report warns of: white
/// noise alone keeps it within a few per cent of 1 over thousands of samples.
pub const MISFIT: f64 = 1.5;

fn rms(v: &[f64]) -> f64 {
    (v.iter().map(|e| e * e).sum::<f64>() / v.len() as f64).sqrt()
}

/// The identification at the optimizer's last coordinates (termination and wall time to be
/// set by the caller).
///
/// # Errors
/// A record that does not determine a value; errors of the runs.
pub fn conclude(
    problem: &FitProblem,
    scene: &Scene,
    noise: &[(f64, NoiseSource)],
    model: &FitModel,
    window: String,
) -> Result<Identification> {
    let values = problem.values(&problem.u);
    let evaluation = problem.evaluation_at(&problem.u)?;
    let (predictions, residuals) = (&evaluation.predictions, &evaluation.residuals);
    // a value on a bound stays in the covariance where it can (the others' deviations then
    // include its uncertainty); only where the record does not see it at all is it held
    let all: Vec<usize> = (0..values.len()).collect();
    let inside: Vec<usize> = all
        .iter()
        .copied()
        .filter(|&j| !problem.free[j].at_bound(values[j]))
        .collect();
    let eliminated = problem.eliminated(&evaluation);
    let (used, spread) = match spread_of(problem, &values, (residuals, eliminated), &all) {
        Ok(spread) => (all, Some(spread)),
        Err(_) if inside.len() < values.len() && !inside.is_empty() => {
            let spread = spread_of(problem, &values, (residuals, eliminated), &inside)?;
            (inside.clone(), Some(spread))
        }
        Err(_) if inside.is_empty() => (Vec::new(), None),
        Err(e) => return Err(e),
    };
    let held: Vec<String> = (0..values.len())
        .filter(|j| !used.contains(j))
        .map(|j| problem.free[j].key.clone())
        .collect();
    let std_theta: Vec<Option<f64>> = (0..values.len())
        .map(|j| {
            let k = inside
                .contains(&j)
                .then(|| used.iter().position(|&i| i == j))??;
            Some(spread.as_ref()?.std_theta[k])
        })
        .collect();
    let keys: Vec<String> = problem.free.iter().map(|f| f.key.clone()).collect();
    let fitted_values = fitted_values(problem, &values, &std_theta);
    let pairs: Vec<(&str, f64)> = keys.iter().map(String::as_str).zip(values).collect();
    let sensors = sensor_fits(problem, predictions, noise, model);
    let (measured, fitted) = overlay(problem, predictions);
    Ok(Identification {
        scene: scene.with_values(&pairs)?,
        values: fitted_values,
        correlation: spread
            .as_ref()
            .map_or(Vec::new(), |s| s.correlation.clone()),
        correlated: used.iter().map(|&j| keys[j].clone()).collect(),
        held,
        variance_factor: spread.as_ref().map_or(f64::NAN, |s| s.variance_factor),
        correlation_factor: spread.as_ref().map_or(f64::NAN, |s| s.correlation_factor),
        sensors,
        model: model.clone(),
        window,
        start: evaluation.start,
        force_noise: problem
            .record
            .force
            .as_deref()
            .and_then(super::noise::force_noise),
        runs: problem.runs.load(std::sync::atomic::Ordering::Relaxed),
        termination: String::new(),
        wall_s: 0.0,
        measured,
        fitted,
    })
}

/// The uncertainty of the values `inside` (the others held) from the `residuals` with
/// `eliminated` values solved in closed form; a value on a bound is not refused for a
/// deviation wider than its bounds.
fn spread_of(
    problem: &FitProblem,
    values: &[f64],
    (residuals, eliminated): (&[f64], usize),
    inside: &[usize],
) -> Result<super::uncertainty::Uncertainty> {
    let full = problem.jacobian_in_scale(values)?;
    let jacobian =
        nalgebra::DMatrix::from_fn(full.nrows(), inside.len(), |i, k| full[(i, inside[k])]);
    let keys: Vec<String> = inside
        .iter()
        .map(|&j| problem.free[j].key.clone())
        .collect();
    let record = problem.record;
    let spans: Vec<f64> = inside
        .iter()
        .map(|&j| {
            let f = &problem.free[j];
            if f.at_bound(values[j]) {
                f64::INFINITY
            } else {
                f.theta(f.high) - f.theta(f.low)
            }
        })
        .collect();
    uncertainty(
        &jacobian,
        residuals,
        record.times.len(),
        eliminated,
        &keys,
        &spans,
        &record.source,
    )
}

fn fitted_values(
    problem: &FitProblem,
    values: &[f64],
    std_theta: &[Option<f64>],
) -> Vec<FittedValue> {
    problem
        .free
        .iter()
        .zip(values)
        .zip(std_theta)
        .map(|((f, &value), s)| FittedValue {
            key: f.key.clone(),
            unit: f.unit,
            start: f.start,
            value,
            std: s.map(|s| if f.logarithmic { value * s } else { s }),
            bounds: (f.low, f.high),
        })
        .collect()
}

fn sensor_fits(
    problem: &FitProblem,
    predictions: &[Vec<f64>],
    noise: &[(f64, NoiseSource)],
    model: &FitModel,
) -> Vec<SensorFit> {
    problem
        .record
        .sensors
        .iter()
        .zip(predictions)
        .enumerate()
        .map(|(i, ((output, y), p))| {
            let offset = offset_of(p, y, problem.offsets);
            let residual: Vec<f64> = p.iter().zip(y).map(|(p, y)| p - y - offset).collect();
            SensorFit {
                output: *output,
                noise: noise[i],
                offset: -offset,
                rms_residual: rms(&residual),
                model_error: model.errors[i],
            }
        })
        .collect()
}

/// The record's sensors and the fitted run's (offsets applied) as trajectories.
fn overlay(problem: &FitProblem, predictions: &[Vec<f64>]) -> (Trajectory, Trajectory) {
    let record = problem.record;
    let columns: Vec<Column> = record
        .sensors
        .iter()
        .map(|(o, _)| Column::Output(*o))
        .collect();
    let rows = |value: &dyn Fn(usize, usize) -> f64| -> Vec<Vec<f64>> {
        (0..record.times.len())
            .map(|i| {
                std::iter::once(record.times[i])
                    .chain((0..columns.len()).map(|s| value(s, i)))
                    .collect()
            })
            .collect()
    };
    let offsets: Vec<f64> = record
        .sensors
        .iter()
        .zip(predictions)
        .map(|((_, y), p)| offset_of(p, y, problem.offsets))
        .collect();
    let measured = rows(&|s, i| record.sensors[s].1[i]);
    let fitted = rows(&|s, i| predictions[s][i] - offsets[s]);
    (
        Trajectory::new(columns.clone(), measured, RunStats::default()),
        Trajectory::new(columns, fitted, RunStats::default()),
    )
}

impl Identification {
    /// The report as text: the values, their uncertainty and correlation, the sensors, the
    /// model and the optimizer.
    pub fn to_text(&self) -> String {
        let mut out = String::new();
        let _ = writeln!(
            out,
            "fitted values (standard deviation from the Jacobian at the optimum):"
        );
        for v in &self.values {
            let std = match v.std {
                Some(s) => format!("+- {s:.3e} ({:.2} %)", 100.0 * s / v.value.abs()),
                None => format!(
                    "on a bound of {:e}:{:e}: not determined",
                    v.bounds.0, v.bounds.1
                ),
            };
            let _ = writeln!(
                out,
                "  {:<24} {:>12.6e} {:<6} {std}   (scene {:e})",
                v.key, v.value, v.unit, v.start
            );
        }
        if self.correlated.len() > 1 {
            let _ = writeln!(out, "correlation:");
            for (key, row) in self.correlated.iter().zip(&self.correlation) {
                let cells: Vec<String> = row.iter().map(|c| format!("{c:>6.3}")).collect();
                let _ = writeln!(out, "  {key:<24} {}", cells.join(" "));
            }
        }
        let _ = writeln!(
            out,
            "sensors (residual RMS at the optimum against the noise):"
        );
        for s in &self.sensors {
            let model = s
                .model_error
                .map_or("not estimated".to_string(), |e| format!("{e:.2e}"));
            let _ = writeln!(
                out,
                "  {:<10} residual {:.3e}, noise {:.3e} ({}), offset {:.3e}, model's own error {model}",
                s.output.to_string(),
                s.rms_residual,
                s.noise.0,
                s.noise.1.word(),
                s.offset
            );
        }
        if let Some(start) = &self.start {
            let speed = start.vehicle_speed.map_or(String::new(), |v| {
                format!("; the vehicle's speed at the first sample {v:.4e} m/s")
            });
            let _ = writeln!(
                out,
                "start in motion: the free motion of the {} slowest modes fitted ({} amplitudes, \
                 solved in closed form at every run){speed}",
                start.modes, start.amplitudes
            );
        }
        if let Some(sigma) = self.force_noise {
            let _ = writeln!(
                out,
                "the force record: noise {sigma:.3e} N (estimated); the model is driven by it \
                 as recorded, so the sensors' response to that noise is in their residuals"
            );
        }
        if !self.held.is_empty() {
            let _ = writeln!(
                out,
                "WARNING: the deviations hold {} at its bound: the record does not see it, \
                 and the deviations do not include its uncertainty",
                self.held.join(", ")
            );
        }
        for s in self.misfits() {
            let _ = writeln!(
                out,
                "WARNING: {}'s residual is {:.1} times its noise: the model does not explain it \
                 (a wrong noise figure, a value not freed, a record that does not start at \
                 rest as the model does, a noisy force record, or a model that lacks what the \
                 machine does); the deviations above do not cover such a misfit",
                s.output,
                s.rms_residual / s.noise.0
            );
        }
        let _ = writeln!(out, "{}", self.summary_line());
        out
    }

    /// The sensors whose residual RMS exceeds [`MISFIT`] times their noise.
    pub fn misfits(&self) -> impl Iterator<Item = &SensorFit> {
        self.sensors
            .iter()
            .filter(|s| s.rms_residual > MISFIT * s.noise.0)
    }

    /// The model, the window, the optimizer and the widening, in one line.
    fn summary_line(&self) -> String {
        format!(
            "model {} modes per section ({}); fitted {}; {} runs, {:.2} s; optimizer: {}; \
             residual variance factor {:.2}, widened x{:.2} for correlated residuals",
            self.model.size,
            if self.model.within_noise {
                "its error is within every sensor's noise"
            } else {
                "WARNING: its error exceeds a sensor's noise, the fit absorbs it"
            },
            self.window,
            self.runs,
            self.wall_s,
            self.termination,
            self.variance_factor,
            self.correlation_factor.sqrt()
        )
    }

    /// The fitted scene as a scene file (TOML): the scene as given with the fitted values.
    pub fn scene_toml(&self) -> String {
        self.scene.file.to_toml()
    }

    /// Draws the record's sensors and the fitted run over each other, one panel per
    /// sensor, to an SVG or PNG file.
    ///
    /// # Errors
    /// [`crate::Error::Plot`] or [`crate::Error::Destination`].
    #[cfg(feature = "plot")]
    pub fn write_figure(&self, path: &std::path::Path) -> Result<()> {
        use crate::plot::{Curve, Marks, Role, plot};
        let figures = telescopic_runtime::scene::Figures {
            panels: Some(self.sensors.iter().map(|s| s.output).collect()),
            paper: Vec::new(),
        };
        let curve = |label: &str, traj, role| Curve {
            label: label.into(),
            traj,
            half_band: 0.0,
            role,
        };
        let curves = [
            curve("measured", &self.measured, Role::Scene),
            curve("fitted", &self.fitted, Role::Compared),
        ];
        plot(&figures, &curves, &Marks::default(), path)
    }
}
