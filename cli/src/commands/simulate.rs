//! `telescopic simulate`: integrates a scene, writes its outputs as CSV (complete or not at
//! all), a run summary on stderr, and optionally the paper's figures.

use super::progress::Progress;
use super::{SceneArgs, check_chart, check_output};
use clap::Args;
use std::path::PathBuf;
use telescopic::Scene;
use telescopic::analysis::metrics::drive_stop;
use telescopic::control::{ControllerFile, compare_file_with_open_loop};
use telescopic::io::output::write_to;
use telescopic::plot::{Curve, Marks, Role, clearance_label, plot, with_stated_error};
use telescopic::report::Reporter;
use telescopic::run::models::ModelChoice;
use telescopic::run::stress::Station;
use telescopic::run::{MethodChoice, SimulationOptions, simulate_scene, write_csv};

/// How a scene is run: the method, tolerances, accuracy and model (shared by `simulate` and
/// `animate`).
#[derive(Debug, Args)]
pub struct RunArgs {
    /// Integration method: auto (default: the cheapest method and tolerance that reach
    /// 1e-6 m in tip_rel by the measured table, e.g. exact for a scene that is linear and
    /// time-invariant between contact switches), exact, dopri5, dop853, esdirk, imex, bdf,
    /// bdf<K>, rk4, verlet, galpha, galpha-fixed, galpha-rho<R> (see docs/numerics.md).
    #[arg(long, default_value = "auto", value_name = "NAME")]
    pub method: MethodChoice,
    /// The whole error asked for in tip_rel against the beams (m, 1e-5 to 0.1): the basis,
    /// the modes per section, the method and the tolerance that reach it cheapest are picked
    /// and named in the summary (docs/numerics.md). With --modes-as-given: the integration
    /// error alone (1e-11 to 1e-2 m). Default: the scene's `accuracy` when it states one
    /// and no method, tolerance or model is given; else the scene's modes, integrated to
    /// 1e-6 m.
    #[arg(long, value_name = "METRES", conflicts_with_all = ["rtol", "atol"])]
    pub accuracy: Option<f64>,
    /// Keep the scene's modes and basis (the paper's N on the paper's scenes), whatever
    /// accuracy the scene states: --accuracy then bounds the integration error only, and the
    /// summary says whether the whole error meets it.
    #[arg(long)]
    pub modes_as_given: bool,
    /// With --accuracy: the largest truncation error of a station's moment, as a fraction of
    /// its peak (default 0.02).
    #[arg(long, value_name = "FRACTION", requires = "accuracy")]
    pub moment_tolerance: Option<f64>,
    /// With --accuracy on a scene with clearance: the largest relative truncation error of
    /// the RMS and peak of tip_rel and the peak moment beyond the pointwise window (default
    /// 0.05).
    #[arg(long, value_name = "FRACTION", requires = "accuracy")]
    pub statistics_tolerance: Option<f64>,
    /// Relative tolerance of adaptive methods (default 1e-6).
    #[arg(long, value_name = "R")]
    pub rtol: Option<f64>,
    /// Absolute tolerance of adaptive methods (m and m/s; default 1e-9).
    #[arg(long, value_name = "A")]
    pub atol: Option<f64>,
    /// Step (s) of fixed-step methods; first trial step of adaptive ones.
    #[arg(long, value_name = "H")]
    pub dt: Option<f64>,
    /// Let dop853's step grow beyond its stable step while a contact is closed (the step
    /// control then hovers at the stability boundary; for comparison).
    #[arg(long)]
    pub no_step_cap: bool,
    /// Keep method exact on its short steps while a contact is closed instead of stepping
    /// over the contact's fast modes where their bound certifies it (for comparison).
    #[arg(long)]
    pub no_long_steps: bool,
    /// Which model computes the right-hand side: auto, generated or assembled.
    #[arg(long, default_value = "auto", value_name = "MODEL")]
    pub model: ModelChoice,
}

impl RunArgs {
    /// The library's options of these flags (no stations, the error estimated).
    pub fn options(&self) -> anyhow::Result<SimulationOptions> {
        Ok(SimulationOptions {
            method: self.method,
            rtol: self.rtol,
            atol: self.atol,
            dt: self.dt,
            step_cap: !self.no_step_cap,
            long_steps: !self.no_long_steps,
            model: self.model,
            accuracy: self.accuracy,
            modes_as_given: self.modes_as_given,
            moment_tolerance: self
                .moment_tolerance
                .unwrap_or(SimulationOptions::default().moment_tolerance),
            statistics_tolerance: self
                .statistics_tolerance
                .unwrap_or(SimulationOptions::default().statistics_tolerance),
            memory_budget: crate::memory_budget()?,
            ..SimulationOptions::default()
        })
    }
}

