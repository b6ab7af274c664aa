//! Where fixed-step methods fail: the stiffest frequency of a scene and the largest stable
//! step of each fixed-step method on the scene's own linearized model.
//!
//! With every contact closed (pressed against a guide, or the linear law for `l_S = 0`) and
//! the branches held fixed, the right-hand side is affine in the state, so one step of a
//! method is an affine map `y1 = G(h) y0 + c`. Its matrix `G(h)` is built column by column
//! from steps of the real stepper, and the step is stable while the spectral radius of
//! `G(h)` does not exceed what the physics allows (`e^(sigma h)`, `sigma` the largest growth
//! rate of the continuous system, zero for a stable scene). Bisection on `h` gives the limit.
//! This is exact for the model, damping included; the textbook numbers (`h omega_max` of
//! 2.785 on the negative real axis and 2.828 on the imaginary axis for RK4, 2 for undamped
//! Stormer-Verlet) bracket it for a lightly damped structure.

use super::events::ContactTracker;
use super::{Method, RunStats, Settings, System, make_stepper};
use crate::analysis::eigen::{EigenError, eigenvalues, modal_analysis};
use crate::model::Model;
use crate::scene::TimeSpan;
use nalgebra::DMatrix;

/// The largest `|h lambda|` on the negative real axis inside RK4's stability region.
pub const RK4_REAL_AXIS: f64 = 2.785_293_563_405_282;
/// The same on the imaginary axis: `2 sqrt(2)`.
pub const RK4_IMAGINARY_AXIS: f64 = 2.0 * std::f64::consts::SQRT_2;
/// Stormer-Verlet's limit `h omega` for an undamped oscillator.
pub const VERLET_LIMIT: f64 = 2.0;

/// The stability facts of a model at one time.
#[derive(Debug, Clone)]
pub struct StabilityReport {
    /// Time the model was linearized at (s).
    pub time: f64,
    /// Largest natural circular frequency with closed contacts (rad/s).
    pub omega_max: f64,
    /// Largest growth rate `Re(lambda)` of the closed-contact system (1/s; 0 when stable).
    pub growth_rate: f64,
    /// Largest stable step of RK4 on the model (s).
    pub rk4_step: f64,
    /// Largest stable step of Stormer-Verlet on the model (s).
    pub verlet_step: f64,
}

/// The branches of a closed contact set: all pressed against the upper guide (the lower
/// one has the same slope; the offset is in the affine part).
fn closed(model: &dyn Model, t: f64) -> ContactTracker {
    let mut tracker = ContactTracker::new(model, t, &vec![0.0; 2 * model.dof()]);
    tracker.press_all();
    tracker
}

/// The matrix `G(h)` of one step of `method` from time `t` with closed contacts, in a run
/// whose longest step is `longest_step` (s; the output sample interval, which sets imex's
/// stiff modes).
pub fn step_matrix(
    model: &dyn Model,
    method: Method,
    t: f64,
    h: f64,
    longest_step: f64,
) -> DMatrix<f64> {
    let n = 2 * model.dof();
    let settings = Settings {
        dt: Some(h),
        ..Settings::default()
    };
    let mut stepper = make_stepper(method, model.dof(), &settings, None, longest_step);
    let mut sys = System {
        model,
        tracker: closed(model, t),
        stats: RunStats::default(),
        time_cap: f64::INFINITY,
    };
    let (mut y0, mut f0, mut y1) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    let mut step = |y0: &[f64], f0: &mut [f64], y1: &mut [f64]| {
        sys.rhs(t, y0, f0);
        stepper.restart();
        // a failed implicit step would leave zeros: it shows as an unstable column
        let _ = stepper.step(&mut sys, t, y0, f0, h, y1);
    };
    let mut offset = vec![0.0; n];
    step(&y0, &mut f0, &mut offset);
    let mut g = DMatrix::zeros(n, n);
    for j in 0..n {
        y0.fill(0.0);
        y0[j] = 1.0;
        step(&y0, &mut f0, &mut y1);
        for i in 0..n {
            g[(i, j)] = y1[i] - offset[i];
        }
    }
    g
}

