//! Controller design on the linear models and its test on the full nonlinear model with
//! clearance: the Riccati solver ([`riccati`]), input shapers ([`shaper`]), the gain-scheduled
//! LQR and its controller file ([`design`](mod@design)), the controlled model ([`controlled`]), and the
//! figures a design is judged by ([`ControlMetrics`]).
//!
//! ```no_run
//! use telescopic::control::{DesignOptions, compare_variants};
//! use telescopic::{Scene, Silent};
//!
//! let scene = Scene::load("scenes/case-study.toml".as_ref(), &[])?;
//! for row in compare_variants(&scene, &DesignOptions::default(), &Silent)? {
//!     println!("{}: residual {:.4} m", row.variant, row.metrics.residual_std);
//! }
//! # Ok::<(), telescopic::Error>(())
//! ```

pub mod controlled;
pub mod design;
pub mod riccati;
pub mod shaper;

pub use controlled::{ControlLaw, Controlled, Observed};
pub use design::{Controller, ControllerKind, DesignOptions, design};
pub use shaper::ShaperKind;

use crate::model_choice::build_model;
use crate::report::Reporter;
use crate::simulation::{
    MethodChoice, Simulation, SimulationOptions, Trajectory, plan, run_trajectory, simulate_scene,
};
use crate::{Error, Result};
use telescopic_runtime::{Method, Scene, specializations};

/// Simulates `scene` with `controller` driving it, on the full nonlinear model. `auto`
/// (the default method) is dopri5 here: the feedback and the saturation make the scene
/// neither linear nor time-invariant.
///
/// # Errors
/// [`Error::Option`] when the controller does not fit the scene or the method is `exact`;
/// the errors of a simulation.
pub fn simulate_controlled(
    scene: &Scene,
    controller: &Controller,
    options: &SimulationOptions,
    reporter: &dyn Reporter,
) -> Result<Simulation> {
    controller.check_fits(scene)?;
    let method = match options.method {
        MethodChoice::Auto => Method::Dopri5,
        MethodChoice::Method(Method::Exact) => {
            return Err(Error::option(
                "--method",
                "exact stepping needs a linear time-invariant scene; with a controller, take \
                 dopri5 or another integrator",
            ));
        }
        MethodChoice::Method(m) => m,
    };
    let mut resolved = plan(
        scene,
        &SimulationOptions {
            method: MethodChoice::Method(method),
            ..options.clone()
        },
    )?;
    resolved.how = format!("controller {}; ", controller.kind);
    let chosen = build_model(&scene.params, options.model)?;
    if let Some(note) = &chosen.note {
        reporter.note(note);
    }
    let base = chosen.model.as_ref();
    let (start, end) = (scene.time.start, scene.time.end);
    let trajectory = if controller.kind.has_observer() {
        if !matches!(method, Method::Dopri5 | Method::Dop853) {
            return Err(Error::option(
                "--method",
                "a controller with a Kalman filter runs with dopri5 or dop853",
            ));
        }
        let model = Observed::new(base, controller, start, end)?;
        // the filter adds no stiffness of its own: the budget is the structure's
        crate::budget::check_run(scene, base, method, &resolved.settings)?;
        run_trajectory(scene, &model, method, &resolved.settings, reporter)?
    } else {
        let model = Controlled::new(base, controller, start, end)?;
        crate::budget::check_run(scene, &model, method, &resolved.settings)?;
        run_trajectory(scene, &model, method, &resolved.settings, reporter)?
    };
    let specials = specializations(base, &scene.time, method, None);
    Ok(Simulation {
        scene: scene.name.clone(),
        span: (scene.time.start, scene.time.end),
        model: chosen.description,
        // a controlled scene is not linear time-invariant: exact stepping never applies
        specializations: specials
            .into_iter()
            .filter(|s| !s.contains("exact stepping"))
            .collect(),
        plan: resolved,
        trajectory,
    })
}

