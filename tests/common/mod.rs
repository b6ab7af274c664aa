//! What several test files share: the shipped scenes and their generated models, a single
//! section of the test rig's data on its vehicle, the C compiler call of the emitted code's tests;
//! reference runs and the predictability horizon ([`references`]).
// each test binary uses its own part of this module
#![allow(dead_code)]

pub mod references;

use std::path::Path;
use telescopic::Scene;
use telescopic::runtime::Model;

/// A shipped scene (`scenes/<name>.toml`) with `--set` overrides.
pub fn scene(name: &str, overrides: &[&str]) -> Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scenes")
        .join(format!("{name}.toml"));
    let overrides: Vec<String> = overrides.iter().map(|s| s.to_string()).collect();
    Scene::load(&path, &overrides).unwrap()
}

/// The committed generated model of a shipped scene.
pub fn generated(scene: &Scene) -> Box<dyn Model> {
    telescopic_generated::prepare(&scene.params)
        .expect("every shipped scene has a generated model")
        .unwrap()
}

/// One section of the test rig (1.35 m steel, A = 0.001 m^2, I = 0.83e-8 m^4) on a 100 kg
/// vehicle with a 5 kg load, gravity off; `drive` is the `[drive]` table's body, `end` and
/// `sample` the time span (s); `overrides` as `--set` (modes, damping, ...).
pub fn single_section(
    name: &str,
    drive: &str,
    end: f64,
    sample: f64,
    overrides: &[String],
) -> Scene {
    let text = format!(
        "name = \"{name}\"\n[sections]\ncount = 1\nlength = 1.35\narea = 0.001\n\
         inertia = 0.83e-8\ndensity = 7850.0\nyoungs_modulus = 2.1e11\nmodes = 5\n\
         [masses]\nvehicle = 100.0\nload = 5.0\n[gravity]\ng = 0.0\n[drive]\n{drive}\n\
         [time]\nend = {end}\nsample = {sample}\n"
    );
    Scene::from_toml_str(&text, Path::new(&format!("{name}.toml")), overrides).unwrap()
}

/// Compiles C99 `sources` (headers from `include`) with every warning an error and `flags`
/// into `out`, linking the maths library.
pub fn compile_c(
    flags: &[&str],
    sources: &[&std::path::Path],
    include: &std::path::Path,
    out: &std::path::Path,
) {
    let compiled = std::process::Command::new("cc")
        .args(["-std=c99", "-Wall", "-Wextra", "-Werror", "-pedantic"])
        .args(flags)
        .arg("-I")
        .arg(include)
        .args(sources)
        .arg("-o")
        .arg(out)
        .arg("-lm")
        .output()
        .expect("cc runs");
    assert!(
        compiled.status.success(),
        "{}",
        String::from_utf8_lossy(&compiled.stderr)
    );
}
