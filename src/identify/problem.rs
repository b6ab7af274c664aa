//! The least-squares problem of a fit: the model run on the record's time grid with the
//! free values at the optimizer's coordinates, its residuals against the record (each
//! sensor weighted by its noise, its offset removed), and their Jacobian by central
//! differences, the free values' runs side by side (rayon).

use super::free::Free;
use super::offsets::{Offsets, offset_of};
use super::record::Record;
use super::start::{FreeMotion, StartFit};
use crate::report::Reporter;
use crate::run::{ModelSize, PreparedRun, SimulationOptions, Trajectory};
use crate::{Error, Result};
use levenberg_marquardt::LeastSquaresProblem;
use nalgebra_lm::storage::Owned;
use nalgebra_lm::{DMatrix, DVector, Dyn};
use rayon::prelude::*;
use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};
use telescopic_runtime::Scene;

/// Step of the optimizer's central differences in its coordinate (relative to `1 + |u|`),
/// and the first step of the covariance's in the scale coordinate (the optimizer's at the
/// middle of the bounds).
const DIFFERENCE_STEP: f64 = 1e-3;

/// The covariance's difference step of each value follows its own column: the step at which
/// the weighted residuals move by about one (a standard deviation of the value, were it
/// alone), within these fractions of the bounds' width. A run's outputs jump with its values
/// at the level of its rounding and discrete choices, about 0.01-0.07 in weighted residuals
/// on adams-linear at modes+static 21: at the optimizer's step the contact damping's column
/// came out twice its size (the jumps), and a stiffness step that large sits on the
/// frequency's curvature. At one standard deviation the secant is the slope the covariance
/// needs, and the jumps are a few per cent of it.
const STEP_RANGE: (f64, f64) = (1e-12, 0.25);

/// Most sets of runs the covariance's Jacobian is refined by, each with the steps the last
/// columns set.
const COVARIANCE_REFINEMENTS: usize = 2;

/// The optimizer's coordinate is `u + SHIFT`: MINPACK sizes its first trust region by the
/// coordinates' magnitude, and `u` starts at 0 (a start in the middle of its bounds), which
/// would make the first steps of the order of rounding.
const SHIFT: f64 = 1.0;

/// What every fit of one identification shares: the driven scene, the model size, the free
/// values, the weights, and the progress.
pub struct FitSetup<'a> {
    /// The scene on the record's grid with its input.
    pub driven: &'a Scene,
    /// The model size every run of the fit takes.
    pub size: ModelSize,
    /// The free values.
    pub free: &'a [Free],
    /// Each sensor's noise (its unit), in the record's order.
    pub noise: &'a [f64],
    /// Offsets fitted or zero.
    pub offsets: Offsets,
    /// With a record that starts in motion, the slowest modes whose free motion is fitted
    /// ([`super::start`]); `None`: the record starts at rest.
    pub start_modes: Option<usize>,
    /// Progress and notes.
    pub reporter: &'a dyn Reporter,
    /// Runs the optimizer may make (for progress).
    pub budget: usize,
}

/// A run's sensors on the record's grid and their weighted residuals.
#[derive(Debug, Clone)]
pub struct Evaluation {
    /// Each sensor's model samples (with the fitted free motion of a start in motion).
    pub predictions: Vec<Vec<f64>>,
    /// The weighted residuals, sensors one after the other.
    pub residuals: Vec<f64>,
    /// What a start in motion fitted.
    pub start: Option<StartFit>,
}

/// The fit's problem: the setup's model against one part of the record, at the optimizer's
/// coordinates.
pub struct FitProblem<'a> {
    /// The scene on the record's grid with its input, at the model size of the fit.
    pub driven: &'a Scene,
    /// The model size every run of the fit takes.
    pub size: ModelSize,
    /// The free values.
    pub free: &'a [Free],
    /// The record (the part fitted).
    pub record: &'a Record,
    /// Each sensor's noise (its unit), in the record's order.
    pub noise: &'a [f64],
    /// Offsets fitted or zero.
    pub offsets: Offsets,
    /// The slowest modes whose free motion a start in motion fits; `None`: at rest.
    pub start_modes: Option<usize>,
    /// The optimizer's coordinates.
    pub u: Vec<f64>,
    /// Runs made.
    pub runs: AtomicUsize,
    /// The first error of a run, reported after the optimizer stops.
    pub failure: Mutex<Option<Error>>,
    /// The last evaluation the optimizer asked for, and its coordinates.
    last: Mutex<Option<(Vec<f64>, Evaluation)>>,
    /// Progress and notes.
    reporter: &'a dyn Reporter,
    /// Runs the optimizer may make (for progress).
    budget: usize,
}

