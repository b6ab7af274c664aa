//! The generated models of the configurations listed in `generated/models.toml`, and a
//! lookup to find the one that fits a scene.
//!
//! The modules are committed in `src/models/` (written by `telescopic_codegen::Builder::
//! write_to`), so this crate, and the `telescopic` tool on top of it, build without running
//! Symbolica, whose free use is non-commercial; a test (`tests/committed.rs`) checks that
//! they equal a fresh generation. The feature `regenerate` generates them into `OUT_DIR` at
//! build time instead.
//!
//! Add a configuration: append a `[[model]]` entry to `models.toml` (the `telescopic` CLI
//! prints the exact entry when a scene has no generated model), then regenerate the
//! committed copy:
//!
//! ```text
//! cargo run -p telescopic-codegen -- write generated/models.toml generated/src/models
//! ```
//!
//! ```
//! let scene = telescopic_runtime::Scene::load("../scenes/test-rig.toml".as_ref(), &[]).unwrap();
//! let model = telescopic_generated::prepare(&scene.params).expect("generated").unwrap();
//! assert_eq!(model.dof(), 10);
//! ```

#![warn(missing_docs)]

#[cfg(not(feature = "regenerate"))]
include!("models/telescopic_models.rs");
#[cfg(feature = "regenerate")]
include!(concat!(env!("OUT_DIR"), "/telescopic_models.rs"));

/// Where the committed models live, relative to this crate's root.
pub const COMMITTED_DIR: &str = "src/models";
