//! Identification: scene values fitted to a measured record of the machine.
//!
//! The record ([`record`]) gives the time, the drive force the machine applied (`F`, held
//! between samples) and sensors by their output names. The fit frees scene values by key
//! ([`free`]) and minimizes the sensors' residuals, each weighted by its noise ([`noise`])
//! and with its offset removed ([`offsets::Offsets`]), by Levenberg-Marquardt
//! (the `levenberg-marquardt` crate, MINPACK's method) on a model whose own error against
//! the beams is below the noise ([`model_size`]). The values' standard deviations and
//! correlations come from the Jacobian at the optimum ([`uncertainty`]). With clearance the
//! fit keeps to the pointwise window, up to the first contact switch, unless asked to go
//! further: beyond it the motion is chaotic and a pointwise fit means nothing. It grows
//! that window in stages (a quarter, a half, the whole), each bounding it by the fitted
//! values' own first switch.
//!
//! ```
//! use telescopic::identify::{IdentifyOptions, FreeValue, Record, identify};
//! use telescopic::run::{SimulationOptions, simulate_scene};
//! use telescopic::{Scene, Silent};
//! // a record the scene's own model (the paper's 5 modes) makes with a heavier load
//! let scene = Scene::load("scenes/adams-linear.toml".as_ref(), &["time.end=1".into()])?;
//! let truth = scene.with_values(&[("masses.load", 25.0)])?;
//! let run = simulate_scene(&truth, &SimulationOptions::default(), &Silent)?.trajectory;
//! let names = vec!["t".to_string(), "vehicle".into(), "tip_rel".into()];
//! let columns = (0..3).map(|j| run.rows.iter().map(|r| r[j]).collect()).collect();
//! let record = Record::from_columns("made", &names, columns)?;
//! let options = IdentifyOptions {
//!     free: FreeValue::parse_list("masses.load")?,
//!     size: Some("5".parse().expect("a size")), // the model that made the record
//!     ..Default::default()
//! };
//! let fit = identify(&scene, &record, &options, &Silent)?;
//! assert!((fit.values[0].value - 25.0).abs() < 1e-3);
//! # Ok::<(), telescopic::Error>(())
//! ```

pub mod free;
pub mod model_size;
pub mod noise;
pub mod offsets;
pub mod problem;
pub mod record;
pub mod report;
pub mod start;
pub mod uncertainty;

pub use free::{Free, FreeValue};
pub use offsets::Offsets;
pub use record::Record;
pub use report::{FittedValue, Identification, SensorFit, SensorPrediction};
pub use start::{Start, StartFit};

use crate::report::Reporter;
use crate::{Error, Result};
use levenberg_marquardt::LevenbergMarquardt;
use problem::{FitProblem, FitSetup};
use std::time::Instant;
use telescopic_runtime::{Output, Profile, Scene, ShapedProfile};

/// Options of a fit.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct IdentifyOptions {
    /// The scene values to fit, with optional bounds.
    pub free: Vec<FreeValue>,
    /// Sensors' noise standard deviations (their units) given instead of estimated.
    pub noise: Vec<(Output, f64)>,
    /// Offsets fitted (default) or zero.
    pub offsets: Offsets,
    /// The model's size; `None`: the smallest whose truncation is within every sensor's
    /// noise ([`model_size`]).
    pub size: Option<crate::run::ModelSize>,
    /// Fit only the record up to this time (s); `None`: the whole record without clearance,
    /// the pointwise window with it.
    pub until: Option<f64>,
    /// At rest at the record's first sample (default), or in motion ([`start`]).
    pub start: Start,
}

/// The optimizer's patience: at most this many times (free values + 1) runs.
const PATIENCE: usize = 20;

/// Fits `options.free` of `scene` to `record` (see the module documentation).
///
/// # Errors
/// [`Error::Option`] for bad free values; [`Error::Input`] for a record the scene cannot
/// produce or that does not determine a value (named); errors of the runs.
pub fn identify(
    scene: &Scene,
    record: &Record,
    options: &IdentifyOptions,
    reporter: &dyn Reporter,
) -> Result<Identification> {
    let started = Instant::now();
    let driven = driven_scene(scene, record)?;
    start::check(&driven, options.start)?;
    let free = FreeValue::resolve(&options.free, &driven)?;
    let noise: Vec<(f64, noise::NoiseSource)> = record
        .sensors
        .iter()
        .map(|(o, y)| noise::noise_of(*o, y, &options.noise))
        .collect();
    reporter.start(&format!(
        "identifying {} from {}",
        scene.name, record.source
    ));
    let outcome = fit_record(scene, &driven, record, options, &free, &noise, reporter);
    reporter.finish();
    Ok(Identification {
        wall_s: started.elapsed().as_secs_f64(),
        ..outcome?
    })
}