impl<'a> FitSetup<'a> {
    /// The problem of fitting `record` (or a part of it) at the free values' starts.
    pub fn problem(&self, record: &'a Record) -> FitProblem<'a> {
        FitProblem {
            driven: self.driven,
            size: self.size,
            free: self.free,
            record,
            noise: self.noise,
            offsets: self.offsets,
            start_modes: self.start_modes,
            u: self.free.iter().map(|f| f.u_of(f.start)).collect(),
            runs: AtomicUsize::new(0),
            failure: Mutex::new(None),
            last: Mutex::new(None),
            reporter: self.reporter,
            budget: self.budget,
        }
    }
}

impl FitProblem<'_> {
    /// The problem starting at the free values `values` instead of the scene's.
    pub fn starting_at(mut self, values: &[f64]) -> Self {
        self.u = each(self.free, values, Free::u_of);
        self
    }

    /// The free values at coordinates `u`.
    pub fn values(&self, u: &[f64]) -> Vec<f64> {
        each(self.free, u, Free::value_of_u)
    }

    /// The driven scene with `values` at the fit's model size, ending at the fitted
    /// record's last sample.
    pub fn scene_with(&self, values: &[f64]) -> Result<Scene> {
        let end =
            self.record.times[0] + self.driven.time.sample * (self.record.times.len() - 1) as f64;
        let pairs: Vec<(&str, f64)> = self
            .free
            .iter()
            .zip(values)
            .map(|(f, &v)| (f.key.as_str(), v))
            .chain(std::iter::once(("time.end", end)))
            .collect();
        Ok(self.size.apply(&self.driven.with_values(&pairs)?))
    }

    /// The model's run with `values`.
    pub fn run(&self, values: &[f64]) -> Result<Trajectory> {
        Ok(self.run_and_free_motion(values)?.0)
    }

    /// The model's run with `values`, and the free motions of a start in motion.
    fn run_and_free_motion(&self, values: &[f64]) -> Result<(Trajectory, Option<FreeMotion>)> {
        let scene = self.scene_with(values)?;
        let run = PreparedRun::new(&scene, &run_options(), &crate::Silent)?;
        let trajectory = run.integrate(&crate::Silent)?;
        let free = self
            .start_modes
            .map(|modes| FreeMotion::of(run.model(), &scene, self.record, modes))
            .transpose()?;
        let done = self.runs.fetch_add(1, Ordering::Relaxed) + 1;
        self.reporter
            .progress((done as f64 / self.budget as f64).min(0.99));
        Ok((trajectory, free))
    }

    /// Each sensor's model samples on the record's grid.
    pub fn predictions(&self, trajectory: &Trajectory) -> Result<Vec<Vec<f64>>> {
        predictions(trajectory, self.record)
    }

    /// The weighted residuals of `predictions`: per sensor `(model - record - offset) /
    /// noise`, sensors one after the other.
    pub fn weighted(&self, predictions: &[Vec<f64>]) -> Vec<f64> {
        let mut out = Vec::with_capacity(predictions.len() * self.record.times.len());
        for ((p, (_, y)), sigma) in predictions.iter().zip(&self.record.sensors).zip(self.noise) {
            let offset = offset_of(p, y, self.offsets);
            out.extend(p.iter().zip(y).map(|(p, y)| (p - y - offset) / sigma));
        }
        out
    }

    /// The sensors' model samples (with the free motion a start in motion fits) and their
    /// weighted residuals with `values`.
    fn evaluate(&self, values: &[f64]) -> Result<Evaluation> {
        let (trajectory, free) = self.run_and_free_motion(values)?;
        let mut predictions = self.predictions(&trajectory)?;
        let start = free
            .map(|free| free.add_fitted(&mut predictions, self.record, self.noise, self.offsets));
        let residuals = self.weighted(&predictions);
        Ok(Evaluation {
            predictions,
            residuals,
            start,
        })
    }

