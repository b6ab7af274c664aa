//! The structural configuration of a set of parameters, in the words of the generator
//! (`telescopic-codegen`): its key, which names a generated module, and the `[[model]]`
//! entry of a models file that would generate it. Kept equal to the generator's own
//! `ModelConfig::key` by a test of the generated crate.

use crate::params::{Drive, ForceFlow, ModelParams};

/// The words of a configuration: `(flow in keys, flow in models files, clearance,
/// positions, drive)`.
fn words(params: &ModelParams) -> (&'static str, &'static str, bool, &'static str, &'static str) {
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

/// The configuration key of these parameters, as the generator names its module, e.g.
/// `s2_m5x5_c3_cable_linear_fixed_force`.
///
/// ```
/// # let scene = telescopic_runtime::Scene::load("../scenes/test-rig.toml".as_ref(), &[]).unwrap();
/// assert_eq!(
///     telescopic_runtime::configuration_key(&scene.params),
///     "s2_m5x5_c3_cable_linear_fixed_force"
/// );
/// ```
pub fn configuration_key(params: &ModelParams) -> String {
    let modes: Vec<String> = params.modes().iter().map(|m| m.to_string()).collect();
    let (flow, _, clearance, positions, drive) = words(params);
    let law = if clearance { "clearance" } else { "linear" };
    format!(
        "s{}_m{}_c{}_{flow}_{law}_{positions}_{drive}",
        params.sections.len(),
        modes.join("x"),
        params.contact_points
    )
}

/// The `[[model]]` entry of a models file that generates a model for these parameters.
pub fn models_toml_entry(params: &ModelParams) -> String {
    let (_, flow, clearance, positions, drive) = words(params);
    format!(
        "[[model]]\nmodes = {:?}\ncontacts = {}\nforce_flow = \"{flow}\"\nclearance = \
         {clearance}\npositions = \"{positions}\"\ndrive = \"{drive}\"\n",
        params.modes(),
        params.contact_points,
    )
}
