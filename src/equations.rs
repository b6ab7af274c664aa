//! The derived equations of a scene's generated model, as rendered when it was generated
//! (the library never runs Symbolica).

use crate::Result;
use crate::model_choice::no_generated_model;
use std::fmt;
use std::str::FromStr;
use telescopic_runtime::{Scene, configuration_key};

/// A rendering of the equations.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum EquationFormat {
    /// Plain text.
    #[default]
    Text,
    /// A standalone LaTeX document.
    Latex,
    /// The emitted Rust module.
    Rust,
    /// JSON (for controller-design tools).
    Json,
}

impl EquationFormat {
    /// The name the generated lookup takes.
    pub fn name(self) -> &'static str {
        match self {
            EquationFormat::Text => "text",
            EquationFormat::Latex => "latex",
            EquationFormat::Rust => "rust",
            EquationFormat::Json => "json",
        }
    }
}

impl FromStr for EquationFormat {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "text" => Ok(EquationFormat::Text),
            "latex" => Ok(EquationFormat::Latex),
            "rust" => Ok(EquationFormat::Rust),
            "json" => Ok(EquationFormat::Json),
            _ => Err(format!(
                "`{s}` is not a format; use text, latex, rust or json"
            )),
        }
    }
}

impl fmt::Display for EquationFormat {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// The equations of `scene`'s generated model in `format`.
///
/// # Errors
/// [`crate::Error::Model`] when the scene's configuration was not generated (with the entry to add).
pub fn equations(scene: &Scene, format: EquationFormat) -> Result<&'static str> {
    let key = configuration_key(&scene.params);
    telescopic_generated::rendering(&key, format.name())
        .ok_or_else(|| no_generated_model(&scene.params, "no derived equations to show"))
}
