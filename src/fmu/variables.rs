//! The variables of a scene's FMU, in value-reference order: the one table that both the
//! `modelDescription.xml` writer and the FMU's shared library build from the scene, so their
//! value references cannot disagree.
//!
//! | value references | what |
//! |---|---|
//! | 0 | `F` (N), input: the drive force, held over a communication step (`a_vehicle`, m/s^2, the vehicle's acceleration, for a prescribed motion) |
//! | 1 .. | the outputs of `telescopic simulate` (`vehicle`, `tip_rel`, `top1_rel`, gaps `xi_k_j`, contact forces `f_k_j`, `drive_force` for a prescribed motion, `kappa_1_0`, `acc_load`) |
//! | then | parameters, named by their scene keys (`masses.load`, `contact.clearance`, ...) |
//! | then | the continuous states (`u`, `q_1_2`, ..., `u_dot`, ...: docs/linear.md) |
//! | then | their derivatives `der(u)`, ... |

use crate::Result;
use telescopic_runtime::analysis::linear::{output_signal, state_names};
use telescopic_runtime::model::sensors::SENSOR_OUTPUTS;
use telescopic_runtime::scene::SceneKey;
use telescopic_runtime::{Drive, Layout, Scene};

/// What a variable is to the importing tool.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Causality {
    /// Set by the importer every step (`F`).
    Input,
    /// Computed by the FMU.
    Output,
    /// Set before initialization.
    Parameter,
    /// A continuous state or its derivative.
    Local,
}

/// One scalar variable (all are `Real`).
#[derive(Debug, Clone, PartialEq)]
pub struct Variable {
    /// Name (flat naming convention; parameters are the scene keys of `--set`).
    pub name: String,
    /// Value reference.
    pub reference: u32,
    /// Causality.
    pub causality: Causality,
    /// SI unit (empty for none).
    pub unit: String,
    /// What it is.
    pub description: String,
    /// Start value (inputs, parameters, states).
    pub start: Option<f64>,
    /// For a derivative, the index (1-based, as in the XML) of its state's variable.
    pub derivative_of: Option<usize>,
}

/// The scene keys an FMU exposes as parameters (their units and descriptions are the
/// scene's [`telescopic_runtime::scene::KEYS`]). They do not change the model's
/// configuration, except `contact.clearance` between zero and nonzero (the FMU then runs on
/// the assembled model).
const PARAMETERS: [&str; 7] = [
    "masses.vehicle",
    "masses.load",
    "gravity.g",
    "contact.stiffness",
    "contact.damping",
    "contact.clearance",
    "sections.damping_ratio",
];

/// The variables of `scene`'s FMU.
#[derive(Debug, Clone, PartialEq)]
pub struct FmuVariables {
    /// Every variable, in value-reference order (index = value reference).
    pub variables: Vec<Variable>,
    /// Number of outputs (value references `1..=outputs`).
    pub outputs: usize,
    /// Value reference of the first parameter.
    pub first_parameter: u32,
    /// Value reference of the first state.
    pub first_state: u32,
    /// Number of continuous states.
    pub states: usize,
    /// Number of event indicators (two per contact with clearance: the band's edges).
    pub event_indicators: usize,
}

/// The FMU's one input (value reference 0): the drive force, or the vehicle's acceleration
/// when the scene prescribes its motion; its start is the scene's value at the start.
fn input_variable(scene: &Scene, motion: bool) -> Variable {
    let p = &scene.params;
    let (input, unit, description, start) = if motion {
        (
            "a_vehicle",
            "m/s2",
            "the vehicle's acceleration, replacing the scene's prescribed motion",
            p.drive_profile().acceleration(scene.time.start),
        )
    } else {
        (
            "F",
            "N",
            "drive force on the vehicle, replacing the scene's profile",
            p.drive_profile().value(scene.time.start),
        )
    };
    Variable {
        name: input.into(),
        reference: 0,
        causality: Causality::Input,
        unit: unit.into(),
        description: description.into(),
        start: Some(start),
        derivative_of: None,
    }
}