/// The figures a controller is judged by.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ControlMetrics {
    /// Start of the residual-vibration window (s): the drive's last change.
    pub window_start: f64,
    /// Standard deviation of `tip_rel` over the window (m): the oscillation about its mean.
    pub residual_std: f64,
    /// Largest |drive force| (N).
    pub peak_force: f64,
    /// Final vehicle position (m).
    pub final_vehicle: f64,
}

/// When the scene's drive makes its last change (s): its last breakpoint inside the span,
/// else the start.
pub fn drive_stop(scene: &Scene) -> f64 {
    scene
        .params
        .drive_profile()
        .breakpoints()
        .into_iter()
        .filter(|&b| b > scene.time.start && b < scene.time.end)
        .fold(scene.time.start, f64::max)
}

/// The metrics of a run over the window `[window_start, end]`; the drive force is the
/// `drive_force` column when the run has one, else the scene's drive profile.
pub fn metrics(scene: &Scene, trajectory: &Trajectory, window_start: f64) -> ControlMetrics {
    let t = trajectory.column("t").expect("t");
    let tip = trajectory.column("tip_rel").expect("tip_rel");
    let window: Vec<f64> = t
        .iter()
        .zip(&tip)
        .filter(|(t, _)| **t >= window_start)
        .map(|(_, v)| *v)
        .collect();
    let mean = window.iter().sum::<f64>() / window.len().max(1) as f64;
    let var = window.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / window.len().max(1) as f64;
    let peak_force = match trajectory.column("drive_force") {
        Some(f) => f.iter().fold(0.0f64, |m, v| m.max(v.abs())),
        None => t
            .iter()
            .map(|&t| scene.params.drive_profile().value(t).abs())
            .fold(0.0, f64::max),
    };
    ControlMetrics {
        window_start,
        residual_std: var.sqrt(),
        peak_force,
        final_vehicle: trajectory
            .column("vehicle")
            .and_then(|v| v.last().copied())
            .unwrap_or(0.0),
    }
}

/// One row of the variants table.
#[derive(Debug, Clone, PartialEq)]
pub struct VariantRow {
    /// `open loop`, `shaper`, `lqr` or `lqr+shaper`.
    pub variant: String,
    /// Its figures.
    pub metrics: ControlMetrics,
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
/// The errors of [`design()`] and of the simulations.
pub fn compare_variants(
    scene: &Scene,
    options: &DesignOptions,
    reporter: &dyn Reporter,
) -> Result<Vec<VariantRow>> {
    let sim = SimulationOptions {
        method: MethodChoice::Method(Method::Dopri5),
        model: options.model,
        ..SimulationOptions::default()
    };
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
    for kind in [
        ControllerKind::Shaper,
        ControllerKind::Lqr,
        ControllerKind::LqrShaper,
        ControllerKind::LqrShaperKalman,
    ] {
        reporter.note(&format!("{}: {kind}", scene.name));
        let controller = design(
            scene,
            &DesignOptions {
                kind,
                ..options.clone()
            },
        )?;
        let run = simulate_controlled(scene, &controller, &sim, reporter)?;
        let m = metrics(scene, &run.trajectory, window);
        rows.push(VariantRow {
            variant: kind.to_string(),
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
    let mut s = format!(
        "{:<18} {:>17} {:>10} {:>15} {:>18} {:>10} {:>8}\n",
        "variant",
        "residual std [m]",
        "reduction",
        "peak force [N]",
        "final vehicle [m]",
        "travel",
        "wall [s]"
    );
    for r in rows {
        s += &format!(
            "{:<18} {:>17.5} {:>9.1}x {:>15.1} {:>18.4} {:>9.4}% {:>8.2}\n",
            r.variant,
            r.metrics.residual_std,
            r.reduction,
            r.metrics.peak_force,
            r.metrics.final_vehicle,
            100.0 * r.travel_ratio,
            r.wall
        );
    }
    s
}
