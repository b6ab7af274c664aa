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
use telescopic_runtime::linear::{output_signal, state_names};
use telescopic_runtime::sensors::SENSOR_OUTPUTS;
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

/// The parameters an FMU exposes: `(scene key, unit, description)`. They do not change the
/// model's configuration, except `contact.clearance` between zero and nonzero (the FMU then
/// runs on the assembled model).
const PARAMETERS: [(&str, &str, &str); 7] = [
    ("masses.vehicle", "kg", "vehicle mass m_T"),
    (
        "masses.load",
        "kg",
        "load mass m_L at the top of the last section",
    ),
    ("gravity.g", "m/s2", "gravitational acceleration"),
    ("contact.stiffness", "N/m", "contact stiffness c"),
    ("contact.damping", "N.s/m", "contact damping d"),
    (
        "contact.clearance",
        "m",
        "total clearance l_S of every overlap",
    ),
    (
        "sections.damping_ratio",
        "1",
        "modal structural damping ratio of every mode",
    ),
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

impl FmuVariables {
    /// The variables of `scene`.
    ///
    /// # Errors
    /// None today; the `Result` leaves room for scenes an FMU cannot take.
    pub fn of(scene: &Scene) -> Result<Self> {
        let p = &scene.params;
        let motion = matches!(p.drive, Drive::Motion(_));
        let layout = Layout::new(&p.modes(), p.contact_points);
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
        let mut variables = vec![Variable {
            name: input.into(),
            reference: 0,
            causality: Causality::Input,
            unit: unit.into(),
            description: description.into(),
            start: Some(start),
            derivative_of: None,
        }];
        let mut names = layout.output_names(motion);
        names.extend(SENSOR_OUTPUTS.iter().map(|s| s.to_string()));
        for name in &names {
            let signal = output_signal(name);
            variables.push(Variable {
                reference: variables.len() as u32,
                causality: Causality::Output,
                // FMI's unit names have no caret
                unit: signal.unit.replace('^', ""),
                description: signal.description,
                start: None,
                derivative_of: None,
                name: name.clone(),
            });
        }
        let outputs = names.len();
        let first_parameter = variables.len() as u32;
        for (key, unit, description) in PARAMETERS {
            let Some(value) = parameter_value(scene, key) else {
                continue;
            };
            variables.push(Variable {
                name: key.into(),
                reference: variables.len() as u32,
                causality: Causality::Parameter,
                unit: unit.into(),
                description: description.into(),
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

/// The scene's value of parameter `key`; `None` when the scene has no such value (no
/// contacts in a single section, damping ratios by mode or Rayleigh damping).
fn parameter_value(scene: &Scene, key: &str) -> Option<f64> {
    if key == "sections.damping_ratio"
        && (scene.file.sections.rayleigh_alpha.is_some()
            || scene.file.sections.rayleigh_beta.is_some())
    {
        return None;
    }
    scene.value(key).ok()
}
