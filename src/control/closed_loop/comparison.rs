//! A controller judged on the nonlinear model: its run beside the open loop's, the figures
//! of both, and the table of the design's variants.

use crate::OptionName;
use crate::analysis::metrics::{RunMetrics, drive_stop, metrics};
use crate::control::closed_loop::sampled;
use crate::control::design::{self, DesignOptions};
use crate::control::file::schema::{Controller, ControllerKind, SampledLaw};
use crate::control::law::controlled::{Controlled, Observed};
use crate::report::Reporter;
use crate::run::PreparedRun;
use crate::run::{MethodChoice, Simulation, SimulationOptions, simulate_scene};
use crate::{Error, Result};
use telescopic_runtime::{Method, Scene};

/// The method a controlled run takes for `options`: `auto` is dopri5 (the feedback and the
/// saturation make the scene neither linear nor time-invariant); `exact` is refused.
fn controlled_method(options: &SimulationOptions) -> Result<Method> {
    match options.method {
        MethodChoice::Auto => Ok(Method::Dopri5),
        MethodChoice::Method(Method::Exact) => Err(Error::option(
            OptionName::Method,
            "exact stepping needs a linear time-invariant scene; with a controller, take \
             dopri5 or another integrator",
        )),
        MethodChoice::Method(m) => Ok(m),
    }
}

/// `options` with `auto` resolved as a controlled run resolves it: the open loop a
/// controller is compared with runs on the same method and settings as the controlled run.
pub fn comparison_options(options: &SimulationOptions) -> Result<SimulationOptions> {
    Ok(SimulationOptions {
        method: MethodChoice::Method(controlled_method(options)?),
        ..options.clone()
    })
}

/// The options a run with `controller` takes for `options`: a sampled controller holds its
/// force over each tick, so the scene stays linear and time-invariant between ticks where
/// it was and `auto` is the scene's own plan (its exact stepping once the positions rest,
/// tick by tick); a continuous law makes the scene neither, so `auto` is dopri5 there
/// ([`comparison_options`]).
///
/// # Errors
/// [`Error::Option`] for method `exact` with a continuous law.
pub fn controlled_options(
    controller: &Controller,
    options: &SimulationOptions,
) -> Result<SimulationOptions> {
    if controller.sampled.is_some() {
        Ok(options.clone())
    } else {
        comparison_options(options)
    }
}

/// Simulates `scene` with `controller` driving it, on the full nonlinear model, with
/// [`controlled_options`].
///
/// # Errors
/// [`Error::Option`] when the controller does not fit the scene, or the method is `exact`
/// with a continuous law; the errors of a simulation (a sampled controller on method `exact`
/// where the positions move among them).
pub fn simulate_controlled(
    scene: &Scene,
    controller: &Controller,
    options: &SimulationOptions,
    reporter: &dyn Reporter,
) -> Result<Simulation> {
    controller.check_fits(scene)?;
    if controller.sampled.is_some() {
        let run = PreparedRun::new(scene, &controlled_options(controller, options)?, reporter)?;
        return Ok(sampled::simulate_sampled(run, controller, reporter)?.simulation);
    }
    let mut run = PreparedRun::new(scene, &comparison_options(options)?, reporter)?;
    let method = run.plan.method;
    run.plan.reason = crate::run::MethodReason::Controller(controller.kind);
    let base = run.model();
    let (start, end) = (scene.time.start, scene.time.end);
    let trajectory = if controller.kind.has_observer() {
        if !matches!(method, Method::Dopri5 | Method::Dop853) {
            return Err(Error::option(
                OptionName::Method,
                "a controller with a Kalman filter runs with dopri5 or dop853",
            ));
        }
        // the filter adds no stiffness of its own: the budget is the structure's
        let model = Observed::new(base, controller, start, end)?;
        run.integrate_on(&model, base, reporter)?
    } else {
        let model = Controlled::new(base, controller, start, end)?;
        run.integrate_on(&model, &model, reporter)?
    };
    let mut simulation = run.into_simulation(trajectory);
    // a controlled scene is not linear time-invariant: exact stepping never applies
    simulation
        .specializations
        .retain(|s| !s.is_exact_stepping());
    Ok(simulation)
}

