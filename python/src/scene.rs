//! `telescopic.Scene`: a validated scene with the text and overrides it came from, so that
//! `with_set` re-validates from the source like `--set` does.

use crate::errors::{argument, to_python};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};
use std::path::{Path, PathBuf};
use telescopic::Scene;

/// A scene: geometry, materials, masses, contacts, telescopic positions, drive and time span.
#[pyclass(name = "Scene", module = "telescopic._telescopic", frozen)]
pub struct PyScene {
    /// The validated scene.
    pub scene: Scene,
    text: String,
    origin: PathBuf,
    overrides: Vec<String>,
}

/// Deepest nesting of lists a `set=` value may have: a scene's deepest value is a list of
/// numbers inside a list; the bound keeps a hostile value from exhausting the stack.
const MAX_SET_DEPTH: usize = 8;

/// A Python value as a TOML value's text (numbers, booleans, strings, lists, NumPy scalars and
/// arrays), at most [`MAX_SET_DEPTH`] lists deep.
fn toml_value(key: &str, value: &Bound<'_, PyAny>, depth: usize) -> PyResult<String> {
    let bad = |rule: String| argument(&format!("set[{key:?}]"), rule);
    if value.is_instance_of::<PyBool>() {
        return Ok(value.extract::<bool>()?.to_string());
    }
    if value.is_instance_of::<PyInt>() {
        return value
            .extract::<i64>()
            .map(|v| v.to_string())
            .map_err(|_| bad("the integer does not fit in 64 bits".into()));
    }
    if value.is_instance_of::<PyString>() {
        return Ok(toml::Value::String(value.extract()?).to_string());
    }
    let listlike = value.is_instance_of::<PyList>() || value.is_instance_of::<PyTuple>();
    // NumPy arrays and scalars: `tolist` gives nested lists or the Python scalar
    if listlike || value.hasattr("tolist")? {
        if depth >= MAX_SET_DEPTH {
            return Err(bad(format!("lists nest deeper than {MAX_SET_DEPTH}")));
        }
        // a NumPy array becomes its nested list
        let list = if listlike {
            value.clone()
        } else {
            value.call_method0("tolist")?
        };
        if !(list.is_instance_of::<PyList>() || list.is_instance_of::<PyTuple>()) {
            return toml_value(key, &list, depth + 1);
        }
        let items: Vec<String> = list
            .try_iter()?
            .map(|item| toml_value(key, &item?, depth + 1))
            .collect::<PyResult<_>>()?;
        return Ok(format!("[{}]", items.join(", ")));
    }
    // NumPy integers have __index__; floats (Python's and NumPy's) __float__
    if !value.is_instance_of::<PyFloat>()
        && let Ok(v) = value.extract::<i64>()
    {
        return Ok(v.to_string());
    }
    match value.extract::<f64>() {
        Ok(v) if v.is_finite() => Ok(format!("{v:e}")),
        Ok(v) => Err(bad(format!("{v} is not a finite number"))),
        Err(_) => Err(bad(format!(
            "{} is not a number, string, bool or list",
            value.get_type().name()?
        ))),
    }
}

/// `{"contact.clearance": 0.005}` as `["contact.clearance=5e-3"]`.
pub fn overrides(set: Option<&Bound<'_, PyDict>>) -> PyResult<Vec<String>> {
    let Some(set) = set else {
        return Ok(Vec::new());
    };
    set.iter()
        .map(|(k, v)| {
            let key: String = k
                .extract()
                .map_err(|_| argument("set", "keys are dotted scene keys (strings)"))?;
            if key.contains('=') {
                return Err(argument(
                    &format!("set[{key:?}]"),
                    "a key holds no `=` (the value is the dictionary's)",
                ));
            }
            Ok(format!("{key}={}", toml_value(&key, &v, 0)?))
        })
        .collect()
}

impl PyScene {
    /// The file the scene was read from (or the name given for its text).
    pub fn origin(&self) -> &std::path::Path {
        &self.origin
    }

    fn build(text: String, origin: PathBuf, overrides: Vec<String>) -> PyResult<Self> {
        let scene = Scene::from_toml_str(&text, &origin, &overrides)
            .map_err(|e| to_python(telescopic::Error::Scene(e)))?;
        Ok(PyScene {
            scene,
            text,
            origin,
            overrides,
        })
    }
}

