//! Animated views of a run and of a scene's modes: the telescope drawn in the plane of the
//! motion, each section bent by its mode expansion, the guides and contacts, the load and the
//! vehicle on its rail; beside it `tip_rel`, the vehicle and the drive force against time.
//! One self-contained HTML file ([`page`]: no network, no external file) or an animated GIF
//! ([`mod@gif`]).
//!
//! The movie holds the generalized coordinates per frame and the shape functions at the
//! drawing points once ([`geometry`]); the page forms the deflection. Frames are samples of
//! the run ([`run_movie`]), never interpolated.
//!
//! ```
//! use telescopic::animate::{AnimationOptions, RunRequest, animate_run};
//! use telescopic::run::SimulationOptions;
//! use telescopic::{Scene, Silent};
//!
//! let scene = Scene::load("scenes/adams-clearance.toml".as_ref(), &["time.end=0.5".into()])?;
//! let request = RunRequest::new(&scene, SimulationOptions::default());
//! let movie = animate_run(&request, &AnimationOptions::default(), &Silent)?;
//! assert_eq!(movie.frame_count(), 26); // 0 .. 0.5 s at 50 frames per second
//! let html = movie.html();
//! assert!(html.starts_with("<!DOCTYPE html>") && !html.contains("https://"));
//! # Ok::<(), telescopic::Error>(())
//! ```

pub mod geometry;
pub mod gif;
pub mod memory;
pub mod mode_movie;
pub mod options;
pub mod page;
pub mod run_movie;

pub use mode_movie::ModeMovie;
pub use options::AnimationOptions;
pub use run_movie::{RunMovie, RunTrack, Take};

use crate::analysis::modes::{ModesOptions, ModesReport, compute_modes};
use crate::control::{ControllerFile, compare_file_with_open_loop};
use crate::io::output::Destination;
use crate::plot::{Role, clearance_label};
use crate::report::Reporter;
use crate::run::{Simulation, SimulationOptions, simulate_scene};
use crate::{Error, OptionName, Result};
use std::path::Path;
use telescopic_runtime::Scene;

/// What to run for a movie: a scene with the options `simulate` takes, and optionally a
/// controller (the run with it beside the run without) or a second scene side by side.
pub struct RunRequest<'a> {
    /// The scene.
    pub scene: &'a Scene,
    /// How to simulate it (the coordinates are recorded whatever this says; no companion
    /// run estimates the error).
    pub options: SimulationOptions,
    /// A controller driving the scene.
    pub controller: Option<&'a ControllerFile>,
    /// A second scene run with the same options, side by side.
    pub compare: Option<&'a Scene>,
}

impl<'a> RunRequest<'a> {
    /// `scene` run with `options`, alone.
    pub fn new(scene: &'a Scene, options: SimulationOptions) -> Self {
        RunRequest {
            scene,
            options,
            controller: None,
            compare: None,
        }
    }

    /// The scenes whose runs a page of this request shows (a controlled run's scene twice:
    /// with its controller and without).
    pub fn shown(&self) -> Vec<&'a Scene> {
        let mut shown = vec![self.scene];
        shown.extend(self.controller.map(|_| self.scene));
        shown.extend(self.compare);
        shown
    }

    /// Refuses a page of this request at `fps` (frames per second) whose building would
    /// pass the options' memory budget, before any run.
    ///
    /// # Errors
    /// [`Error::OverMemoryBudget`] naming the frame rate, time.sample and time.end.
    pub fn check_page(&self, fps: f64) -> Result<()> {
        memory::check_page(&self.shown(), fps, self.options.memory_budget)
    }
}