/// The fit of [`identify`] once the scene is driven as the record was and the free values
/// and noise are known: the model size, the window, the growing horizon with clearance,
/// the last fit and its report.
fn fit_record(
    scene: &Scene,
    driven: &Scene,
    record: &Record,
    options: &IdentifyOptions,
    free: &[Free],
    noise: &[(f64, noise::NoiseSource)],
    reporter: &dyn Reporter,
) -> Result<Identification> {
    let sigmas: Vec<f64> = noise.iter().map(|n| n.0).collect();
    let (model, start_run) =
        model_size::fit_model(driven, record, &sigmas, options.size, reporter)?;
    problem::predictions(&start_run.trajectory, record)?;
    let (mut window, mut window_reason) =
        fit_window(driven, &start_run.trajectory, record, options.until)?;
    let start_modes = match options.start {
        Start::Rest => None,
        Start::Moving => Some(start_modes(&model.size.apply(driven), record.interval())?),
    };
    let setup = FitSetup {
        driven,
        size: model.size,
        free,
        noise: &sigmas,
        offsets: options.offsets,
        start_modes,
        reporter,
        budget: PATIENCE * (free.len() + 1) * (free.len() + 1),
    };
    let mut start: Vec<f64> = free.iter().map(|f| f.start).collect();
    // with clearance, a growing horizon: fits of the window's first quarter and half
    // first, each bounding the window by the fitted model's own first switch
    if options.until.is_none() && !driven.params.contact.is_linear() {
        for share in [0.25, 0.5] {
            let samples = ((window as f64 * share) as usize).max(record::MIN_SAMPLES);
            let part = record.first(samples.min(window));
            let (problem, _) = setup.fit(&part, &start)?;
            start = problem.values(&problem.u);
            // the fitted values run over the whole window: their first switch bounds it
            let whole = record.first(window);
            let run = setup.problem(&whole).run(&start)?;
            let switch = crate::run::error_budget::window(&driven.params, &run);
            if switch.reason == crate::run::error_budget::WindowEnd::FirstSwitch {
                let (end, reason) = fit_window(driven, &run, record, None)?;
                if end < window {
                    (window, window_reason) = (end, reason);
                }
            }
        }
    }
    let fitted_record = record.first(window);
    let (problem, lm) = setup.fit(&fitted_record, &start)?;
    Ok(Identification {
        termination: format!("{:?}", lm.termination),
        ..report::conclude(&problem, scene, noise, &model, window_reason)?
    })
}

/// The slowest modes of `sized` a start in motion fits on a record sampled every `interval`
/// seconds ([`start::modes_below_rate`]).
fn start_modes(sized: &Scene, interval: f64) -> Result<usize> {
    let run = crate::run::PreparedRun::new(sized, &problem::run_options(), &crate::Silent)?;
    start::modes_below_rate(run.model(), sized, interval)
}

impl<'a> FitSetup<'a> {
    /// Levenberg-Marquardt on `part` of the record from the free values `start`: the
    /// problem at its optimum and the optimizer's report.
    ///
    /// # Errors
    /// The first error of a run the optimizer asked for.
    fn fit(
        &self,
        part: &'a Record,
        start: &[f64],
    ) -> Result<(FitProblem<'a>, levenberg_marquardt::MinimizationReport<f64>)> {
        let problem = self.problem(part).starting_at(start);
        // every coordinate spans its bounds over a few units: a round trust region in them
        let (problem, lm) = LevenbergMarquardt::new()
            .with_scale_diag(false)
            .with_stepbound(1.0)
            .with_patience(PATIENCE)
            .minimize(problem);
        if let Some(error) = problem.failure.lock().expect("not poisoned").take() {
            return Err(error);
        }
        Ok((problem, lm))
    }
}

