//! The library's entry points for Python: each checks its arguments (errors name them), runs
//! the work off the GIL ([`crate::background::run`]) and returns plain data (NumPy arrays,
//! lists, dicts) that `telescopic/__init__.py` wraps in the objects users see.

use crate::background::run;
use crate::errors::{argument, to_python};
use crate::scene::PyScene;
use numpy::{PyArray1, PyArray2, ndarray::Array2};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::PathBuf;
use std::str::FromStr;
use telescopic::analysis::modes::{ModeKind, ModesOptions, compute_modes};
use telescopic::control::{ControllerFile, ControllerKind, DesignOptions, design as run_design};
use telescopic::linear::{Grid, LinearizeOptions, linearize as run_linearize};
use telescopic::run::models::ModelChoice;
use telescopic::run::stress::Station;
use telescopic::run::{MethodChoice, Simulation, SimulationOptions, simulate_scene};
use telescopic::runtime::ContactMode;

use crate::environment::MEMORY_BUDGET_VARIABLE;

/// The calls' memory budget (bytes): [`MEMORY_BUDGET_VARIABLE`], else the library's default.
pub fn memory_budget() -> PyResult<u64> {
    let text = std::env::var(MEMORY_BUDGET_VARIABLE).ok();
    telescopic::run::memory::parse_budget(text.as_deref()).map_err(to_python)
}

/// `value` parsed by `FromStr`, or an error naming `name`.
fn parsed<T: FromStr>(name: &str, value: &str) -> PyResult<T>
where
    T::Err: std::fmt::Display,
{
    value.parse().map_err(|e| argument(name, e))
}

/// A whole number `>= 0` (a count or a section number), or an error naming `name`: PyO3's own
/// conversion to `usize` raises an `OverflowError` that names no argument.
pub fn whole(name: &str, value: &Bound<'_, PyAny>) -> PyResult<usize> {
    let number: i64 = value
        .extract()
        .map_err(|_| argument(name, format!("must be a whole number (got {value})")))?;
    usize::try_from(number)
        .map_err(|_| argument(name, format!("must be a whole number >= 0 (got {number})")))
}

/// `linearize`'s grid as Python gives it, `(position, (from, to, count))`, the count left
/// unconverted so that a count that is no whole number names the grid.
type GridArgument<'py> = (String, (f64, f64, Bound<'py, PyAny>));

/// A simulation for Python: `(columns, data, summary)`, `data` samples x (1 + columns).
type SimulationData<'py> = (Vec<String>, Bound<'py, PyArray2<f64>>, Bound<'py, PyDict>);

/// A simulation as `(columns, data, summary)`: `data` is samples x (1 + columns), `t` first.
fn simulation_data<'py>(py: Python<'py>, sim: &Simulation) -> PyResult<SimulationData<'py>> {
    let traj = &sim.trajectory;
    let width = traj.columns.len() + 1;
    let flat: Vec<f64> = traj.rows.iter().flatten().copied().collect();
    let array = Array2::from_shape_vec((traj.rows.len(), width), flat)
        .map_err(|e| crate::errors::TelescopicError::new_err(e.to_string()))?;
    let summary = summary_dict(py, sim)?;
    Ok((traj.names(), PyArray2::from_owned_array(py, array), summary))
}

/// The run's summary ([`telescopic::run::RunSummary`]) as a dict with the same keys; each
/// statistic of the error budget as a tuple `(value, relative)`.
fn summary_dict<'py>(py: Python<'py>, sim: &Simulation) -> PyResult<Bound<'py, PyDict>> {
    let json = sim.run_summary().to_json();
    let summary = py
        .import("json")?
        .call_method1("loads", (json,))?
        .cast_into::<PyDict>()?;
    if let Some(error) = summary.get_item("error")?
        && let Ok(error) = error.cast::<PyDict>()
        && let Some(statistics) = error.get_item("statistics")?
    {
        let statistics = statistics.cast::<PyDict>()?;
        for (name, pair) in statistics.iter() {
            let pair: Vec<f64> = pair.extract()?;
            if let [value, relative] = pair[..] {
                statistics.set_item(name, (value, relative))?;
            }
        }
    }
    Ok(summary)
}

