//! Names this build's sources for the records of `telescopic::run::reuse`: a record kept by a
//! build of other sources is stale, even at one version (its budget may come from other code).
//! The digest is the SHA-256 of the library's, the runtime's, the generated models' and the
//! configuration's source files, by path and content.

use sha2::{Digest, Sha256};
use std::path::{Path, PathBuf};

/// The source directories whose files make a run's result and its budget.
const SOURCES: [&str; 4] = ["src", "runtime/src", "generated/src", "config/src"];

fn main() {
    let mut files = Vec::new();
    for dir in SOURCES {
        println!("cargo:rerun-if-changed={dir}");
        collect(Path::new(dir), &mut files);
    }
    files.sort();
    let mut hasher = Sha256::new();
    for file in &files {
        hasher.update(file.to_string_lossy().as_bytes());
        hasher.update([0]);
        hasher.update(std::fs::read(file).unwrap_or_default());
    }
    println!(
        "cargo:rustc-env=TELESCOPIC_SOURCE_DIGEST={:x}",
        hasher.finalize()
    );
}

/// Every file under `dir` (none when it is missing: a packaged crate has only its own).
fn collect(dir: &Path, files: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for entry in entries.flatten() {
        let path = entry.path();
        match path.is_dir() {
            true => collect(&path, files),
            false => files.push(path),
        }
    }
}
