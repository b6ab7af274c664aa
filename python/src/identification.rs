//! Identification for Python: `telescopic.identify` passes the record as named columns and
//! gets the fitted values, the sensors, the residuals and the validation as plain rows, the
//! fitted scene as TOML, and the report; `telescopic/__init__.py` makes DataFrames of them.

use crate::background::run_showing;
use crate::errors::{argument, to_python};
use crate::scene::PyScene;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use telescopic::identify::noise::parse_noise;
use telescopic::identify::{
    FreeValue, Identification, IdentifyOptions, Offsets, Record, SensorPrediction, Start,
    identify as fit, validate,
};
use telescopic::run::ModelSize;

/// A record's column names and columns.
type Columns = (Vec<String>, Vec<Vec<f64>>);

/// One dict per fitted value.
fn value_rows<'py>(py: Python<'py>, fit: &Identification) -> PyResult<Vec<Bound<'py, PyDict>>> {
    fit.values
        .iter()
        .map(|v| {
            let row = PyDict::new(py);
            row.set_item("key", &v.key)?;
            row.set_item("value", v.value)?;
            row.set_item("std", v.std)?;
            row.set_item("unit", v.unit)?;
            row.set_item("start", v.start)?;
            row.set_item("low", v.bounds.0)?;
            row.set_item("high", v.bounds.1)?;
            Ok(row)
        })
        .collect()
}

/// One dict per sensor.
fn sensor_rows<'py>(py: Python<'py>, fit: &Identification) -> PyResult<Vec<Bound<'py, PyDict>>> {
    fit.sensors
        .iter()
        .map(|s| {
            let row = PyDict::new(py);
            row.set_item("sensor", s.output.to_string())?;
            row.set_item("noise", s.noise.0)?;
            row.set_item("noise_source", s.noise.1.word())?;
            row.set_item("offset", s.offset)?;
            row.set_item("rms_residual", s.rms_residual)?;
            row.set_item("model_error", s.model_error)?;
            Ok(row)
        })
        .collect()
}

/// The residual of each sensor at each sample (fitted minus measured): `(names, rows)`.
fn residuals(fit: &Identification) -> (Vec<String>, Vec<Vec<f64>>) {
    let names = std::iter::once("t".to_string())
        .chain(fit.measured.names())
        .collect();
    let rows = fit
        .measured
        .rows
        .iter()
        .zip(&fit.fitted.rows)
        .map(|(m, f)| {
            std::iter::once(m[0])
                .chain(m[1..].iter().zip(&f[1..]).map(|(m, f)| f - m))
                .collect()
        })
        .collect();
    (names, rows)
}

/// Scene values fitted to a record (see `telescopic.identify`): `(values, sensors,
/// residuals, validation, fitted scene TOML, summary)`.
#[pyfunction]
#[pyo3(signature = (scene, record, free, noise = None, offsets = "fitted", size = None,
    until = None, unseen = None, progress = None, notes = true, start = "rest"))]
#[allow(clippy::too_many_arguments, clippy::type_complexity)]
pub fn identify<'py>(
    py: Python<'py>,
    scene: &PyScene,
    record: Columns,
    free: Vec<(String, Option<(f64, f64)>)>,
    noise: Option<String>,
    offsets: &str,
    size: Option<String>,
    until: Option<f64>,
    unseen: Option<Columns>,
    progress: Option<&Bound<'py, PyAny>>,
    notes: bool,
    start: &str,
) -> PyResult<(
    Vec<Bound<'py, PyDict>>,
    Vec<Bound<'py, PyDict>>,
    Columns,
    Option<Vec<Bound<'py, PyDict>>>,
    String,
    Bound<'py, PyDict>,
)> {
    let offsets: Offsets = offsets.parse().map_err(|rule| argument("offsets", rule))?;
    let start: Start = start.parse().map_err(|rule| argument("start", rule))?;
    let size = size
        .map(|s| {
            s.parse::<ModelSize>()
                .map_err(|rule| argument("size", rule))
        })
        .transpose()?;
    let options = IdentifyOptions {
        free: free
            .into_iter()
            .map(|(key, bounds)| FreeValue { key, bounds })
            .collect(),
        noise: noise
            .as_deref()
            .map(parse_noise)
            .transpose()
            .map_err(to_python)?
            .unwrap_or_default(),
        offsets,
        size,
        until,
        start,
    };
    let record = Record::from_columns("data", &record.0, record.1).map_err(to_python)?;
    let unseen = unseen
        .map(|(names, columns)| Record::from_columns("validate", &names, columns))
        .transpose()
        .map_err(to_python)?;
    let scene = &scene.scene;
    let (fit, predictions) = run_showing(py, progress, notes, |reporter| {
        let fit = fit(scene, &record, &options, reporter)?;
        let predictions = unseen
            .as_ref()
            .map(|u| validate(&fit, u, offsets, start))
            .transpose()?;
        Ok((fit, predictions))
    })?;
    let validation = predictions.map(|p| validation_rows(py, &p)).transpose()?;
    let summary = summary(py, &fit)?;
    Ok((
        value_rows(py, &fit)?,
        sensor_rows(py, &fit)?,
        residuals(&fit),
        validation,
        fit.scene_toml(),
        summary,
    ))
}

/// Each sensor's prediction of the unseen record as a dict.
fn validation_rows<'py>(
    py: Python<'py>,
    p: &[SensorPrediction],
) -> PyResult<Vec<Bound<'py, PyDict>>> {
    p.iter()
        .map(|s| {
            let row = PyDict::new(py);
            row.set_item("sensor", s.output.to_string())?;
            row.set_item("peak", s.peak)?;
            row.set_item("max_error", s.max_error)?;
            row.set_item("relative", s.relative())?;
            row.set_item("rms_error", s.rms_error)?;
            Ok(row)
        })
        .collect::<PyResult<Vec<_>>>()
}

/// The fit's summary: its report, model, runs, window, correlation, start and force noise.
fn summary<'py>(py: Python<'py>, fit: &Identification) -> PyResult<Bound<'py, PyDict>> {
    let summary = PyDict::new(py);
    summary.set_item("text", fit.to_text())?;
    summary.set_item("size", fit.model.size.to_string())?;
    summary.set_item("runs", fit.runs)?;
    summary.set_item("wall_s", fit.wall_s)?;
    summary.set_item("window", &fit.window)?;
    summary.set_item(
        "start_vehicle_speed",
        fit.start.and_then(|s| s.vehicle_speed),
    )?;
    summary.set_item("start_amplitudes", fit.start.map_or(0, |s| s.amplitudes))?;
    summary.set_item("force_noise", fit.force_noise)?;
    summary.set_item("correlated", &fit.correlated)?;
    summary.set_item("correlation", &fit.correlation)?;
    Ok(summary)
}
