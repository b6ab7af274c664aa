//! A sampled controller in the loop with the full nonlinear model: the plant is integrated
//! from tick to tick with the force held, the sensors are read at each tick with seeded
//! Gaussian noise, and the controller's force acts from the next tick on.

use crate::control::file::schema::{Controller, Estimator};
use crate::control::law::controlled::Controlled;
use crate::control::law::sampled::{DiscreteController, SampledController};
use crate::control::law::servo::ServoCorrected;
use crate::report::Reporter;
use crate::run::PreparedRun;
use crate::run::trajectory::{self, Column};
use crate::run::{HeldInputStepper, Simulation, Trajectory};
use crate::{Error, Result};
use rand::{Rng, SeedableRng};
use telescopic_runtime::model::sensors::Sensors;
use telescopic_runtime::{Model, Scene, TimeSpan, rest_state};

/// A sampled run: the simulation and the command the controller gave at every tick.
#[derive(Debug, Clone, PartialEq)]
pub struct SampledRun {
    /// The controlled simulation (its `drive_force` column is the held force, or a
    /// velocity-servo's reaction).
    pub simulation: Simulation,
    /// `(t_k, u_{k+1})`: each tick's time and its command: a force (N), or a velocity
    /// correction (m/s) for a velocity servo.
    pub forces: Vec<(f64, f64)>,
}

/// Standard normal samples (Box-Muller; hand-written: `rand_distr` for one function is not
/// worth a dependency).
fn gaussian(rng: &mut impl Rng) -> f64 {
    let u1: f64 = rng.random::<f64>().max(f64::MIN_POSITIVE);
    let u2: f64 = rng.random();
    (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
}

/// Runs `run`'s scene with the sampled controller of `file`, stepped through `controller`
/// (the in-library [`DiscreteController`] or another implementation of the same law).
///
/// # Errors
/// [`Error::Option`] for a controller without a sampled part or an output grid that is not a
/// multiple of the controller's period; the errors of a simulation.
pub fn run_sampled(
    run: PreparedRun<'_>,
    file: &Controller,
    controller: &mut dyn SampledController,
    reporter: &dyn Reporter,
) -> Result<SampledRun> {
    let sampled = file.sampled_part()?;
    tick_grid(sampled.rate_hz, &run.scene.time)?;
    check_ticks(run.scene, file, run.model().dof())?;
    let span = run.scene.time;
    let model = Controlled::sampled(run.model(), file, span.start, span.end)?;
    let setup = TickSetup {
        rate_hz: sampled.rate_hz,
        sensors: &sampled.sensors,
        noise: &sampled.noise,
        seed: sampled.seed,
        scheduled: file.scheduled_section(),
    };
    let ticked = tick_loop(&run, HeldPlant::Force(&model), &setup, controller, reporter)?;
    Ok(finish(run, setup.rate_hz, ticked))
}

/// What a tick loop ran: its trajectory, each tick's command and where its ticks stepped
/// exactly from.
pub(crate) struct TickedRun {
    /// The run's trajectory.
    pub trajectory: Trajectory,
    /// Each tick's time (s) and command.
    pub commands: Vec<(f64, f64)>,
    /// Where the ticks were stepped exactly from (s); `None` when the plan's method stepped
    /// them all (no hand-over planned, or the model refused it).
    pub exact_from: Option<f64>,
}

/// The sampled run of `run` from its tick loop's result.
pub(crate) fn finish(run: PreparedRun<'_>, rate_hz: f64, ticked: TickedRun) -> SampledRun {
    let mut plan = run.plan.clone();
    plan.reason = crate::run::MethodReason::SampledController {
        rate_hz,
        exact_from: ticked.exact_from,
    };
    let simulation = run.into_simulation(ticked.trajectory);
    SampledRun {
        simulation: Simulation { plan, ..simulation },
        forces: ticked.commands,
    }
}

/// The plant of a sampled loop and what its command holds over a tick.
#[derive(Clone, Copy)]
pub(crate) enum HeldPlant<'a> {
    /// The drive force (N), replacing the scene's.
    Force(&'a Controlled<'a>),
    /// The velocity servo's correction (m/s) on the scene's prescribed motion.
    ServoCorrection(&'a ServoCorrected<'a>),
}

impl HeldPlant<'_> {
    /// The model integrated.
    fn model(&self) -> &dyn Model {
        match self {
            HeldPlant::Force(m) => *m,
            HeldPlant::ServoCorrection(m) => *m,
        }
    }

    /// Holds `command` from now on.
    fn hold(&self, command: f64) {
        match self {
            HeldPlant::Force(m) => m.law().hold(command),
            HeldPlant::ServoCorrection(m) => m.hold(command),
        }
    }
}

