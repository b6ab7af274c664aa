//! A record that starts in motion: the model starts from rest at the record's first sample,
//! the machine did not. Where the model is linear (closed contacts, fixed positions), the
//! machine's motion is the model's run from rest plus the free motion of its state at that
//! sample, and a free motion is a sum of the model's modes: each mode's sensors
//! `C v e^(lambda t)` from an eigenpair `(lambda, v)` of the scene's linear model `A`. The
//! slowest modes' amplitudes, the vehicle's speed (and position) at the first sample and each
//! sensor's offset enter the sensors linearly: they are eliminated in closed form at every run
//! of the fit (weighted least squares, variable projection), beside the free values. The
//! modes above the kept ones are taken to have died out or to stay below the noise; the
//! residual shows when they do not.

use super::offsets::Offsets;
use super::record::Record;
use crate::{Error, OptionName, Result};
use nalgebra::{Complex, DMatrix, DVector};
use telescopic_runtime::analysis::eigen::eigenvalues;
use telescopic_runtime::analysis::linear::{ContactMode, Lpv};
use telescopic_runtime::{Drive, Model, Output, Scene};

/// How the machine was moving at the record's first sample.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Start {
    /// At rest, as the model starts: nothing more is fitted.
    #[default]
    Rest,
    /// In motion: the free motion of the slowest modes and the vehicle's speed at the first
    /// sample are fitted beside the offsets (closed contacts and fixed positions only).
    Moving,
}

crate::named::named_enum!(Start, "a start", {
    Rest => "rest",
    Moving => "moving",
});

/// Most modes whose free motion a start in motion fits: the slowest of those below half the
/// record's sample rate (a faster mode's motion is not resolved by the samples, and its fitted
/// amplitude would take up the first sample's noise).
pub const MOST_START_MODES: usize = 16;

/// Eigenvalues below this (rad/s) are the vehicle's rigid motion, fitted as its speed and
/// position instead.
const RIGID: f64 = 1e-3;

/// The free motions a start in motion adds to the model's sensors: one column per real
/// amplitude, each with the sensors' samples on the record's grid, sensors in the record's
/// order.
pub struct FreeMotion {
    /// `columns[c][s][i]`: column `c`, sensor `s`, sample `i`.
    columns: Vec<Vec<Vec<f64>>>,
    /// Each column's vehicle rate at the first sample (m/s per unit), when the vehicle is a
    /// sensor.
    vehicle_rates: Option<Vec<f64>>,
    /// The column that is the vehicle's position at the first sample: left out where the
    /// offsets are fitted (the vehicle's offset is that position).
    position: Option<usize>,
    /// Modes kept.
    pub modes: usize,
}

/// What the elimination found for a start in motion.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StartFit {
    /// Modes whose free motion was fitted.
    pub modes: usize,
    /// Amplitudes fitted beside the offsets (the values a start in motion adds: the columns'
    /// rank beyond the offsets').
    pub amplitudes: usize,
    /// The vehicle's speed at the first sample (m/s), the rate of the fitted free motion
    /// there (the model's run starts at rest), when the vehicle is a sensor.
    pub vehicle_speed: Option<f64>,
}

/// Refuses a start in motion where the model is not linear in its state: clearance (the
/// contacts switch) or moving positions (the model changes in time).
///
/// # Errors
/// [`Error::Option`] naming the rule.
pub fn check(scene: &Scene, start: Start) -> Result<()> {
    if start == Start::Rest {
        return Ok(());
    }
    let why = if !scene.params.contact.is_linear() {
        Some(
            "the scene has clearance: its contacts switch, and a free motion added to a run \
             from rest is no motion of the model",
        )
    } else if scene.params.positions.iter().any(|p| !p.is_constant()) {
        Some("the scene's positions move: its modes change in time")
    } else {
        None
    };
    match why {
        Some(why) => Err(Error::option(
            OptionName::Start,
            format!(
                "a start in motion is fitted on closed contacts (contact.clearance = 0) and \
                 fixed positions only; {why}. Trim the record to start at rest"
            ),
        )),
        None => Ok(()),
    }
}

/// How many of the slowest modes of `scene` (on `model`) a start in motion fits on a
/// record sampled every `interval` seconds: those below half the sample rate, at most
/// [`MOST_START_MODES`].
///
/// # Errors
/// The linear model's errors.
pub fn modes_below_rate(model: &dyn Model, scene: &Scene, interval: f64) -> Result<usize> {
    // half the sample rate (Nyquist), in rad/s
    let limit = std::f64::consts::PI / interval;
    let count = slowest_eigenvalues(model, scene)?
        .iter()
        .take_while(|l| l.norm() <= limit)
        .count();
    Ok(count.min(MOST_START_MODES))
}

