//! `telescopic work-precision`: speed against accuracy for every method on one scene.
//!
//! A reference from two independent tight runs (dop853 at rtol 1e-12, dopri5 at 1e-10);
//! where they agree to 1e-9 m in `tip_rel` is the scene's predictability horizon `T_h`.
//! Each method then runs a sweep of tolerances (steps for fixed-step methods). Errors are
//! measured pointwise on `[0, T_h]` (`tip_rel` and the first contact gap) and, over the whole
//! span, on statistics that converge even where the motion does not: per-second peak and RMS
//! of `tip_rel`, and the number of contact switches. Wall time is the median of repeated runs.

use crate::OptionName;
use crate::report::Reporter;
use crate::run::PreparedRun;
use crate::run::Trajectory;
use crate::run::models::{ModelChoice, ModelRegistry};
use crate::{Error, Result};
use std::io::Write;
use telescopic_runtime::Output;
use telescopic_runtime::integrate::stability::stability_report;
use telescopic_runtime::{Method, Model, Scene, Settings, auto_plan, setting_label};

/// The methods compared by default: every method, and `auto` (simulate's default).
pub const DEFAULT_METHODS: &str =
    "exact,auto,dopri5,dop853,dop853-imex,esdirk,imex,bdf,galpha,rk4,verlet";

/// Most timed repetitions per setting.
pub const MAX_REPEAT: usize = 100;

/// Options of [`work_precision`].
#[derive(Debug, Clone, PartialEq)]
pub struct WorkPrecisionOptions {
    /// Methods to compare by name (`auto` is simulate's default; `exact` is skipped, with a
    /// note, on a scene that is not linear and time-invariant between contact switches).
    pub methods: Vec<String>,
    /// Timed repetitions per setting (the median is reported), 1 to [`MAX_REPEAT`].
    pub repeat: usize,
    /// Relative tolerances of the adaptive methods' sweep (`atol = 1e-3 rtol`), each in
    /// `(0, 0.1]` and at least 1e-13; default 1e-3 to 1e-8 by decades.
    pub rtols: Vec<f64>,
    /// Which model computes the right-hand side.
    pub model: ModelChoice,
    /// Where generated models come from (default: the committed ones).
    pub models: ModelRegistry,
    /// The memory a run's outputs may take (bytes,
    /// [`crate::run::memory::DEFAULT_MEMORY_BUDGET`] by default): a longer run is refused
    /// before it starts.
    pub memory_budget: u64,
}

impl Default for WorkPrecisionOptions {
    fn default() -> Self {
        WorkPrecisionOptions {
            methods: DEFAULT_METHODS.split(',').map(String::from).collect(),
            repeat: 3,
            rtols: TOLERANCES.to_vec(),
            model: ModelChoice::Auto,
            models: ModelRegistry::default(),
            memory_budget: crate::run::memory::DEFAULT_MEMORY_BUDGET,
        }
    }
}

/// The result of [`work_precision`]: the reference's horizon and floor, and one point per
/// run of the sweep.
#[derive(Debug, Clone, PartialEq)]
pub struct WorkPrecision {
    /// The scene's name.
    pub scene: String,
    /// Predictability horizon `T_h` (s): where the two references part by 1e-9 m.
    pub horizon: f64,
    /// End of the scene's span (s).
    pub end: f64,
    /// The statistics floor: how much the two references differ in per-second peak/RMS of
    /// `tip_rel` and in the switch count (relative).
    pub floor: (f64, f64),
    /// One point per run.
    pub points: Vec<Point>,
}

/// Agreement of the two reference runs that defines the predictability horizon (m).
pub const HORIZON_AGREEMENT: f64 = 1e-9;
/// The two reference runs: method and relative tolerance (`atol = 1e-3 rtol`). The first is
/// the reference every run is measured against; where the two part defines the horizon.
pub const REFERENCE_RUNS: [(Method, f64); 2] = [(Method::Dop853, 1e-12), (Method::Dopri5, 1e-10)];
/// Agreement with the reference that ends a run's own horizon (m).
const RUN_AGREEMENT: f64 = 1e-6;
/// Relative tolerances of the adaptive sweep by default (`atol = 1e-3 rtol`).
const TOLERANCES: [f64; 6] = [1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8];
/// The longest step (s) of imex's second sweep, whose steps cross output samples
/// (`Settings::longest_step`): eight samples of the shipped scenes' 1 ms.
const CROSSING_STEP: f64 = 8e-3;
/// Fixed steps as fractions of the method's stability limit (rk4, verlet).
const EXPLICIT_FRACTIONS: [f64; 5] = [0.9, 0.5, 0.25, 0.125, 0.0625];
/// Fixed steps of the implicit fixed-step methods (s).
const IMPLICIT_STEPS: [f64; 5] = [1e-3, 3e-4, 1e-4, 3e-5, 1e-5];

