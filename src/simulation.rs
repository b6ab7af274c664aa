//! Simulating a scene: the method (`auto` resolved on the scene), the model, the integration
//! with the clearance contact law, every output sample, and the run summary.
//!
//! ```
//! use telescopic::simulation::{SimulationOptions, simulate_scene};
//! use telescopic::{Scene, Silent};
//!
//! let scene = Scene::load("scenes/adams-linear.toml".as_ref(), &["time.end=0.5".into()])?;
//! let run = simulate_scene(&scene, &SimulationOptions::default(), &Silent)?;
//! let tip = run.trajectory.column("tip_rel").expect("every model has tip_rel");
//! assert_eq!(tip.len(), 501); // 0 .. 0.5 s every millisecond
//! println!("{}", run.summary());
//! # Ok::<(), telescopic::Error>(())
//! ```

use crate::error_budget::{self, ErrorBudget};
use crate::models::{ModelChoice, ModelRegistry};
use crate::report::{Phase, Reporter};
use crate::run::PreparedRun;
use crate::{Error, Result};
use std::fmt;
use std::io::Write;
use std::path::Path;
use std::str::FromStr;
use telescopic_runtime::accuracy::Resolve;
use telescopic_runtime::integrate::StepControl;
use telescopic_runtime::{
    DEFAULT_ACCURACY_M, Method, RunStats, Scene, Settings, plan_for_accuracy,
};

/// The method of a run: `auto` (chosen on the scene) or one named method.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum MethodChoice {
    /// `exact` for a scene linear and time-invariant between contact switches, else
    /// `dopri5`, handing over to `exact` once the telescopic positions rest.
    #[default]
    Auto,
    /// This method throughout.
    Method(Method),
}

impl FromStr for MethodChoice {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "auto" => Ok(MethodChoice::Auto),
            name => Method::from_name(name).map(MethodChoice::Method),
        }
    }
}

impl fmt::Display for MethodChoice {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            MethodChoice::Auto => f.write_str("auto"),
            MethodChoice::Method(m) => write!(f, "{m}"),
        }
    }
}

/// Options of a simulation; the defaults are `simulate`'s.
#[derive(Debug, Clone, PartialEq)]
pub struct SimulationOptions {
    /// The method (default `auto`).
    pub method: MethodChoice,
    /// Relative tolerance of adaptive methods (default 1e-6).
    pub rtol: Option<f64>,
    /// Absolute tolerance of adaptive methods (m, m/s; default 1e-9).
    pub atol: Option<f64>,
    /// Step (s) of fixed-step methods; first trial step of adaptive ones.
    pub dt: Option<f64>,
    /// Cap dop853's step below its stable step while a contact is closed (default true).
    pub step_cap: bool,
    /// Let method `exact` step over closed contacts' fast modes where certified (default
    /// true; false: its short steps throughout, for comparison).
    pub long_steps: bool,
    /// Which model computes the right-hand side (default `auto`).
    pub model: ModelChoice,
    /// Where generated models come from (default: the committed ones).
    pub models: ModelRegistry,
    /// The error asked for in `tip_rel` inside the predictability horizon (m): `auto` then
    /// picks the method and tolerance that reach it cheapest from the measured table
    /// ([`telescopic_runtime::accuracy`]); `None`: the default accuracy, 1e-6 m, unless a
    /// method or tolerance is given.
    pub accuracy: Option<f64>,
    /// Stations whose bending moment (and stress) become output columns (default none).
    pub stations: Vec<crate::stress::Station>,
    /// Keep the scene's modes and basis under [`SimulationOptions::accuracy`], which then
    /// bounds the integration error only (default false: the accuracy is the whole error
    /// against the beams, and the run picks the modes too).
    pub modes_as_given: bool,
    /// Estimate the run's truncation error from a companion run with more modes (default
    /// true; [`crate::error_budget`]).
    pub error_estimate: bool,
    /// Largest truncation error of a station's moment, relative to its peak, that
    /// [`SimulationOptions::accuracy`] accepts (default 0.02).
    pub moment_tolerance: f64,
    /// Largest relative truncation error of the statistics beyond the pointwise window
    /// (RMS and peak of `tip_rel`, peak moment) that [`SimulationOptions::accuracy`] accepts
    /// (default 0.05).
    pub statistics_tolerance: f64,
}