/// Runs what `request` asks and makes its movie with `animation`.
///
/// # Errors
/// [`Error::Option`] for bad animation options or a controller with a compared scene; the
/// errors of the runs.
pub fn animate_run(
    request: &RunRequest,
    animation: &AnimationOptions,
    reporter: &dyn Reporter,
) -> Result<RunMovie> {
    animation.check()?;
    let options = SimulationOptions {
        coordinates: true,
        error_estimate: false,
        ..request.options.clone()
    };
    let scene = request.scene;
    let mut runs: Vec<(String, &Scene, Simulation, Role)> = Vec::new();
    match (request.controller, request.compare) {
        (Some(_), Some(_)) => {
            return Err(Error::option(
                OptionName::Controller,
                "a movie shows a controlled run beside its open loop, or two scenes, not both",
            ));
        }
        (Some(controller), None) => {
            let comparison = compare_file_with_open_loop(scene, controller, &options, reporter)?;
            runs.push((
                "without control".into(),
                scene,
                comparison.open_loop,
                Role::Scene,
            ));
            runs.push((
                "with control".into(),
                scene,
                comparison.controlled,
                Role::Controlled,
            ));
        }
        (None, compare) => {
            let run = simulate_scene(scene, &options, reporter)?;
            runs.push((clearance_label(scene), scene, run, Role::Scene));
            if let Some(other) = compare {
                let run = simulate_scene(other, &options, reporter)?;
                runs.push((clearance_label(other), other, run, Role::Compared));
            }
        }
    }
    let models = runs
        .iter()
        .map(|(_, s, run, _)| model_that_ran(s, run, &options))
        .collect::<Result<Vec<_>>>()?;
    let takes: Vec<Take> = runs
        .iter()
        .zip(&models)
        .map(|((label, s, run, role), model)| Take {
            label: label.clone(),
            scene: s,
            run,
            model: model.model.as_ref(),
            color: hex(role.color()),
        })
        .collect();
    RunMovie::new(format!("{}: animated run", scene.name), &takes, animation)
}

/// The model `run` of `scene` ran on: the scene's configuration with the run's basis and
/// modes (an accuracy-driven run picks its own).
fn model_that_ran(
    scene: &Scene,
    run: &Simulation,
    options: &SimulationOptions,
) -> Result<crate::run::models::ChosenModel> {
    let mut params = scene.params.clone();
    params.basis = run.basis;
    for (section, &modes) in params.sections.iter_mut().zip(&run.modes) {
        section.modes = modes;
    }
    options.models.build(&params, options.model)
}

/// A colour as `#rrggbb`.
fn hex(c: plotters::style::RGBColor) -> String {
    format!("#{:02x}{:02x}{:02x}", c.0, c.1, c.2)
}

/// The modes of `scene` (with `options`) and their movie, drawn with `points` points per
/// section.
///
/// # Errors
/// [`Error::Option`] for fewer than 2 or more than 1000 points; the errors of
/// [`compute_modes`].
pub fn animate_modes(
    scene: &Scene,
    options: &ModesOptions,
    points: usize,
) -> Result<(ModesReport, ModeMovie)> {
    AnimationOptions {
        points,
        ..AnimationOptions::default()
    }
    .check()?;
    if options.count == Some(0) {
        return Err(Error::option(
            OptionName::ModesCount,
            "0: a modes' animation shows at least one mode",
        ));
    }
    let report = compute_modes(scene, options)?;
    if report.frequencies_hz.is_empty() {
        return Err(Error::option(
            OptionName::ModesCount,
            format!("scene {} has no vibration mode to animate", scene.name),
        ));
    }
    let chosen = options.models.build(&scene.params, options.model)?;
    let movie = ModeMovie::new(scene, &report, chosen.model.as_ref(), points);
    Ok((report, movie))
}

impl RunMovie {
    /// The self-contained HTML document of the movie.
    pub fn html(&self) -> String {
        page::document(&self.title, self)
    }
}

impl ModeMovie {
    /// The self-contained HTML document of the movie.
    pub fn html(&self) -> String {
        page::document(&self.title, self)
    }
}

/// What an animation file is, by its extension.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AnimationFormat {
    /// `.html` or `.htm`: the self-contained page.
    Html,
    /// `.gif`: the animated picture.
    Gif,
}