    /// The values eliminated in closed form at `evaluation`: the offsets and the amplitudes
    /// of a start in motion.
    pub fn eliminated(&self, evaluation: &Evaluation) -> usize {
        self.offsets.count(self.record.sensors.len()) + evaluation.start.map_or(0, |s| s.amplitudes)
    }

    /// Keeps the first failure for after the optimizer stops.
    fn fail(&self, error: Error) {
        let mut failure = self.failure.lock().expect("not poisoned");
        failure.get_or_insert(error);
    }

    /// The evaluation at coordinates `u`: the last one when it was at `u`, else a run.
    pub fn evaluation_at(&self, u: &[f64]) -> Result<Evaluation> {
        if let Some((at, last)) = &*self.last.lock().expect("not poisoned")
            && at == u
        {
            return Ok(last.clone());
        }
        let evaluation = self.evaluate(&self.values(u))?;
        *self.last.lock().expect("not poisoned") = Some((u.to_vec(), evaluation.clone()));
        Ok(evaluation)
    }

    /// The Jacobian of the weighted residuals in the optimizer's coordinates `u` at `u`.
    pub fn jacobian_at(&self, u: &[f64]) -> Result<DMatrix<f64>> {
        let steps: Vec<f64> = u
            .iter()
            .map(|u| DIFFERENCE_STEP * (1.0 + u.abs()))
            .collect();
        let unbounded = vec![(f64::NEG_INFINITY, f64::INFINITY); u.len()];
        self.central_differences(u, &steps, &unbounded, &|u| {
            Ok(self.evaluate(&self.values(u))?.residuals)
        })
    }

    /// The Jacobian of the weighted residuals in the scale coordinates `theta` (a value's
    /// logarithm, or the value) at `values`: what the covariance is made from. Unlike the
    /// optimizer's coordinates it does not flatten at the bounds. Each value's step is
    /// refined until its column moves the residuals by about one over it (within a quarter
    /// of the bounds' width; at most two more sets of runs).
    pub fn jacobian_in_scale(&self, values: &[f64]) -> Result<DMatrix<f64>> {
        let theta = each(self.free, values, Free::theta);
        let limits: Vec<(f64, f64)> = self.free.iter().map(Free::theta_bounds).collect();
        // the optimizer's step at the middle of the bounds, to begin with
        let mut steps: Vec<f64> = self
            .free
            .iter()
            .map(|f| DIFFERENCE_STEP * f.dtheta_du(0.0))
            .collect();
        let mut refinements = 0;
        loop {
            let jacobian = self.central_differences(&theta, &steps, &limits, &|theta| {
                Ok(self
                    .evaluate(&each(self.free, theta, Free::value_of_theta))?
                    .residuals)
            })?;
            let next = self.steps_of(&jacobian);
            let settled = next
                .iter()
                .zip(&steps)
                .all(|(new, old)| (new / old).log2().abs() < 1.0);
            if settled || refinements == COVARIANCE_REFINEMENTS {
                return Ok(jacobian);
            }
            (steps, refinements) = (next, refinements + 1);
        }
    }

    /// Each value's step from its column of `jacobian` (scale coordinates): the step over
    /// which the weighted residuals move by one, within [`STEP_RANGE`] of the bounds' width.
    fn steps_of(&self, jacobian: &DMatrix<f64>) -> Vec<f64> {
        self.free
            .iter()
            .enumerate()
            .map(|(j, f)| {
                let norm = jacobian.column(j).norm();
                let (a, b) = f.theta_bounds();
                let (low, high) = (STEP_RANGE.0 * (b - a), STEP_RANGE.1 * (b - a));
                if norm.is_finite() && norm > 0.0 {
                    (1.0 / norm).clamp(low, high)
                } else {
                    high
                }
            })
            .collect()
    }

