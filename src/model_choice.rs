//! Which implementation of the equations runs a scene: the generated model of its
//! configuration when `telescopic-generated` has one, else the quadrature-assembled model.

use crate::{Error, Result};
use telescopic_runtime::{
    AssembledModel, Model, ModelParams, configuration_key, models_toml_entry,
};

/// Which implementation of the equations to use (`--model`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ModelChoice {
    /// The generated model if one matches the scene, else the assembled one (with a note).
    #[default]
    Auto,
    /// The generated model; an error if the scene's configuration was not generated.
    Generated,
    /// The quadrature-assembled reference model (any configuration).
    Assembled,
}

crate::named::named_enum!(ModelChoice, "a model choice", {
    Auto => "auto",
    Generated => "generated",
    Assembled => "assembled",
});

/// A prepared model and what it is.
pub struct ChosenModel {
    /// The model.
    pub model: Box<dyn Model>,
    /// `generated model <key>` or `quadrature-assembled model`.
    pub description: String,
    /// Set when `auto` fell back to the assembled model: why, and the `models.toml` entry
    /// that would generate one.
    pub note: Option<String>,
}

/// How to generate a model for a configuration that has none.
fn how_to_generate(params: &ModelParams) -> String {
    format!(
        "add this entry to generated/models.toml and run `cargo run -p telescopic-codegen -- \
         write generated/models.toml generated/src/models` (see docs/generator.md):\n{}",
        models_toml_entry(params)
    )
}

/// The model for `params` by `choice`.
///
/// # Errors
/// [`Error::Model`] when `generated` is asked for a configuration that has none, or a model
/// rejects the parameters.
pub fn build_model(params: &ModelParams, choice: ModelChoice) -> Result<ChosenModel> {
    let key = configuration_key(params);
    let generated = match choice {
        ModelChoice::Assembled => None,
        _ => telescopic_generated::prepare(params),
    };
    match (generated, choice) {
        (Some(model), _) => Ok(ChosenModel {
            model: model.map_err(Error::Model)?,
            description: format!("generated model {key}"),
            note: None,
        }),
        (None, ModelChoice::Generated) => Err(Error::Model(format!(
            "--model generated: no generated model for configuration {key}; {}",
            how_to_generate(params)
        ))),
        (None, choice) => Ok(ChosenModel {
            model: Box::new(AssembledModel::new(params).map_err(|e| Error::Model(e.to_string()))?),
            description: "quadrature-assembled model".to_string(),
            note: (choice == ModelChoice::Auto).then(|| {
                format!(
                    "note: no generated model for configuration {key}; using the \
                     quadrature-assembled model (slower). To generate one, {}",
                    how_to_generate(params)
                )
            }),
        }),
    }
}

/// A message for a scene that has no generated model: the key and how to generate one.
pub fn no_generated_model(params: &ModelParams, what: &str) -> Error {
    Error::Model(format!(
        "no generated model for configuration {}, so {what}; {}",
        configuration_key(params),
        how_to_generate(params)
    ))
}
