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

use crate::model_choice::{ModelChoice, build_model};
use crate::report::Reporter;
use crate::{Error, Result};
use std::fmt;
use std::io::Write;
use std::path::Path;
use std::str::FromStr;
use telescopic_runtime::integrate::StepControl;
use telescopic_runtime::{
    Method, Model, RunStats, Scene, Settings, auto_plan, model::rest_state, simulate,
    specializations,
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
    /// Which model computes the right-hand side (default `auto`).
    pub model: ModelChoice,
}

impl Default for SimulationOptions {
    fn default() -> Self {
        SimulationOptions {
            method: MethodChoice::Auto,
            rtol: None,
            atol: None,
            dt: None,
            step_cap: true,
            model: ModelChoice::Auto,
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
}

/// Resolves `options` on `scene`: `auto` becomes a method, tolerances are checked.
///
/// # Errors
/// [`Error::Option`] for an unknown method or tolerances outside their range (checked for
/// every method, even those that do not use them).
pub fn plan(scene: &Scene, options: &SimulationOptions) -> Result<Plan> {
    let mut settings = Settings::default();
    let (method, how) = match options.method {
        MethodChoice::Auto => {
            let (m, exact_from, why) = auto_plan(&scene.params, &scene.time);
            settings.exact_from = exact_from;
            (m, format!("auto: {why}; "))
        }
        MethodChoice::Method(m) => (m, String::new()),
    };
    if let Some(r) = options.rtol {
        settings.rtol = r;
    }
    if let Some(a) = options.atol {
        settings.atol = a;
    }
    settings.dt = options.dt;
    settings.step_cap = options.step_cap;
    if !(settings.rtol > 0.0 && settings.rtol < 1.0 && settings.atol > 0.0)
        || !settings.atol.is_finite()
    {
        return Err(Error::option(
            "--rtol/--atol",
            format!(
                "tolerances must be positive with rtol < 1 (got --rtol {}, --atol {})",
                settings.rtol, settings.atol
            ),
        ));
    }
    if let Some(dt) = settings.dt
        && !(dt > 0.0 && dt.is_finite())
    {
        return Err(Error::option(
            "--dt",
            format!("must be a finite number of seconds > 0 (got {dt})"),
        ));
    }
    if method.step_control() == StepControl::Fixed && settings.dt.is_none() {
        return Err(Error::option(
            "--dt",
            format!("method {method} takes a fixed step: give --dt (see `telescopic stability`)"),
        ));
    }
    Ok(Plan {
        method,
        how,
        settings,
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

/// Largest magnitude and root mean square of `values` (both 0 for none).
pub fn peak_and_rms(values: &[f64]) -> (f64, f64) {
    if values.is_empty() {
        return (0.0, 0.0);
    }
    let peak = values.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let rms = (values.iter().map(|v| v * v).sum::<f64>() / values.len() as f64).sqrt();
    (peak, rms)
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
        let tol = match self.plan.method.step_control() {
            StepControl::Adaptive if s.exponentials > 0 => format!(
                "rtol {:e}, atol {:e}{cap}; {} matrix exponentials",
                settings.rtol, settings.atol, s.exponentials
            ),
            StepControl::Adaptive => {
                format!("rtol {:e}, atol {:e}{cap}", settings.rtol, settings.atol)
            }
            StepControl::Fixed => format!("dt {:e} s", settings.dt.unwrap_or(f64::NAN)),
            StepControl::Exact => format!("{} matrix exponentials", s.exponentials),
        };
        let special = if self.specializations.is_empty() {
            "none".to_string()
        } else {
            self.specializations.join("; ")
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
        )
    }
}

/// Simulates `scene` with `options`: chooses the model and the method, checks that the run
/// fits the resource limits and is affordable, integrates from rest, collects every sample.
///
/// # Errors
/// [`Error`] for bad options, a model that cannot be had, an unaffordable run (with the
/// estimate), or a failed integration (time, method, likely cause).
pub fn simulate_scene(
    scene: &Scene,
    options: &SimulationOptions,
    reporter: &dyn Reporter,
) -> Result<Simulation> {
    let plan = plan(scene, options)?;
    let chosen = build_model(&scene.params, options.model)?;
    if let Some(note) = &chosen.note {
        reporter.note(note);
    }
    let model = chosen.model.as_ref();
    crate::budget::check_run(scene, model, plan.method, &plan.settings)?;
    let trajectory = run_trajectory(scene, model, plan.method, &plan.settings, reporter)?;
    Ok(Simulation {
        scene: scene.name.clone(),
        span: (scene.time.start, scene.time.end),
        model: chosen.description,
        specializations: specializations(model, &scene.time, plan.method, plan.settings.exact_from),
        plan,
        trajectory,
    })
}

/// Integrates `scene` on `model` from rest with `method` and `settings`, collecting every
/// output sample. The building block of [`simulate_scene`] and the multi-run analyses; it
/// does not check the work budget.
///
/// # Errors
/// [`Error::Simulation`] for a failed run, [`Error::NonFiniteOutput`] for an output that is
/// not finite.
pub fn run_trajectory(
    scene: &Scene,
    model: &dyn Model,
    method: Method,
    settings: &Settings,
    reporter: &dyn Reporter,
) -> Result<Trajectory> {
    let names = model.output_names();
    let mut rows: Vec<Vec<f64>> = Vec::with_capacity(crate::budget::sample_count(&scene.time));
    let mut out = vec![0.0; names.len()];
    let mut bad_output: Option<(f64, String)> = None;
    let mut observe = |t: f64, y: &[f64], ydot: &[f64]| {
        model.outputs(t, y, ydot, &mut out);
        if bad_output.is_none()
            && let Some(i) = out.iter().position(|v| !v.is_finite())
        {
            bad_output = Some((t, names[i].clone()));
        }
        let mut row = Vec::with_capacity(out.len() + 1);
        row.push(t);
        row.extend_from_slice(&out);
        rows.push(row);
    };
    let span = scene.time;
    let mut tick = |t: f64| reporter.progress((t - span.start) / (span.end - span.start));
    reporter.start(&format!("simulating {}", scene.name));
    let y0 = rest_state(model, span.start);
    let result = simulate(
        model,
        &y0,
        &span,
        method,
        settings,
        &mut observe,
        Some(&mut tick),
    );
    reporter.finish();
    let stats = result.map_err(|error| Error::Simulation {
        scene: scene.name.clone(),
        error,
    })?;
    if let Some((t, name)) = bad_output {
        return Err(Error::NonFiniteOutput {
            name,
            t,
            method: method.name(),
        });
    }
    Ok(Trajectory { names, rows, stats })
}

/// Writes the CSV of `trajectory` to `path` (atomically) or to standard output.
///
/// # Errors
/// [`Error::Write`] or [`Error::Stdout`].
pub fn write_csv(trajectory: &Trajectory, path: Option<&Path>) -> Result<()> {
    crate::output::write_to(path, |w| trajectory.write_csv(w))
}
