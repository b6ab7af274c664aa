//! The models file of the generator. The configuration's vocabulary ([`ModelConfig`] and
//! its words) is `telescopic-config`'s, which the runtime re-exports, so that the generator
//! and the lookup of a scene's model cannot disagree.

use serde::{Deserialize, Serialize};
pub use telescopic_config::{DriveKind, ForceFlow, ModelConfig, Positions, StaticKnots};

/// `generated/models.toml`: `[[model]]` tables.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ModelList {
    /// The configurations to generate.
    pub model: Vec<ModelConfig>,
}