/// How a run is asked for from Python, as a dict with these keys (what
/// `telescopic.Simulation` keeps to run its scene again).
#[derive(FromPyObject)]
#[pyo3(from_item_all)]
pub struct RunArguments {
    method: String,
    rtol: Option<f64>,
    atol: Option<f64>,
    dt: Option<f64>,
    accuracy: Option<f64>,
    model: String,
    modes_as_given: bool,
}

impl RunArguments {
    /// The library's options (errors name the argument).
    pub fn into_options(self) -> PyResult<SimulationOptions> {
        Ok(SimulationOptions {
            method: parsed::<MethodChoice>("method", &self.method)?,
            rtol: self.rtol,
            atol: self.atol,
            dt: self.dt,
            accuracy: self.accuracy,
            model: parsed::<ModelChoice>("model", &self.model)?,
            modes_as_given: self.modes_as_given,
            memory_budget: memory_budget()?,
            ..SimulationOptions::default()
        })
    }
}

/// Simulates a scene (see `telescopic.simulate`).
#[pyfunction]
#[pyo3(signature = (scene, method = "auto", rtol = None, atol = None, dt = None, accuracy = None,
    controller = None, stations = None, model = "auto", progress = None, modes_as_given = false,
    error_estimate = true, moment_tolerance = None, statistics_tolerance = None, reuse = true,
    weighed_load = None))]
#[allow(clippy::too_many_arguments)]
pub fn simulate<'py>(
    py: Python<'py>,
    scene: &PyScene,
    method: &str,
    rtol: Option<f64>,
    atol: Option<f64>,
    dt: Option<f64>,
    accuracy: Option<f64>,
    controller: Option<String>,
    stations: Option<Vec<(Bound<'py, PyAny>, f64)>>,
    model: &str,
    progress: Option<&Bound<'py, PyAny>>,
    modes_as_given: bool,
    error_estimate: bool,
    moment_tolerance: Option<f64>,
    statistics_tolerance: Option<f64>,
    reuse: bool,
    weighed_load: Option<f64>,
) -> PyResult<SimulationData<'py>> {
    let defaults = SimulationOptions::default();
    let stations = stations
        .unwrap_or_default()
        .into_iter()
        .map(|(section, x)| {
            Ok(Station {
                section: whole("stations", &section)?,
                x,
            })
        })
        .collect::<PyResult<Vec<Station>>>()?;
    let options = SimulationOptions {
        method: parsed::<MethodChoice>("method", method)?,
        rtol,
        atol,
        dt,
        accuracy,
        model: parsed::<ModelChoice>("model", model)?,
        stations,
        modes_as_given,
        error_estimate,
        moment_tolerance: moment_tolerance.unwrap_or(defaults.moment_tolerance),
        statistics_tolerance: statistics_tolerance.unwrap_or(defaults.statistics_tolerance),
        memory_budget: memory_budget()?,
        reuse: reuse.then(telescopic::run::reuse::default_dir).flatten(),
        ..SimulationOptions::default()
    };
    let controller = controller_of(controller.as_deref(), weighed_load)?;
    let scene = &scene.scene;
    let sim = run(py, progress, |reporter| match &controller {
        Some(c) => c.simulate(scene, &options, reporter),
        None => simulate_scene(scene, &options.for_scene(scene), reporter),
    })?;
    simulation_data(py, &sim)
}

/// The controller of JSON `text`, its velocity feedback told the `weighed` load (kg) when
/// one is given.
pub(crate) fn controller_of(
    text: Option<&str>,
    weighed: Option<f64>,
) -> PyResult<Option<ControllerFile>> {
    let Some(text) = text else {
        return match weighed {
            Some(_) => Err(to_python(telescopic::Error::option(
                telescopic::OptionName::WeighedLoad,
                "tells a controller's velocity feedback the load: give a controller",
            ))),
            None => Ok(None),
        };
    };
    let file = ControllerFile::from_json(text).map_err(to_python)?;
    Ok(Some(match weighed {
        Some(load) => file.with_weighed_load(load).map_err(to_python)?,
        None => file,
    }))
}

