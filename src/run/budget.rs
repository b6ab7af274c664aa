//! What a run will cost, checked before it starts: a run whose step count, predicted from
//! the stability limits of its method and the span, exceeds the step limit stops at once
//! with the estimate and the cause, instead of running for minutes into the same limit.
//!
//! The prediction: an explicit method's step is bounded by `h rho <= c_m` (its stability
//! region along the negative real axis and the imaginary axis, `c_m` below), where `rho`
//! is the spectral radius of the closed-contact system, estimated as the larger of its
//! fastest natural frequency and its fastest contact damping rate
//! ([`telescopic_runtime::fastest_rates`]); exact stepping takes `h omega <= 1.5`; a
//! fixed-step method takes `span / dt` steps. Implicit adaptive methods have no such bound.

use crate::{Error, Result};
use telescopic_runtime::integrate::StepControl;
use telescopic_runtime::integrate::stability::{linearization_times, stable_h_rho};
use telescopic_runtime::{
    FastestRates, Method, Model, Scene, Settings, StructuralDamping, TimeSpan, fastest_rates,
};

/// Output samples of a span (the start included, and the end when it is off the grid);
/// bounded by the scene's validation.
pub fn sample_count(span: &TimeSpan) -> usize {
    let n = telescopic_runtime::scene::limits::sample_count(span.start, span.end, span.sample);
    usize::try_from(n).unwrap_or(usize::MAX).min(1 << 28)
}

/// A predicted step count and where it comes from.
#[derive(Debug, Clone, PartialEq)]
pub struct WorkEstimate {
    /// Predicted steps over the span.
    pub steps: f64,
    /// The step the prediction assumes (s).
    pub step: f64,
    /// The fastest rates at the stiffest time checked (`None` for a fixed step given).
    pub rates: Option<FastestRates>,
}

/// The fastest rates of `model` over `span`: at its start, or at the stiffest of several
/// times when the positions move.
///
/// # Errors
/// [`Error::Eigen`] when the eigen analysis fails.
pub fn stiffest_rates(scene: &Scene, model: &dyn Model) -> Result<FastestRates> {
    let mut stiffest: Option<FastestRates> = None;
    for t in linearization_times(model, &scene.time) {
        let rates = fastest_rates(model, t).map_err(|error| Error::Eigen {
            scene: scene.name.clone(),
            error,
        })?;
        if stiffest.is_none_or(|s| rates.spectral_radius() > s.spectral_radius()) {
            stiffest = Some(rates);
        }
    }
    Ok(stiffest.expect("at least one linearization time"))
}

/// The predicted step count of `method` with `settings` on `scene`; `None` when the method
/// has no bound to predict from (implicit adaptive methods).
///
/// # Errors
/// [`Error::Eigen`] when the eigen analysis fails.
pub fn estimate_steps(
    scene: &Scene,
    model: &dyn Model,
    method: Method,
    settings: &Settings,
) -> Result<Option<WorkEstimate>> {
    let span = scene.time.end - scene.time.start;
    if method.step_control() == StepControl::Fixed {
        let dt = settings.dt.unwrap_or(f64::NAN);
        return Ok(Some(WorkEstimate {
            steps: span / dt,
            step: dt,
            rates: None,
        }));
    }
    let Some(h_rho) = stable_h_rho(method) else {
        return Ok(None);
    };
    let rates = stiffest_rates(scene, model)?;
    let rho = rates.spectral_radius();
    let steps = match settings.exact_from {
        // `auto` on moving positions: the method while they move, exact stepping after
        Some(t) if method != Method::Exact => {
            (t - scene.time.start) * rho / h_rho + (scene.time.end - t) * rates.omega_max / 1.5
        }
        _ => span * rho / h_rho,
    };
    Ok(Some(WorkEstimate {
        steps,
        step: h_rho / rho,
        rates: Some(rates),
    }))
}

/// Refuses, before any work, a run whose predicted steps exceed `settings.max_steps`.
///
/// # Errors
/// [`Error::Unaffordable`] with the estimate, the cause and what to change;
/// [`Error::Eigen`] when the estimate cannot be made.
pub fn check_run(
    scene: &Scene,
    model: &dyn Model,
    method: Method,
    settings: &Settings,
) -> Result<()> {
    let Some(estimate) = estimate_steps(scene, model, method, settings)? else {
        return Ok(());
    };
    let limit = settings.max_steps as f64;
    if estimate.steps.is_nan() || estimate.steps <= limit {
        return Ok(());
    }
    let span = scene.time.end - scene.time.start;
    let reason = match estimate.rates {
        None => format!(
            "method {method} with the step dt = {:.3e} s needs about {:.2e} steps over {span} s, more \
             than the step limit of {limit:.0e}; raise the step dt (the stability analysis gives the \
             largest stable step) or use an adaptive method",
            estimate.step, estimate.steps
        ),
        Some(r) => {
            let (cause, fields) = if r.damping_rate > r.omega_max {
                // the damping rate is of the contacts' and the structure's damping together
                let (what, fields) = match scene.params.damping {
                    StructuralDamping::None => (
                        "the contact damping",
                        "contact.damping against the masses at the contacts",
                    ),
                    StructuralDamping::Rayleigh { .. } => (
                        "the damping",
                        "sections.rayleigh_alpha and sections.rayleigh_beta, or contact.damping \
                         against the masses at the contacts",
                    ),
                    StructuralDamping::Modal { .. } => (
                        "the damping",
                        "sections.damping_ratio, or contact.damping against the masses at the \
                         contacts",
                    ),
                };
                (
                    format!(
                        "{what}: the fastest damping rate with closed contacts is {:.3e} 1/s, \
                         above the fastest natural frequency {:.3e} rad/s",
                        r.damping_rate, r.omega_max
                    ),
                    fields,
                )
            } else {
                (
                    format!(
                        "the stiffest mode with closed contacts: omega_max = {:.3e} rad/s \
                         ({:.3e} Hz) at t = {} s",
                        r.omega_max,
                        r.omega_max / (2.0 * std::f64::consts::PI),
                        r.time
                    ),
                    "contact.stiffness and the section stiffnesses against the section masses \
                     (sections.area, sections.density)",
                )
            };
            let alternative = if method == Method::Exact {
                "exact stepping resolves every mode too; check the parameters"
            } else {
                "an implicit method is not bound by it (the method esdirk or bdf), or check the \
                 parameters"
            };
            format!(
                "method {method} would need about {:.2e} steps over {span} s, more than the step \
                 limit of {limit:.0e}: its stable step is about {:.3e} s (h rho <= {}), set by \
                 {cause}. The cause lies in {fields}; {alternative}.",
                estimate.steps,
                estimate.step,
                stable_h_rho(method).unwrap_or(f64::NAN)
            )
        }
    };
    Err(Error::Unaffordable {
        scene: scene.name.clone(),
        reason,
    })
}
