//! `telescopic animate`: a run (or two side by side, or a controlled run beside its open
//! loop) as a self-contained HTML page or an animated GIF.

use super::progress::Progress;
use super::simulate::{RunArgs, load_controller};
use super::{SceneArgs, of_flag};
use clap::Args;
use std::path::PathBuf;
use telescopic::Scene;
use telescopic::animate::memory;
use telescopic::animate::options::{DEFAULT_GIF_FPS, DEFAULT_PAGE_FPS};
use telescopic::animate::{
    AnimationFormat, AnimationOptions, RunRequest, animate_run, describe, save_run,
};

/// Options of `telescopic animate`.
#[derive(Debug, Args)]
pub struct AnimateArgs {
    #[command(flatten)]
    scene: SceneArgs,
    #[command(flatten)]
    run: RunArgs,
    /// The file to write: .html (a self-contained page: opens from disk, offline, in any
    /// current browser and in Jupyter) or .gif.
    #[arg(long, value_name = "FILE.html|FILE.gif")]
    out: PathBuf,
    /// A second scene run with the same options and shown side by side.
    #[arg(long, value_name = "SCENE2", conflicts_with = "controller")]
    compare: Option<PathBuf>,
    /// Drive the scene with this controller (a file of `telescopic design`); the run without
    /// it is shown beside.
    #[arg(long, value_name = "CONTROLLER.json")]
    controller: Option<PathBuf>,
    /// The load (kg) a plan's velocity feedback is told (default: the scene's masses.load).
    #[arg(long, value_name = "KG", requires = "controller")]
    weighed_load: Option<f64>,
    /// Frames per second of simulation time, picked from the run's samples (default 50 for
    /// a page, 25 for a GIF).
    #[arg(long, value_name = "N")]
    fps: Option<f64>,
    /// Exaggeration of the transverse deflection (default: a round number that draws the
    /// largest deflection at a fifth of the telescope's height).
    #[arg(long, value_name = "FACTOR")]
    scale: Option<f64>,
    /// A GIF's size in pixels (default 720x480).
    #[arg(long, value_name = "WxH", value_parser = parse_size)]
    size: Option<(u32, u32)>,
    /// A GIF's speed: simulation seconds per second of playback (default 1; 0.1 is slow
    /// motion).
    #[arg(long, value_name = "FACTOR")]
    speed: Option<f64>,
}

/// `WxH` as pixels.
fn parse_size(text: &str) -> Result<(u32, u32), String> {
    let (w, h) = text
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("{text}: give the size as WIDTHxHEIGHT, e.g. 720x480"))?;
    let number = |s: &str| {
        s.trim()
            .parse::<u32>()
            .map_err(|_| format!("{text}: width and height are whole pixels, e.g. 720x480"))
    };
    Ok((number(w)?, number(h)?))
}

/// Runs `telescopic animate`.
pub fn animate(args: &AnimateArgs) -> anyhow::Result<()> {
    let mut inputs = vec![args.scene.scene.as_path()];
    inputs.extend(args.compare.as_deref());
    inputs.extend(args.controller.as_deref());
    crate::signals::watch_output(&args.out);
    let format = AnimationFormat::of_path(&args.out).map_err(of_flag("--out"))?;
    telescopic::io::output::check_not_an_input(&args.out, &inputs).map_err(of_flag("--out"))?;
    if format == AnimationFormat::Html && (args.size.is_some() || args.speed.is_some()) {
        anyhow::bail!(
            "--size and --speed are a GIF's; a page is sized by the browser and has its own speed control"
        );
    }
    let scene = args.scene.load()?;
    let other = match &args.compare {
        Some(path) => Some(Scene::load(path, &args.scene.overrides)?),
        None => None,
    };
    let controller = load_controller(args.controller.as_deref(), args.weighed_load, &scene)?;
    let defaults = AnimationOptions::default();
    let animation = AnimationOptions {
        fps: args.fps.unwrap_or(match format {
            AnimationFormat::Html => DEFAULT_PAGE_FPS,
            AnimationFormat::Gif => DEFAULT_GIF_FPS,
        }),
        scale: args.scale,
        size: args.size.unwrap_or(defaults.size),
        speed: args.speed.unwrap_or(defaults.speed),
        ..defaults
    };
    animation.check()?;
    let options = args.run.options()?;
    let request = RunRequest {
        scene: &scene,
        options,
        controller: controller.as_ref(),
        compare: other.as_ref(),
    };
    match format {
        AnimationFormat::Html => request.check_page(animation.fps)?,
        AnimationFormat::Gif => {
            memory::check_gif_frames(memory::frames(&scene, animation.fps), animation.fps)?;
        }
    }
    let progress = Progress::new();
    let movie = animate_run(&request, &animation, &progress)?;
    let bytes = save_run(&movie, &animation, &args.out, &progress)?;
    eprintln!("{}", describe(&movie, &args.out, bytes));
    Ok(())
}