impl Default for SimulationOptions {
    fn default() -> Self {
        SimulationOptions {
            method: MethodChoice::Auto,
            rtol: None,
            atol: None,
            dt: None,
            step_cap: true,
            long_steps: true,
            model: ModelChoice::Auto,
            models: ModelRegistry::default(),
            accuracy: None,
            stations: Vec::new(),
            modes_as_given: false,
            error_estimate: true,
            moment_tolerance: 0.02,
            statistics_tolerance: 0.05,
        }
    }
}

/// The resolved method and settings of a run.
#[derive(Debug, Clone, PartialEq)]
pub struct Plan {
    /// The method that starts the run.
    pub method: Method,
    /// For `auto`: why this method (`auto: ...; `), else empty.
    pub how: String,
    /// Tolerances, steps and the hand-over to exact stepping.
    pub settings: Settings,
    /// The measured error in `tip_rel` (m) of the run the method was picked from; `None`
    /// when a method was given.
    pub integration_error_m: Option<f64>,
    /// The relative error of the statistics to expect of that run (with clearance, the
    /// spread of correct runs); `None` when a method was given.
    pub integration_statistics_rel: Option<f64>,
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
    // moments at stations need the contact modes resolved
    let resolve = if options.stations.is_empty() {
        Resolve::Displacements
    } else {
        Resolve::Moments
    };
    let (method, how) = match (options.method, options.accuracy) {
        (MethodChoice::Auto, Some(accuracy)) => {
            if options.rtol.is_some() || options.atol.is_some() {
                return Err(Error::option(
                    "SimulationOptions::accuracy",
                    "picks the tolerances itself: give an accuracy or rtol/atol, not both",
                ));
            }
            let chosen = plan_for_accuracy(&scene.params, &scene.time, accuracy, resolve)
                .map_err(|e| Error::option("SimulationOptions::accuracy", e))?;
            settings.exact_from = chosen.exact_from;
            settings.rtol = chosen.rtol;
            settings.atol = 1e-3 * chosen.rtol;
            integration_error_m = Some(chosen.error_m);
            integration_statistics_rel = Some(chosen.statistics_rel);
            (
                chosen.method,
                format!("accuracy {accuracy:e} m: {}; ", chosen.why),
            )
        }
        (MethodChoice::Method(m), Some(_)) => {
            return Err(Error::option(
                "SimulationOptions::accuracy",
                format!("picks the method itself: leave the method at auto (got {m})"),
            ));
        }
        (MethodChoice::Auto, None) => {
            let chosen = plan_for_accuracy(&scene.params, &scene.time, DEFAULT_ACCURACY_M, resolve)
                .expect("every kind of scene has a measured run within the default accuracy");
            settings.exact_from = chosen.exact_from;
            integration_error_m = Some(chosen.error_m);
            integration_statistics_rel = Some(chosen.statistics_rel);
            (chosen.method, format!("auto: {}; ", chosen.why))
        }
        (MethodChoice::Method(m), None) => (m, String::new()),
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
    if !(settings.rtol > 0.0
        && settings.rtol < 1.0
        && settings.atol > 0.0
        && settings.atol.is_finite())
    {
        return Err(Error::option(
            "SimulationOptions::rtol/atol",
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
            "SimulationOptions::dt",
            format!("must be a finite number of seconds > 0 (got {dt})"),
        ));
    }
    let span = scene.time.end - scene.time.start;
    if let Some(dt) = settings.dt
        && dt > span
    {
        return Err(Error::option(
            "SimulationOptions::dt",
            format!("{dt} s is longer than the scene's span ({span} s): a step must fit in it"),
        ));
    }
    if method.step_control() == StepControl::Fixed && settings.dt.is_none() {
        return Err(Error::option(
            "SimulationOptions::dt",
            format!(
                "method {method} takes a fixed step: give SimulationOptions::dt (see the stability analysis)"
            ),
        ));
    }
    Ok(Plan {
        method,
        how,
        settings,
        integration_error_m,
        integration_statistics_rel,
    })
}

/// The samples of one run: output names and rows `[t, outputs...]`.
#[derive(Debug, Clone, PartialEq)]
pub struct Trajectory {
    /// Output names, without `t` (the model documentation's section on outputs).
    pub names: Vec<String>,
    /// Rows `[t, outputs...]` (s, then SI units of each output).
    pub rows: Vec<Vec<f64>>,
    /// What the run did.
    pub stats: RunStats,
}

impl Trajectory {
    /// Index in a row of the output `name` (`t` is index 0).
    pub fn index(&self, name: &str) -> Option<usize> {
        if name == "t" {
            return Some(0);
        }
        self.names.iter().position(|n| n == name).map(|i| i + 1)
    }