/// A controlled run beside its open loop, on the same method, settings and window.
#[derive(Debug, Clone, PartialEq)]
pub struct ControlComparison {
    /// The run with the controller.
    pub controlled: Simulation,
    /// The same scene without it.
    pub open_loop: Simulation,
    /// The controlled run's figures.
    pub with: RunMetrics,
    /// The open loop's figures.
    pub without: RunMetrics,
}

impl ControlComparison {
    /// One paragraph: residual vibration, peak force and travel, with and without control.
    pub fn summary(&self, controller: &Controller) -> String {
        self.summary_of(&controller.describe(), Some(controller.force_limit_n))
    }

    /// [`ControlComparison::summary`] for a controller described as `description`, with
    /// the force limit it saturates at if any.
    pub fn summary_of(&self, description: &str, force_limit: Option<f64>) -> String {
        let (with, without) = (&self.with, &self.without);
        let limit = force_limit.map_or(String::new(), |l| format!(" (limit {l} N)"));
        format!(
            "controller {}: residual tip vibration (standard deviation of tip_rel from t = \
             {} s) {:.5} m with control, {:.5} m without ({:.1}x less); peak drive force \
             {:.1} N with{limit}, {:.1} N without; final vehicle position {:.4} m with, \
             {:.4} m without ({:+.3} %)",
            description,
            with.window_start,
            with.residual_std,
            without.residual_std,
            without.residual_std / with.residual_std,
            with.peak_force,
            without.peak_force,
            with.final_vehicle,
            without.final_vehicle,
            100.0 * (with.final_vehicle / without.final_vehicle - 1.0)
        ) + &format!(
            "; residual amplitude (peak to peak) {:.5} m with, {:.5} m without ({:.1} % of \
             open loop); settling to +-{} mm about the final rest {} with, {} without; contact \
             switches in the window {} with, {} without",
            with.residual_p2p,
            without.residual_p2p,
            100.0 * with.residual_p2p / without.residual_p2p,
            1e3 * crate::analysis::metrics::SETTLING_BAND,
            settling(with.settling_time),
            settling(without.settling_time),
            with.window_switches,
            without.window_switches
        )
    }
}

/// A settling time for a sentence.
fn settling(t: Option<f64>) -> String {
    t.map_or("not within the run".into(), |t| format!("after {t:.2} s"))
}

/// Simulates `scene` with `controller` and without it, with the same method and settings,
/// and measures both over the window after the drive stops.
///
/// # Errors
/// The errors of [`simulate_controlled`] and of the open-loop simulation.
pub fn compare_with_open_loop(
    scene: &Scene,
    controller: &Controller,
    options: &SimulationOptions,
    reporter: &dyn Reporter,
) -> Result<ControlComparison> {
    crate::run::memory::check_runs(&[scene, scene], options.memory_budget)?;
    let controlled = simulate_controlled(scene, controller, options, reporter)?;
    let open_loop_options = controlled_options(controller, options)?;
    beside_open_loop(scene, controlled, &open_loop_options, reporter)
}

/// The `controlled` run of `scene` beside its open loop, run here with `options` (those the
/// controlled run took), both measured over the window after the drive stops.
///
/// # Errors
/// The errors of the open-loop simulation.
pub(crate) fn beside_open_loop(
    scene: &Scene,
    controlled: Simulation,
    options: &SimulationOptions,
    reporter: &dyn Reporter,
) -> Result<ControlComparison> {
    let open_loop = simulate_scene(scene, options, reporter)?;
    let window = drive_stop(scene);
    Ok(ControlComparison {
        with: metrics(scene, &controlled.trajectory, window),
        without: metrics(scene, &open_loop.trajectory, window),
        controlled,
        open_loop,
    })
}

/// One row of the variants table.
#[derive(Debug, Clone, PartialEq)]
pub struct VariantRow {
    /// `open loop`, `shaper`, `lqr` or `lqr+shaper`.
    pub variant: String,
    /// Its figures.
    pub metrics: RunMetrics,
    /// Residual vibration relative to the open loop's.
    pub reduction: f64,
    /// Final vehicle position relative to the open loop's travel.
    pub travel_ratio: f64,
    /// The run's wall time (s).
    pub wall: f64,
}

