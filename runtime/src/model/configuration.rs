//! The structural configuration of a model: everything that changes the equations' form
//! (modes per section, contacts per overlap, force flow, clearance law, fixed or moving
//! positions, drive). Physical values (lengths, masses, stiffnesses) stay parameters. The
//! generator (`telescopic-codegen`) generates a model per [`ModelConfig`]; the runtime finds
//! a scene's model by [`configuration_key`]; both speak the words of `telescopic-config`,
//! re-exported here with the configuration of a set of parameters.

pub use telescopic_config::{DriveKind, ForceFlow, ModelConfig, Positions, StaticKnots};

use crate::model::params::{Basis, Drive, ModelParams, correction_knots};

/// The configuration of a set of parameters.
pub fn config_of(params: &ModelParams) -> ModelConfig {
    ModelConfig {
        modes: params.modes(),
        contacts: params.contact_points,
        force_flow: params.force_flow,
        clearance: params.contact.clearance > 0.0,
        positions: if params.positions.iter().all(|p| p.is_constant()) {
            Positions::Fixed
        } else {
            Positions::Moving
        },
        drive: match params.drive {
            Drive::Force(_) => DriveKind::Force,
            Drive::Motion(_) => DriveKind::Motion,
        },
        static_knots: match params.basis {
            Basis::Modes => None,
            Basis::ModesAndStatic => Some(StaticKnots(
                (1..=params.sections.len())
                    .map(|k| {
                        let l = params.sections[k - 1].length;
                        correction_knots(params, k).iter().map(|x| x / l).collect()
                    })
                    .collect(),
            )),
        },
    }
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
    config_of(params).key()
}

/// The `[[model]]` entry of a models file that generates a model for these parameters.
pub fn models_toml_entry(params: &ModelParams) -> String {
    config_of(params).models_toml_entry()
}