/// One run of the sweep.
#[derive(Debug, Clone, PartialEq)]
pub struct Point {
    /// Method label (`auto` or a method name).
    pub method: String,
    /// `rtol=...` or `dt=...`.
    pub setting: String,
    /// Accepted steps.
    pub steps: u64,
    /// Right-hand side evaluations.
    pub rhs_evals: u64,
    /// Median wall time (s).
    pub wall: f64,
    /// Largest `|tip_rel - reference|` on `[0, T_h]` (m).
    pub tip_error: f64,
    /// Largest gap error on `[0, T_h]` (m).
    pub gap_error: f64,
    /// Largest relative error of the per-second peak and RMS of `tip_rel`.
    pub statistics_error: f64,
    /// Contact switches.
    pub switches: u64,
    /// Relative error of the switch count.
    pub switch_error: f64,
    /// Time the run stays within 1e-6 m of the reference (s).
    pub agrees_until: f64,
    /// Empty when the run finished, else the error.
    pub failure: String,
}

/// Peak and RMS of output `col` per whole second.
fn per_second(traj: &Trajectory, col: usize) -> Vec<(f64, f64)> {
    let mut out: Vec<(f64, f64, usize)> = Vec::new();
    let t0 = traj.rows[0][0];
    for r in &traj.rows {
        let k = (r[0] - t0).floor() as usize;
        while out.len() <= k {
            out.push((0.0, 0.0, 0));
        }
        let e = &mut out[k];
        e.0 = e.0.max(r[col].abs());
        e.1 += r[col] * r[col];
        e.2 += 1;
    }
    out.into_iter()
        .filter(|e| e.2 > 1)
        .map(|(p, s, n)| (p, (s / n as f64).sqrt()))
        .collect()
}

/// The predictability horizon `T_h` (s) of two reference runs: the first sample where their
/// `tip_rel` differ by more than [`HORIZON_AGREEMENT`], or their last sample.
pub fn predictability_horizon(a: &Trajectory, b: &Trajectory) -> f64 {
    let tip = a.index_of(Output::TipRel).expect("every model has tip_rel");
    let end = a.rows.last().map_or(0.0, |r| r[0]);
    a.rows
        .iter()
        .zip(&b.rows)
        .find(|(x, y)| (x[tip] - y[tip]).abs() > HORIZON_AGREEMENT)
        .map_or(end, |(x, _)| x[0])
}

/// The largest relative difference of the per-second peak and RMS of `tip_rel` between `run`
/// and `reference` (the `statistics_error_rel` of the work-precision table).
pub fn statistics_error(run: &Trajectory, reference: &Trajectory) -> f64 {
    let tip = reference
        .index_of(Output::TipRel)
        .expect("every model has tip_rel");
    per_second(run, tip)
        .iter()
        .zip(per_second(reference, tip))
        .map(|(a, b)| ((a.0 - b.0).abs() / b.0.max(1e-12)).max((a.1 - b.1).abs() / b.1.max(1e-12)))
        .fold(0.0, f64::max)
}

/// The largest `|tip_rel|` difference (m) of `run` from `reference` up to `horizon` (s): the
/// `tip_error_horizon_m` of the work-precision table.
pub fn tip_error_in_horizon(run: &Trajectory, reference: &Trajectory, horizon: f64) -> f64 {
    let tip = reference
        .index_of(Output::TipRel)
        .expect("every model has tip_rel");
    run.rows
        .iter()
        .zip(&reference.rows)
        .take_while(|(_, b)| b[0] <= horizon)
        .map(|(a, b)| (a[tip] - b[tip]).abs())
        .fold(0.0, f64::max)
}

/// How far a run is from the reference.
#[derive(Debug, Clone, Copy, PartialEq)]
struct RunErrors {
    /// Largest `tip_rel` difference inside the horizon (m).
    tip: f64,
    /// Largest difference of the first gap inside the horizon (m).
    gap: f64,
    /// Relative error of the per-second peak and RMS of `tip_rel` over the span.
    statistics: f64,
    /// Relative error of the switch count.
    switches: f64,
    /// Until when the run stays within [`RUN_AGREEMENT`] of the reference (s).
    agrees_until: f64,
}

