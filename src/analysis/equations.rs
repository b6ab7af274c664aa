//! The derived equations of a scene's generated model, as rendered when it was generated
//! (the library never runs Symbolica).

use crate::Result;
use crate::run::models::ModelRegistry;
use telescopic_runtime::Scene;

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

// the names are also those the generated lookup takes
crate::named::named_enum!(EquationFormat, "a format", {
    Text => "text",
    Latex => "latex",
    Rust => "rust",
    Json => "json",
});

/// The equations of `scene`'s generated model in `format`, from the first set of `models`
/// that holds its configuration.
///
/// # Errors
/// [`crate::Error::Model`] when the scene's configuration was not generated (with the entry to add).
pub fn equations(
    scene: &Scene,
    format: EquationFormat,
    models: &ModelRegistry,
) -> Result<&'static str> {
    models.rendering(&scene.params, format.name())
}
