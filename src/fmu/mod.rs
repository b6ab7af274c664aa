//! The nonlinear model as an FMI 2.0 FMU (`telescopic fmu`, docs/fmu.md): the variables of a
//! scene ([`variables`]), its `modelDescription.xml` ([`description`]), the zip
//! ([`write_fmu`]), and the model with a held drive input the FMU's shared library steps
//! ([`held::HeldDrive`]). The shared library itself is the crate `telescopic-fmu` (`fmu/`),
//! which exports the FMI C functions over this library.
//!
//! ```
//! use telescopic::Scene;
//! use telescopic::fmu::{FmuKind, model_description, scene_text};
//!
//! let scene = Scene::load("scenes/adams-clearance.toml".as_ref(), &[])?;
//! let (_, scene) = scene_text(&scene)?;
//! let xml = model_description(&scene, FmuKind::Both)?;
//! assert!(xml.contains(r#"<ScalarVariable name="tip_rel" valueReference="2""#));
//! # Ok::<(), telescopic::Error>(())
//! ```

pub mod description;
pub mod held;
pub mod variables;

pub use description::{FmuKind, MODEL_IDENTIFIER, guid, model_description, scene_guid};
pub use variables::{Causality, FmuVariables, Variable};

use crate::OptionName;
use crate::{Error, Result};
use std::io::Write;
use std::path::Path;
use telescopic_runtime::Scene;

/// Where the scene goes inside the FMU.
pub const SCENE_RESOURCE: &str = "scene.toml";

/// The scene as the FMU carries it (overrides applied), and the scene read back from that
/// text: what the FMU's library will see, so the description is built from the same.
///
/// # Errors
/// [`Error::Model`] when the scene does not serialize, or does not read back.
pub fn scene_text(scene: &Scene) -> Result<(String, Scene)> {
    let text = toml::to_string(&scene.file)
        .map_err(|e| Error::Model(format!("the scene does not serialize as TOML: {e}")))?;
    let back = Scene::from_toml_str(&text, Path::new(SCENE_RESOURCE), &[])?;
    Ok((text, back))
}

/// Writes the FMU of `scene` to `out` (whole or not at all): `modelDescription.xml`,
/// `binaries/linux64/telescopic_fmu.so` (a copy of `library`, the built `telescopic-fmu`
/// cdylib) and `resources/scene.toml`.
///
/// # Errors
/// [`Error::Option`] for a scene an FMU cannot take or a missing library; [`Error::Write`].
pub fn write_fmu(scene: &Scene, library: &Path, kind: FmuKind, out: &Path) -> Result<()> {
    let (text, scene) = scene_text(scene)?;
    let xml = model_description(&scene, kind)?;
    let binary = std::fs::read(library).map_err(|e| {
        Error::option(
            OptionName::FmuLibrary,
            format!(
                "{}: {e}; build it with `cargo build --release --manifest-path fmu/Cargo.toml` (docs/fmu.md)",
                library.display()
            ),
        )
    })?;
    crate::io::output::write_atomically(out, |w| {
        let mut zip = zip::ZipWriter::new(std::io::Cursor::new(Vec::new()));
        let options = zip::write::SimpleFileOptions::default()
            .compression_method(zip::CompressionMethod::Stored);
        for (name, bytes) in [
            ("modelDescription.xml".to_string(), xml.as_bytes()),
            (
                format!("binaries/linux64/{MODEL_IDENTIFIER}.so"),
                &binary[..],
            ),
            (format!("resources/{SCENE_RESOURCE}"), text.as_bytes()),
        ] {
            zip.start_file(name, options)
                .map_err(std::io::Error::other)?;
            zip.write_all(bytes)?;
        }
        let cursor = zip.finish().map_err(std::io::Error::other)?;
        w.write_all(cursor.get_ref())
    })
}
