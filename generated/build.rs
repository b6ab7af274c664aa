//! With the feature `regenerate`, generates the models of `models.toml` into `OUT_DIR` (this
//! runs Symbolica). Without it (the default) the crate builds from the committed copy in
//! `src/models/`, and nothing here runs: see the crate documentation.

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    #[cfg(feature = "regenerate")]
    {
        println!("cargo:rerun-if-env-changed=TELESCOPIC_SYMBOLICA_LOCK");
        let mut builder = telescopic_codegen::Builder::new().models_file("models.toml");
        if let Some(lock) = std::env::var_os("TELESCOPIC_SYMBOLICA_LOCK") {
            builder = builder.symbolica_lock(lock);
        }
        builder
            .compile()
            .expect("the models of generated/models.toml generate");
    }
}