/// Compares a run with the reference.
fn measure(run: &Trajectory, reference: &Trajectory, horizon: f64) -> RunErrors {
    let tip = reference
        .index_of(Output::TipRel)
        .expect("every model has tip_rel");
    let gap = reference.gap_columns().first().copied();
    let tip_error = tip_error_in_horizon(run, reference, horizon);
    let mut gap_error = 0.0f64;
    let mut agrees_until = f64::NAN;
    for (a, b) in run.rows.iter().zip(&reference.rows) {
        if agrees_until.is_nan() && (a[tip] - b[tip]).abs() > RUN_AGREEMENT {
            agrees_until = a[0];
        }
        if let Some(g) = gap
            && a[0] <= horizon
        {
            gap_error = gap_error.max((a[g] - b[g]).abs());
        }
    }
    if agrees_until.is_nan() {
        agrees_until = reference.rows.last().map_or(0.0, |r| r[0]);
    }
    let stats = statistics_error(run, reference);
    let switch_error = if reference.stats.switches == 0 {
        0.0
    } else {
        (run.stats.switches as f64 - reference.stats.switches as f64).abs()
            / reference.stats.switches as f64
    };
    RunErrors {
        tip: tip_error,
        gap: gap_error,
        statistics: stats,
        switches: switch_error,
        agrees_until,
    }
}

/// Adaptive settings at `rtol` with `atol = 1e-3 rtol` (m, m/s).
fn tolerance(rtol: f64) -> Settings {
    Settings {
        rtol,
        atol: 1e-3 * rtol,
        ..Settings::default()
    }
}

/// The settings swept for `method` on `model`, adaptive ones at `rtols`.
fn sweep(
    method: Method,
    model: &dyn Model,
    scene: &Scene,
    rtols: &[f64],
) -> Result<Vec<(String, Settings)>> {
    let fixed = |dt: f64| Settings {
        dt: Some(dt),
        ..Settings::default()
    };
    Ok(match method {
        // exact up to rounding: nothing to sweep but its long steps over closed contacts'
        // modes, beside its short steps throughout where there are contacts to close
        Method::Exact if scene.params.contact.clearance > 0.0 => vec![
            ("exact".to_string(), Settings::default()),
            (
                "short-steps".to_string(),
                Settings {
                    long_steps: false,
                    ..Settings::default()
                },
            ),
        ],
        Method::Exact => vec![("exact".to_string(), Settings::default())],
        Method::Rk4 | Method::Verlet => {
            let r = stability_report(model, scene.time.start)
                .map_err(|e| Error::Analysis(format!("scene {}: {e}", scene.name)))?;
            let limit = if method == Method::Rk4 {
                r.rk4_step
            } else {
                r.verlet_step
            };
            EXPLICIT_FRACTIONS
                .iter()
                .map(|f| (format!("dt={:.3e}", f * limit), fixed(f * limit)))
                .collect()
        }
        m if m.step_control() == telescopic_runtime::integrate::StepControl::Fixed => {
            IMPLICIT_STEPS
                .iter()
                .map(|&dt| (format!("dt={dt:.0e}"), fixed(dt)))
                .collect()
        }
        // imex also across samples, where its longest step is longer than one
        Method::Imex if CROSSING_STEP > scene.time.sample => {
            let across = |r: f64| Settings {
                longest_step: Some(CROSSING_STEP),
                ..tolerance(r)
            };
            rtols
                .iter()
                .map(|&r| (setting_label(r, None), tolerance(r)))
                .chain(
                    rtols
                        .iter()
                        .map(|&r| (setting_label(r, Some(CROSSING_STEP)), across(r))),
                )
                .collect()
        }
        _ => rtols
            .iter()
            .map(|&r| (setting_label(r, None), tolerance(r)))
            .collect(),
    })
}

