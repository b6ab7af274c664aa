//! `telescopic modes` and `telescopic equations`: the scene's linear model, as
//! eigenfrequencies or as the derived equations.

use super::{SceneArgs, check_chart, of_flag};
use clap::Args;
use std::path::PathBuf;
use telescopic::analysis::equations::{EquationFormat, equations as rendered_equations};
use telescopic::analysis::modes::{ModesOptions, compute_modes};
use telescopic::animate::geometry::DEFAULT_POINTS;
use telescopic::animate::{AnimationFormat, animate_modes, save_modes};
use telescopic::io::output::write_to;
use telescopic::plot::modes::ModeShapeFigure;
use telescopic::run::models::ModelChoice;

/// Options of `telescopic modes`.
#[derive(Debug, Args)]
pub struct ModesArgs {
    #[command(flatten)]
    scene: SceneArgs,
    /// Print JSON instead of a table.
    #[arg(long)]
    json: bool,
    /// Time (s) whose telescopic positions are used; default: the scene's start time.
    #[arg(long, value_name = "SECONDS")]
    at: Option<f64>,
    /// How many frequencies to print (default: all).
    #[arg(long, value_name = "N")]
    count: Option<usize>,
    /// Also give mode shapes, sampled at this many points per section (JSON: `mode_shapes`).
    #[arg(long, value_name = "POINTS")]
    shapes: Option<usize>,
    /// Which model computes the matrices: auto, generated or assembled.
    #[arg(long, default_value = "auto", value_name = "MODEL")]
    model: ModelChoice,
    /// Draw the mode shapes (the first 8 of those listed) to an SVG or PNG file (by
    /// extension): the telescope upright, each section along its own axis.
    #[arg(long, value_name = "FILE.svg|FILE.png")]
    plot: Option<PathBuf>,
    /// Write the modes listed as a self-contained HTML page: each mode shape oscillating
    /// (slowed to one cycle per 2 s) with its frequency, damping ratio and kind.
    #[arg(long, value_name = "FILE.html")]
    animate: Option<PathBuf>,
}

/// Points per section of a plotted mode shape.
const PLOT_POINTS: usize = 61;

/// Runs `telescopic modes`.
pub fn modes(args: &ModesArgs) -> anyhow::Result<()> {
    crate::stdout::check_stdout_open()?;
    check_chart(
        "--plot",
        args.plot.as_deref(),
        &[args.scene.scene.as_path()],
    )?;
    if let Some(path) = &args.animate {
        crate::signals::watch_output(path);
        let format = AnimationFormat::of_path(path).map_err(of_flag("--animate"))?;
        if format != AnimationFormat::Html {
            anyhow::bail!(
                "--animate {}: the modes' animation is a page; the file name must end in .html",
                path.display()
            );
        }
        telescopic::io::output::check_not_an_input(path, &[args.scene.scene.as_path()])
            .map_err(of_flag("--animate"))?;
    }
    let scene = args.scene.load()?;
    let options = ModesOptions {
        at: args.at,
        count: args.count,
        shapes: args.shapes,
        model: args.model,
        models: Default::default(),
        memory_budget: crate::memory_budget()?,
    };
    let report = compute_modes(&scene, &options)?;
    if let Some(path) = &args.plot {
        let sampled = ModesOptions {
            shapes: Some(PLOT_POINTS),
            ..options.clone()
        };
        ModeShapeFigure::new(&scene, &compute_modes(&scene, &sampled)?)?.save(path)?;
        eprintln!("wrote {}", path.display());
    }
    if let Some(path) = &args.animate {
        let (_, movie) = animate_modes(&scene, &options, DEFAULT_POINTS)?;
        let bytes = save_modes(&movie, path)?;
        eprintln!(
            "wrote {} ({} modes, {})",
            path.display(),
            movie.modes.len(),
            telescopic::io::size::human(bytes)
        );
    }
    if let Some(note) = &report.note {
        eprintln!("{note}");
    }
    let text = if args.json {
        report.to_json() + "\n"
    } else {
        report.to_table()
    };
    write_to(None, |w| w.write_all(text.as_bytes()))?;
    Ok(())
}

/// Options of `telescopic equations`.
#[derive(Debug, Args)]
pub struct EquationsArgs {
    #[command(flatten)]
    scene: SceneArgs,
    /// Output format: text, latex (a standalone document), rust (the emitted module) or json.
    #[arg(long, default_value = "text", value_name = "FORMAT")]
    format: EquationFormat,
}

/// Runs `telescopic equations`.
pub fn equations(args: &EquationsArgs) -> anyhow::Result<()> {
    crate::stdout::check_stdout_open()?;
    let scene = args.scene.load()?;
    let text = rendered_equations(&scene, args.format, &Default::default())?;
    write_to(None, |w| w.write_all(text.as_bytes()))?;
    Ok(())
}
