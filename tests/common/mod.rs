//! Helpers shared by the end-to-end tests of the binary.
#![allow(dead_code)]

use std::process::{Command, Output};

/// Runs the binary from the workspace root.
pub fn telescopic(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_telescopic"))
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .expect("the binary runs")
}

/// The command failed cleanly: non-zero exit, an error line naming `needles`, no panic.
pub fn fails_with(args: &[&str], needles: &[&str]) {
    let out = telescopic(args);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "{args:?} should fail");
    assert!(!err.contains("panicked"), "{args:?} panicked: {err}");
    assert!(
        out.stdout.is_empty(),
        "{args:?} printed to stdout on failure"
    );
    for n in needles {
        assert!(err.contains(n), "{args:?}: stderr lacks `{n}`:\n{err}");
    }
}