/// Options of `telescopic simulate`.
#[derive(Debug, Args)]
pub struct SimulateArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    #[command(flatten)]
    pub run: RunArgs,
    /// Skip the companion run with more modes that estimates the truncation error.
    #[arg(long)]
    pub no_error_estimate: bool,
    /// Estimate the error budget afresh and keep no record of it. By default a run keeps its
    /// budget (and its accuracy search's pick) in $TELESCOPIC_CACHE_DIR (`off`: none), else
    /// $XDG_CACHE_HOME/telescopic/budgets or ~/.cache/telescopic/budgets, and a repeated run
    /// of the same scene and options whose outputs equal the kept run's to the bit reuses
    /// it (docs/numerics.md).
    #[arg(long)]
    pub no_reuse: bool,
    /// CSV file for the outputs (written to a temporary file and renamed when complete);
    /// default: standard output.
    #[arg(long, value_name = "FILE")]
    pub out: Option<PathBuf>,
    /// Also print the run summary as JSON on standard output (the keys of Python's
    /// `summary`; the CSV then goes to --out)
    #[arg(long, requires = "out")]
    pub json: bool,
    /// Draw the paper's figures for this scene to an SVG or PNG file (by extension).
    #[arg(long, value_name = "FILE.svg|FILE.png")]
    pub plot: Option<PathBuf>,
    /// A second scene to simulate with the same method and overlay in the plot (e.g. the
    /// case-study without clearance).
    #[arg(
        long,
        value_name = "SCENE2",
        requires = "plot",
        conflicts_with = "controller"
    )]
    pub compare: Option<PathBuf>,
    /// Drive the scene with this controller (a file of `telescopic design`) on the full
    /// model; the run without it is made too, for the comparison in the summary and the plot.
    #[arg(long, value_name = "CONTROLLER.json")]
    pub controller: Option<PathBuf>,
    /// The load (kg) a plan's velocity feedback is told, as a machine that weighs it wrongly
    /// would (default: the scene's masses.load, the load carried).
    #[arg(long, value_name = "KG", requires = "controller")]
    pub weighed_load: Option<f64>,
    /// Add the bending moment (and, when the scene gives sections.section_modulus or
    /// sections.height, the stress) at these stations as columns moment_K_X (N m) and
    /// stress_K_X (Pa): section K at X metres from its foot, e.g. 1:0,1:0.675,2:0; the
    /// summary gives the stress envelope.
    #[arg(long, value_name = "K:X,...")]
    pub stations: Option<String>,
}

/// Runs `telescopic simulate`.
pub fn simulate(args: &SimulateArgs) -> anyhow::Result<()> {
    // every input and output is checked before the run
    let mut inputs = vec![args.scene.scene.as_path()];
    inputs.extend(args.compare.as_deref());
    inputs.extend(args.controller.as_deref());
    check_chart("--plot", args.plot.as_deref(), &inputs)?;
    check_output("--out", args.out.as_deref(), &inputs)?;
    if let (Some(plot), Some(out)) = (&args.plot, &args.out) {
        telescopic::io::output::check_not_an_input(plot, &[out])
            .map_err(super::of_flag("--plot"))?;
    }
    if args.out.is_none() || args.json {
        crate::stdout::check_stdout_open()?;
    }
    let scene = args.scene.load()?;
    let other = match &args.compare {
        Some(path) => Some(Scene::load(path, &args.scene.overrides)?),
        None => None,
    };
    if let Some(other) = &other {
        telescopic::run::memory::check_runs(&[&scene, other], crate::memory_budget()?)?;
    }
    let controller = load_controller(args.controller.as_deref(), args.weighed_load, &scene)?;
    let options = simulation_options(args)?;
    let progress = Progress::new();
    // the compared scene is drawn only: it runs beside the scene where a core is free
    let compared_for_plot = other.as_ref().filter(|_| args.plot.is_some());
    let mut compared = None;
    let (run, comparison) = match &controller {
        Some(c) => {
            let comparison = compare_file_with_open_loop(&scene, c, &options, &progress)?;
            let summary = c.summary(&comparison);
            (comparison.controlled, Some((summary, comparison.open_loop)))
        }
        None => match compared_for_plot {
            Some(other) => {
                let (run, other_run) = telescopic::report::both_named(
                    &progress,
                    0.5,
                    [&scene.name, &other.name],
                    |r| simulate_stated(&scene, &options, r),
                    |r| simulate_stated(other, &options, r),
                );
                // the scene's own failure first: it stops the compared run
                let run = run?;
                compared = Some(other_run?);
                (run, None)
            }
            None => (simulate_stated(&scene, &options, &progress)?, None),
        },
    };
    write_csv(&run, args.out.as_deref())?;
    eprintln!("{}", run.summary());
    if args.json {
        write_to(None, |w| {
            w.write_all(run.run_summary().to_json().as_bytes())
        })?;
    }
    if let Some(p) = &args.out {
        eprintln!("wrote {} ({} rows)", p.display(), run.trajectory.rows.len());
    }
    let open_loop = comparison.map(|(summary, open_loop)| {
        eprintln!("{summary}");
        open_loop
    });
    if let Some(plot_path) = &args.plot {
        let runs = PlottedRuns {
            scene: &scene,
            run: &run,
            open_loop: open_loop.as_ref(),
            other: other.as_ref(),
            compared,
            controller: controller.as_ref(),
        };
        plot_runs(runs, &options, &progress, plot_path)?;
    }
    Ok(())
}

