//! Where models come from: a [`ModelRegistry`] holds sets of generated models (the committed
//! ones of `telescopic-generated`, and any set a downstream crate generated in its own
//! `build.rs`) and falls back to the quadrature-assembled model; a [`ModelChoice`] says which
//! of them a run may use. Every analysis takes the registry through its options, so a
//! downstream crate's own configuration runs through all of them.
//!
//! ```
//! use telescopic::run::models::{ModelChoice, ModelRegistry, ModelSet};
//!
//! // the committed models, plus a set of one's own (here the same lookup, to show the call;
//! // a downstream crate passes the functions of the module its Builder wrote to OUT_DIR)
//! let mine = ModelSet::new(
//!     "my-crate",
//!     telescopic_generated::CONFIGURATIONS,
//!     telescopic_generated::prepare_by_key,
//! );
//! let registry = ModelRegistry::default().with(mine);
//! let scene = telescopic::Scene::load("scenes/test-rig.toml".as_ref(), &[])?;
//! let chosen = registry.build(&scene.params, ModelChoice::Auto)?;
//! assert!(chosen.description.starts_with("generated model"));
//! # Ok::<(), telescopic::Error>(())
//! ```

use crate::{Error, OptionName, Result};
use std::fmt;
use telescopic_runtime::{
    AssembledModel, Basis, Model, ModelParams, configuration_key, models_toml_entry,
};

/// Which implementation of the equations to use.
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

/// The name of the set of committed models (runs on them say only `generated model <key>`).
const COMMITTED_SET: &str = "telescopic-generated";

/// A generated module's lookup: `None` if it has no model `key`, `Some(Err)` if the
/// parameters do not fit it (the `prepare_by_key` every generated models module defines).
pub type PrepareFn = fn(&str, &ModelParams) -> Option<Result<Box<dyn Model>, String>>;

/// A generated module's renderings: the equations of `key` in a format (`text`, `latex`,
/// `json`, `rust`), the `rendering` every generated models module defines.
pub type RenderingFn = fn(&str, &str) -> Option<&'static str>;

/// One set of generated models: the `telescopic_models.rs` module a `Builder` wrote.
#[derive(Clone, Copy)]
pub struct ModelSet {
    /// Who generated it (a crate name), shown in the run summary.
    pub name: &'static str,
    /// The configuration keys it holds.
    pub configurations: &'static [&'static str],
    /// Its `prepare_by_key`.
    pub prepare: PrepareFn,
    /// Its `rendering`, if renderings are to be served.
    pub rendering: Option<RenderingFn>,
}

impl ModelSet {
    /// A set from a generated module's `CONFIGURATIONS` and `prepare_by_key`.
    pub fn new(
        name: &'static str,
        configurations: &'static [&'static str],
        prepare: PrepareFn,
    ) -> Self {
        ModelSet {
            name,
            configurations,
            prepare,
            rendering: None,
        }
    }

    /// The same set, serving its module's `rendering` to `equations`.
    pub fn with_renderings(mut self, rendering: RenderingFn) -> Self {
        self.rendering = Some(rendering);
        self
    }

    /// The models committed in `telescopic-generated`.
    pub fn committed() -> Self {
        ModelSet::new(
            COMMITTED_SET,
            telescopic_generated::CONFIGURATIONS,
            telescopic_generated::prepare_by_key,
        )
        .with_renderings(telescopic_generated::rendering)
    }

    fn holds(&self, key: &str) -> bool {
        self.configurations.contains(&key)
    }
}

impl fmt::Debug for ModelSet {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("ModelSet")
            .field("name", &self.name)
            .field("configurations", &self.configurations)
            .finish_non_exhaustive()
    }
}

impl PartialEq for ModelSet {
    fn eq(&self, other: &Self) -> bool {
        self.name == other.name && self.configurations == other.configurations
    }
}

/// The sets of generated models a run may use, searched in the order they were added, and
/// the assembled model as the fallback. The default holds the committed models.
#[derive(Debug, Clone, PartialEq)]
pub struct ModelRegistry {
    sets: Vec<ModelSet>,
}

impl Default for ModelRegistry {
    fn default() -> Self {
        ModelRegistry {
            sets: vec![ModelSet::committed()],
        }
    }
}