    /// The samples of one output (or `t`), in time order.
    pub fn column(&self, name: &str) -> Option<Vec<f64>> {
        let i = self.index(name)?;
        Some(self.rows.iter().map(|r| r[i]).collect())
    }

    /// Writes the CSV: a header `t,<names>` and one row per sample.
    ///
    /// # Errors
    /// The writer's error.
    pub fn write_csv(&self, w: &mut dyn Write) -> std::io::Result<()> {
        writeln!(w, "t,{}", self.names.join(","))?;
        let mut line = String::new();
        for row in &self.rows {
            line.clear();
            for (i, &v) in row.iter().enumerate() {
                if i > 0 {
                    line.push(',');
                }
                line.push_str(&crate::output::csv_number(v));
            }
            line.push('\n');
            w.write_all(line.as_bytes())?;
        }
        Ok(())
    }
}

/// A finished simulation: what ran and every sample.
#[derive(Debug, Clone, PartialEq)]
pub struct Simulation {
    /// The scene's name.
    pub scene: String,
    /// The scene's time span `(start, end)` (s).
    pub span: (f64, f64),
    /// Which model ran it (`generated model <key>` or `quadrature-assembled model`).
    pub model: String,
    /// The method and settings.
    pub plan: Plan,
    /// The specializations that applied, one phrase each.
    pub specializations: Vec<String>,
    /// The samples and the run's statistics.
    pub trajectory: Trajectory,
    /// Modes per section of the model that ran.
    pub modes: Vec<usize>,
    /// Its basis.
    pub basis: telescopic_runtime::Basis,
    /// The run's error in two parts ([`crate::error_budget`]); `None` when not asked for.
    pub error: Option<ErrorBudget>,
}

impl Simulation {
    /// The run summary: scene, model, method (and why, for `auto`), specializations, and
    /// what the run did.
    pub fn summary(&self) -> String {
        let s = &self.trajectory.stats;
        let settings = &self.plan.settings;
        let cap = s.step_cap.map_or(String::new(), |c| {
            format!("; step capped at {c:.3e} s while a contact is closed (its stable step)")
        });
        let long = if s.long_steps > 0 {
            format!(", {} steps over the closed contacts' modes", s.long_steps)
        } else {
            String::new()
        };
        let tol = match self.plan.method.step_control() {
            StepControl::Adaptive if s.exponentials > 0 => format!(
                "rtol {:e}, atol {:e}{cap}; {} matrix exponentials{long}",
                settings.rtol, settings.atol, s.exponentials
            ),
            StepControl::Adaptive => {
                format!("rtol {:e}, atol {:e}{cap}", settings.rtol, settings.atol)
            }
            StepControl::Fixed => format!("dt {:e} s", settings.dt.unwrap_or(f64::NAN)),
            StepControl::Exact => format!("{} matrix exponentials{long}", s.exponentials),
        };
        let special = if self.specializations.is_empty() {
            "none".to_string()
        } else {
            self.specializations.join("; ")
        };
        let stress = match crate::stress::StressEnvelope::of(&self.trajectory) {
            Some(envelope) => format!("\n{}", envelope.describe()),
            None if self
                .trajectory
                .names
                .iter()
                .any(|n| n.starts_with("moment_")) =>
            {
                "\nstresses: none (the scene gives neither sections.section_modulus nor \
                 sections.height)"
                    .to_string()
            }
            None => String::new(),
        };
        format!(
            "{} on the {}: method {} ({}{tol}), t = {} .. {} s, {} samples\n\
             specializations: {special}\n\
             steps {} (rejected {}), rhs evaluations {}, Jacobian evaluations {}, \
             factorizations {}, contact switches {}, wall time {:.3} s",
            self.scene,
            self.model,
            self.plan.method,
            self.plan.how,
            self.span.0,
            self.span.1,
            self.trajectory.rows.len(),
            s.steps,
            s.rejected,
            s.rhs_evals,
            s.jacobian_evals,
            s.factorizations,
            s.switches,
            s.wall.as_secs_f64()
        ) + &stress
            + &self
                .error_lines()
                .map(|l| format!("\n{l}"))
                .collect::<String>()
    }

