//! The library's error type: every failure names what it concerns (the scene, the option or
//! field and its rule, the file, the time and method of a failed run). Each message is whole
//! on its own: causes are part of it, not a separate `source` chain to print after it.

use std::path::PathBuf;

/// Result of the library's functions.
pub type Result<T, E = Error> = std::result::Result<T, E>;

/// Why a library call failed.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// The scene file is unreadable, malformed or breaks a rule.
    #[error(transparent)]
    Scene(#[from] telescopic_runtime::SceneError),
    /// An option is out of its range: names the option and the rule.
    #[error("{option}: {rule}")]
    Option {
        /// The option, as the CLI spells it (e.g. `--rtol`).
        option: String,
        /// The rule and the value given.
        rule: String,
    },
    /// No model could be prepared for the scene.
    #[error("{0}")]
    Model(String),
    /// The run would exceed a resource limit or take absurdly long: the estimate and the
    /// cause, before any work is done.
    #[error("scene {scene}: {reason}")]
    Unaffordable {
        /// The scene.
        scene: String,
        /// The estimate, the cause and what to change.
        reason: String,
    },
    /// Integration stopped early.
    #[error("scene {scene} could not be simulated: {error}")]
    Simulation {
        /// The scene.
        scene: String,
        /// What stopped it (time, method, likely cause).
        error: telescopic_runtime::SimError,
    },
    /// An output came out non-finite.
    #[error("output `{name}` is not finite at t = {t} s (method {method}); no output written")]
    NonFiniteOutput {
        /// The output's name.
        name: String,
        /// Time (s).
        t: f64,
        /// Method name.
        method: String,
    },
    /// The eigen analysis failed.
    #[error("scene {scene}: {error}")]
    Eigen {
        /// The scene.
        scene: String,
        /// What failed.
        error: telescopic_runtime::EigenError,
    },
    /// An analysis could not reach its goal (the message says why and what to change).
    #[error("{0}")]
    Analysis(String),
    /// One trial of a multi-run analysis failed.
    #[error("{what}: {error}")]
    Trial {
        /// Which trial (e.g. `6 modes per section, 2 contacts per overlap`).
        what: String,
        /// Why.
        error: Box<Error>,
    },
    /// A file could not be written (nothing is left at its path).
    #[error("writing {path}: {error}")]
    Write {
        /// The file.
        path: PathBuf,
        /// The cause.
        error: std::io::Error,
    },
    /// Standard output could not be written.
    #[error("writing to standard output: {0}")]
    Stdout(std::io::Error),
    /// A multi-run command was stopped between runs (Ctrl-C); what it finished is kept.
    #[error("interrupted: {0}")]
    Interrupted(String),
    /// One run of a multi-run command panicked: a bug in telescopic, recorded as that run's
    /// error so the others go on.
    #[error("the run panicked (a bug in telescopic; please report it with the run's values): {0}")]
    Panicked(String),
    /// Drawing a chart failed.
    #[error("drawing failed: {0}")]
    Plot(String),
}

impl Error {
    /// The error of a caught panic (a bug): [`Error::Panicked`] with the panic's message.
    pub fn from_panic(payload: &(dyn std::any::Any + Send)) -> Self {
        let what = payload
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| payload.downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "unknown panic".into());
        Error::Panicked(what)
    }

    /// An [`Error::Option`] for `option` breaking `rule`.
    pub fn option(option: &str, rule: impl Into<String>) -> Self {
        Error::Option {
            option: option.to_string(),
            rule: rule.into(),
        }
    }
}
