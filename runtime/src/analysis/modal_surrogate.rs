//! A linear modal surrogate of a run's `tip_rel`: the a priori estimate that predicts a
//! model's size before any run.
//!
//! With closed contacts (no clearance) the truncation of a Ritz model shows first as errors
//! of its lowest frequencies, which drift the phase of the vibration the drive excites, and
//! of its quasi-static compliance. The surrogate keeps exactly those: at
//! [`FREQUENCY_SAMPLES`] times over the span (one when the positions rest) it takes the
//! closed-contact modes ([`modal_analysis`]), and integrates the [`SURROGATE_MODES`] lowest
//! as single oscillators driven by the scene's input (the drive force, or the prescribed
//! vehicle's acceleration), frequencies and participations interpolated in time; the modes
//! above them answer quasi-statically. Its `tip_rel` is
//!
//! `y(t) = sum_k p_k(t) q_k(t) + r(t) u(t)`, with `q_k'' + w_k(t)^2 q_k = u(t)`,
//!
//! where `p_k = b_k c_k` is mode `k`'s participation (its share of the input `b_k` times its
//! share of `tip_rel` `c_k`, mass-normalized shapes) and `r = sum_{k > K} p_k / w_k^2` the
//! residual compliance. Two sizes' surrogates differ by what their truncation changes in
//! the linear response; damping, gravity's sag and the contacts' opening are left out (with
//! clearance a run's error is set by impacts, which this estimate does not see).
//!
//! Each step is exact for an input held over the step (the oscillator's matrix
//! exponential), so the surrogate needs no step control.

use crate::analysis::eigen::{EigenError, ModalAnalysis, modal_analysis};
use crate::model::Model;
use crate::model::params::Drive;
use crate::profile::Profile;
use std::f64::consts::PI;

/// How many of the lowest modes the surrogate integrates; those above answer
/// quasi-statically.
pub const SURROGATE_MODES: usize = 6;

/// The times over the span at which moving positions are sampled for the modes.
pub const FREQUENCY_SAMPLES: usize = 33;

/// One sample time's modal data.
struct ModalSample {
    /// Angular frequencies (rad/s) of the integrated modes.
    omega: Vec<f64>,
    /// Participations `b_k c_k` (m per unit modal input).
    participation: Vec<f64>,
    /// The residual compliance of the modes above (m per unit input).
    residual: f64,
}

/// The surrogate's `tip_rel` (m) of `model` over `span` (s), one value per `step` (s) from
/// the start.
///
/// # Errors
/// The eigen analysis's error at a sample time.
///
/// ```
/// use telescopic_runtime::analysis::modal_surrogate::surrogate_tip;
/// use telescopic_runtime::{AssembledModel, Scene};
/// let scene = Scene::load(std::path::Path::new("../scenes/adams-linear.toml"), &[]).unwrap();
/// let model = AssembledModel::exact(&scene.params).unwrap();
/// let tip = surrogate_tip(&model, (0.0, 1.0), 1e-3).unwrap();
/// assert_eq!(tip.len(), 1001);
/// ```
pub fn surrogate_tip(
    model: &dyn Model,
    span: (f64, f64),
    step: f64,
) -> Result<Vec<f64>, EigenError> {
    let (start, end) = span;
    let params = model.params();
    let times = if params.positions.iter().all(Profile::is_constant) {
        vec![start]
    } else {
        (0..FREQUENCY_SAMPLES)
            .map(|i| start + (end - start) * i as f64 / (FREQUENCY_SAMPLES - 1) as f64)
            .collect()
    };
    let samples = times
        .iter()
        .map(|&t| modal_analysis(model, t).map(|a| modal_sample(model, &a)))
        .collect::<Result<Vec<_>, _>>()?;
    let steps = ((end - start) / step).round() as usize;
    let modes = samples.iter().map(|s| s.omega.len()).min().unwrap_or(0);
    // (q_k, q_k') per mode
    let mut oscillators = vec![(0.0, 0.0); modes];
    let mut tip = Vec::with_capacity(steps + 1);
    for i in 0..=steps {
        let t = start + i as f64 * step;
        let u = input(&params.drive, t);
        let (at, weight) = interpolation(&times, t);
        let blend = |f: &dyn Fn(&ModalSample) -> f64| match at + 1 < samples.len() {
            true => f(&samples[at]) * (1.0 - weight) + f(&samples[at + 1]) * weight,
            false => f(&samples[at]),
        };
        let mut y = blend(&|s| s.residual) * u;
        for (k, (q, v)) in oscillators.iter_mut().enumerate() {
            y += blend(&|s| s.participation[k]) * *q;
            let w = blend(&|s| s.omega[k]);
            let (c, s) = ((w * step).cos(), (w * step).sin());
            let held = u / (w * w);
            (*q, *v) = (
                (*q - held) * c + *v * s / w + held,
                -(*q - held) * w * s + *v * c,
            );
        }
        tip.push(y);
    }
    Ok(tip)
}

/// The surrogate's input at `t`: the drive force (N), or the prescribed vehicle's
/// acceleration (m/s^2).
fn input(drive: &Drive, t: f64) -> f64 {
    match drive {
        Drive::Force(force) => force.value(t),
        Drive::Motion(position) => position.acceleration(t),
    }
}

/// The sample at or before `t` and the weight of the next one.
fn interpolation(times: &[f64], t: f64) -> (usize, f64) {
    if times.len() < 2 {
        return (0, 0.0);
    }
    let width = times[1] - times[0];
    let at = (((t - times[0]) / width).floor().max(0.0) as usize).min(times.len() - 2);
    (at, ((t - times[at]) / width).clamp(0.0, 1.0))
}

/// The modal data of `analysis`: the input enters through the drive vector (a force) or the
/// vehicle's inertia coupling (a prescribed motion), `tip_rel` is the top's displacement
/// relative to the vehicle.
fn modal_sample(model: &dyn Model, analysis: &ModalAnalysis) -> ModalSample {
    let params = model.params();
    let (n, mass) = (params.sections.len(), model.mass_matrix());
    let length = params.sections[n - 1].length;
    let mut sample = ModalSample {
        omega: Vec::new(),
        participation: Vec::new(),
        residual: 0.0,
    };
    for (shape, f) in analysis.shapes.iter().zip(&analysis.frequencies_hz) {
        let b = match params.drive {
            Drive::Force(_) => model.drive_vector().dot(shape),
            Drive::Motion(_) => -(1..shape.len())
                .map(|i| shape[i] * mass[(i, 0)])
                .sum::<f64>(),
        };
        let c = model.displacement(n, length, shape.as_slice()) - shape[0];
        let omega = 2.0 * PI * f;
        if sample.omega.len() < SURROGATE_MODES {
            sample.omega.push(omega);
            sample.participation.push(b * c);
        } else {
            sample.residual += b * c / (omega * omega);
        }
    }
    sample
}