/// A prepared model and what it is.
pub struct ChosenModel {
    /// The model.
    pub model: Box<dyn Model>,
    /// `generated model <key>` (with its set when not the committed one) or
    /// `quadrature-assembled model`.
    pub description: String,
    /// Set when `auto` fell back to the assembled model: why, and the `models.toml` entry
    /// that would generate one.
    pub note: Option<String>,
}

impl ChosenModel {
    /// The quadrature-assembled model of `params`.
    ///
    /// # Errors
    /// [`Error::Model`] when the parameters do not make a model.
    pub fn assembled(params: &ModelParams) -> Result<Self> {
        Ok(ChosenModel {
            model: Box::new(AssembledModel::new(params).map_err(Error::from)?),
            description: match params.basis {
                Basis::Modes => "quadrature-assembled model".to_string(),
                basis => format!("quadrature-assembled model (basis {})", basis.word()),
            },
            note: None,
        })
    }
}

impl ModelRegistry {
    /// The names of its sets, searched last to first.
    pub fn set_names(&self) -> Vec<&'static str> {
        self.sets.iter().map(|set| set.name).collect()
    }

    /// A registry with no generated models: every run takes the assembled model.
    pub fn assembled_only() -> Self {
        ModelRegistry { sets: Vec::new() }
    }

    /// This registry with `set` added; its models are searched before those added earlier
    /// (a downstream crate's own model of a configuration wins over the committed one).
    pub fn with(mut self, set: ModelSet) -> Self {
        self.sets.insert(0, set);
        self
    }

    /// The sets, in search order.
    pub fn sets(&self) -> &[ModelSet] {
        &self.sets
    }

    /// The set that holds configuration `key`, if any.
    fn set_of(&self, key: &str) -> Option<&ModelSet> {
        self.sets.iter().find(|s| s.holds(key))
    }

    /// The model for `params` by `choice`.
    ///
    /// # Errors
    /// [`Error::Option`] naming [`OptionName::Model`] when `generated` is asked for a
    /// configuration that no set holds; [`Error::Model`] when a model rejects the parameters.
    pub fn build(&self, params: &ModelParams, choice: ModelChoice) -> Result<ChosenModel> {
        let key = configuration_key(params);
        let set = match choice {
            ModelChoice::Assembled => None,
            _ => self.set_of(&key),
        };
        if let Some(set) = set {
            let model = (set.prepare)(&key, params)
                .unwrap_or_else(|| Err(format!("{} lists {key} but has no model for it", set.name)))
                .map_err(Error::Model)?;
            let description = if set.name == COMMITTED_SET {
                format!("generated model {key}")
            } else {
                format!("generated model {key} ({})", set.name)
            };
            return Ok(ChosenModel {
                model,
                description,
                note: None,
            });
        }
        if choice == ModelChoice::Generated {
            return Err(Error::option(
                OptionName::Model,
                format!(
                    "`generated`: no generated model for configuration {key}; {}",
                    how_to_generate(params)
                ),
            ));
        }
        let mut chosen = ChosenModel::assembled(params)?;
        chosen.note = (choice == ModelChoice::Auto).then(|| {
            format!(
                "note: no generated model for configuration {key}; using the \
                 quadrature-assembled model (slower). To generate one, {}",
                how_to_generate(params)
            )
        });
        Ok(chosen)
    }

    /// The equations of `params`' generated model as rendered at generation, in `format`.
    ///
    /// # Errors
    /// [`Error::Model`] when no set holds the configuration with that rendering.
    pub fn rendering(&self, params: &ModelParams, format: &str) -> Result<&'static str> {
        let key = configuration_key(params);
        self.set_of(&key)
            .and_then(|s| s.rendering)
            .and_then(|render| render(&key, format))
            .ok_or_else(|| no_generated_model(params, "no derived equations to show"))
    }
}

/// How to generate a model for a configuration that has none.
fn how_to_generate(params: &ModelParams) -> String {
    format!(
        "add this entry to generated/models.toml and run `cargo run -p telescopic-codegen -- \
         write generated/models.toml generated/src/models` (see docs/generator.md), or \
         generate it in your own crate's build.rs and register it in a ModelRegistry:\n{}",
        models_toml_entry(params)
    )
}

/// A message for a scene that has no generated model: the key and how to generate one.
pub fn no_generated_model(params: &ModelParams, what: &str) -> Error {
    Error::Model(format!(
        "no generated model for configuration {}, so {what}; {}",
        configuration_key(params),
        how_to_generate(params)
    ))
}