/// Natural frequencies, damping and mode shapes (see `telescopic.modes`).
#[pyfunction]
#[pyo3(signature = (scene, at = None, count = None, points = None, model = "auto"))]
pub fn modes<'py>(
    py: Python<'py>,
    scene: &PyScene,
    at: Option<f64>,
    count: Option<Bound<'py, PyAny>>,
    points: Option<Bound<'py, PyAny>>,
    model: &str,
) -> PyResult<Bound<'py, PyDict>> {
    let options = ModesOptions {
        at,
        count: count.map(|c| whole("count", &c)).transpose()?,
        shapes: Some(points.map_or(Ok(51), |p| whole("points", &p))?),
        model: parsed("model", model)?,
        memory_budget: memory_budget()?,
        ..ModesOptions::default()
    };
    let scene = &scene.scene;
    let report = run(py, None, |_| compute_modes(scene, &options))?;
    let out = PyDict::new(py);
    out.set_item("scene", &report.scene)?;
    out.set_item("time_s", report.time_s)?;
    out.set_item("model", &report.model)?;
    out.set_item(
        "frequencies_hz",
        PyArray1::from_slice(py, &report.frequencies_hz),
    )?;
    out.set_item(
        "damped_frequencies_hz",
        PyArray1::from_slice(py, &report.damped_frequencies_hz),
    )?;
    out.set_item(
        "damping_ratios",
        PyArray1::from_slice(py, &report.damping_ratios),
    )?;
    let kinds: Vec<&str> = report
        .kinds
        .iter()
        .map(|k| match k {
            ModeKind::Structural => "structural",
            ModeKind::Contact => "contact",
        })
        .collect();
    out.set_item("kinds", kinds)?;
    out.set_item("rigid_modes", report.rigid_modes)?;
    let shapes: Vec<Vec<Bound<'py, PyArray1<f64>>>> = report
        .mode_shapes
        .iter()
        .flatten()
        .map(|m| {
            m.sections
                .iter()
                .map(|w| PyArray1::from_slice(py, w))
                .collect()
        })
        .collect();
    out.set_item("shapes", shapes)?;
    out.set_item("table", report.to_table())?;
    Ok(out)
}

/// `{"a2": 0.8}` as `[(2, 0.8)]`, each name and value judged by the library's rules.
fn positions(map: Option<Vec<(String, f64)>>) -> PyResult<Vec<(usize, f64)>> {
    map.unwrap_or_default()
        .iter()
        .map(|(name, value)| telescopic::linear::position_value(name, *value))
        .collect::<Result<_, _>>()
        .map_err(|e| argument("positions", e))
}

/// Linear models (see `telescopic.linearize`).
#[pyfunction]
#[pyo3(signature = (scene, positions = None, at_time = None, contacts = "closed", grid = None,
    disturbance = false, discrete = None, model = "auto"))]
