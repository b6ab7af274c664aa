//! Building a [`Scene`]: from a file, TOML text or a parsed table with `--set` overrides or
//! typed edits ([`SceneEdit`]),
//! from a typed scene file, or from another scene with typed edits of its values.

use super::error::{SceneError, clipped_lines};
use super::keys::SceneKey;
use super::overrides::SceneEdit;
use super::schema::SceneFile;
use super::validate;
use super::validated::Scene;
use std::path::Path;

impl Scene {
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
        let edits = SceneEdit::parse_all(overrides)?;
        Self::from_toml_edited(text, path, &edits)
    }

    /// As [`Scene::from_toml_str`], with typed edits.
    ///
    /// # Errors
    /// [`SceneError`] naming the field and the rule for every problem found.
    pub fn from_toml_edited(
        text: &str,
        path: &Path,
        edits: &[SceneEdit],
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
        Self::from_table_edited(table, path, edits)
    }

    /// As [`Scene::from_toml_str`], from a parsed TOML table.
    ///
    /// # Errors
    /// [`SceneError`] naming the field and the rule for every problem found.
    pub fn from_table(
        table: toml::Table,
        path: &Path,
        overrides: &[String],
    ) -> Result<Self, SceneError> {
        let edits = SceneEdit::parse_all(overrides)?;
        Self::from_table_edited(table, path, &edits)
    }

    /// A scene from a parsed TOML table with typed edits applied in order (a sweep edits one
    /// parsed scene many times; Python's `set=` gives values, not text).
    ///
    /// # Errors
    /// [`SceneError`] naming the field and the rule for every problem found.
    pub fn from_table_edited(
        mut table: toml::Table,
        path: &Path,
        edits: &[SceneEdit],
    ) -> Result<Self, SceneError> {
        for edit in edits {
            edit.apply(&mut table)?;
        }
        let origin = if edits.is_empty() {
            path.display().to_string()
        } else {
            let edits: Vec<String> = edits.iter().map(SceneEdit::to_string).collect();
            format!("{} (with overrides {})", path.display(), edits.join(", "))
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

    /// The scene of a scene file as a value (no text): validated as [`Scene::load`] does;
    /// `origin` names it in messages.
    ///
    /// # Errors
    /// [`SceneError::Invalid`] naming every broken rule.
    pub fn from_file(file: SceneFile, origin: &str) -> Result<Self, SceneError> {
        validate::build(file, origin)
    }

    /// This scene with continuous values replaced by key ([`super::keys::KEYS`]:
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

    /// The continuous value of `key` ([`super::keys::KEYS`]) in this scene.
    ///
    /// # Errors
    /// A message naming the key when it is not a continuous value of this scene.
    pub fn value(&self, key: &str) -> Result<f64, String> {
        SceneKey::parse(key)?
            .get(&self.file)
            .map_err(|e| format!("`{key}`: {e}"))
    }
}