/// Runs `scene` with `options`, to the accuracy the scene states when the options leave
/// the choice to it (said on stderr).
fn simulate_stated(
    scene: &Scene,
    options: &SimulationOptions,
    progress: &dyn Reporter,
) -> anyhow::Result<telescopic::run::Simulation> {
    let stated = options.for_scene(scene);
    if let (None, Some(accuracy)) = (options.accuracy, stated.accuracy) {
        eprintln!(
            "{}: the scene states accuracy = {accuracy:e} m; the run picks the model size \
             that meets it (--modes-as-given keeps the scene's modes)",
            scene.name
        );
    }
    Ok(simulate_scene(scene, &stated, progress)?)
}

/// The controller file at `path`, checked to fit `scene`, told the `weighed` load (kg) when
/// one is given.
pub fn load_controller(
    path: Option<&std::path::Path>,
    weighed: Option<f64>,
    scene: &Scene,
) -> anyhow::Result<Option<ControllerFile>> {
    let Some(path) = path else { return Ok(None) };
    let c = ControllerFile::load(path)?;
    c.check_fits(scene)
        .map_err(|e| anyhow::anyhow!("--controller {}: {e}", path.display()))?;
    Ok(Some(match weighed {
        Some(load) => c.with_weighed_load(load)?,
        None => c,
    }))
}

/// The library's options of a simulate command.
fn simulation_options(args: &SimulateArgs) -> anyhow::Result<SimulationOptions> {
    Ok(SimulationOptions {
        stations: match &args.stations {
            Some(text) => Station::parse_list(text)?,
            None => Vec::new(),
        },
        error_estimate: !args.no_error_estimate,
        reuse: match args.no_reuse {
            true => None,
            false => telescopic::run::reuse::default_dir(),
        },
        ..args.run.options()?
    })
}

/// What a simulate command's figure shows: the run, the open loop beside a controlled run,
/// and a compared scene (with its run when it ran beside the scene's; else run here).
struct PlottedRuns<'a> {
    scene: &'a Scene,
    run: &'a telescopic::run::Simulation,
    open_loop: Option<&'a telescopic::run::Simulation>,
    other: Option<&'a Scene>,
    compared: Option<telescopic::run::Simulation>,
    controller: Option<&'a ControllerFile>,
}

/// Draws the runs' figure to `plot_path`, running the compared scene with `options`.
fn plot_runs(
    runs: PlottedRuns,
    options: &SimulationOptions,
    progress: &Progress,
    plot_path: &std::path::Path,
) -> anyhow::Result<()> {
    let (scene, run, controller) = (runs.scene, runs.run, runs.controller);
    let half_band = scene.params.contact.half_band();
    // the labels say what differs: the controller, or the clearance of a compared scene
    let (label, role) = match controller {
        Some(c) => (
            format!("{} with {}", scene.name, c.describe()),
            Role::Controlled,
        ),
        None => (clearance_label(scene), Role::Scene),
    };
    let mut curves = vec![Curve {
        label: with_stated_error(label, run),
        traj: &run.trajectory,
        half_band,
        role,
    }];
    if let Some(open) = runs.open_loop {
        curves.push(Curve {
            label: format!("{} without control", scene.name),
            traj: &open.trajectory,
            half_band,
            role: Role::Scene,
        });
    }
    let compared = match (runs.other, runs.compared) {
        (Some(other), None) => Some(simulate_stated(other, options, progress)?),
        (_, compared) => compared,
    };
    if let Some(run) = &compared {
        eprintln!("{}", run.summary());
    }
    if let (Some(other), Some(run)) = (runs.other, &compared) {
        curves.push(Curve {
            label: with_stated_error(clearance_label(other), run),
            traj: &run.trajectory,
            half_band: other.params.contact.half_band(),
            role: Role::Compared,
        });
    }
    let marks = match controller {
        Some(c) => Marks {
            force_limit: c.force_limit(),
            residual_window: Some((drive_stop(scene), scene.time.end)),
        },
        None => Marks::default(),
    };
    plot(&scene.figures, &curves, &marks, plot_path)?;
    eprintln!("wrote {}", plot_path.display());
    Ok(())
}
