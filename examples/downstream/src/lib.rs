//! The generated model of this crate's configuration (see `build.rs`), the scene that goes
//! with it, and a model registry that makes every analysis of the `telescopic` library run
//! on it.

include!(concat!(env!("OUT_DIR"), "/telescopic_models.rs"));

/// The scene file shipped with this example: a three-section telescope on a rack feeder.
pub const SCENE: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/scene.toml");

/// The committed models of `telescopic` plus the one this crate generated: pass it as the
/// `models` of any options struct (`SimulationOptions`, `ModesOptions`, `LinearizeOptions`,
/// `DesignOptions`, ...).
pub fn models() -> telescopic::run::models::ModelRegistry {
    let own = telescopic::run::models::ModelSet::new(
        env!("CARGO_PKG_NAME"),
        CONFIGURATIONS,
        prepare_by_key,
    )
    .with_renderings(rendering);
    telescopic::run::models::ModelRegistry::default().with(own)
}
