//! `telescopic equations`: the derived equations of the scene's generated model, as rendered
//! at build time (the CLI never runs Symbolica).

use crate::cli::SceneArgs;
use clap::{Args, ValueEnum};

/// Output format of `telescopic equations`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum, Default)]
pub enum Format {
    /// Plain text.
    #[default]
    Text,
    /// A standalone LaTeX document.
    Latex,
    /// The emitted Rust module.
    Rust,
    /// JSON.
    Json,
}

/// Options of `telescopic equations`.
#[derive(Debug, Args)]
pub struct EquationsArgs {
    #[command(flatten)]
    scene: SceneArgs,
    /// Output format.
    #[arg(long, value_enum, default_value_t)]
    format: Format,
}

/// Runs `telescopic equations`.
pub fn run(args: &EquationsArgs) -> anyhow::Result<()> {
    let scene = args.scene.load()?;
    let key = telescopic_generated::key_for(&scene.params);
    let format = match args.format {
        Format::Text => "text",
        Format::Latex => "latex",
        Format::Rust => "rust",
        Format::Json => "json",
    };
    let text = telescopic_generated::rendering(&key, format).ok_or_else(|| {
        anyhow::anyhow!(
            "no generated model for configuration {key}, so no derived equations to show; add this entry to \
             generated/models.toml and rebuild:\n{}",
            telescopic_generated::models_toml_entry(&scene.params)
        )
    })?;
    print!("{text}");
    Ok(())
}
