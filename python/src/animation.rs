//! Animated views for Python: a run's or a scene's modes' page as a `Movie` that
//! `telescopic/__init__.py` wraps in an object Jupyter shows inline.

use crate::background::run;
use crate::errors::{argument, to_python};
use crate::scene::PyScene;
use pyo3::prelude::*;
use std::path::PathBuf;
use telescopic::analysis::modes::ModesOptions;
use telescopic::animate::geometry::DEFAULT_POINTS;
use telescopic::animate::options::{DEFAULT_GIF_FPS, DEFAULT_PAGE_FPS};
use telescopic::animate::{
    AnimationFormat, AnimationOptions, ModeMovie, RunMovie, RunRequest, animate_modes, animate_run,
    save_modes, save_run,
};
use telescopic::run::SimulationOptions;

/// A finished movie: its page, and for a run what a GIF needs.
#[pyclass(name = "Movie", module = "telescopic._telescopic", frozen)]
pub struct PyMovie {
    movie: Movie,
    options: AnimationOptions,
    /// The files the movie was made from: `save` never writes onto one of them (through a
    /// symbolic link either).
    inputs: Vec<PathBuf>,
    /// Whether the caller chose the frame rate: else a GIF takes the CLI's GIF rate.
    fps_given: bool,
}

/// What a [`PyMovie`] shows.
enum Movie {
    Run(RunMovie),
    Modes(ModeMovie),
}

#[pymethods]
impl PyMovie {
    /// The self-contained HTML document.
    #[getter]
    fn html(&self) -> String {
        match &self.movie {
            Movie::Run(m) => m.html(),
            Movie::Modes(m) => m.html(),
        }
    }

    /// Frames (a run) or modes (a modes' movie).
    #[getter]
    fn frame_count(&self) -> usize {
        match &self.movie {
            Movie::Run(m) => m.frame_count(),
            Movie::Modes(m) => m.modes.len(),
        }
    }

    /// Writes the movie to `path` (.html, or .gif for a run), completely or not at all;
    /// returns its size in bytes.
    fn save(&self, py: Python<'_>, path: PathBuf) -> PyResult<u64> {
        let inputs: Vec<&std::path::Path> = self.inputs.iter().map(PathBuf::as_path).collect();
        telescopic::io::output::check_not_an_input(&path, &inputs).map_err(to_python)?;
        // off the interpreter, a Ctrl-C stopping a GIF between frames (no file is left)
        run(py, None, |reporter| match &self.movie {
            Movie::Run(m)
                if !self.fps_given && AnimationFormat::of_path(&path)? == AnimationFormat::Gif =>
            {
                // the GIF's rate, as `telescopic animate` gives a .gif (the page's is double)
                save_run(&m.at_rate(DEFAULT_GIF_FPS), &self.options, &path, reporter)
            }
            Movie::Run(m) => save_run(m, &self.options, &path, reporter),
            Movie::Modes(m) => save_modes(m, &path),
        })
    }
}

/// A run's movie (see `telescopic.Simulation.animate`).
#[pyfunction]
#[pyo3(signature = (scene, options, controller = None, compare = None, fps = None, scale = None,
    size = None, speed = None, progress = None, weighed_load = None))]
#[allow(clippy::too_many_arguments)]
pub fn animate(
    py: Python<'_>,
    scene: &PyScene,
    options: crate::calls::RunArguments,
    controller: Option<String>,
    compare: Option<&PyScene>,
    fps: Option<f64>,
    scale: Option<f64>,
    size: Option<(Bound<'_, PyAny>, Bound<'_, PyAny>)>,
    speed: Option<f64>,
    progress: Option<&Bound<'_, PyAny>>,
    weighed_load: Option<f64>,
) -> PyResult<PyMovie> {
    let defaults = AnimationOptions::default();
    let animation = AnimationOptions {
        fps: fps.unwrap_or(DEFAULT_PAGE_FPS),
        scale,
        size: match &size {
            Some((w, h)) => (pixels(w)?, pixels(h)?),
            None => defaults.size,
        },
        speed: speed.unwrap_or(defaults.speed),
        ..defaults
    };
    let simulation: SimulationOptions = options.into_options()?;
    animation.check().map_err(to_python)?;
    let controller = crate::calls::controller_of(controller.as_deref(), weighed_load)?;
    let request = RunRequest {
        scene: &scene.scene,
        options: simulation,
        controller: controller.as_ref(),
        compare: compare.map(|c| &c.scene),
    };
    // a view is a page: its memory is priced before the runs
    request.check_page(animation.fps).map_err(to_python)?;
    let movie = run(py, progress, |reporter| {
        animate_run(&request, &animation, reporter)
    })?;
    let mut inputs = vec![scene.origin().to_path_buf()];
    inputs.extend(compare.map(|c| c.origin().to_path_buf()));
    Ok(PyMovie {
        movie: Movie::Run(movie),
        options: animation,
        inputs,
        fps_given: fps.is_some(),
    })
}

/// A scene's modes' movie (see `telescopic.Modes.animate`).
#[pyfunction]
#[pyo3(signature = (scene, at = None, count = None, model = "auto"))]
pub fn animate_modes_of(
    py: Python<'_>,
    scene: &PyScene,
    at: Option<f64>,
    count: Option<Bound<'_, PyAny>>,
    model: &str,
) -> PyResult<PyMovie> {
    let options = ModesOptions {
        at,
        count: count
            .map(|c| crate::calls::whole("count", &c))
            .transpose()?,
        model: model.parse().map_err(|e| argument("model", e))?,
        memory_budget: crate::calls::memory_budget()?,
        ..ModesOptions::default()
    };
    let inputs = vec![scene.origin().to_path_buf()];
    let scene = &scene.scene;
    let (_, movie) = run(py, None, |_| animate_modes(scene, &options, DEFAULT_POINTS))?;
    Ok(PyMovie {
        movie: Movie::Modes(movie),
        options: AnimationOptions::default(),
        inputs,
        fps_given: false,
    })
}

/// A GIF's width or height (pixels), or an error naming `size` (its range is the library's
/// to judge).
fn pixels(value: &Bound<'_, PyAny>) -> PyResult<u32> {
    let n = crate::calls::whole("size", value)?;
    u32::try_from(n).map_err(|_| argument("size", format!("{n} pixels is far above any size")))
}
