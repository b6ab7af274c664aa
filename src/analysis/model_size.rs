//! `telescopic work-precision --modes`: the model-size axis. Every model size (basis and modes
//! per section) runs with every method and tolerance, and each run's error is measured
//! against the beams ([`crate::analysis::beam_reference`]), not against a tighter run of the same
//! model: so the table and chart show the whole error (truncation and integration) against
//! its cost, one curve per size, with the Pareto front marked.
//!
//! The error of a run is its largest `|tip_rel|` difference from the beams inside the beams'
//! window ([`crate::run::error_budget::window`]: the whole span without clearance, up to the first
//! contact switch with it) and, with clearance, the larger relative difference of the RMS and
//! peak of `tip_rel` beyond it.

use crate::OptionName;
use crate::analysis::beam_reference::{BeamResponse, beam_response};
use crate::analysis::work_precision::{check_distinct, check_rtols};
use crate::report::Reporter;
use crate::run::PreparedRun;
use crate::run::error_budget::{Window, WindowEnd, window};
use crate::run::{MethodChoice, SimulationOptions, Trajectory};
use crate::{Error, Result};
use std::io::Write;
use telescopic_runtime::Output;
use telescopic_runtime::{Method, Scene};

pub use crate::run::sized::ModelSize;

/// Options of [`model_size_study`].
#[derive(Debug, Clone, PartialEq)]
pub struct ModelSizeOptions {
    /// The sizes to compare.
    pub sizes: Vec<ModelSize>,
    /// Methods (`auto` is simulate's default); each adaptive one runs at every tolerance.
    pub methods: Vec<MethodChoice>,
    /// Relative tolerances (`atol = 1e-3 rtol`) of the adaptive methods.
    pub rtols: Vec<f64>,
    /// Timed repetitions per run (the median is reported).
    pub repeat: usize,
    /// The memory a run's outputs may take (bytes,
    /// [`crate::run::memory::DEFAULT_MEMORY_BUDGET`] by default): a longer run is refused
    /// before it starts.
    pub memory_budget: u64,
}

impl Default for ModelSizeOptions {
    fn default() -> Self {
        ModelSizeOptions {
            sizes: ["4", "6", "8", "static:2", "static:3", "static:4"]
                .iter()
                .map(|s| s.parse().expect("valid sizes"))
                .collect(),
            methods: vec![MethodChoice::Auto],
            rtols: vec![1e-4, 1e-5, 1e-6, 1e-7],
            repeat: 3,
            memory_budget: crate::run::memory::DEFAULT_MEMORY_BUDGET,
        }
    }
}

/// One run of the study.
#[derive(Debug, Clone, PartialEq)]
pub struct SizePoint {
    /// The model size.
    pub size: ModelSize,
    /// The method's name (`auto` resolved).
    pub method: String,
    /// `rtol=...`, or `exact`.
    pub setting: String,
    /// Median wall time (s): reported, never ranked on (it changes with the machine's load).
    pub wall: f64,
    /// Accepted steps of the run.
    pub steps: u64,
    /// The run's counted work ([`telescopic_runtime::RunStats::operations`]): the cost that
    /// the front and the cheapest choices rank by.
    pub operations: f64,
    /// Largest `|tip_rel|` difference from the beams inside the window (m).
    pub tip_error: f64,
    /// With clearance, the larger relative difference of the RMS and peak of `tip_rel`
    /// beyond the window; 0 without.
    pub statistics_error: f64,
    /// Not beaten in both counted work and `tip_error` by another point (with statistics within
    /// 5 % where there are any).
    pub pareto: bool,
}

/// The result of [`model_size_study`].
#[derive(Debug, Clone, PartialEq)]
pub struct ModelSizeStudy {
    /// The scene's name.
    pub scene: String,
    /// The beams' window.
    pub window: Window,
    /// What the errors are measured against.
    pub reference: String,
    /// One point per run.
    pub points: Vec<SizePoint>,
}

/// Relative statistics error a point may carry and still count (for the front and the
/// cheapest choices).
pub const STATISTICS_LIMIT: f64 = 0.05;

