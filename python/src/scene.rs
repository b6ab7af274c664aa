//! `telescopic.Scene`: a validated scene with the text and overrides it came from, so that
//! `with_set` re-validates from the source like `--set` does.

use crate::errors::{argument, to_python};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};
use std::path::{Path, PathBuf};
use telescopic::Scene;
use telescopic::runtime::scene::SceneEdit;

/// A scene: geometry, materials, masses, contacts, telescopic positions, drive and time span.
#[pyclass(name = "Scene", module = "telescopic._telescopic", frozen)]
pub struct PyScene {
    /// The validated scene.
    pub scene: Scene,
    text: String,
    origin: PathBuf,
    edits: Vec<SceneEdit>,
}

/// Deepest nesting of lists a `set=` value may have: a scene's deepest value is a list of
/// numbers inside a list; the bound keeps a hostile value from exhausting the stack.
const MAX_SET_DEPTH: usize = 8;

/// A Python value as a TOML value (numbers, booleans, strings, lists, dicts, NumPy scalars
/// and arrays), at most [`MAX_SET_DEPTH`] lists or dicts deep; `what` names it in errors.
pub fn toml_value(what: &str, value: &Bound<'_, PyAny>, depth: usize) -> PyResult<toml::Value> {
    let bad = |rule: String| argument(what, rule);
    if value.is_instance_of::<PyBool>() {
        return Ok(toml::Value::Boolean(value.extract()?));
    }
    if value.is_instance_of::<PyInt>() {
        return value
            .extract::<i64>()
            .map(toml::Value::Integer)
            .map_err(|_| bad("the integer does not fit in 64 bits".into()));
    }
    if value.is_instance_of::<PyString>() {
        return Ok(toml::Value::String(value.extract()?));
    }
    if depth >= MAX_SET_DEPTH {
        return Err(bad(format!("lists nest deeper than {MAX_SET_DEPTH}")));
    }
    if let Ok(dict) = value.cast::<PyDict>() {
        return toml_table(what, dict, depth + 1).map(toml::Value::Table);
    }
    let listlike = value.is_instance_of::<PyList>() || value.is_instance_of::<PyTuple>();
    // NumPy arrays and scalars: `tolist` gives nested lists or the Python scalar
    if listlike || value.hasattr("tolist")? {
        let list = if listlike {
            value.clone()
        } else {
            value.call_method0("tolist")?
        };
        if !(list.is_instance_of::<PyList>() || list.is_instance_of::<PyTuple>()) {
            return toml_value(what, &list, depth + 1);
        }
        return list
            .try_iter()?
            .map(|item| toml_value(what, &item?, depth + 1))
            .collect::<PyResult<Vec<_>>>()
            .map(toml::Value::Array);
    }
    // NumPy integers have __index__; floats (Python's and NumPy's) __float__
    if !value.is_instance_of::<PyFloat>()
        && let Ok(v) = value.extract::<i64>()
    {
        return Ok(toml::Value::Integer(v));
    }
    match value.extract::<f64>() {
        Ok(v) if v.is_finite() => Ok(toml::Value::Float(v)),
        Ok(v) => Err(bad(format!("{v} is not a finite number"))),
        Err(_) => Err(bad(format!(
            "{} is not a number, string, bool, list or dict",
            value.get_type().name()?
        ))),
    }
}

/// A Python dict with string keys as a TOML table.
pub fn toml_table(what: &str, dict: &Bound<'_, PyDict>, depth: usize) -> PyResult<toml::Table> {
    dict.iter()
        .map(|(k, v)| {
            let key: String = k
                .extract()
                .map_err(|_| argument(what, "keys are strings"))?;
            let value = toml_value(&format!("{what}[{key:?}]"), &v, depth)?;
            Ok((key, value))
        })
        .collect()
}

/// `{"contact.clearance": 0.005}` as typed scene edits.
pub fn edits(set: Option<&Bound<'_, PyDict>>) -> PyResult<Vec<SceneEdit>> {
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
            let value = toml_value(&format!("set[{key:?}]"), &v, 0)?;
            Ok(SceneEdit::new(key, value))
        })
        .collect()
}

impl PyScene {
    /// The file the scene was read from (or the name given for its text).
    pub fn origin(&self) -> &std::path::Path {
        &self.origin
    }

    fn build(text: String, origin: PathBuf, edits: Vec<SceneEdit>) -> PyResult<Self> {
        let scene = Scene::from_toml_edited(&text, &origin, &edits)
            .map_err(|e| to_python(telescopic::Error::Scene(e)))?;
        Ok(PyScene {
            scene,
            text,
            origin,
            edits,
        })
    }

    /// The edits as `KEY=VALUE` text, as `--set` reads them.
    fn edit_texts(&self) -> Vec<String> {
        self.edits.iter().map(SceneEdit::to_string).collect()
    }
}

#[pymethods]
impl PyScene {
    /// Reads and validates a scene file, with `set` overrides (`{"contact.clearance": 0.005}`,
    /// the keys of `--set`).
    #[staticmethod]
    #[pyo3(signature = (path, set = None))]
    fn load(path: PathBuf, set: Option<&Bound<'_, PyDict>>) -> PyResult<Self> {
        let edits = edits(set)?;
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
        Self::build(text, path, edits)
    }

    /// A scene from TOML text, with `set` overrides.
    #[staticmethod]
    #[pyo3(signature = (text, set = None))]
    fn from_toml(text: String, set: Option<&Bound<'_, PyDict>>) -> PyResult<Self> {
        Self::build(text, PathBuf::from("<string>"), edits(set)?)
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
                scene.edit_texts(),
            ),
        ))
    }

    /// The scene of a pickle: its text, origin and overrides.
    #[staticmethod]
    fn _restore(text: String, origin: String, overrides: Vec<String>) -> PyResult<Self> {
        let edits =
            SceneEdit::parse_all(&overrides).map_err(|e| to_python(telescopic::Error::Scene(e)))?;
        Self::build(text, PathBuf::from(origin), edits)
    }

    /// A new scene: this one with more overrides (checked like `--set`).
    fn with_set(&self, set: &Bound<'_, PyDict>) -> PyResult<Self> {
        let mut all = self.edits.clone();
        all.extend(edits(Some(set))?);
        Self::build(self.text.clone(), self.origin.clone(), all)
    }

    /// The scene as TOML, overrides applied.
    fn to_toml(&self) -> String {
        self.scene.file.to_toml()
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
        self.edit_texts()
    }

    /// The file it was read from (`<string>` for text).
    #[getter]
    fn path(&self) -> &Path {
        &self.origin
    }

    fn __repr__(&self) -> String {
        let p = &self.scene.params;
        let set = if self.edits.is_empty() {
            String::new()
        } else {
            format!(", set {:?}", self.edit_texts())
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
        .map_err(|error| to_python(telescopic::Error::input(path.display(), error)))
}
