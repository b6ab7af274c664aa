//! The library's error type: every failure names what it concerns (the scene, the option or
//! field and its rule, the file, the time and method of a failed run). Each message is whole
//! on its own: causes are part of it, not a separate `source` chain to print after it.

use std::path::PathBuf;

use crate::OptionName;

/// Result of the library's functions.
pub type Result<T, E = Error> = std::result::Result<T, E>;

/// Why a library call failed.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// The scene file is unreadable, malformed or breaks a rule.
    #[error(transparent)]
    Scene(#[from] telescopic_runtime::SceneError),
    /// An option is out of its range: names the option and the rule.
    #[error("{option}: {rule}{}", see.map_or(String::new(), |o| format!(" (see {o})")))]
    Option {
        /// The option (each face spells it its own way: a flag, an argument).
        option: OptionName,
        /// The rule and the value given.
        rule: String,
        /// Another option that does what was likely meant, or gives what is missing.
        see: Option<OptionName>,
    },
    /// An input (a controller file, a sweep file, a sweep's results, a run handed over) is
    /// unreadable or breaks a rule.
    #[error("{subject}: {rule}")]
    Input {
        /// The file, or the field of one, or the run.
        subject: String,
        /// The rule it breaks, or why it cannot be read.
        rule: String,
    },
    /// An output path cannot be written (checked before any work).
    #[error("{}: {rule}", path.display())]
    Destination {
        /// The path.
        path: PathBuf,
        /// Why it cannot be written.
        rule: String,
    },
    /// The work would need more memory than the budget allows (checked before any work).
    #[error(
        "{subject}: {what} would take about {} of memory, more than the budget of {}; change \
         {remedy}, or raise the memory budget",
        crate::io::size::human(*bytes),
        crate::io::size::human(*budget)
    )]
    OverMemoryBudget {
        /// The option whose value asks for the work, if one does (else the scene's or the
        /// input's size does).
        option: Option<OptionName>,
        /// The scene or the input the work belongs to.
        subject: String,
        /// What would be held.
        what: String,
        /// Its size (bytes).
        bytes: u64,
        /// The budget (bytes).
        budget: u64,
        /// What to change to need less.
        remedy: String,
    },
    /// No model could be prepared for the scene.
    #[error("{0}")]
    Model(String),
    /// The quadrature-assembled model could not be built.
    #[error(transparent)]
    Assembly(#[from] telescopic_runtime::ModelError),
    /// A linear model could not be had at an operating point.
    #[error(transparent)]
    Linear(#[from] telescopic_runtime::analysis::linear::LinearError),
    /// The finite-element model of the beams could not be built or solved.
    #[error(transparent)]
    Elements(#[from] telescopic_runtime::analysis::elements::ElementError),
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
    /// The eigen analysis of a linear model failed (the caller names the scene or the grid
    /// point where it knows it: [`Error::Eigen`], [`Error::Trial`]).
    #[error(transparent)]
    Modes(#[from] telescopic_runtime::EigenError),
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
    #[error(
        "interrupted: {finished} of {total} runs done, {}",
        match kept {
            Some(path) => format!("kept in {}; resuming the sweep finishes it", path.display()),
            None => "not kept (the output is a stream)".into(),
        }
    )]
    Interrupted {
        /// Runs finished.
        finished: usize,
        /// Runs in all.
        total: usize,
        /// The work file that keeps the finished runs (none when the output is a stream).
        kept: Option<PathBuf>,
    },
    /// A call stopped at its caller's request (a Ctrl-C, or an exception of a progress
    /// callable) before it finished; nothing was written.
    #[error("{what} stopped at the caller's request; nothing was written")]
    Stopped {
        /// What stopped, e.g. `the plan, evaluating zvd scheduled`.
        what: String,
    },
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

    /// An [`Error::Input`] for `subject` (a file, or a field of one) breaking `rule`.
    pub fn input(subject: impl std::fmt::Display, rule: impl std::fmt::Display) -> Self {
        Error::Input {
            subject: subject.to_string(),
            rule: rule.to_string(),
        }
    }

    /// An [`Error::Option`] for `option` breaking `rule`.
    pub fn option(option: OptionName, rule: impl Into<String>) -> Self {
        Error::Option {
            option,
            rule: rule.into(),
            see: None,
        }
    }

    /// An [`Error::Option`] for `option` breaking `rule`, pointing to the option `see`.
    pub fn option_see(option: OptionName, rule: impl Into<String>, see: OptionName) -> Self {
        Error::Option {
            option,
            rule: rule.into(),
            see: Some(see),
        }
    }
}