#[pymethods]
impl PyScene {
    /// Reads and validates a scene file, with `set` overrides (`{"contact.clearance": 0.005}`,
    /// the keys of `--set`).
    #[staticmethod]
    #[pyo3(signature = (path, set = None))]
    fn load(path: PathBuf, set: Option<&Bound<'_, PyDict>>) -> PyResult<Self> {
        let overrides = overrides(set)?;
        let text = telescopic::runtime::input::read_text(
            &path,
            telescopic::runtime::input::MAX_TEXT_INPUT_BYTES,
        )
        .map_err(|error| {
            to_python(telescopic::Error::Scene(
                telescopic::runtime::SceneError::Io {
                    path: path.clone(),
                    error,
                },
            ))
        })?;
        Self::build(text, path, overrides)
    }

    /// A scene from TOML text, with `set` overrides.
    #[staticmethod]
    #[pyo3(signature = (text, set = None))]
    fn from_toml(text: String, set: Option<&Bound<'_, PyDict>>) -> PyResult<Self> {
        Self::build(text, PathBuf::from("<string>"), overrides(set)?)
    }

    /// Pickling (multiprocessing with `spawn` needs it): the scene is rebuilt from its text,
    /// origin and overrides, and validated again.
    #[allow(clippy::type_complexity)]
    fn __reduce__<'py>(
        slf: &Bound<'py, Self>,
    ) -> PyResult<(Bound<'py, PyAny>, (String, String, Vec<String>))> {
        let restore = slf.get_type().getattr("_restore")?;
        let scene = slf.get();
        Ok((
            restore,
            (
                scene.text.clone(),
                scene.origin.to_string_lossy().into_owned(),
                scene.overrides.clone(),
            ),
        ))
    }

    /// The scene of a pickle: its text, origin and overrides.
    #[staticmethod]
    fn _restore(text: String, origin: String, overrides: Vec<String>) -> PyResult<Self> {
        Self::build(text, PathBuf::from(origin), overrides)
    }

    /// A new scene: this one with more overrides (checked like `--set`).
    fn with_set(&self, set: &Bound<'_, PyDict>) -> PyResult<Self> {
        let mut all = self.overrides.clone();
        all.extend(overrides(Some(set))?);
        Self::build(self.text.clone(), self.origin.clone(), all)
    }

    /// The scene as TOML, overrides applied.
    fn to_toml(&self) -> PyResult<String> {
        toml::to_string(&self.scene.file)
            .map_err(|e| crate::errors::TelescopicError::new_err(e.to_string()))
    }

    /// Short name.
    #[getter]
    fn name(&self) -> &str {
        &self.scene.name
    }

    /// One line on what the scene is.
    #[getter]
    fn description(&self) -> &str {
        &self.scene.description
    }

    /// `(start, end, sample)` (s).
    #[getter]
    fn time(&self) -> (f64, f64, f64) {
        let t = &self.scene.time;
        (t.start, t.end, t.sample)
    }

    /// The overrides applied, as `KEY=VALUE` strings.
    #[getter]
    fn overrides(&self) -> Vec<String> {
        self.overrides.clone()
    }

    /// The file it was read from (`<string>` for text).
    #[getter]
    fn path(&self) -> &Path {
        &self.origin
    }

    fn __repr__(&self) -> String {
        let p = &self.scene.params;
        let set = if self.overrides.is_empty() {
            String::new()
        } else {
            format!(", set {:?}", self.overrides)
        };
        format!(
            "Scene({:?}: {} section(s), modes {:?}, clearance {} m, t = {} .. {} s{set})",
            self.scene.name,
            p.sections.len(),
            p.modes(),
            p.contact.clearance,
            self.scene.time.start,
            self.scene.time.end
        )
    }
}

/// The text of an input file (a controller file), read with the size cap every input has:
/// a device or a huge file is refused, not read whole.
#[pyfunction]
pub fn read_input(path: PathBuf) -> PyResult<String> {
    telescopic::runtime::input::read_text(&path, telescopic::runtime::input::MAX_TEXT_INPUT_BYTES)
        .map_err(|error| {
            to_python(telescopic::Error::Input(format!(
                "{}: {error}",
                path.display()
            )))
        })
}
