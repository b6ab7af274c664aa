//! A run of a scene with its velocity feedback in the loop.

use crate::Result;
use crate::control::closed_loop::sampled::{
    HeldPlant, SampledRun, TickSetup, check_tick_cost, finish, tick_grid, tick_loop,
};
use crate::control::file::velocity::VelocityFeedback;
use crate::control::law::servo::ServoCorrected;
use crate::control::law::velocity::VelocityController;
use crate::report::Reporter;
use crate::run::{PreparedRun, SimulationOptions};
use telescopic_runtime::{Drive, Scene};

/// Simulates `scene` with the velocity feedback of `file` on the full nonlinear model,
/// sampled at its rate with seeded measurement noise, the law told the scene's load (the
/// machine weighs it). `auto` is dopri5.
///
/// # Errors
/// [`crate::Error::Input`]/[`crate::Error::Option`] when the file does not fit the scene; the errors of a
/// simulation.
pub fn simulate_velocity(
    scene: &Scene,
    file: &VelocityFeedback,
    options: &SimulationOptions,
    reporter: &dyn Reporter,
) -> Result<SampledRun> {
    simulate_velocity_told(scene, file, scene.params.load_mass, options, reporter)
}

/// [`simulate_velocity`] with the law told a load of `load_kg` (kg), whatever the scene
/// carries: a machine that weighs its load wrongly.
///
/// # Errors
/// Those of [`simulate_velocity`]; [`crate::Error::Input`] for a load that is not finite
/// or is negative.
pub fn simulate_velocity_told(
    scene: &Scene,
    file: &VelocityFeedback,
    load_kg: f64,
    options: &SimulationOptions,
    reporter: &dyn Reporter,
) -> Result<SampledRun> {
    file.check_fits(scene)?;
    let Drive::Motion(setpoint) = &scene.params.drive else {
        unreachable!("check_fits refuses a force drive")
    };
    let mut controller = VelocityController::new(file, setpoint.clone(), load_kg)?;
    let run = PreparedRun::new(
        scene,
        &crate::control::comparison_options(options)?,
        reporter,
    )?;
    tick_grid(file.rate_hz, &scene.time)?;
    check_tick_cost(scene, file.rate_hz, run.model().dof(), 50.0)?;
    let model = ServoCorrected::new(run.model(), file.rate_hz)?;
    let setup = TickSetup {
        rate_hz: file.rate_hz,
        sensors: &file.sensors,
        noise: &file.noise,
        seed: file.seed,
        scheduled: file.scheduled_index().map(|i| i + 2),
    };
    let ticked = tick_loop(
        &run,
        HeldPlant::ServoCorrection(&model),
        &setup,
        &mut controller,
        reporter,
    )?;
    Ok(finish(run, file.rate_hz, ticked))
}