/// Spectral radius of a real square matrix.
fn spectral_radius(m: DMatrix<f64>) -> Result<f64, EigenError> {
    Ok(eigenvalues(m, "eigenvalues of a step matrix G(h)")?
        .iter()
        .map(|z| z.norm())
        .fold(0.0, f64::max))
}

/// Largest growth rate `max Re(lambda)` of the closed-contact system at `t` (1/s, >= 0).
fn growth_rate(model: &dyn Model, t: f64) -> Result<f64, EigenError> {
    let n = 2 * model.dof();
    let mut sys = System {
        model,
        tracker: closed(model, t),
        stats: RunStats::default(),
        time_cap: f64::INFINITY,
    };
    let mut jac = DMatrix::zeros(n, n);
    sys.jacobian(t, &vec![0.0; n], &mut jac);
    Ok(
        eigenvalues(jac, "eigenvalues of the closed-contact Jacobian")?
            .iter()
            .map(|z| z.re)
            .fold(0.0, f64::max),
    )
}

/// Largest stable step of `method` at time `t` (s), by bisection on the spectral radius of
/// its step matrix, to a relative precision of 1e-6. `omega_max` (rad/s) brackets the search;
/// `longest_step` is the run's output sample interval (s).
///
/// # Errors
/// [`EigenError`] when an eigenvalue computation fails (non-finite entries, no convergence).
pub fn stable_step(
    model: &dyn Model,
    method: Method,
    t: f64,
    omega_max: f64,
    longest_step: f64,
) -> Result<f64, EigenError> {
    stable_step_within(model, method, t, (omega_max, longest_step), 1e-6)
}

/// Most doublings of the trial step above `4 / omega_max` (an unconditionally stable method
/// would double forever; 2^40 is far beyond any explicit method's region).
const MAX_DOUBLINGS: u32 = 40;

