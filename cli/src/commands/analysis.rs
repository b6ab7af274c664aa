//! The analysis commands: `stability`, `work-precision`, `converge` and `shape-errors`. Each
//! checks its outputs, calls the library, writes the table and the chart.

use super::progress::Progress;
use super::{SceneArgs, check_chart, check_output};
use crate::stdout::{check_stdout_open, write_to};
use clap::Args;
use std::path::PathBuf;
use telescopic::analysis::converge::{ConvergeOptions, converge as run_converge};
use telescopic::analysis::model_size::{ModelSize, ModelSizeOptions, model_size_study};
use telescopic::analysis::shape_errors::{ShapeErrorsOptions, shape_errors as run_shape_errors};
use telescopic::analysis::stability::stability_analysis;
use telescopic::analysis::work_precision::{
    DEFAULT_METHODS, WorkPrecisionOptions, work_precision as run_wp,
};
use telescopic::plot::{Figure, save};
use telescopic::run::MethodChoice;
use telescopic::run::models::ModelChoice;

/// Options of `telescopic stability`.
#[derive(Debug, Args)]
pub struct StabilityArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Which model is linearized: auto, generated or assembled.
    #[arg(long, default_value = "auto", value_name = "MODEL")]
    pub model: ModelChoice,
}

/// Runs `telescopic stability`.
pub fn stability(args: &StabilityArgs) -> anyhow::Result<()> {
    check_stdout_open()?;
    let scene = args.scene.load()?;
    let report = stability_analysis(&scene, args.model, &Default::default())?;
    if let Some(note) = &report.note {
        eprintln!("{note}");
    }
    let text = report.render() + "\n";
    write_to(None, |w| w.write_all(text.as_bytes()))?;
    Ok(())
}

/// `--out` and `--csv`: the chart and the table of an analysis.
#[derive(Debug, Args)]
pub struct Outputs {
    /// Chart (SVG or PNG by extension).
    #[arg(long, value_name = "FILE.svg|FILE.png")]
    pub out: Option<PathBuf>,
    /// The table behind the chart as CSV, one row per run, model or mode (default: standard
    /// output, except for converge, which prints its answer there).
    #[arg(long, value_name = "FILE")]
    pub csv: Option<PathBuf>,
}

impl Outputs {
    /// Checks the paths before any work; `stdout`: something will be printed.
    fn check(&self, stdout: bool, inputs: &[&std::path::Path]) -> anyhow::Result<()> {
        check_chart("--out", self.out.as_deref(), inputs)?;
        check_output("--csv", self.csv.as_deref(), inputs)?;
        if stdout {
            check_stdout_open()?;
        }
        Ok(())
    }

    /// Writes the table (to stdout without `--csv` when `table_to_stdout`) and the chart.
    fn write(
        &self,
        table: impl FnOnce(&mut dyn std::io::Write) -> std::io::Result<()>,
        chart: &impl Figure,
        table_to_stdout: bool,
    ) -> anyhow::Result<()> {
        if self.csv.is_some() || table_to_stdout {
            write_to(self.csv.as_deref(), table)?;
        }
        if let Some(path) = &self.csv {
            eprintln!("wrote {}", path.display());
        }
        if let Some(path) = &self.out {
            save(chart, path)?;
            eprintln!("wrote {}", path.display());
        }
        Ok(())
    }
}

/// Options of `telescopic work-precision`.
#[derive(Debug, Args)]
pub struct WorkPrecisionArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Methods to compare, comma-separated (`exact` is skipped, with a note, on a scene that
    /// is not linear and time-invariant between contact switches; `auto` is simulate's
    /// default, e.g. dopri5 while the positions move and exact once they rest).
    #[arg(long, value_delimiter = ',', default_value = DEFAULT_METHODS)]
    pub methods: Vec<String>,
    #[command(flatten)]
    pub outputs: Outputs,
    /// Timed repetitions per setting (the median is reported), 1 to 100.
    #[arg(long, default_value_t = 3)]
    pub repeat: usize,
    /// Relative tolerances of the adaptive methods, comma-separated, each 1e-13 to 0.1
    /// (`atol = 1e-3 rtol`) [default: 1e-3,1e-4,1e-5,1e-6,1e-7,1e-8].
    #[arg(long, value_delimiter = ',', value_name = "RTOLS")]
    pub rtols: Vec<f64>,
    /// Which model computes the right-hand side: auto, generated or assembled.
    #[arg(long, default_value = "auto", value_name = "MODEL")]
    pub model: ModelChoice,
    /// The model-size axis: these sizes (N for the paper's N modes per section, static:N
    /// with the static correction shapes), each with every method (default auto) and
    /// tolerance, measured against the beams (finite elements for fixed positions, the most
    /// refined Ritz model for moving ones): the whole error against its cost, the Pareto
    /// front marked, and the cheapest run for 1 cm, 1 mm and 0.1 mm.
    #[arg(long, value_delimiter = ',', value_name = "SIZES")]
    pub modes: Vec<ModelSize>,
}

