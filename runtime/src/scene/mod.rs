//! Scenes: TOML files that describe a telescope, its drive and a time span; loading,
//! `--set` overrides and validation with errors that name the field and the rule.

pub mod keys;
pub mod limits;
mod overrides;
pub mod plausibility;
pub mod schema;
mod validate;

pub use keys::{KEYS, KeyField, SceneKey};
pub use overrides::apply_override;
pub use schema::SceneFile;
pub use validate::profile_errors;

use crate::params::ModelParams;
use std::fmt;
use std::path::{Path, PathBuf};

/// Time span and output sampling of a scene (s).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TimeSpan {
    /// Start time (s).
    pub start: f64,
    /// End time (s).
    pub end: f64,
    /// Output sample interval (s).
    pub sample: f64,
}

/// A validated scene: the model parameters, the time span and the reference values.
#[derive(Debug, Clone, PartialEq)]
pub struct Scene {
    /// Short name.
    pub name: String,
    /// One line on what the scene is.
    pub description: String,
    /// Physical parameters of the model.
    pub params: ModelParams,
    /// Time span and sampling.
    pub time: TimeSpan,
    /// Published frequency columns to compare with.
    pub references: Vec<schema::ReferenceSpec>,
    /// The file as read, after overrides (for echoing into outputs).
    pub file: SceneFile,
}

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

impl Scene {
    /// The section moduli `W_k` (m^3), bottom up, from `sections.section_modulus` or from
    /// `sections.height` (`W = 2 I / h`); `None` when the scene gives neither.
    pub fn section_moduli(&self) -> Option<Vec<f64>> {
        let s = &self.file.sections;
        let n = self.params.sections.len();
        if let Some(w) = &s.section_modulus {
            return (1..=n).map(|k| w.get(k)).collect();
        }
        let h = s.height.as_ref()?;
        (1..=n)
            .map(|k| Some(2.0 * s.inertia.get(k)? / h.get(k)?))
            .collect()
    }

    /// Reads, overrides and validates a scene file. `overrides` are `KEY=VALUE` strings with
    /// dotted TOML keys (`contact.clearance=0.01`, `sections.length.1=1.2`).
    ///
    /// # Errors
    /// [`SceneError`] naming the field and the rule for every problem found.
    pub fn load(path: &Path, overrides: &[String]) -> Result<Self, SceneError> {
        let text =
            crate::input::read_text(path, crate::input::MAX_TEXT_INPUT_BYTES).map_err(|error| {
                SceneError::Io {
                    path: path.to_owned(),
                    error,
                }
            })?;
        Self::from_toml_str(&text, path, overrides)
    }

    /// As [`Scene::load`], from TOML text; `path` only names the origin in messages.
    ///
    /// # Errors
    /// [`SceneError`] naming the field and the rule for every problem found.
    pub fn from_toml_str(
        text: &str,
        path: &Path,
        overrides: &[String],
    ) -> Result<Self, SceneError> {
        if text.len() as u64 > crate::input::MAX_TEXT_INPUT_BYTES {
            return Err(SceneError::Io {
                path: path.to_owned(),
                error: std::io::Error::other(format!(
                    "{} bytes of text; a scene is at most {} bytes",
                    text.len(),
                    crate::input::MAX_TEXT_INPUT_BYTES
                )),
            });
        }
        let table: toml::Table = text
            .parse()
            .map_err(|e: toml::de::Error| SceneError::Syntax {
                path: path.to_owned(),
                message: clipped_lines(&e.to_string()),
            })?;
        Self::from_table(table, path, overrides)
    }

    /// As [`Scene::from_toml_str`], from a parsed TOML table (a sweep applies its overrides to
    /// one parsed scene many times).
    ///
    /// # Errors
    /// [`SceneError`] naming the field and the rule for every problem found.
    pub fn from_table(
        mut table: toml::Table,
        path: &Path,
        overrides: &[String],
    ) -> Result<Self, SceneError> {
        for o in overrides {
            apply_override(&mut table, o)?;
        }
        let origin = if overrides.is_empty() {
            path.display().to_string()
        } else {
            format!(
                "{} (with overrides {})",
                path.display(),
                overrides.join(", ")
            )
        };
        let file: SceneFile =
            serde_path_to_error::deserialize(toml::Value::Table(table)).map_err(|e| {
                let field = e.path().to_string();
                SceneError::Schema {
                    origin: origin.clone(),
                    field,
                    message: e.into_inner().to_string(),
                }
            })?;
        validate::build(file, &origin)
    }
}

impl Scene {
    /// The scene of a scene file as a value (no text): validated as [`Scene::load`] does;
    /// `origin` names it in messages.
    ///
    /// # Errors
    /// [`SceneError::Invalid`] naming every broken rule.
    pub fn from_file(file: SceneFile, origin: &str) -> Result<Self, SceneError> {
        validate::build(file, origin)
    }

    /// This scene with continuous values replaced by key ([`keys::KEYS`]:
    /// `contact.clearance`, `sections.length.1`, ...) and validated again: no text is
    /// written or parsed.
    ///
    /// ```
    /// use telescopic_runtime::Scene;
    /// let scene = Scene::load("../scenes/adams-linear.toml".as_ref(), &[]).unwrap();
    /// let heavier = scene.with_values(&[("masses.load", 30.0)]).unwrap();
    /// assert_eq!(heavier.params.load_mass, 30.0);
    /// let err = scene.with_values(&[("contact.clearance", -1.0)]).unwrap_err();
    /// assert!(err.to_string().contains("contact.clearance"));
    /// ```
    ///
    /// # Errors
    /// [`SceneError::Override`] naming the key for a key that is not a continuous scene
    /// value of this scene; [`SceneError::Invalid`] for values that break the scene's rules.
    pub fn with_values(&self, values: &[(&str, f64)]) -> Result<Self, SceneError> {
        let mut file = self.file.clone();
        for &(key, value) in values {
            let refused = |rule: String| SceneError::Override {
                argument: format!("{key} = {value}"),
                rule,
            };
            if !value.is_finite() {
                return Err(refused("the value must be a finite number".into()));
            }
            SceneKey::parse(key)
                .and_then(|k| k.set(&mut file, value))
                .map_err(refused)?;
        }
        let origin = format!(
            "{} (with {})",
            self.name,
            values
                .iter()
                .map(|(k, v)| format!("{k} = {v}"))
                .collect::<Vec<_>>()
                .join(", ")
        );
        validate::build(file, &origin)
    }

    /// The continuous value of `key` ([`keys::KEYS`]) in this scene.
    ///
    /// # Errors
    /// A message naming the key when it is not a continuous value of this scene.
    pub fn value(&self, key: &str) -> Result<f64, String> {
        SceneKey::parse(key)?
            .get(&self.file)
            .map_err(|e| format!("`{key}`: {e}"))
    }
}

/// Longest line of a parser's message kept whole: the parser quotes the offending line, which
/// in a hostile file can be megabytes long.
const MAX_MESSAGE_LINE: usize = 240;

/// `message` with every line cut to [`MAX_MESSAGE_LINE`] characters (marked with `...`).
fn clipped_lines(message: &str) -> String {
    message
        .lines()
        .map(|line| match line.char_indices().nth(MAX_MESSAGE_LINE) {
            Some((cut, _)) => format!("{}...", &line[..cut]),
            None => line.to_string(),
        })
        .collect::<Vec<_>>()
        .join("\n")
}