impl AnimationFormat {
    /// The format of `path` by its extension, after checking that it can be written.
    ///
    /// # Errors
    /// [`Error::Destination`] naming the path and the rule.
    pub fn of_path(path: &Path) -> Result<Self> {
        let format = match path.extension().and_then(|e| e.to_str()) {
            Some("html" | "htm") => AnimationFormat::Html,
            Some("gif") => AnimationFormat::Gif,
            // a device or a pipe (`/dev/null`, `/dev/stdout`) takes the page as a stream
            _ if matches!(Destination::of(path), Ok(Destination::Stream(_))) => {
                AnimationFormat::Html
            }
            _ => {
                return Err(Error::Destination {
                    path: path.to_path_buf(),
                    rule:
                        "the file name must end in .html, .htm or .gif (the format follows it); a \
                           device or pipe takes a page"
                            .into(),
                });
            }
        };
        crate::io::output::check_writable(path)?;
        Ok(format)
    }
}

/// Writes `movie` to `path` as HTML or GIF by its extension (completely or not at all; a
/// GIF frame by frame, with `reporter`'s progress, stopping when it asks); returns the
/// file's size (bytes).
///
/// # Errors
/// [`Error::Destination`], [`Error::Plot`], [`Error::Write`], or [`Error::Stopped`].
pub fn save_run(
    movie: &RunMovie,
    options: &AnimationOptions,
    path: &Path,
    reporter: &dyn Reporter,
) -> Result<u64> {
    match AnimationFormat::of_path(path)? {
        AnimationFormat::Html => {
            let bytes = movie.html().into_bytes();
            crate::io::output::write_atomically(path, |w| w.write_all(&bytes))?;
            Ok(bytes.len() as u64)
        }
        AnimationFormat::Gif => {
            memory::check_gif_frames(movie.frame_count() as u64, movie.fps)?;
            // streamed frame by frame; a failure or a stop between frames leaves no file
            let mut failure = None;
            let mut written = 0;
            let outcome = crate::io::output::write_atomically(path, |w| {
                let mut counted = CountingWriter { inner: w, bytes: 0 };
                let result = gif::write_gif(movie, options, &mut counted, reporter);
                written = counted.bytes;
                result.map_err(|e| {
                    failure = Some(e);
                    std::io::Error::other("the GIF was not finished")
                })
            });
            if let Some(error) = failure {
                return Err(error);
            }
            outcome?;
            Ok(written)
        }
    }
}

/// A writer that counts the bytes it passes on.
struct CountingWriter<'w> {
    inner: &'w mut dyn std::io::Write,
    bytes: u64,
}

impl std::io::Write for CountingWriter<'_> {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        let n = self.inner.write(buf)?;
        self.bytes += n as u64;
        Ok(n)
    }
    fn flush(&mut self) -> std::io::Result<()> {
        self.inner.flush()
    }
}

/// Writes the page of `movie` to `path` (completely or not at all); returns its size
/// (bytes).
///
/// # Errors
/// [`Error::Destination`] for a path that does not end in `.html`, or [`Error::Write`].
pub fn save_modes(movie: &ModeMovie, path: &Path) -> Result<u64> {
    if AnimationFormat::of_path(path)? != AnimationFormat::Html {
        return Err(Error::Destination {
            path: path.to_path_buf(),
            rule: "the modes' animation is a page: the file name must end in .html or .htm".into(),
        });
    }
    let bytes = movie.html().into_bytes();
    crate::io::output::write_atomically(path, |w| w.write_all(&bytes))?;
    Ok(bytes.len() as u64)
}

/// One line on a written movie: frames, rate, scale and size.
pub fn describe(movie: &RunMovie, path: &Path, bytes: u64) -> String {
    format!(
        "wrote {} ({} frames at {} per second of simulation, deflection x {}, {})",
        path.display(),
        movie.frame_count(),
        movie.fps,
        movie.scale,
        crate::io::size::human(bytes)
    )
}