/// Every size with every method and tolerance against the beams (see the module docs).
///
/// # Errors
/// [`Error::Option`] for no sizes, no methods or a repeat count out of range; any error of
/// the beam reference.
pub fn model_size_study(
    scene: &Scene,
    options: &ModelSizeOptions,
    reporter: &dyn Reporter,
) -> Result<ModelSizeStudy> {
    if options.sizes.is_empty() || options.methods.is_empty() {
        return Err(Error::option(
            OptionName::Sizes,
            "give at least one model size and one method",
        ));
    }
    if !(1..=crate::analysis::work_precision::MAX_REPEAT).contains(&options.repeat) {
        return Err(Error::option(
            OptionName::Repeat,
            format!(
                "must be 1 to {} (got {})",
                crate::analysis::work_precision::MAX_REPEAT,
                options.repeat
            ),
        ));
    }
    check_distinct(OptionName::Sizes, "model size", &options.sizes)?;
    check_distinct(OptionName::Methods, "method", &options.methods)?;
    check_rtols(&options.rtols)?;
    let beams = beam_response(scene, &[], reporter)?;
    let window = window(&scene.params, &beams.trajectory);
    reporter.note(&format!(
        "errors against {}, pointwise up to t = {} s",
        beams.reference, window.end
    ));
    let mut points = Vec::new();
    for &size in &options.sizes {
        let sized = size.apply(scene);
        for &method in &options.methods {
            for (setting, simulation) in settings(&sized, method, options)? {
                let point = measure(
                    &sized,
                    size,
                    &setting,
                    &simulation,
                    options.repeat,
                    (&beams, window),
                    reporter,
                )?;
                if let Some(p) = point {
                    reporter.note(&describe(&p));
                    points.push(p);
                }
            }
        }
    }
    mark_front(&mut points);
    Ok(ModelSizeStudy {
        scene: scene.name.clone(),
        window,
        reference: beams.reference.to_string(),
        points,
    })
}

/// The runs of `method`: one per tolerance for an adaptive method, one for `exact`.
fn settings(
    scene: &Scene,
    method: MethodChoice,
    options: &ModelSizeOptions,
) -> Result<Vec<(String, SimulationOptions)>> {
    let base = SimulationOptions {
        method,
        error_estimate: false,
        memory_budget: options.memory_budget,
        ..SimulationOptions::default()
    };
    let plan = crate::run::plan(scene, &base)?;
    if plan.method == Method::Exact {
        return Ok(vec![("exact".into(), base)]);
    }
    Ok(options
        .rtols
        .iter()
        .map(|&r| {
            (
                format!("rtol={r:e}"),
                SimulationOptions {
                    rtol: Some(r),
                    atol: Some(1e-3 * r),
                    ..base.clone()
                },
            )
        })
        .collect())
}

/// One point: `repeat` timed runs; `None` for a run the budget refuses.
fn measure(
    scene: &Scene,
    size: ModelSize,
    setting: &str,
    options: &SimulationOptions,
    repeat: usize,
    (beams, window): (&BeamResponse, Window),
    reporter: &dyn Reporter,
) -> Result<Option<SizePoint>> {
    let run = PreparedRun::new(scene, options, &crate::Silent)?;
    let mut walls = Vec::with_capacity(repeat);
    let mut last: Option<Trajectory> = None;
    for _ in 0..repeat {
        match run.integrate(reporter) {
            Ok(t) => {
                walls.push(t.stats.wall.as_secs_f64());
                last = Some(t);
            }
            Err(Error::Unaffordable { .. }) => return Ok(None),
            Err(e) => return Err(e),
        }
    }
    let trajectory = last.expect("at least one run");
    walls.sort_by(f64::total_cmp);
    let (tip_error, statistics_error) = errors(&trajectory, &beams.trajectory, window);
    Ok(Some(SizePoint {
        size,
        method: run.plan.method.name().to_string(),
        setting: setting.to_string(),
        wall: walls[walls.len() / 2],
        steps: trajectory.stats.steps,
        operations: trajectory.stats.operations(),
        tip_error,
        statistics_error,
        pareto: false,
    }))
}

