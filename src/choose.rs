//! Which model runs a scene: the generated one for its configuration when `generated/` has
//! it, else the quadrature-assembled model (said on stderr, with the entry to add).

use clap::ValueEnum;
use telescopic_runtime::{AssembledModel, Model, ModelParams};

/// `--model`: which implementation of the equations to use.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum, Default)]
pub enum ModelChoice {
    /// The generated model if one matches the scene, else the assembled one.
    #[default]
    Auto,
    /// The generated model; an error if the scene's configuration was not generated.
    Generated,
    /// The quadrature-assembled reference model.
    Assembled,
}

/// The model for `params` and a word on which it is.
pub fn build_model(
    params: &ModelParams,
    choice: ModelChoice,
) -> anyhow::Result<(Box<dyn Model>, String)> {
    let key = telescopic_generated::key_for(params);
    let generated = match choice {
        ModelChoice::Assembled => None,
        _ => telescopic_generated::prepare(params),
    };
    match (generated, choice) {
        (Some(model), _) => Ok((
            model.map_err(anyhow::Error::msg)?,
            format!("generated model {key}"),
        )),
        (None, ModelChoice::Generated) => anyhow::bail!(
            "--model generated: no generated model for configuration {key}; add this entry to \
             generated/models.toml and rebuild:\n{}",
            telescopic_generated::models_toml_entry(params)
        ),
        (None, choice) => {
            if choice == ModelChoice::Auto {
                eprintln!(
                    "note: no generated model for configuration {key}; using the quadrature-assembled model \
                     (slower). To generate one, add to generated/models.toml and rebuild:\n{}",
                    telescopic_generated::models_toml_entry(params)
                );
            }
            Ok((
                Box::new(AssembledModel::new(params)?),
                "quadrature-assembled model".to_string(),
            ))
        }
    }
}