/// Runs `telescopic work-precision`.
pub fn work_precision(args: &WorkPrecisionArgs) -> anyhow::Result<()> {
    args.outputs
        .check(args.outputs.csv.is_none(), &[&args.scene.scene])?;
    let scene = args.scene.load()?;
    if !args.modes.is_empty() {
        return model_sizes(args, &scene);
    }
    let defaults = WorkPrecisionOptions::default();
    let options = WorkPrecisionOptions {
        methods: args.methods.clone(),
        repeat: args.repeat,
        rtols: if args.rtols.is_empty() {
            defaults.rtols
        } else {
            args.rtols.clone()
        },
        model: args.model,
        memory_budget: crate::memory_budget()?,
        ..defaults
    };
    let result = run_wp(&scene, &options, &Progress::new())?;
    args.outputs
        .write(|w| result.write_table(w), &result.chart(), true)
}

/// `telescopic work-precision --modes`: the model-size axis.
fn model_sizes(args: &WorkPrecisionArgs, scene: &telescopic::Scene) -> anyhow::Result<()> {
    let defaults = ModelSizeOptions::default();
    // `auto` alone unless methods are named
    let methods = if args.methods.join(",") == DEFAULT_METHODS {
        defaults.methods.clone()
    } else {
        args.methods
            .iter()
            .map(|m| {
                m.parse::<MethodChoice>()
                    .map_err(|e| anyhow::anyhow!("--methods: {e}"))
            })
            .collect::<anyhow::Result<_>>()?
    };
    let options = ModelSizeOptions {
        sizes: args.modes.clone(),
        methods,
        rtols: if args.rtols.is_empty() {
            defaults.rtols
        } else {
            args.rtols.clone()
        },
        repeat: args.repeat,
        memory_budget: crate::memory_budget()?,
    };
    let study = model_size_study(scene, &options, &Progress::new())?;
    eprintln!("{}", study.summary());
    args.outputs
        .write(|w| study.write_table(w), &study.chart(), true)
}

/// Options of `telescopic converge`.
#[derive(Debug, Args)]
pub struct ConvergeArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Largest relative change between consecutive models that counts as converged.
    #[arg(long, value_name = "TOL")]
    pub tol: f64,
    /// Most modes per section tried (2 to 30).
    #[arg(long, default_value_t = 12, value_name = "N")]
    pub max_modes: usize,
    /// Most contact points per overlap tried (from 2; 3 to 32).
    #[arg(long, default_value_t = 5, value_name = "N")]
    pub max_contacts: usize,
    #[command(flatten)]
    pub outputs: Outputs,
}

/// Runs `telescopic converge`.
pub fn converge(args: &ConvergeArgs) -> anyhow::Result<()> {
    args.outputs.check(true, &[&args.scene.scene])?;
    let scene = args.scene.load()?;
    let options = ConvergeOptions {
        tol: args.tol,
        max_modes: args.max_modes,
        max_contacts: args.max_contacts,
        memory_budget: crate::memory_budget()?,
    };
    let result = run_converge(&scene, &options, &Progress::new())?;
    let text = result.render();
    write_to(None, |w| w.write_all(text.as_bytes()))?;
    args.outputs
        .write(|w| result.write_table(w), &result.chart(), false)
}

/// Options of `telescopic shape-errors`.
#[derive(Debug, Args)]
pub struct ShapeErrorsArgs {
    /// Section length (m); the errors barely depend on it.
    #[arg(long, default_value_t = 1.35, value_name = "M")]
    pub length: f64,
    /// Evaluation points along the section (derivatives 0 to 3 at each).
    #[arg(long, default_value_t = 41, value_name = "N")]
    pub points: usize,
    #[command(flatten)]
    pub outputs: Outputs,
}

/// Runs `telescopic shape-errors`.
pub fn shape_errors(args: &ShapeErrorsArgs) -> anyhow::Result<()> {
    args.outputs.check(args.outputs.csv.is_none(), &[])?;
    let result = run_shape_errors(&ShapeErrorsOptions {
        length: args.length,
        points: args.points,
    })?;
    args.outputs
        .write(|w| result.write_table(w), &result.chart(), true)
}