#[allow(clippy::too_many_arguments)]
pub fn linearize<'py>(
    py: Python<'py>,
    scene: &PyScene,
    positions: Option<Vec<(String, f64)>>,
    at_time: Option<f64>,
    contacts: &str,
    grid: Option<GridArgument<'py>>,
    disturbance: bool,
    discrete: Option<f64>,
    model: &str,
) -> PyResult<Bound<'py, PyDict>> {
    let contacts = parsed::<ContactMode>("contacts", contacts)?;
    let grid = match grid {
        Some((name, (from, to, count))) => {
            let count = whole("grid", &count)?;
            Some(Grid::new(&name, from, to, count).map_err(|e| argument("grid", e))?)
        }
        None => None,
    };
    let options = LinearizeOptions {
        positions: self::positions(positions)?,
        at_time,
        contacts,
        grid,
        model: parsed("model", model)?,
        disturbance,
        discrete,
        memory_budget: memory_budget()?,
        ..LinearizeOptions::default()
    };
    let scene = &scene.scene;
    let export = run(py, None, |_| run_linearize(scene, &options))?;
    let out = PyDict::new(py);
    let names = |s: &[telescopic::runtime::Signal]| -> Vec<String> {
        s.iter().map(|x| x.name.clone()).collect()
    };
    out.set_item("states", names(&export.states))?;
    out.set_item("inputs", names(&export.inputs))?;
    out.set_item("outputs", names(&export.outputs))?;
    out.set_item("operating_point", &export.operating_point)?;
    out.set_item("model", &export.model)?;
    let matrix = |m: &telescopic::runtime::nalgebra::DMatrix<f64>| {
        let rows: Vec<Vec<f64>> = m.row_iter().map(|r| r.iter().copied().collect()).collect();
        PyArray2::from_vec2(py, &rows)
            .map_err(|e| crate::errors::TelescopicError::new_err(e.to_string()))
    };
    let mut points = Vec::new();
    for (k, p) in export.points.iter().enumerate() {
        let d = PyDict::new(py);
        d.set_item("A", matrix(&p.a)?)?;
        d.set_item("B", matrix(&p.b)?)?;
        d.set_item("C", matrix(&p.c)?)?;
        d.set_item("D", matrix(&p.d)?)?;
        let named = PyDict::new(py);
        for (i, a) in p.positions.iter().enumerate() {
            named.set_item(format!("a{}", i + 2), a)?;
        }
        d.set_item("positions", named)?;
        if let Some(disc) = &export.discrete {
            d.set_item("Ad", matrix(&disc.points[k].0)?)?;
            d.set_item("Bd", matrix(&disc.points[k].1)?)?;
            d.set_item("dt", disc.dt)?;
        }
        points.push(d);
    }
    out.set_item("points", points)?;
    out.set_item("grid", export.grid.clone())?;
    out.set_item(
        "json",
        serde_json::to_string(&export.to_json()).unwrap_or_default(),
    )?;
    Ok(out)
}

/// Designs a controller; returns its JSON (see `telescopic.design`).
#[pyfunction]
#[pyo3(signature = (scene, controller = None, force_limit = None, sensors = None,
    rate_hz = None, law = None, shaper_timing = None, tip_scale = None, vehicle_scale = None,
    estimator = None, process_noise_floor = None, added_damping = None, model = "auto",
    progress = None))]
#[allow(clippy::too_many_arguments)]
pub fn design(
    py: Python<'_>,
    scene: &PyScene,
    controller: Option<&str>,
    force_limit: Option<f64>,
    sensors: Option<Vec<String>>,
    rate_hz: Option<f64>,
    law: Option<&str>,
    shaper_timing: Option<&str>,
    tip_scale: Option<f64>,
    vehicle_scale: Option<f64>,
    estimator: Option<&str>,
    process_noise_floor: Option<f64>,
    added_damping: Option<f64>,
    model: &str,
    progress: Option<&Bound<'_, PyAny>>,
) -> PyResult<String> {
    let defaults = DesignOptions::default();
    let options = DesignOptions {
        kind: match controller {
            Some(text) => parsed::<ControllerKind>("controller", text)?,
            None => defaults.kind,
        },
        force_limit: force_limit.unwrap_or(defaults.force_limit),
        sensors: sensors.unwrap_or(defaults.sensors.clone()),
        rate_hz: rate_hz.unwrap_or(defaults.rate_hz),
        law: match law {
            Some(text) => parsed("law", text)?,
            None => defaults.law,
        },
        shaper_timing: match shaper_timing {
            Some(text) => parsed("shaper_timing", text)?,
            None => defaults.shaper_timing,
        },
        tip_scale: tip_scale.unwrap_or(defaults.tip_scale),
        vehicle_scale: vehicle_scale.unwrap_or(defaults.vehicle_scale),
        estimator: match estimator {
            Some(text) => parsed("estimator", text)?,
            None => defaults.estimator,
        },
        process_noise_floor: process_noise_floor.unwrap_or(defaults.process_noise_floor),
        added_damping: added_damping.unwrap_or(defaults.added_damping),
        model: parsed("model", model)?,
        memory_budget: memory_budget()?,
        ..defaults
    };
    let scene = &scene.scene;
    let controller = run(py, progress, |_| run_design(scene, &options))?;
    Ok(controller.to_json())
}