/// What a sampled loop reads from its controller file.
pub(crate) struct TickSetup<'a> {
    /// Controller rate (Hz).
    pub rate_hz: f64,
    /// The measured outputs.
    pub sensors: &'a [String],
    /// Their noise (standard deviations).
    pub noise: &'a [f64],
    /// Seed of the noise.
    pub seed: u64,
    /// The scheduled section (its position `a_k` is passed to the law), if any.
    pub scheduled: Option<usize>,
}

/// The tick loop of a sampled run: at each tick the outputs and the noisy measurements of
/// `plant`, the command of `controller`, which the plant holds for the next tick on (one
/// sample of computation delay); the plant integrated from tick to tick.
pub(crate) fn tick_loop(
    run: &PreparedRun<'_>,
    plant: HeldPlant<'_>,
    setup: &TickSetup<'_>,
    controller: &mut dyn SampledController,
    reporter: &dyn Reporter,
) -> Result<TickedRun> {
    let model = plant.model();
    let scene: &Scene = run.scene;
    let span = scene.time;
    let (period, every) = tick_grid(setup.rate_hz, &span)?;
    let coordinates = if run.coordinates { model.dof() } else { 0 };
    crate::run::memory::check_run(scene, (0, coordinates), run.memory_budget)?;
    let sensors = Sensors::new(model);
    let own = model.output_quantities().len();
    let mut columns = trajectory::model_and_sensor_columns(model);
    let measured = measured_columns(&columns, setup.sensors)?;
    columns.extend(trajectory::coordinate_columns(coordinates));
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(setup.seed);
    let ticks = ((span.end - span.start) / period).round() as usize;
    let n = model.dof();
    let mut ydot = vec![0.0; 2 * n];
    let mut out = vec![0.0; columns.len() - coordinates];
    let mut measurement = vec![0.0; measured.len()];
    let mut rows = Vec::with_capacity(ticks / every + 1);
    let mut forces = Vec::with_capacity(ticks);
    let started = std::time::Instant::now();
    // steps end on the ticks
    let ticked = TimeSpan {
        sample: period,
        ..span
    };
    let simulation_error = |error| Error::Simulation {
        scene: scene.name.clone(),
        error,
    };
    let mut stepper =
        HeldInputStepper::new(&run.plan, model, &ticked, &rest_state(model, span.start))
            .map_err(simulation_error)?;
    reporter.start(&format!(
        "simulating {} with a sampled controller",
        scene.name
    ));
    for k in 0..=ticks {
        let t = span.start + k as f64 * period;
        let y = stepper.state();
        // the outputs and the measurements at the tick, with the command held now
        model.rhs(t, y, None, &mut ydot);
        let (own_out, sensor_out) = out.split_at_mut(own);
        model.outputs(t, y, &ydot, own_out);
        sensors.values(n, y, &ydot, sensor_out);
        if k % every == 0 {
            let mut row = Vec::with_capacity(out.len() + 1);
            row.push(t);
            row.extend_from_slice(&out);
            row.extend_from_slice(&y[..coordinates]);
            rows.push(row);
        }
        if k == ticks {
            break;
        }
        measure(&out, &measured, setup.noise, &mut rng, &mut measurement);
        let a = setup
            .scheduled
            .map_or(0.0, |s| model.params().positions[s - 2].value(t));
        let command = controller.step(t, &measurement, a);
        forces.push((t, command));
        stepper
            .advance_to(span.start + (k + 1) as f64 * period)
            .map_err(simulation_error)?;
        plant.hold(command);
        stepper.input_changed();
        reporter.progress((k + 1) as f64 / ticks as f64);
        if reporter.stop_requested() {
            return Err(Error::Simulation {
                scene: scene.name.clone(),
                error: telescopic_runtime::SimError::Stopped {
                    t: t + period,
                    method: run.plan.method.name(),
                },
            });
        }
    }
    reporter.finish();
    let mut stats = stepper.stats();
    stats.wall = started.elapsed();
    Ok(TickedRun {
        trajectory: Trajectory::new(columns, rows, stats),
        commands: forces,
        exact_from: run.plan.settings.exact_from.filter(|_| stepper.is_exact()),
    })
}

/// The measured outputs (`out` at the columns `measured`) with Gaussian noise of standard
/// deviations `noise`, into `measurement`.
fn measure(
    out: &[f64],
    measured: &[usize],
    noise: &[f64],
    rng: &mut impl Rng,
    measurement: &mut [f64],
) {
    for (m, &i) in measurement.iter_mut().zip(measured) {
        *m = out[i];
    }
    for (m, sigma) in measurement.iter_mut().zip(noise) {
        *m += sigma * gaussian(rng);
    }
}