/// The linear model of `scene` on `model` at its first sample with closed contacts: `A`,
/// `C` and the outputs' names.
fn linear_model(
    model: &dyn Model,
    scene: &Scene,
) -> Result<(DMatrix<f64>, DMatrix<f64>, Vec<String>)> {
    let lpv = Lpv::new(model, ContactMode::Closed)?;
    let t0 = scene.time.start;
    let positions: Vec<f64> = scene.params.positions.iter().map(|p| p.value(t0)).collect();
    let linear = lpv.at(&positions, &vec![0.0; positions.len()])?;
    let names = lpv.outputs().iter().map(|s| s.name.clone()).collect();
    Ok((linear.a, linear.c, names))
}

/// The eigenvalues of `scene`'s linear model on `model` ([`slowest_of`]).
fn slowest_eigenvalues(model: &dyn Model, scene: &Scene) -> Result<Vec<Complex<f64>>> {
    let (a, _, _) = linear_model(model, scene)?;
    slowest_of(&a)
}

/// The eigenvalues of `a` that are not rigid, one of each complex pair (the one with a
/// positive imaginary part), slowest first.
fn slowest_of(a: &DMatrix<f64>) -> Result<Vec<Complex<f64>>> {
    let mut lambdas: Vec<Complex<f64>> = eigenvalues(a.clone(), "eigenvalues of a start in motion")
        .map_err(telescopic_runtime::analysis::linear::LinearError::from)?
        .into_iter()
        .filter(|l| l.norm() > RIGID && l.im >= -RIGID * 1e-3)
        .collect();
    lambdas.sort_by(|x, y| x.norm().total_cmp(&y.norm()));
    Ok(lambdas)
}

impl FreeMotion {
    /// The free motions of the `modes` slowest modes of `scene` on `model` (and the vehicle's
    /// rigid motion when it is force-driven) at `record`'s sensors and samples.
    ///
    /// # Errors
    /// A sensor the linear model lacks (named), and the linear model's errors.
    pub fn of(model: &dyn Model, scene: &Scene, record: &Record, modes: usize) -> Result<Self> {
        let (a, c, names) = linear_model(model, scene)?;
        let rows = sensor_rows(record, &names)?;
        let taus: Vec<f64> = record.times.iter().map(|t| t - record.times[0]).collect();
        let vehicle = record
            .sensors
            .iter()
            .position(|(o, _)| *o == Output::Vehicle);
        let mut columns = Vec::new();
        let mut rates = Vec::new();
        let lambdas = slowest_of(&a)?;
        for &lambda in lambdas.iter().take(modes) {
            let v = eigenvector(&a, lambda);
            let w: Vec<Complex<f64>> = rows
                .iter()
                .map(|&r| (0..a.ncols()).map(|j| v[j] * c[(r, j)]).sum())
                .collect();
            let pair = lambda.im.abs() > RIGID * 1e-3;
            let parts: &[fn(Complex<f64>) -> f64] = if pair {
                &[|z| z.re, |z| z.im]
            } else {
                &[|z| z.re]
            };
            for part in parts {
                let column = w.iter().map(|&ws| {
                    taus.iter()
                        .map(|&t| part(ws * (lambda * t).exp()))
                        .collect()
                });
                columns.push(column.collect());
                rates.push(vehicle.map_or(0.0, |s| part(w[s] * lambda)));
            }
        }
        let mut position = None;
        if let (Some(s), Drive::Force(_)) = (vehicle, &scene.params.drive) {
            // the whole telescope translating: the vehicle moves, nothing else does
            let only = |f: &dyn Fn(f64) -> f64| -> Vec<Vec<f64>> {
                (0..record.sensors.len())
                    .map(|k| {
                        taus.iter()
                            .map(|&t| if k == s { f(t) } else { 0.0 })
                            .collect()
                    })
                    .collect()
            };
            position = Some(columns.len());
            columns.extend([only(&|_| 1.0), only(&|t| t)]);
            rates.extend([0.0, 1.0]);
        }
        Ok(FreeMotion {
            columns,
            vehicle_rates: vehicle.map(|_| rates),
            position,
            modes: modes.min(lambdas.len()),
        })
    }

