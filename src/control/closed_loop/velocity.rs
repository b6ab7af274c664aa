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
/// sampled at its rate with seeded measurement noise. `auto` is dopri5.
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
    file.check_fits(scene)?;
    let Drive::Motion(setpoint) = &scene.params.drive else {
        unreachable!("check_fits refuses a force drive")
    };
    let run = PreparedRun::new(
        scene,
        &crate::control::comparison_options(options)?,
        reporter,
    )?;
    tick_grid(file.rate_hz, &scene.time)?;
    check_tick_cost(scene, file.rate_hz, run.model().dof(), 50.0)?;
    let model = ServoCorrected::new(run.model(), file.rate_hz)?;
    let mut controller = VelocityController::new(file, setpoint.clone());
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