/// Most operations a sampled-controller run may take (about 20 s on one core): beyond it a
/// run is refused before it starts, with the estimate.
pub const MAX_SAMPLED_OPERATIONS: f64 = 2e10;

/// Refuses a sampled run whose ticks cost more than [`MAX_SAMPLED_OPERATIONS`]: each tick
/// evaluates the model (`~ (2 n)^2` for `n` degrees of freedom, with an integrator's stages)
/// and runs the controller (the extended filter's covariance `~ 10 m^3` for `m` states, the
/// linear filter's `~ 4 m^2`).
fn check_ticks(scene: &Scene, file: &Controller, dof: usize) -> Result<()> {
    let sampled = file.sampled_part()?;
    let m = file.states.len() as f64;
    let controller = match (sampled.estimator, &sampled.strain_rate) {
        (_, Some(_)) | (Estimator::None, None) => 50.0,
        (Estimator::Extended, None) => 10.0 * m * m * m,
        (Estimator::Linear, None) => 4.0 * m * m,
    };
    check_tick_cost(scene, sampled.rate_hz, dof, controller)
}

/// [`check_ticks`] for a law of `controller` operations a tick at `rate_hz`.
pub(crate) fn check_tick_cost(
    scene: &Scene,
    rate_hz: f64,
    dof: usize,
    controller: f64,
) -> Result<()> {
    let ticks = (scene.time.end - scene.time.start) * rate_hz;
    let model = 12.0 * (2.0 * dof as f64).powi(2);
    let operations = ticks * (model + controller);
    if operations <= MAX_SAMPLED_OPERATIONS {
        return Ok(());
    }
    Err(Error::Unaffordable {
        scene: scene.name.clone(),
        reason: format!(
            "the sampled controller at {rate_hz} Hz over {} s is {ticks:.3e} ticks of about \
             {:.1e} operations each ({operations:.1e} in all), more than the limit of \
             {MAX_SAMPLED_OPERATIONS:.0e}; design the controller at a lower rate, or shorten \
             time.end",
            scene.time.end - scene.time.start,
            model + controller
        ),
    })
}

/// The controller's period (s) and how many ticks make one output sample.
///
/// # Errors
/// [`Error::Option`] naming `time.sample` when it is not a multiple of the period.
pub(crate) fn tick_grid(rate_hz: f64, span: &TimeSpan) -> Result<(f64, usize)> {
    let period = 1.0 / rate_hz;
    let ratio = span.sample / period;
    if (ratio - ratio.round()).abs() > 1e-9 * ratio.max(1.0) || ratio.round() < 1.0 {
        return Err(Error::input(
            "time.sample",
            format!(
                "{} s is not a multiple of the controller's period {period} s ({rate_hz} Hz)",
                span.sample
            ),
        ));
    }
    Ok((period, ratio.round() as usize))
}

/// The output columns (in `columns`) the sensors read.
///
/// # Errors
/// [`Error::Input`] naming a sensor that is not an output.
fn measured_columns(columns: &[Column], sensors: &[String]) -> Result<Vec<usize>> {
    sensors
        .iter()
        .map(|s| {
            columns
                .iter()
                .position(|c| c.to_string() == *s)
                .ok_or_else(|| {
                    Error::input(
                        "controller `sampled.sensors`",
                        format!("`{s}` is not an output of the scene"),
                    )
                })
        })
        .collect()
}

/// Runs the in-library sampled controller of `file` on `run`'s scene.
///
/// # Errors
/// As [`run_sampled`].
pub fn simulate_sampled(
    run: PreparedRun<'_>,
    file: &Controller,
    reporter: &dyn Reporter,
) -> Result<SampledRun> {
    let (start, end) = (run.scene.time.start, run.scene.time.end);
    let extended = file
        .sampled
        .as_ref()
        .is_some_and(|s| s.estimator == crate::control::file::schema::Estimator::Extended);
    if extended {
        // the filter predicts with the model its file records, not the plant's
        let mut controller = crate::control::law::ekf::ExtendedKalman::new(file, start, end)?;
        return run_sampled(run, file, &mut controller, reporter);
    }
    if file
        .sampled
        .as_ref()
        .is_some_and(|s| s.strain_rate.is_some())
    {
        let mut controller =
            crate::control::law::strain::StrainRateController::new(file, start, end)?;
        return run_sampled(run, file, &mut controller, reporter);
    }
    let mut controller = DiscreteController::new(file, start, end)?;
    run_sampled(run, file, &mut controller, reporter)
}
