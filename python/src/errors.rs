//! The library's errors as Python exceptions: `TelescopicError` and its subclasses
//! `SceneError` (with `.errors`, a list of `(field, rule)`), `OptionError` (a bad argument,
//! named), `SolverError` (with `.time` and `.method` of a numerical failure).

use pyo3::create_exception;
use pyo3::exceptions::PyException;
use pyo3::prelude::*;

create_exception!(
    _telescopic,
    TelescopicError,
    PyException,
    "An error of telescopic; the message is complete on its own."
);
create_exception!(
    _telescopic,
    SceneError,
    TelescopicError,
    "A scene that cannot be read or breaks a rule; `.errors` lists (field, rule)."
);
create_exception!(
    _telescopic,
    OptionError,
    TelescopicError,
    "A bad argument (an unknown method, a negative tolerance, ...), named in the message."
);
create_exception!(
    _telescopic,
    SolverError,
    TelescopicError,
    "A numerical failure: `.time` (s), `.method` and the likely cause in the message."
);

/// The Python exception of a library error.
pub fn to_python(error: telescopic::Error) -> PyErr {
    use telescopic::Error;
    let message = error.to_string();
    Python::attach(|py| match &error {
        Error::Scene(e) => {
            let err = SceneError::new_err(message);
            let fields: Vec<(String, String)> = e
                .field_errors()
                .iter()
                .map(|f| (f.field.clone(), f.rule.clone()))
                .collect();
            let _ = err.value(py).setattr("errors", fields);
            err
        }
        Error::Option { option, rule } => {
            let argument = argument_name(option);
            let err = OptionError::new_err(format!("{argument}: {rule}"));
            let _ = err.value(py).setattr("option", argument);
            err
        }
        Error::Simulation { error: sim, .. } => {
            let err = SolverError::new_err(message);
            if let Some((t, method)) = sim.at() {
                let _ = err.value(py).setattr("time", t);
                let _ = err.value(py).setattr("method", method.to_string());
            }
            err
        }
        Error::Unaffordable { .. } | Error::NonFiniteOutput { .. } => SolverError::new_err(message),
        _ => TelescopicError::new_err(message),
    })
}

/// The Python argument of a library option name (`SimulationOptions::rtol/atol` ->
/// `rtol/atol`, `DesignOptions::kind` -> `controller`): what the package's functions call it.
fn argument_name(option: &str) -> String {
    match option {
        "DesignOptions::kind" => "controller".into(),
        o => match o.split_once("::") {
            Some((holder, field)) if holder.ends_with("Options") || holder == "Settings" => {
                field.to_string()
            }
            _ => o.to_string(),
        },
    }
}

/// An argument error naming `argument`.
pub fn argument(argument: &str, rule: impl std::fmt::Display) -> PyErr {
    OptionError::new_err(format!("{argument}: {rule}"))
}