    /// Adds to `predictions` the free motion that, with each sensor's offset when `offsets`
    /// are fitted, best explains `record` (each sensor weighted by its `noise`): weighted
    /// least squares by the singular values, a column that adds nothing dropped by their
    /// rank (the vehicle's position is left out where the offsets are fitted: it is the
    /// vehicle's offset).
    pub fn add_fitted(
        &self,
        predictions: &mut [Vec<f64>],
        record: &Record,
        noise: &[f64],
        offsets: Offsets,
    ) -> StartFit {
        let n = record.times.len();
        let sensors = record.sensors.len();
        let offset_columns = offsets.count(sensors);
        // the vehicle's position is its offset where the offsets are fitted
        let used: Vec<usize> = (0..self.columns.len())
            .filter(|&c| offset_columns == 0 || Some(c) != self.position)
            .collect();
        let count = offset_columns + used.len();
        let mut design = DMatrix::zeros(n * sensors, count);
        let mut rhs = DVector::zeros(n * sensors);
        for (s, ((_, y), sigma)) in record.sensors.iter().zip(noise).enumerate() {
            for i in 0..n {
                let row = s * n + i;
                rhs[row] = (y[i] - predictions[s][i]) / sigma;
                if offset_columns > 0 {
                    design[(row, s)] = 1.0 / sigma;
                }
                for (k, &c) in used.iter().enumerate() {
                    design[(row, offset_columns + k)] = self.columns[c][s][i] / sigma;
                }
            }
        }
        // columns of one scale, so that the rank's tolerance treats them alike
        let norms: Vec<f64> = (0..count)
            .map(|c| {
                let norm = design.column(c).norm().max(f64::MIN_POSITIVE);
                design.column_mut(c).unscale_mut(norm);
                norm
            })
            .collect();
        let svd = design.svd(true, true);
        let tolerance = 1e-10 * svd.singular_values.max();
        let rank = svd.rank(tolerance);
        let solution = svd
            .solve(&rhs, tolerance)
            .unwrap_or_else(|_| DVector::zeros(count));
        let mut amplitudes = vec![0.0; self.columns.len()];
        for (k, &c) in used.iter().enumerate() {
            amplitudes[c] = solution[offset_columns + k] / norms[offset_columns + k];
        }
        for (column, &a) in self.columns.iter().zip(&amplitudes) {
            for (p, col) in predictions.iter_mut().zip(column) {
                for (p, v) in p.iter_mut().zip(col) {
                    *p += a * v;
                }
            }
        }
        StartFit {
            modes: self.modes,
            amplitudes: rank.saturating_sub(offset_columns),
            vehicle_speed: self
                .vehicle_rates
                .as_ref()
                .map(|rates| rates.iter().zip(&amplitudes).map(|(r, a)| r * a).sum()),
        }
    }
}

/// The row of each of `record`'s sensors among the linear model's outputs `names`.
///
/// # Errors
/// [`Error::Option`] naming a sensor the linear model lacks.
fn sensor_rows(record: &Record, names: &[String]) -> Result<Vec<usize>> {
    record
        .sensors
        .iter()
        .map(|(output, _)| {
            let name = output.to_string();
            names.iter().position(|n| *n == name).ok_or_else(|| {
                Error::option(
                    OptionName::Start,
                    format!(
                        "a start in motion is fitted on the linear model's outputs ({}); it \
                         has no {name}",
                        names.join(", ")
                    ),
                )
            })
        })
        .collect()
}

/// The eigenvector of `a` for its eigenvalue `lambda`, by inverse iteration (two solves with
/// a shift just off `lambda`). Hand-written: nalgebra gives the eigenvalues of a general real
/// matrix, not its eigenvectors.
fn eigenvector(a: &DMatrix<f64>, lambda: Complex<f64>) -> DVector<Complex<f64>> {
    let n = a.nrows();
    let shift = lambda + Complex::new(1e-9, 1e-9) * lambda.norm();
    let shifted = DMatrix::from_fn(n, n, |i, j| {
        Complex::new(a[(i, j)], 0.0)
            - if i == j {
                shift
            } else {
                Complex::new(0.0, 0.0)
            }
    });
    let lu = shifted.lu();
    let mut v = DVector::from_element(n, Complex::new(1.0, 0.0));
    for _ in 0..2 {
        if let Some(next) = lu.solve(&v) {
            let norm = next.norm();
            if norm.is_finite() && norm > 0.0 {
                v = next.unscale(norm);
            }
        }
    }
    v
}