/// The tip error inside `window` and the statistics error beyond it of `run` against
/// `beams`.
fn errors(run: &Trajectory, beams: &Trajectory, window: Window) -> (f64, f64) {
    let (a, b) = (
        run.column_of(Output::TipRel).expect("tip_rel"),
        beams.column_of(Output::TipRel).expect("tip_rel"),
    );
    let t = run.column("t").expect("t");
    let inside = t.iter().take_while(|&&t| t <= window.end).count();
    let tip = a[..inside]
        .iter()
        .zip(&b[..inside])
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max);
    if window.reason == WindowEnd::SpanEnd {
        return (tip, 0.0);
    }
    let stats = |v: &[f64]| {
        let rms = (v.iter().map(|x| x * x).sum::<f64>() / v.len().max(1) as f64).sqrt();
        (rms, v.iter().fold(0.0_f64, |m, x| m.max(x.abs())))
    };
    let (r1, p1) = stats(&a[inside..]);
    let (r2, p2) = stats(&b[inside..]);
    let relative = |x: f64, y: f64| (x - y).abs() / y.abs().max(f64::MIN_POSITIVE);
    (tip, relative(r1, r2).max(relative(p1, p2)))
}

/// Marks the points no other point beats in both counted work and tip error (among those
/// with statistics within [`STATISTICS_LIMIT`]).
fn mark_front(points: &mut [SizePoint]) {
    let counts = |p: &SizePoint| p.statistics_error <= STATISTICS_LIMIT;
    let snapshot: Vec<(f64, f64, bool)> = points
        .iter()
        .map(|p| (p.operations, p.tip_error, counts(p)))
        .collect();
    for (i, p) in points.iter_mut().enumerate() {
        let (w, e, ok) = snapshot[i];
        p.pareto = ok
            && !snapshot.iter().enumerate().any(|(j, &(w2, e2, ok2))| {
                j != i && ok2 && w2 <= w && e2 <= e && (w2 < w || e2 < e)
            });
    }
}

fn describe(p: &SizePoint) -> String {
    format!(
        "{:>9} {:>11} {:<14} {} steps, {:.2e} operations, wall {:.4} s, tip error {:.2e} m, \
         statistics {:.1} %",
        p.size.to_string(),
        p.method,
        p.setting,
        p.steps,
        p.operations,
        p.wall,
        p.tip_error,
        100.0 * p.statistics_error
    )
}

impl ModelSizeStudy {
    /// The point of least counted work whose tip error is within `error` (m) and statistics
    /// within [`STATISTICS_LIMIT`].
    pub fn cheapest_within(&self, error: f64) -> Option<&SizePoint> {
        self.points
            .iter()
            .filter(|p| p.tip_error <= error && p.statistics_error <= STATISTICS_LIMIT)
            .min_by(|a, b| a.operations.total_cmp(&b.operations))
    }

    /// Lines for the summary: the cheapest point for 1 cm, 1 mm and 0.1 mm.
    pub fn summary(&self) -> String {
        [1e-2, 1e-3, 1e-4]
            .iter()
            .map(|&e| match self.cheapest_within(e) {
                Some(p) => format!(
                    "cheapest within {e:e} m: modes {} {} {} ({:.2e} operations, {} steps, \
                     {:.4} s, {:.2e} m)",
                    p.size, p.method, p.setting, p.operations, p.steps, p.wall, p.tip_error
                ),
                None => format!("cheapest within {e:e} m: none of the runs"),
            })
            .collect::<Vec<_>>()
            .join("\n")
    }

    /// The CSV table, one row per run.
    ///
    /// # Errors
    /// The writer's error.
    pub fn write_table(&self, w: &mut dyn Write) -> std::io::Result<()> {
        writeln!(
            w,
            "basis,modes,method,setting,wall_s,tip_error_window_m,statistics_error_rel,pareto,\
             steps,operations"
        )?;
        for p in &self.points {
            writeln!(
                w,
                "{},{},{},{},{:e},{:e},{:e},{},{},{:e}",
                p.size.basis.word(),
                p.size.modes,
                p.method,
                p.setting,
                p.wall,
                p.tip_error,
                p.statistics_error,
                p.pareto,
                p.steps,
                p.operations
            )?;
        }
        Ok(())
    }
}
