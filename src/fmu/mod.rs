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

/// Largest FMU library read (bytes): the release build is a few MiB.
const MAX_LIBRARY_BYTES: u64 = 256 << 20;

/// The FMU's shared library at `library`: read with a size cap, and checked to be a 64-bit
/// ELF shared object that exports the FMI functions.
///
/// # Errors
/// [`Error::Option`] naming the file and what it is not.
fn read_library(library: &Path) -> Result<Vec<u8>> {
    let refused = |why: String| {
        Error::option(
            OptionName::FmuLibrary,
            format!(
                "{}: {why}; build it with `cargo build --release --manifest-path fmu/Cargo.toml` \
                 (docs/fmu.md)",
                library.display()
            ),
        )
    };
    // the header first: a device or a large file of another kind is refused unread
    let mut header = [0u8; 18];
    std::fs::File::open(library)
        .and_then(|mut f| std::io::Read::read_exact(&mut f, &mut header))
        .map_err(|e| refused(e.to_string()))?;
    // ELF magic, 64-bit class, and e_type ET_DYN (3) at byte 16, little-endian
    if header[..4] != *b"\x7fELF" || header[4] != 2 || header[16..18] != [3, 0] {
        return Err(refused("not a 64-bit ELF shared library".into()));
    }
    let binary = telescopic_runtime::input::read_bytes(library, MAX_LIBRARY_BYTES)
        .map_err(|e| refused(e.to_string()))?;
    if has_interpreter(&binary) {
        return Err(refused("an executable, not a shared library".into()));
    }
    let exports = |name: &[u8]| binary.windows(name.len()).any(|w| w == name);
    if !exports(b"fmi2Instantiate") || !exports(b"fmi2DoStep") {
        return Err(refused(
            "a shared library without the FMI 2.0 functions (fmi2Instantiate, fmi2DoStep)".into(),
        ));
    }
    Ok(binary)
}

/// Whether the 64-bit little-endian ELF `binary` asks for a program interpreter (a
/// `PT_INTERP` program header): an executable, a position-independent one included, which
/// has the shared library's ELF type. Hand-read: three header fields and the program
/// headers' types; no ELF crate is needed for that.
fn has_interpreter(binary: &[u8]) -> bool {
    let field = |at: usize, len: usize| -> Option<u64> {
        let bytes = binary.get(at..at.checked_add(len)?)?;
        Some(bytes.iter().rev().fold(0, |v, b| (v << 8) | u64::from(*b)))
    };
    let (Some(offset), Some(size), Some(count)) = (field(32, 8), field(54, 2), field(56, 2)) else {
        return false;
    };
    (0..count).any(|i| {
        i.checked_mul(size)
            .and_then(|d| d.checked_add(offset))
            .and_then(|at| usize::try_from(at).ok())
            .and_then(|at| field(at, 4))
            == Some(3)
    })
}

/// Where the scene goes inside the FMU.
pub const SCENE_RESOURCE: &str = "scene.toml";

/// The scene as the FMU carries it (overrides applied), and the scene read back from that
/// text: what the FMU's library will see, so the description is built from the same.
///
/// # Errors
/// [`Error::Scene`] when the scene does not read back.
pub fn scene_text(scene: &Scene) -> Result<(String, Scene)> {
    let text = scene.file.to_toml();
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
    let binary = read_library(library)?;
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