    /// The error budget's lines, empty when it was not estimated.
    fn error_lines(&self) -> impl Iterator<Item = String> {
        self.error
            .as_ref()
            .map(|e| e.describe(&self.modes))
            .unwrap_or_default()
            .into_iter()
    }

    /// Writes the CSV: the error budget as `#` lines, then the samples
    /// ([`Trajectory::write_csv`]).
    ///
    /// # Errors
    /// The writer's error.
    pub fn write_csv(&self, w: &mut dyn Write) -> std::io::Result<()> {
        for line in self.error_lines() {
            writeln!(w, "# {line}")?;
        }
        self.trajectory.write_csv(w)
    }
}

/// Simulates `scene` with `options`: chooses the model and the method, checks that the run
/// fits the resource limits and is affordable, integrates from rest, collects every sample,
/// and estimates the run's error ([`crate::error_budget`]). With
/// [`SimulationOptions::accuracy`] (and not [`SimulationOptions::modes_as_given`]) it also
/// picks the basis and the modes per section ([`crate::total_accuracy`]).
///
/// # Errors
/// [`Error`] for bad options, a model that cannot be had, an unaffordable run (with the
/// estimate), or a failed integration (time, method, likely cause).
pub fn simulate_scene(
    scene: &Scene,
    options: &SimulationOptions,
    reporter: &dyn Reporter,
) -> Result<Simulation> {
    if options.accuracy.is_some() && !options.modes_as_given {
        return crate::total_accuracy::simulate_for_accuracy(scene, options, reporter);
    }
    // with the companion run, the run is the first part of the progress
    let main_share = if options.error_estimate {
        COMPANION_SPLIT
    } else {
        1.0
    };
    let main = Phase {
        inner: reporter,
        share: (0.0, main_share),
    };
    let run = PreparedRun::new(scene, options, &main)?;
    let trajectory = run.integrate(&main)?;
    let mut simulation = run.into_simulation(trajectory);
    if options.error_estimate {
        let companion = Phase {
            inner: reporter,
            share: (main_share, 1.0),
        };
        simulation.error = Some(estimate_error(scene, options, &simulation, &companion)?);
    }
    Ok(simulation)
}

/// The share of a run's progress before its companion run starts (the companion, with more
/// modes, takes one to three times as long on the shipped scenes).
const COMPANION_SPLIT: f64 = 0.4;

/// The error budget of `simulation`, a run of `scene` with `options`: its integration part
/// from the plan, its truncation part from a companion run of the refined model.
///
/// # Errors
/// A failed companion run (an unaffordable one is reported as missing instead).
pub fn estimate_error(
    scene: &Scene,
    options: &SimulationOptions,
    simulation: &Simulation,
    reporter: &dyn Reporter,
) -> Result<ErrorBudget> {
    let window = error_budget::window(&scene.params, &simulation.trajectory);
    let mut budget = ErrorBudget {
        window,
        integration_m: simulation.plan.integration_error_m,
        integration_statistics: simulation.plan.integration_statistics_rel,
        truncation: None,
        missing: None,
    };
    let Some(refined) = error_budget::refined(&scene.params) else {
        budget.missing = Some(format!(
            "every section has {} modes, the most there are",
            telescopic_runtime::MAX_MODES
        ));
        return Ok(budget);
    };
    let mut companion_scene = scene.clone();
    companion_scene.params = refined;
    let companion_options = SimulationOptions {
        error_estimate: false,
        // a generated model of the refined size may not exist: the registry falls back
        model: match options.model {
            ModelChoice::Generated => ModelChoice::Auto,
            other => other,
        },
        ..options.clone()
    };
    let prepared = PreparedRun::new(&companion_scene, &companion_options, &crate::Silent)?;
    match prepared.integrate(reporter) {
        Ok(companion) => {
            budget.truncation = Some(error_budget::truncation(
                &simulation.trajectory,
                &companion,
                companion_scene.params.modes(),
                window,
            ));
        }
        Err(Error::Unaffordable { reason, .. }) => {
            budget.missing = Some(format!("the refined model's run is unaffordable: {reason}"));
        }
        Err(e) => return Err(e),
    }
    Ok(budget)
}

/// Writes the CSV of `simulation` to `path` (atomically) or to standard output.
///
/// # Errors
/// [`Error::Write`] or [`Error::Stdout`].
pub fn write_csv(simulation: &Simulation, path: Option<&Path>) -> Result<()> {
    crate::output::write_to(path, |w| simulation.write_csv(w))
}
