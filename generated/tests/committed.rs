//! The committed models in `src/models/` are exactly what the generator makes from
//! `models.toml` now, so the crate that builds from them (without Symbolica) builds the
//! equations the generator derives. After changing `models.toml` or the generator:
//! `cargo run -p telescopic-codegen -- write generated/models.toml generated/src/models`.

#[test]
fn the_committed_models_equal_a_fresh_generation() {
    let root = env!("CARGO_MANIFEST_DIR");
    telescopic_codegen::Builder::new()
        .models_file(format!("{root}/models.toml"))
        .verify(format!("{root}/{}", telescopic_generated::COMMITTED_DIR))
        .unwrap_or_else(|e| panic!("{e}"));
}