/// Every variant on `scene`: open loop, shaper, LQR, both, and both on a Kalman filter's
/// estimate (the design settings of
/// `options`, its `kind` aside), each simulated on the full nonlinear model with dopri5.
///
/// # Errors
/// The errors of [`design::design`] and of the simulations.
pub fn compare_variants(
    scene: &Scene,
    options: &DesignOptions,
    reporter: &dyn Reporter,
) -> Result<Vec<VariantRow>> {
    let sim = comparison_options(&SimulationOptions {
        model: options.model,
        models: options.models.clone(),
        memory_budget: options.memory_budget,
        ..SimulationOptions::default()
    })?;
    let window = drive_stop(scene);
    reporter.note(&format!("{}: open loop", scene.name));
    let open = simulate_scene(scene, &sim, reporter)?;
    let base = metrics(scene, &open.trajectory, window);
    let mut rows = vec![VariantRow {
        variant: "open loop".into(),
        metrics: base,
        reduction: 1.0,
        travel_ratio: 1.0,
        wall: open.trajectory.stats.wall.as_secs_f64(),
    }];
    // the continuous variants (full state, or the Kalman filter on vehicle and tip_rel), then
    // with sensors the sampled output-feedback ones
    let continuous = [
        ControllerKind::Shaper,
        ControllerKind::Lqr,
        ControllerKind::LqrShaper,
        ControllerKind::LqrShaperKalman,
    ]
    .map(|kind| (kind, Vec::new()));
    let sampled = [ControllerKind::Lqr, ControllerKind::LqrShaper]
        .map(|kind| (kind, options.sensors.clone()));
    let with_sensors = if options.sensors.is_empty() {
        &[][..]
    } else {
        &sampled[..]
    };
    for (kind, sensors) in continuous.iter().chain(with_sensors).cloned() {
        let variant = if sensors.is_empty() {
            kind.to_string()
        } else if design::sampled_law(options) == SampledLaw::StrainRate {
            let shaped = if kind.has_shaper() { " + shaper" } else { "" };
            format!("strain-rate{shaped} from {}", sensors.join("+"))
        } else {
            format!("{kind} from {}", sensors.join("+"))
        };
        reporter.note(&format!("{}: {variant}", scene.name));
        let controller = design::design(
            scene,
            &DesignOptions {
                kind,
                sensors,
                ..options.clone()
            },
        )?;
        let run = simulate_controlled(scene, &controller, &sim, reporter)?;
        let m = metrics(scene, &run.trajectory, window);
        rows.push(VariantRow {
            variant,
            metrics: m,
            reduction: base.residual_std / m.residual_std,
            travel_ratio: m.final_vehicle / base.final_vehicle,
            wall: run.trajectory.stats.wall.as_secs_f64(),
        });
    }
    Ok(rows)
}

/// The variants as a text table.
pub fn variants_table(rows: &[VariantRow]) -> String {
    let width = rows
        .iter()
        .map(|r| r.variant.len())
        .max()
        .unwrap_or(0)
        .max(18);
    let mut s = format!(
        "{:<width$} {:>17} {:>10} {:>9} {:>10} {:>9} {:>15} {:>18} {:>10} {:>8}\n",
        "variant",
        "residual std [m]",
        "reduction",
        "p2p [%]",
        "settle [s]",
        "switches",
        "peak force [N]",
        "final vehicle [m]",
        "travel",
        "wall [s]"
    );
    let open_p2p = rows.first().map_or(f64::NAN, |r| r.metrics.residual_p2p);
    for r in rows {
        s += &format!(
            "{:<width$} {:>17.5} {:>9.1}x {:>9.1} {:>10} {:>9} {:>15.1} {:>18.4} {:>9.4}% {:>8.2}\n",
            r.variant,
            r.metrics.residual_std,
            r.reduction,
            100.0 * r.metrics.residual_p2p / open_p2p,
            r.metrics
                .settling_time
                .map_or("-".into(), |t| format!("{t:.2}")),
            r.metrics.window_switches,
            r.metrics.peak_force,
            r.metrics.final_vehicle,
            100.0 * r.travel_ratio,
            r.wall
        );
    }
    s
}
