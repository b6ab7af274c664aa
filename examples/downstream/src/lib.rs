//! The generated model of this crate's configuration (see `build.rs`), and the scene that
//! goes with it.

include!(concat!(env!("OUT_DIR"), "/telescopic_models.rs"));

/// The scene file shipped with this example: a three-section telescope on a rack feeder.
pub const SCENE: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/scene.toml");