/// [`stable_step`] to a relative precision `rel` (the result is at most that far below the
/// limit).
fn stable_step_within(
    model: &dyn Model,
    method: Method,
    t: f64,
    (omega_max, longest_step): (f64, f64),
    rel: f64,
) -> Result<f64, EigenError> {
    let sigma = growth_rate(model, t)?;
    let stable = |h: f64| -> Result<bool, EigenError> {
        Ok(
            spectral_radius(step_matrix(model, method, t, h, longest_step))?
                <= (sigma * h).exp() + 1e-7,
        )
    };
    let mut lo = 0.0;
    let mut hi = 4.0 / omega_max;
    let mut doublings = 0;
    while stable(hi)? {
        lo = hi;
        hi *= 2.0;
        doublings += 1;
        if doublings > MAX_DOUBLINGS {
            return Ok(f64::INFINITY);
        }
    }
    while hi - lo > rel * hi {
        let mid = 0.5 * (lo + hi);
        if stable(mid)? {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    Ok(lo)
}

/// The stability report of `model` at time `t`.
///
/// # Errors
/// A message when the modal analysis or an eigenvalue computation fails (mass matrix not
/// positive definite, digits lost, no convergence).
pub fn stability_report(model: &dyn Model, t: f64) -> Result<StabilityReport, String> {
    let modal = modal_analysis(model, t).map_err(|e| e.to_string())?;
    let omega_max = 2.0
        * std::f64::consts::PI
        * modal
            .frequencies_hz
            .last()
            .copied()
            .ok_or("the model has no elastic modes")?;
    Ok(StabilityReport {
        time: t,
        omega_max,
        growth_rate: growth_rate(model, t).map_err(|e| e.to_string())?,
        // rk4 and verlet have no stiff split: the sample interval is not read
        rk4_step: stable_step(model, Method::Rk4, t, omega_max, f64::INFINITY)
            .map_err(|e| e.to_string())?,
        verlet_step: stable_step(model, Method::Verlet, t, omega_max, f64::INFINITY)
            .map_err(|e| e.to_string())?,
    })
}

/// Times checked when the telescopic positions move (the start, the end and between).
pub const TIMES_WHEN_MOVING: usize = 9;

/// The times (s) a scene is linearized at: its start, or [`TIMES_WHEN_MOVING`] evenly spread
/// over the span when a telescopic position moves (the contact vectors, and with them
/// `omega_max`, change along the way).
pub fn linearization_times(model: &dyn Model, span: &TimeSpan) -> Vec<f64> {
    let moving = model.params().positions.iter().any(|p| !p.is_constant());
    if !moving {
        return vec![span.start];
    }
    let last = (TIMES_WHEN_MOVING - 1) as f64;
    (0..TIMES_WHEN_MOVING)
        .map(|i| span.start + (span.end - span.start) * i as f64 / last)
        .collect()
}

/// Fraction of the model's stable step that caps dop853's step while a contact is closed
/// (margin for times between the linearization times).
pub const STEP_CAP_SAFETY: f64 = 0.95;

/// Largest stable step (s) of a `method` with an explicit part (dopri5, dop853, rk4, verlet,
/// imex) with closed
/// contacts at the stiffest (largest `omega_max`) of the [`linearization_times`], to three
/// digits. `None` for implicit methods (no limit), for a model without contacts, or when the
/// modal analysis fails.
pub fn closed_contact_stable_step(
    model: &dyn Model,
    method: Method,
    span: &TimeSpan,
) -> Option<f64> {
    let explicit = matches!(
        method,
        Method::Dopri5 | Method::Dop853 | Method::Rk4 | Method::Verlet | Method::Imex
    );
    if !explicit || model.layout().contact_count() == 0 {
        return None;
    }
    // the stiffest time: one bisection there (each costs about a millisecond)
    let mut stiffest: Option<(f64, f64)> = None;
    for t in linearization_times(model, span) {
        let modal = modal_analysis(model, t).ok()?;
        let omega = 2.0 * std::f64::consts::PI * modal.frequencies_hz.last().copied()?;
        if stiffest.is_none_or(|(_, w)| omega > w) {
            stiffest = Some((t, omega));
        }
    }
    let (t, omega_max) = stiffest?;
    stable_step_within(model, method, t, (omega_max, span.sample), 1e-3).ok()
}

/// The largest `h rho` an explicit method or exact stepping takes, about: the extent of its
/// stability region along the negative real axis (for these methods close to that along
/// the imaginary axis), with `rho` the spectral radius of the system; `None` for methods
/// without a stability bound on the step. dop853-imex has dop853's: its bound wherever no
/// closed contact settles.
pub fn stable_h_rho(method: Method) -> Option<f64> {
    match method {
        Method::Dopri5 => Some(3.3),
        Method::Dop853 | Method::Dop853Imex => Some(6.0),
        Method::Rk4 => Some(RK4_REAL_AXIS),
        Method::Verlet => Some(VERLET_LIMIT),
        Method::Exact => Some(super::exact::STEP_OMEGA),
        _ => None,
    }
}

/// The step cap (s) of dop853 while a contact is closed: [`STEP_CAP_SAFETY`] times its
/// [`closed_contact_stable_step`]; `None` for every other method.
///
/// Without it dop853's step control (I control, Hairer's default) hovers at the stability
/// boundary on a contact-stiff scene: it grows the step until the contact mode starts to
/// grow, rejects, shrinks and grows again (case-study at rtol 1e-5: 23k rejected steps of
/// 67k; 6k with the cap, 13-15 % less wall time in two benchmark runs). dopri5's PI control already stays off the
/// boundary: capped, it took 9 % longer on case-study, so it is not capped.
pub fn closed_contact_step_cap(model: &dyn Model, method: Method, span: &TimeSpan) -> Option<f64> {
    let capped = method.capped_part()?;
    closed_contact_stable_step(model, capped, span).map(|step| STEP_CAP_SAFETY * step)
}
