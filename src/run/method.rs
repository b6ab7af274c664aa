//! The resolved method and settings of a run: `auto` chosen on the scene, tolerances checked.

use super::models::ModelChoice;
use super::options::{MethodChoice, SimulationOptions};
use super::predicted_size::SizePrediction;
use crate::OptionName;
use crate::{Error, Result};
use telescopic_runtime::analysis::accuracy::{
    AccuracyPlan, COMPANION_RATIO, MeasuredRun, Resolve, SceneKind, companion_accuracy,
};
use telescopic_runtime::integrate::StepControl;
use telescopic_runtime::{Basis, DEFAULT_ACCURACY_M, Method, Scene, Settings, plan_for_accuracy};

/// Why a run has its method.
#[derive(Debug, Clone, PartialEq)]
pub enum MethodReason {
    /// The method was given.
    Given,
    /// `auto`: the cheapest measured run within the default accuracy.
    Auto(AccuracyPlan),
    /// `auto` for an integration accuracy: the cheapest measured run within it.
    Accuracy(AccuracyPlan),
    /// A controlled run (its method is the controller's comparison method).
    Controller(crate::control::ControllerKind),
    /// A sampled controller's run.
    SampledController {
        /// Its rate (Hz).
        rate_hz: f64,
        /// Where its ticks step exactly from (s): the positions rest there and the held
        /// force keeps each tick linear and time-invariant.
        exact_from: Option<f64>,
    },
    /// The size picked for a whole accuracy (m), and how its integration was planned.
    TotalAccuracy {
        /// The accuracy asked for (m of `tip_rel`).
        accuracy_m: f64,
        /// The run's estimated whole error (m).
        estimated_m: f64,
        /// The basis picked.
        basis: Basis,
        /// Modes per section picked.
        modes: usize,
        /// The size predicted before any run, or why none was.
        prediction: SizePrediction,
        /// Whether the pick is the predicted size, confirmed by its companion.
        confirmed: bool,
        /// The sizes tried, described with their verdicts.
        tried: Vec<String>,
        /// Runs the search made (sizes and their companions).
        search_runs: usize,
        /// The whole search's wall time (s), every run included.
        search_s: f64,
        /// The integration's own reason.
        integration: Box<MethodReason>,
    },
}

/// The reason as the run's summary says it: empty for a given method, else `...; `.
impl std::fmt::Display for MethodReason {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            MethodReason::Given => Ok(()),
            MethodReason::Auto(plan) => write!(f, "auto: {plan}; "),
            MethodReason::Accuracy(plan) => write!(f, "accuracy {:e} m: {plan}; ", plan.accuracy_m),
            MethodReason::Controller(kind) => write!(f, "controller {kind}; "),
            MethodReason::SampledController {
                rate_hz,
                exact_from,
            } => {
                write!(f, "sampled controller at {rate_hz} Hz; ")?;
                match exact_from {
                    Some(t) => write!(f, "exact stepping of its ticks from t = {t} s on; "),
                    None => Ok(()),
                }
            }
            MethodReason::TotalAccuracy {
                accuracy_m,
                estimated_m,
                basis,
                modes,
                prediction,
                confirmed,
                tried,
                search_runs,
                search_s,
                integration,
            } => {
                let how = match (prediction, confirmed) {
                    (SizePrediction::Predicted { .. }, true) => "confirmed by its companion",
                    (SizePrediction::Predicted { .. }, false) => {
                        "not confirmed: the cheapest size within it of those tried after it"
                    }
                    (SizePrediction::Skipped(_), _) => "the cheapest size within it of those tried",
                };
                write!(
                    f,
                    "accuracy {accuracy_m:e} m in all (estimated {estimated_m:.1e} m): basis {}, \
                     {modes} modes per section; {prediction}; {how}; sizes tried: {}; the \
                     search: {search_runs} runs, {search_s:.2} s; {integration}",
                    basis.word(),
                    tried.join(", "),
                )
            }
        }
    }
}

/// The resolved method and settings of a run.
#[derive(Debug, Clone, PartialEq)]
pub struct Plan {
    /// The method that starts the run.
    pub method: Method,
    /// Why this method.
    pub reason: MethodReason,
    /// Tolerances, steps and the hand-over to exact stepping.
    pub settings: Settings,
    /// The measured error in `tip_rel` (m) of the run the method was picked from; `None`
    /// when a method was given.
    pub integration_error_m: Option<f64>,
    /// The relative error of the statistics to expect of that run (with clearance, the
    /// spread of correct runs); `None` when a method was given.
    pub integration_statistics_rel: Option<f64>,
}

impl Plan {
    /// The measured run of the table the method and tolerance were picked from, when they
    /// were picked (a tolerance given beside `auto` overrides the row's:
    /// the companion's options check for that).
    pub fn measured_row(&self) -> Option<&MeasuredRun> {
        match &self.reason {
            MethodReason::Auto(chosen) | MethodReason::Accuracy(chosen) => Some(&chosen.row),
            MethodReason::TotalAccuracy { integration, .. } => match integration.as_ref() {
                MethodReason::Auto(chosen) | MethodReason::Accuracy(chosen) => Some(&chosen.row),
                _ => None,
            },
            _ => None,
        }
    }
}