/// Speed against accuracy for every method on `scene`: the reference, its horizon and
/// floor, then each method's sweep. Progress lines go to `reporter`.
///
/// # Errors
/// [`Error::Option`] for an unknown method or a repeat count out of range; a failed
/// reference run. A failed run of the sweep is a point with its error, not an error.
pub fn work_precision(
    scene: &Scene,
    options: &WorkPrecisionOptions,
    reporter: &dyn Reporter,
) -> Result<WorkPrecision> {
    check_options(options)?;
    let methods = labelled_methods(scene, &options.methods)?;
    let chosen = options.models.build(&scene.params, options.model)?;
    if let Some(note) = &chosen.note {
        reporter.note(note);
    }
    let [(first, first_rtol), (second, second_rtol)] = REFERENCE_RUNS;
    reporter.note(&format!(
        "{} on the {}: reference runs ({} rtol {first_rtol:e}, {} rtol {second_rtol:e})",
        scene.name,
        chosen.description,
        first.name(),
        second.name()
    ));
    // every run, the references included, on one prepared run (within the work budget)
    let mut prepared = PreparedRun::with_model(
        scene,
        chosen,
        (Method::Dop853, Settings::default()),
        options.memory_budget,
    );
    let reference = run_with(&mut prepared, first, &tolerance(first_rtol), reporter)?;
    let second = run_with(&mut prepared, second, &tolerance(second_rtol), reporter)?;
    let end = scene.time.end;
    let horizon = predictability_horizon(&reference, &second);
    reporter.note(&format!(
        "predictability horizon T_h = {horizon:.4} s (the two references agree in tip_rel to \
         {HORIZON_AGREEMENT:e} m up to there; span {end} s)"
    ));
    // the statistics of two careful runs differ after T_h: no method can be judged closer
    let floor = measure(&second, &reference, horizon);
    reporter.note(&format!(
        "statistics floor: the two references differ by {:.2} % in per-second peak/RMS of \
         tip_rel and {:.2} % in contact switches",
        100.0 * floor.statistics,
        100.0 * floor.switches
    ));
    let mut points = Vec::new();
    let exact_listed = methods.iter().any(|(l, _, _)| l == "exact");
    for (label, method, exact_from) in &methods {
        let (method, exact_from) = (*method, *exact_from);
        if label == "auto" && method == Method::Exact && exact_from.is_none() && exact_listed {
            reporter.note("auto: the same runs as exact on this scene");
            continue;
        }
        if method == Method::Exact
            && let Some(why) = telescopic_runtime::integrate::exact::lti_obstacle(&scene.params)
        {
            reporter.note(&format!("exact: skipped ({why})"));
            continue;
        }
        for (setting, mut settings) in sweep(method, prepared.model(), scene, &options.rtols)? {
            // `auto` is simulate's default, whose steps end on every sample
            if label == "auto" && settings.longest_step.is_some() {
                continue;
            }
            settings.exact_from = exact_from;
            let outcome = timed_runs(&mut prepared, method, &settings, options.repeat, reporter);
            let point = point_of(label, setting, outcome, &reference, horizon);
            reporter.note(&describe(&point));
            points.push(point);
        }
    }
    Ok(WorkPrecision {
        scene: scene.name.clone(),
        horizon,
        end,
        floor: (floor.statistics, floor.switches),
        points,
    })
}

/// Refuses a repeat count or tolerances out of range.
fn check_options(options: &WorkPrecisionOptions) -> Result<()> {
    if !(1..=MAX_REPEAT).contains(&options.repeat) {
        return Err(Error::option(
            OptionName::Repeat,
            format!(
                "must be 1 to {MAX_REPEAT} (got {}); the median of a few timed runs is \
                 already stable",
                options.repeat
            ),
        ));
    }
    check_rtols(&options.rtols)?;
    check_distinct(OptionName::Methods, "method", &options.methods)
}

/// Most entries of a list option (`--modes`, `--rtols`, `--methods`): each entry is a run
/// or a sweep of runs.
pub const MAX_LIST: usize = 32;

/// Refuses relative tolerances out of range, none, more than [`MAX_LIST`] or one given twice.
///
/// # Errors
/// [`Error::Option`] naming the tolerances and the rule.
pub(crate) fn check_rtols(rtols: &[f64]) -> Result<()> {
    if let Some(r) = rtols
        .iter()
        .find(|r| !(r.is_finite() && (1e-13..=0.1).contains(*r)))
    {
        return Err(Error::option(
            OptionName::Rtols,
            format!("each relative tolerance must be 1e-13 to 0.1 (got {r})"),
        ));
    }
    if rtols.is_empty() {
        return Err(Error::option(
            OptionName::Rtols,
            "give at least one tolerance",
        ));
    }
    check_distinct(OptionName::Rtols, "tolerance", rtols)
}

/// Refuses a list with more than [`MAX_LIST`] entries or an entry given twice (it would run
/// again).
///
/// # Errors
/// [`Error::Option`] naming the list and the rule.
pub(crate) fn check_distinct<T: PartialEq + std::fmt::Debug>(
    option: OptionName,
    what: &str,
    list: &[T],
) -> Result<()> {
    if list.len() > MAX_LIST {
        return Err(Error::option(
            option,
            format!("{} entries, at most {MAX_LIST}", list.len()),
        ));
    }
    for (i, entry) in list.iter().enumerate() {
        if list[..i].contains(entry) {
            return Err(Error::option(
                option,
                format!("the {what} {entry:?} is given twice"),
            ));
        }
    }
    Ok(())
}

