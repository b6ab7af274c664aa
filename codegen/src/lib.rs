//! `telescopic-codegen`: the build-time generator of `telescopic` (the MAPLE program of
//! Barthelis & Wauer, replaced). From a [`ModelConfig`] it derives the Galerkin equations of
//! a telescopic beam with Symbolica and emits a Rust module implementing the runtime's
//! `Model` trait.

#![warn(missing_docs)]

pub mod config;
pub mod derive;
pub mod exact;
pub mod expr;
pub mod precise;
pub mod symbolic;

pub use config::{DriveKind, ForceFlow, ModelConfig, ModelList, Positions};
pub use derive::{Derivation, derive};

/// Why generation failed.
#[derive(Debug, thiserror::Error)]
pub enum CodegenError {
    /// The configuration breaks a rule.
    #[error("invalid configuration: {0}")]
    Config(String),
    /// A Symbolica step failed.
    #[error("symbolic derivation failed: {0}")]
    Symbolica(String),
    /// The emitted code does not parse (a generator bug).
    #[error("emitted code does not parse: {0}")]
    Emit(String),
}