/// The options of the companion run that checks a run of `scene` planned as `run` with
/// `options`: no estimate of its own, its steps ending on every sample (where the run's
/// cross them, the difference holds the run's interpolation), a generated model only where
/// one exists. Where the run's method and tolerance were picked from the table (no
/// tolerance given), the companion's integration is picked at most a
/// [`COMPANION_RATIO`]th of the run's measured error: the difference then holds the run's
/// own integration error, measured on this run. The second value says whether it does.
pub(crate) fn companion_options(
    scene: &Scene,
    options: &SimulationOptions,
    run: &Plan,
) -> (SimulationOptions, bool) {
    let mut companion = SimulationOptions {
        error_estimate: false,
        coordinates: false,
        steps_across_samples: false,
        modes_as_given: true,
        // a generated model of the refined size may not exist: the registry falls back
        model: match options.model {
            ModelChoice::Generated => ModelChoice::Auto,
            other => other,
        },
        ..options.clone()
    };
    let given_tolerance = options.rtol.is_some() || options.atol.is_some();
    let finer = run
        .measured_row()
        .filter(|_| !given_tolerance)
        .and_then(|row| {
            companion_accuracy(SceneKind::of(&scene.params), row, resolve_of(&companion))
        });
    if let Some(accuracy) = finer {
        companion.method = MethodChoice::Auto;
        companion.accuracy = Some(accuracy);
    }
    (companion, finer.is_some())
}

/// The integration error (m) that a `companion` planned with [`companion_options`] adds to
/// the budget of a run planned as `run`: the companion's row's stored figure when that row
/// is at most a [`COMPANION_RATIO`]th of the run's (their difference then holds the run's own
/// integration error); `None` when it is not, and the run's own figure stands.
pub(crate) fn companion_integration(run: &Plan, companion: &Plan) -> Option<f64> {
    let (run, companion) = (run.measured_row()?, companion.measured_row()?);
    (companion.error_m * COMPANION_RATIO <= run.error_m).then_some(companion.error_m)
}

/// What a run with `options` must resolve at its samples.
fn resolve_of(options: &SimulationOptions) -> Resolve {
    // moments at stations need the contact modes resolved
    if !options.stations.is_empty() {
        Resolve::Moments
    } else if options.steps_across_samples {
        Resolve::Displacements
    } else {
        Resolve::EverySample
    }
}

/// Resolves `options` on `scene`: `auto` becomes a method, tolerances are checked.
///
/// # Errors
/// [`Error::Option`] for an unknown method or tolerances outside their range (checked for
/// every method, even those that do not use them).
pub fn plan(scene: &Scene, options: &SimulationOptions) -> Result<Plan> {
    let mut settings = Settings::default();
    let mut integration_error_m = None;
    let mut integration_statistics_rel = None;
    let resolve = resolve_of(options);
    let (method, reason) = match (options.method, options.accuracy) {
        (MethodChoice::Auto, Some(accuracy)) => {
            if options.rtol.is_some() || options.atol.is_some() {
                return Err(Error::option(
                    OptionName::Accuracy,
                    "picks the tolerances itself: give an accuracy or rtol/atol, not both",
                ));
            }
            let chosen = plan_for_accuracy(&scene.params, &scene.time, accuracy, resolve)
                .map_err(|e| Error::option(OptionName::Accuracy, e))?;
            settings.exact_from = chosen.exact_from;
            settings.longest_step = chosen.longest_step;
            settings.rtol = chosen.rtol;
            settings.atol = 1e-3 * chosen.rtol;
            integration_error_m = Some(chosen.error_m);
            integration_statistics_rel = Some(chosen.statistics_rel);
            (chosen.method, MethodReason::Accuracy(chosen))
        }
        (MethodChoice::Method(m), Some(_)) => {
            return Err(Error::option(
                OptionName::Accuracy,
                format!("picks the method itself: leave the method at auto (got {m})"),
            ));
        }
        (MethodChoice::Auto, None) => {
            let chosen = plan_for_accuracy(&scene.params, &scene.time, DEFAULT_ACCURACY_M, resolve)
                .expect("every kind of scene has a measured run within the default accuracy");
            settings.exact_from = chosen.exact_from;
            settings.longest_step = chosen.longest_step;
            integration_error_m = Some(chosen.error_m);
            integration_statistics_rel = Some(chosen.statistics_rel);
            (chosen.method, MethodReason::Auto(chosen))
        }
        (MethodChoice::Method(m), None) => (m, MethodReason::Given),
    };
    if let Some(r) = options.rtol {
        settings.rtol = r;
    }
    if let Some(a) = options.atol {
        settings.atol = a;
    }
    settings.dt = options.dt;
    settings.step_cap = options.step_cap;
    settings.long_steps = options.long_steps;
    check_steps(scene, method, &settings)?;
    Ok(Plan {
        method,
        reason,
        settings,
        integration_error_m,
        integration_statistics_rel,
    })
}

/// Checks the tolerances and the fixed step of `settings` for `method` on `scene`.
///
/// # Errors
/// [`Error::Option`] naming the tolerance or the step.
fn check_steps(scene: &Scene, method: Method, settings: &Settings) -> Result<()> {
    if !(settings.rtol > 0.0
        && settings.rtol < 1.0
        && settings.atol > 0.0
        && settings.atol.is_finite())
    {
        return Err(Error::option(
            OptionName::Tolerances,
            format!(
                "tolerances must be positive with rtol < 1 (got rtol {}, atol {})",
                settings.rtol, settings.atol
            ),
        ));
    }
    if let Some(dt) = settings.dt
        && !(dt > 0.0 && dt.is_finite())
    {
        return Err(Error::option(
            OptionName::Dt,
            format!("must be a finite number of seconds > 0 (got {dt})"),
        ));
    }
    let span = scene.time.end - scene.time.start;
    if let Some(dt) = settings.dt
        && dt > span
    {
        return Err(Error::option(
            OptionName::Dt,
            format!("{dt} s is longer than the scene's span ({span} s): a step must fit in it"),
        ));
    }
    if method.step_control() == StepControl::Fixed && settings.dt.is_none() {
        return Err(Error::option(
            OptionName::Dt,
            format!(
                "method {method} takes a fixed step: give the step dt (see the stability analysis)"
            ),
        ));
    }
    Ok(())
}