/// Checks a controller's JSON (a designed controller or a plan's velocity feedback);
/// returns it (see `telescopic.Controller.from_json`).
#[pyfunction]
pub fn check_controller(text: &str) -> PyResult<String> {
    match ControllerFile::from_json(text).map_err(to_python)? {
        ControllerFile::Force(c) => Ok(c.to_json()),
        ControllerFile::Velocity { file, .. } => Ok(file.to_json()),
    }
}

/// Runs a sweep (a file, or a dict of a sweep file's keys) into `out`; returns `(columns,
/// rows)` of the result (see `telescopic.sweep`).
#[pyfunction]
#[pyo3(signature = (spec, out, jobs = None, progress = None))]
pub fn sweep(
    py: Python<'_>,
    spec: &Bound<'_, PyAny>,
    out: PathBuf,
    jobs: Option<Bound<'_, PyAny>>,
    progress: Option<&Bound<'_, PyAny>>,
) -> PyResult<(String, Vec<String>)> {
    let jobs = match jobs {
        Some(j) => whole("jobs", &j)?,
        None => std::thread::available_parallelism().map_or(1, std::num::NonZeroUsize::get),
    };
    let options = telescopic::sweep::SweepOptions {
        out: out.clone(),
        jobs,
        shard: telescopic::sweep::Shard::whole(),
        resume: false,
        memory_budget: memory_budget()?,
        cancel: telescopic::Cancel::default(),
    };
    // a dict is the sweep file's keys as values: a relative scene is the current directory's
    let table = match spec.cast::<PyDict>() {
        Ok(dict) => Some(crate::scene::toml_table("spec", dict, 0)?),
        Err(_) => None,
    };
    let path: PathBuf = match table {
        Some(_) => PathBuf::from("<the sweep dict>"),
        None => spec.extract().map_err(|_| {
            argument(
                "spec",
                "a sweep file's path or a dict of a sweep file's keys",
            )
        })?,
    };
    let result = run(py, progress, |reporter| {
        let sweep = match table {
            Some(table) => {
                telescopic::sweep::Sweep::from_table(table, &path, options.memory_budget)?
            }
            None => telescopic::sweep::Sweep::load_within(&path, options.memory_budget)?,
        };
        let options = telescopic::sweep::SweepOptions {
            cancel: reporter.cancel.clone(),
            ..options
        };
        telescopic::sweep::run_sweep(&sweep, &options, reporter)?;
        telescopic::sweep::read_table(&out)
    });
    match result {
        Ok(table) => Ok((
            table.columns,
            table.rows.into_iter().map(|(_, r)| r).collect(),
        )),
        Err(e) => {
            // nothing of an interrupted or failed sweep stays
            telescopic::sweep::discard_sweep(&out);
            Err(e)
        }
    }
}

/// The derived equations as text, LaTeX, Rust or JSON (see `telescopic.equations`).
#[pyfunction]
#[pyo3(signature = (scene, format = "latex"))]
pub fn equations(scene: &PyScene, format: &str) -> PyResult<String> {
    let format = parsed::<telescopic::analysis::equations::EquationFormat>("format", format)?;
    telescopic::analysis::equations::equations(&scene.scene, format, &Default::default())
        .map(str::to_string)
        .map_err(to_python)
}

/// Benchmark aid: wall times (s) of `repeat` calls of the library's `simulate_scene` on
/// `scene`, measured in Rust (no Python in the loop), against which `telescopic.simulate`'s
/// overhead is measured (python/benchmarks/overhead.py).
#[pyfunction]
pub fn _time_simulate(py: Python<'_>, scene: &PyScene, repeat: usize) -> PyResult<Vec<f64>> {
    let scene = &scene.scene;
    run(py, None, |reporter| {
        (0..repeat)
            .map(|_| {
                let start = std::time::Instant::now();
                simulate_scene(scene, &SimulationOptions::default(), reporter)?;
                Ok(start.elapsed().as_secs_f64())
            })
            .collect()
    })
}
