//! Scenes: TOML files that describe a telescope, its drive and a time span; loading,
//! `--set` overrides and validation with errors that name the field and the rule.

mod error;
pub mod keys;
pub mod limits;
mod load;
mod overrides;
pub mod plausibility;
pub mod schema;
mod validate;
mod validated;

pub use error::{FieldError, SceneError};
pub use keys::{KEYS, KeyField, SceneKey};
pub use overrides::{SceneEdit, value_text};
pub use schema::{FiguresSpec, SceneFile};
pub use validate::profile_errors;
pub use validated::{Figures, Scene, TimeSpan};