    /// Central differences of `residuals` at `point` with `steps`, each side kept within
    /// `limits` (a value on its bound is differenced on one side: a step past it could
    /// leave what the scene allows, a clearance below zero), the runs side by side.
    fn central_differences(
        &self,
        point: &[f64],
        steps: &[f64],
        limits: &[(f64, f64)],
        residuals: &(dyn Fn(&[f64]) -> Result<Vec<f64>> + Sync),
    ) -> Result<DMatrix<f64>> {
        let side = |k: usize| {
            let (j, (low, high)) = (k / 2, limits[k / 2]);
            let moved = point[j]
                + if k.is_multiple_of(2) {
                    steps[j]
                } else {
                    -steps[j]
                };
            moved.clamp(low.min(point[j]), high.max(point[j]))
        };
        let sides: Vec<Result<Vec<f64>>> = (0..2 * point.len())
            .into_par_iter()
            .map(|k| {
                let mut moved = point.to_vec();
                moved[k / 2] = side(k);
                residuals(&moved)
            })
            .collect();
        let mut sides = sides.into_iter();
        let mut columns = Vec::with_capacity(point.len());
        for j in 0..point.len() {
            let plus = sides.next().expect("two per value")?;
            let minus = sides.next().expect("two per value")?;
            let width = side(2 * j) - side(2 * j + 1);
            let column: Vec<f64> = plus
                .iter()
                .zip(&minus)
                .map(|(p, m)| (p - m) / width)
                .collect();
            columns.push(DVector::from_vec(column));
        }
        Ok(DMatrix::from_columns(&columns))
    }
}

/// The options of every run of a fit, and of a fitted scene's run: the size as given, no
/// error estimate of its own (the fit's model size was checked once, before).
pub fn run_options() -> SimulationOptions {
    SimulationOptions {
        modes_as_given: true,
        error_estimate: false,
        ..SimulationOptions::default()
    }
}

/// `map` of each free value and its entry of `xs`, in order.
fn each(free: &[Free], xs: &[f64], map: impl Fn(&Free, f64) -> f64) -> Vec<f64> {
    free.iter().zip(xs).map(|(f, &x)| map(f, x)).collect()
}

/// Each of `record`'s sensors from `trajectory` (on the record's grid).
///
/// # Errors
/// [`Error::Input`] naming the column when the model has no such output, or when the run's
/// grid does not match the record's.
pub fn predictions(trajectory: &Trajectory, record: &Record) -> Result<Vec<Vec<f64>>> {
    let n = record.times.len();
    record
        .sensors
        .iter()
        .map(|(output, _)| {
            let column = trajectory.column_of(*output).ok_or_else(|| Error::Input {
                subject: format!("{}, column {output}", record.source),
                rule: format!(
                    "the scene cannot produce it; its outputs: {}",
                    trajectory.names().join(", ")
                ),
            })?;
            if column.len() < n {
                return Err(Error::Input {
                    subject: record.source.clone(),
                    rule: format!("{n} samples, the model's run has {}", column.len()),
                });
            }
            Ok(column[..n].to_vec())
        })
        .collect()
}

impl LeastSquaresProblem<f64, Dyn, Dyn> for FitProblem<'_> {
    type ResidualStorage = Owned<f64, Dyn>;
    type JacobianStorage = Owned<f64, Dyn, Dyn>;
    type ParameterStorage = Owned<f64, Dyn>;

    fn set_params(&mut self, x: &DVector<f64>) {
        self.u = x.iter().map(|x| x - SHIFT).collect();
    }

    fn params(&self) -> DVector<f64> {
        DVector::from_iterator(self.u.len(), self.u.iter().map(|u| u + SHIFT))
    }

    fn residuals(&self) -> Option<DVector<f64>> {
        match self.evaluation_at(&self.u) {
            Ok(evaluation) => Some(DVector::from_vec(evaluation.residuals)),
            Err(e) => {
                self.fail(e);
                None
            }
        }
    }

    fn jacobian(&self) -> Option<DMatrix<f64>> {
        if self.reporter.stop_requested() {
            self.fail(Error::Stopped {
                what: "the fit".into(),
            });
            return None;
        }
        match self.jacobian_at(&self.u) {
            Ok(j) => Some(j),
            Err(e) => {
                self.fail(e);
                None
            }
        }
    }
}
