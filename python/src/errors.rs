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

/// The Python exception of a library error, with the attributes its class documents on every
/// path (`None` where the error has no such value).
pub fn to_python(error: telescopic::Error) -> PyErr {
    use telescopic::Error;
    let message = error.to_string();
    Python::attach(|py| match &error {
        Error::Scene(e) => scene_error(py, e, message),
        Error::Option { option, rule, see } => {
            let argument = argument_name(*option);
            let see = see.map_or(String::new(), |o| format!(" (see {})", argument_name(o)));
            option_error(py, format!("{argument}: {rule}{see}"), Some(argument))
        }
        Error::Input { .. } | Error::Destination { .. } => option_error(py, message, None),
        Error::Simulation { error: sim, .. } => solver_error(py, message, sim.at()),
        Error::NonFiniteOutput { t, method, .. } => {
            solver_error(py, message, Some((*t, method.as_str())))
        }
        Error::OverMemoryBudget { option, .. } => {
            let argument = option.map_or(String::new(), |o| format!("{}: ", argument_name(o)));
            let message = format!(
                "{argument}{message} ({} sets the budget)",
                crate::environment::MEMORY_BUDGET_VARIABLE
            );
            solver_error(py, message, None)
        }
        Error::Unaffordable { .. } => solver_error(py, message, None),
        _ => TelescopicError::new_err(message),
    })
}

/// A `SceneError` with `.errors`: every broken rule, or the one field (or `""` for the file)
/// of a file that cannot be read or parsed.
fn scene_error(py: Python<'_>, error: &telescopic::runtime::SceneError, message: String) -> PyErr {
    use telescopic::runtime::SceneError as E;
    let fields: Vec<(String, String)> = match error {
        E::Invalid { errors, .. } => errors
            .iter()
            .map(|f| (f.field.clone(), f.rule.clone()))
            .collect(),
        E::Schema { field, message, .. } => vec![(field.clone(), message.clone())],
        E::Override { argument, rule } => {
            let key = argument
                .split_once('=')
                .map_or(argument.as_str(), |(k, _)| k);
            vec![(key.to_string(), rule.clone())]
        }
        E::Syntax { message, .. } => vec![(String::new(), message.clone())],
        E::Io { error, .. } => vec![(String::new(), error.to_string())],
    };
    let err = SceneError::new_err(message);
    let _ = err.value(py).setattr("errors", fields);
    err
}

/// An `OptionError` with `.option`, the argument's name (`None` for an input file's error).
fn option_error(py: Python<'_>, message: String, option: Option<&str>) -> PyErr {
    let err = OptionError::new_err(message);
    let _ = err.value(py).setattr("option", option);
    err
}

/// A `SolverError` with `.time` (s) and `.method` (`None` for a refusal before the run).
fn solver_error(py: Python<'_>, message: String, at: Option<(f64, &str)>) -> PyErr {
    let err = SolverError::new_err(message);
    let _ = err.value(py).setattr("time", at.map(|a| a.0));
    let _ = err.value(py).setattr("method", at.map(|a| a.1.to_string()));
    err
}

/// The package's name for `option`: the keyword argument (or environment variable) that
/// sets it.
fn argument_name(option: telescopic::OptionName) -> &'static str {
    use telescopic::OptionName as O;
    match option {
        O::Method => "method",
        O::Tolerances => "rtol/atol",
        O::Dt => "dt",
        O::Accuracy => "accuracy",
        O::MomentTolerance => "moment_tolerance",
        O::StatisticsTolerance => "statistics_tolerance",
        O::Stations => "stations",
        O::ModesAsGiven => "modes_as_given",
        O::Model => "model",
        O::MemoryBudget => crate::environment::MEMORY_BUDGET_VARIABLE,
        O::Controller | O::ControllerKind => "controller",
        O::DesignModes => "design_modes",
        O::ForceLimit => "force_limit",
        O::TipScale => "tip_scale",
        O::VehicleScale => "vehicle_scale",
        O::Sensors => "sensors",
        O::SensorNoises => "sensor_noises",
        O::Estimator => "estimator",
        O::RateHz => "rate_hz",
        O::Law => "law",
        O::AddedDamping => "added_damping",
        O::SensorNoise => "sensor_noise",
        O::ForceNoise => "force_noise",
        O::ProcessNoiseFloor => "process_noise_floor",
        O::GridPoints => "grid_points",
        O::Jobs => "jobs",
        O::Resume => "resume",
        O::SweepOut => "out",
        O::Shard => "shard",
        O::ShardCount => "shard_count",
        O::ChartX => "x",
        O::ChartY => "y",
        O::ChartColor => "color",
        O::ChartHeatmap => "heatmap",
        O::ShapeLength => "length",
        O::ShapePoints | O::BodePoints => "points",
        O::ConvergeTol => "tol",
        O::MaxModes => "max_modes",
        O::MaxContacts => "max_contacts",
        O::Repeat => "repeat",
        O::Methods => "methods",
        O::Rtols => "rtols",
        O::Sizes => "sizes",
        O::ModesAt => "at",
        O::ModesCount => "count",
        O::Shapes => "points",
        O::LatexFormat => "format",
        O::AtTime => "at_time",
        O::Positions => "positions",
        O::Grid => "grid",
        O::Discrete => "discrete",
        O::BodeLinear => "grid/discrete",
        O::BodeInputs => "inputs",
        O::BodeOutputs => "outputs",
        O::FromHz => "from_hz",
        O::ToHz => "to_hz",
        O::FmuLibrary => "library",
        O::Fps => "fps",
        O::DeflectionScale => "scale",
        O::AnimationSize => "size",
        O::AnimationSpeed => "speed",
        O::Distance => "distance",
        O::MoveLimits => "v_max/a_max/j_max",
        O::MoveTolerance => "tolerance",
        O::MoveMargin => "margin",
        O::Settle => "settle",
        O::Robust => "robust",
        O::Checks => "checks",
        O::Feedback => "feedback",
        O::CorrectionLimits => "feedback",
        O::WeighedLoad => "weighed_load",
        O::Pick => "pick",
        O::EmitC => "emit_c",
        O::FilterRate => "filter_rate",
        O::Free => "free",
        O::Noise => "noise",
        O::Start => "start",
    }
}

/// An argument error naming `argument` (also its `.option`).
pub fn argument(argument: &str, rule: impl std::fmt::Display) -> PyErr {
    Python::attach(|py| option_error(py, format!("{argument}: {rule}"), Some(argument)))
}