/// `scene` run as `record` was: on its time grid, driven by its force held between samples,
/// or moved along its prescribed position (a smooth monotone cubic through the samples,
/// whatever the scene's own drive), or else by the scene's own drive.
///
/// # Errors
/// [`Error::Input`] when the record has a force and the scene's drive is a motion.
pub fn driven_scene(scene: &Scene, record: &Record) -> Result<Scene> {
    let mut file = scene.file.clone();
    let n = record.times.len();
    let dt = record.interval();
    file.time.start = record.times[0];
    file.time.end = record.times[0] + dt * (n as f64 - 0.5);
    file.time.sample = dt;
    if let Some(force) = &record.force {
        if file.drive.force.is_none() {
            return Err(Error::Input {
                subject: format!("{}, column F", record.source),
                rule: format!(
                    "the record gives the drive force, but {}'s drive is a prescribed motion",
                    scene.name
                ),
            });
        }
        file.drive.force = Some(held(&record.times, force));
    }
    if let Some(position) = &record.position {
        file.drive.force = None;
        file.drive.motion = Some(Profile::Shaped(ShapedProfile::PiecewiseCubic {
            times: record.times.clone(),
            values: position.clone(),
        }));
    }
    Ok(Scene::from_file(
        file,
        &format!("{} driven as {}", scene.name, record.source),
    )?)
}

/// The force `values` at `times`, each held until the next that differs.
fn held(times: &[f64], values: &[f64]) -> Profile {
    if values.iter().all(|&v| v == values[0]) {
        return Profile::Constant(values[0]);
    }
    let (mut t, mut v) = (vec![times[0]], vec![values[0]]);
    for (&time, &value) in times.iter().zip(values).skip(1) {
        if value != *v.last().expect("one pushed") {
            t.push(time);
            v.push(value);
        }
    }
    Profile::Shaped(ShapedProfile::PiecewiseConstant {
        times: t,
        values: v,
    })
}

/// How many of the record's samples the fit uses, and why it stops there: `until`, or the
/// whole record without clearance, or with it up to the first contact switch of `run`.
fn fit_window(
    driven: &Scene,
    run: &crate::run::Trajectory,
    record: &Record,
    until: Option<f64>,
) -> Result<(usize, String)> {
    let n = record.times.len();
    let count = |end: f64| {
        record
            .times
            .iter()
            .take_while(|&&t| t <= end + 1e-12)
            .count()
    };
    let (samples, reason) = match until {
        Some(end) => (count(end), format!("up to t = {end} s, as asked")),
        None if driven.params.contact.is_linear() => (n, "the whole record".to_string()),
        None => {
            let window = crate::run::error_budget::window(&driven.params, run);
            (
                count(window.end),
                format!(
                    "up to the first contact switch at t = {:.3} s: beyond it the motion in the \
                     clearance is chaotic and a pointwise fit means nothing",
                    window.end
                ),
            )
        }
    };
    if samples < record::MIN_SAMPLES {
        return Err(Error::Input {
            subject: record.source.clone(),
            rule: format!(
                "the fit's window ({reason}) holds {samples} samples; at least {} are needed",
                record::MIN_SAMPLES
            ),
        });
    }
    Ok((samples, reason))
}

/// Runs the `fitted` scene (at the fit's model size) as `record` was and compares each
/// sensor: what `--validate` reports. With `offsets` fitted, each sensor's offset is removed
/// as in the fit; with a `start` in motion, the free motion of as many modes as the fit took
/// is fitted to the record first (each sensor weighted by the fit's noise for it, or its
/// noise estimate).
///
/// # Errors
/// As [`identify`]'s runs, and a record with sensors the scene cannot produce.
pub fn validate(
    fitted: &Identification,
    record: &Record,
    offsets: Offsets,
    start: Start,
) -> Result<Vec<SensorPrediction>> {
    let driven = fitted
        .model
        .size
        .apply(&driven_scene(&fitted.scene, record)?);
    start::check(&driven, start)?;
    let run = crate::run::PreparedRun::new(&driven, &problem::run_options(), &crate::Silent)?;
    let trajectory = run.integrate(&crate::Silent)?;
    let mut predictions = problem::predictions(&trajectory, record)?;
    if start == Start::Moving {
        let modes = match fitted.start {
            Some(fit) => fit.modes,
            None => start::modes_below_rate(run.model(), &driven, record.interval())?,
        };
        let noise: Vec<f64> = record
            .sensors
            .iter()
            .map(|(output, y)| {
                fitted
                    .sensors
                    .iter()
                    .find(|s| s.output == *output)
                    .map_or_else(|| noise::noise_of(*output, y, &[]).0, |s| s.noise.0)
            })
            .collect();
        start::FreeMotion::of(run.model(), &driven, record, modes)?.add_fitted(
            &mut predictions,
            record,
            &noise,
            offsets,
        );
    }
    Ok(record
        .sensors
        .iter()
        .zip(&predictions)
        .map(|((output, y), p)| SensorPrediction::of(*output, y, p, offsets))
        .collect())
}