/// The methods by name, each as `(label, method, exact stepping from)`: `auto` is what
/// `simulate` runs by default on `scene`.
fn labelled_methods(scene: &Scene, names: &[String]) -> Result<Vec<(String, Method, Option<f64>)>> {
    names
        .iter()
        .map(|m| match m.trim() {
            "auto" => {
                let (method, exact_from, _) = auto_plan(&scene.params, &scene.time);
                Ok(("auto".to_string(), method, exact_from))
            }
            name => Method::from_name(name)
                .map(|method| (method.name(), method, None))
                .map_err(|e| Error::option(OptionName::Methods, e)),
        })
        .collect()
}

/// One run of `prepared` with `method` and `settings`.
fn run_with(
    prepared: &mut PreparedRun,
    method: Method,
    settings: &Settings,
    reporter: &dyn Reporter,
) -> Result<Trajectory> {
    prepared.plan.method = method;
    prepared.plan.settings = *settings;
    prepared.integrate(reporter)
}

/// `repeat` runs (fewer when one fails): the last outcome and the median wall time (s).
fn timed_runs(
    prepared: &mut PreparedRun,
    method: Method,
    settings: &Settings,
    repeat: usize,
    reporter: &dyn Reporter,
) -> Result<(Trajectory, f64)> {
    let mut walls = Vec::new();
    let mut last = None;
    for _ in 0..repeat {
        let traj = run_with(prepared, method, settings, reporter)?;
        walls.push(traj.stats.wall.as_secs_f64());
        last = Some(traj);
    }
    walls.sort_by(f64::total_cmp);
    Ok((last.expect("repeat >= 1"), walls[walls.len() / 2]))
}

/// The chart's point of a run (or of its failure) against the reference.
fn point_of(
    label: &str,
    setting: String,
    outcome: Result<(Trajectory, f64)>,
    reference: &Trajectory,
    horizon: f64,
) -> Point {
    match outcome {
        Ok((traj, wall)) => {
            let errors = measure(&traj, reference, horizon);
            Point {
                method: label.to_string(),
                setting,
                steps: traj.stats.steps,
                rhs_evals: traj.stats.rhs_evals,
                wall,
                tip_error: errors.tip,
                gap_error: errors.gap,
                statistics_error: errors.statistics,
                switches: traj.stats.switches,
                switch_error: errors.switches,
                agrees_until: errors.agrees_until,
                failure: String::new(),
            }
        }
        Err(e) => Point {
            method: label.to_string(),
            setting,
            steps: 0,
            rhs_evals: 0,
            wall: f64::NAN,
            tip_error: f64::NAN,
            gap_error: f64::NAN,
            statistics_error: f64::NAN,
            switches: 0,
            switch_error: f64::NAN,
            agrees_until: f64::NAN,
            failure: format!("{e:#}").replace([',', '\n'], ";"),
        },
    }
}

impl WorkPrecision {
    /// The CSV table: one row per run.
    ///
    /// # Errors
    /// The writer's error.
    pub fn write_table(&self, w: &mut dyn Write) -> std::io::Result<()> {
        write_table(w, &self.points)
    }
}

fn describe(p: &Point) -> String {
    if !p.failure.is_empty() {
        return format!("{:>8} {:<14} failed: {}", p.method, p.setting, p.failure);
    }
    format!(
        "{:>8} {:<14} wall {:.4} s, rhs {:>9}, tip error on [0,T_h] {:.2e} m, gap {:.2e} m, statistics {:.2e}, switches {} ({:.1} %), within 1e-6 m until {:.3} s",
        p.method,
        p.setting,
        p.wall,
        p.rhs_evals,
        p.tip_error,
        p.gap_error,
        p.statistics_error,
        p.switches,
        100.0 * p.switch_error,
        p.agrees_until
    )
}

fn write_table(w: &mut dyn Write, points: &[Point]) -> std::io::Result<()> {
    writeln!(
        w,
        "method,setting,steps,rhs_evals,wall_s,tip_error_horizon_m,gap_error_horizon_m,statistics_error_rel,switches,switch_error_rel,agrees_until_s,failure"
    )?;
    for p in points {
        let num = |v: f64| {
            if v.is_finite() {
                format!("{v:e}")
            } else {
                String::new()
            }
        };
        writeln!(
            w,
            "{},{},{},{},{},{},{},{},{},{},{},{}",
            p.method,
            p.setting,
            p.steps,
            p.rhs_evals,
            num(p.wall),
            num(p.tip_error),
            num(p.gap_error),
            num(p.statistics_error),
            p.switches,
            num(p.switch_error),
            num(p.agrees_until),
            p.failure
        )?;
    }
    Ok(())
}