impl FmuVariables {
    /// The variables of `scene`.
    ///
    /// # Errors
    /// None today; the `Result` leaves room for scenes an FMU cannot take.
    pub fn of(scene: &Scene) -> Result<Self> {
        let p = &scene.params;
        let motion = matches!(p.drive, Drive::Motion(_));
        let layout = Layout::new(&p.modes(), p.contact_points);
        let mut variables = vec![input_variable(scene, motion)];
        let mut names = layout.output_names(motion);
        names.extend(SENSOR_OUTPUTS.iter().map(|s| s.to_string()));
        for name in &names {
            let signal = output_signal(name);
            variables.push(Variable {
                reference: variables.len() as u32,
                causality: Causality::Output,
                unit: fmi_unit(&signal.unit),
                description: signal.description,
                start: None,
                derivative_of: None,
                name: name.clone(),
            });
        }
        let outputs = names.len();
        let first_parameter = variables.len() as u32;
        for key in PARAMETERS {
            // a value the scene does not have (no contacts in a single section, damping
            // ratios by mode or Rayleigh damping) is no parameter
            let Ok(value) = scene.value(key) else {
                continue;
            };
            let field = SceneKey::parse(key)
                .expect("an FMU parameter is a scene key")
                .field;
            variables.push(Variable {
                name: key.into(),
                reference: variables.len() as u32,
                causality: Causality::Parameter,
                unit: fmi_unit(field.unit),
                description: field.description.into(),
                start: Some(value),
                derivative_of: None,
            });
        }
        let first_state = variables.len() as u32;
        let state_names = state_names(&p.modes());
        for name in &state_names {
            variables.push(Variable {
                name: name.clone(),
                reference: variables.len() as u32,
                causality: Causality::Local,
                unit: String::new(),
                description: "continuous state (docs/linear.md)".into(),
                start: Some(0.0),
                derivative_of: None,
            });
        }
        for (i, name) in state_names.iter().enumerate() {
            variables.push(Variable {
                name: format!("der({name})"),
                reference: variables.len() as u32,
                causality: Causality::Local,
                unit: String::new(),
                description: format!("time derivative of {name}"),
                start: None,
                derivative_of: Some(first_state as usize + i + 1),
            });
        }
        let event_indicators = if p.contact.clearance > 0.0 {
            2 * layout.contact_count()
        } else {
            0
        };
        Ok(FmuVariables {
            outputs,
            first_parameter,
            first_state,
            states: state_names.len(),
            event_indicators,
            variables,
        })
    }

    /// The parameters, as `(value reference, scene key)`.
    pub fn parameters(&self) -> impl Iterator<Item = (u32, &str)> {
        self.variables
            .iter()
            .filter(|v| v.causality == Causality::Parameter)
            .map(|v| (v.reference, v.name.as_str()))
    }
}

/// A unit as FMI names it: no caret, a dot for a product (`m/s^2` -> `m/s2`, `N s/m` ->
/// `N.s/m`).
fn fmi_unit(unit: &str) -> String {
    unit.replace('^', "").replace(' ', ".")
}

#[cfg(test)]
mod tests {
    use super::*;

    fn variables(overrides: &[&str]) -> FmuVariables {
        let overrides: Vec<String> = overrides.iter().map(|s| s.to_string()).collect();
        let scene = Scene::load("scenes/case-study.toml".as_ref(), &overrides).unwrap();
        FmuVariables::of(&scene).unwrap()
    }

    fn parameter<'v>(vars: &'v FmuVariables, key: &str) -> Option<&'v Variable> {
        vars.variables
            .iter()
            .find(|v| v.causality == Causality::Parameter && v.name == key)
    }

    #[test]
    fn parameters_carry_the_scene_keys_units_in_fmi_spelling() {
        let vars = variables(&[]);
        assert_eq!(parameter(&vars, "gravity.g").unwrap().unit, "m/s2");
        assert_eq!(parameter(&vars, "contact.damping").unwrap().unit, "N.s/m");
        assert_eq!(
            parameter(&vars, "sections.damping_ratio").unwrap().start,
            Some(0.0)
        );
    }

    #[test]
    fn a_rayleigh_damped_scene_has_no_modal_damping_ratio_parameter() {
        let vars = variables(&["sections.rayleigh_alpha=0.1"]);
        assert!(parameter(&vars, "sections.damping_ratio").is_none());
        assert!(parameter(&vars, "contact.stiffness").is_some());
    }
}
