//! With the feature `regenerate`, generates the models of `models.toml` into `OUT_DIR` (this
//! runs Symbolica). Without it (the default) the crate builds from the committed copy in
//! `src/models/`, and nothing here runs: see the crate documentation.

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    #[cfg(feature = "regenerate")]
    telescopic_codegen::Builder::new()
        .models_file("models.toml")
        .compile()
        .expect("the models of generated/models.toml generate");
}
