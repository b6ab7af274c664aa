//! Generates the model of this crate's configuration into OUT_DIR: three sections with 3
//! modes each, the external force flow (the upper sections carried by an outside system),
//! the clearance law, fixed telescopic positions and a force drive. Not one of the
//! configurations the `telescopic` tool ships, which is the point.

use telescopic_codegen::{Builder, DriveKind, ForceFlow, ModelConfig, Positions};

fn main() -> Result<(), telescopic_codegen::BuildError> {
    Builder::new()
        .model(ModelConfig {
            modes: vec![3, 3, 3],
            contacts: 2,
            force_flow: ForceFlow::External,
            clearance: true,
            positions: Positions::Fixed,
            drive: DriveKind::Force,
            static_knots: None,
        })
        .compile()?;
    Ok(())
}
