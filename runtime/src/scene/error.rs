//! Why a scene could not be loaded: the errors that name the field and the rule.

use std::fmt;
use std::path::PathBuf;

/// One broken rule, with the dotted path of the field it concerns.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FieldError {
    /// Dotted TOML path, e.g. `contact.points` or `sections.length[1]`.
    pub field: String,
    /// The rule and the offending value.
    pub rule: String,
}

impl fmt::Display for FieldError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "`{}`: {}", self.field, self.rule)
    }
}

/// Why a scene could not be loaded.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// The file could not be read.
    #[error("cannot read scene file {path}: {error}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The cause.
        error: std::io::Error,
    },
    /// The file is not valid TOML.
    #[error("scene file {path} is not valid TOML: {message}")]
    Syntax {
        /// The file.
        path: PathBuf,
        /// The parser's message, with line and column.
        message: String,
    },
    /// An override `KEY=VALUE` (the CLI's `--set`) is malformed or does not fit the file's structure.
    #[error("override {argument}: {rule}")]
    Override {
        /// The argument as given.
        argument: String,
        /// What is wrong.
        rule: String,
    },
    /// A field has the wrong type, is unknown, or is missing.
    #[error("scene {origin}: field `{field}`: {message}")]
    Schema {
        /// The file (and overrides).
        origin: String,
        /// Dotted path of the field.
        field: String,
        /// The deserializer's message.
        message: String,
    },
    /// Values break the rules of the model.
    #[error("scene {origin} is invalid:\n{}", .errors.iter().map(|e| format!("  - {e}")).collect::<Vec<_>>().join("\n"))]
    Invalid {
        /// The file (and overrides).
        origin: String,
        /// Every broken rule.
        errors: Vec<FieldError>,
    },
}

impl SceneError {
    /// The broken rules of an `Invalid` error (empty otherwise).
    pub fn field_errors(&self) -> &[FieldError] {
        match self {
            SceneError::Invalid { errors, .. } => errors,
            _ => &[],
        }
    }
}

/// Longest line of a parser's message kept whole: the parser quotes the offending line, which
/// in a hostile file can be megabytes long.
const MAX_MESSAGE_LINE: usize = 240;

/// `message` with every line cut to [`MAX_MESSAGE_LINE`] characters (marked with `...`).
pub(super) fn clipped_lines(message: &str) -> String {
    message
        .lines()
        .map(|line| match line.char_indices().nth(MAX_MESSAGE_LINE) {
            Some((cut, _)) => format!("{}...", &line[..cut]),
            None => line.to_string(),
        })
        .collect::<Vec<_>>()
        .join("\n")
}
