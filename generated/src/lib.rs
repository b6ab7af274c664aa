//! Models generated at build time by `telescopic-codegen` for the configurations listed in
//! `generated/models.toml`, and a registry to find the one that matches a scene.
//!
//! Add a configuration: append a `[[model]]` entry to `models.toml` (the CLI prints the
//! exact entry when a scene has no generated model) and rebuild.

#![warn(missing_docs)]

use telescopic_runtime::{Drive, ForceFlow, Model, ModelParams};

include!(concat!(env!("OUT_DIR"), "/registry.rs"));

/// The words a configuration key and a `models.toml` entry use for these parameters:
/// `(flow in keys, flow in models.toml, clearance, positions, drive)`.
fn config_words(
    params: &ModelParams,
) -> (&'static str, &'static str, bool, &'static str, &'static str) {
    let (key_flow, toml_flow) = match params.force_flow {
        ForceFlow::Cable => ("cable", "cable"),
        ForceFlow::External => ("external", "external"),
        ForceFlow::None => ("noflow", "none"),
    };
    let positions = if params.positions.iter().all(|p| p.is_constant()) {
        "fixed"
    } else {
        "moving"
    };
    let drive = match params.drive {
        Drive::Force(_) => "force",
        Drive::Motion(_) => "motion",
    };
    (
        key_flow,
        toml_flow,
        params.contact.clearance > 0.0,
        positions,
        drive,
    )
}

/// The configuration key of a scene's parameters, as `telescopic-codegen` names it, e.g.
/// `s2_m5x5_c3_cable_linear_fixed_force`.
pub fn key_for(params: &ModelParams) -> String {
    let modes: Vec<String> = params.modes().iter().map(|m| m.to_string()).collect();
    let (flow, _, clearance, positions, drive) = config_words(params);
    let law = if clearance { "clearance" } else { "linear" };
    format!(
        "s{}_m{}_c{}_{flow}_{law}_{positions}_{drive}",
        params.sections.len(),
        modes.join("x"),
        params.contact_points
    )
}

/// The `models.toml` entry that would generate a model for these parameters.
pub fn models_toml_entry(params: &ModelParams) -> String {
    let (_, flow, clearance, positions, drive) = config_words(params);
    format!(
        "[[model]]\nmodes = {:?}\ncontacts = {}\nforce_flow = \"{flow}\"\nclearance = {clearance}\npositions = \"{positions}\"\ndrive = \"{drive}\"\n",
        params.modes(),
        params.contact_points,
    )
}

/// The generated model for `params`, if its configuration was generated.
///
/// # Errors
/// `Some(Err)` if the generated model rejects the parameters (a mismatch the key missed).
pub fn prepare(params: &ModelParams) -> Option<Result<Box<dyn Model>, String>> {
    prepare_by_key(&key_for(params), params)
}
