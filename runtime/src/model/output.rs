//! The outputs of a run or a linear model as values: what each measures, its column name,
//! unit and description (docs/model.md section 5). A column's name is parsed once; code
//! asks the [`Output`] what it is instead of reading prefixes of names.

use std::fmt;
use std::str::FromStr;

/// What a machine's sensor measures (appended to every run's outputs, in [`Sensor::ALL`]'s
/// order).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Sensor {
    /// `kappa_1_0` (1/m): the bending curvature of section 1 at its foot (a strain gauge
    /// reads it times half the section's height).
    FootCurvature,
    /// `acc_load` (m/s^2): the load's absolute horizontal acceleration (a tip accelerometer).
    LoadAcceleration,
}

impl Sensor {
    /// Every sensor, in the order of the outputs.
    pub const ALL: [Sensor; 2] = [Sensor::FootCurvature, Sensor::LoadAcceleration];

    /// The column's name.
    pub const fn name(self) -> &'static str {
        match self {
            Sensor::FootCurvature => "kappa_1_0",
            Sensor::LoadAcceleration => "acc_load",
        }
    }

    /// The sensor of a column's name.
    pub fn parse(name: &str) -> Option<Sensor> {
        Sensor::ALL.into_iter().find(|s| s.name() == name)
    }
}

/// One input of a linear model.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum LinearInput {
    /// `F` (N): the drive force on the vehicle (a force-driven scene).
    DriveForce,
    /// `a_vehicle` (m/s^2): the vehicle's acceleration (a scene with prescribed motion).
    VehicleAcceleration,
    /// `F_load` (N): a horizontal disturbance force on the load at the top of section n.
    LoadForce,
}

impl LinearInput {
    /// Every input.
    pub const ALL: [LinearInput; 3] = [
        LinearInput::DriveForce,
        LinearInput::VehicleAcceleration,
        LinearInput::LoadForce,
    ];

    /// The input's name in linear models and exports.
    pub const fn name(self) -> &'static str {
        match self {
            LinearInput::DriveForce => "F",
            LinearInput::VehicleAcceleration => "a_vehicle",
            LinearInput::LoadForce => "F_load",
        }
    }

    /// The input's unit.
    pub fn unit(self) -> &'static str {
        match self {
            LinearInput::DriveForce | LinearInput::LoadForce => "N",
            LinearInput::VehicleAcceleration => "m/s^2",
        }
    }

    /// What the input is, in one line.
    pub fn description(self) -> &'static str {
        match self {
            LinearInput::DriveForce => "drive force on the vehicle",
            LinearInput::VehicleAcceleration => "prescribed vehicle acceleration",
            LinearInput::LoadForce => {
                "horizontal disturbance force on the load at the top of section n"
            }
        }
    }
}

impl fmt::Display for LinearInput {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for LinearInput {
    type Err = String;

    fn from_str(name: &str) -> Result<Self, String> {
        LinearInput::ALL
            .into_iter()
            .find(|i| i.name() == name.trim())
            .ok_or_else(|| format!("`{name}` is no input; inputs are F, a_vehicle and F_load"))
    }
}

/// One output of a run or a linear model.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Output {
    /// `vehicle` (m): the vehicle's position `w_1(0,t)`.
    Vehicle,
    /// `tip_rel` (m): the load relative to the foot, `w_n(l_n,t) - w_1(0,t)`.
    TipRel,
    /// `top<k>_rel` (m): the top of section `k` relative to the foot.
    TopRel(usize),
    /// `xi_k_j` (m): the gap at contact point `j` (0-based) of overlap `k` (2..=n).
    Gap {
        /// Overlap `k`: the inner section.
        overlap: usize,
        /// Point `j` along the overlap.
        point: usize,
    },
    /// `f_k_j` (N): the force at contact point `j` of overlap `k`.
    ContactForce {
        /// Overlap `k`: the inner section.
        overlap: usize,
        /// Point `j` along the overlap.
        point: usize,
    },
    /// `drive_force` (N): the force a prescribed motion takes (the drive's reaction).
    DriveForce,
    /// `moment_k_x` (N m): the bending moment of section `k` at `x` m from its foot.
    Moment {
        /// Section `k` (1-based).
        section: usize,
        /// Distance from the section's foot (m).
        x: f64,
    },
    /// `stress_k_x` (Pa): the bending stress at the outer fibre there.
    Stress {
        /// Section `k` (1-based).
        section: usize,
        /// Distance from the section's foot (m).
        x: f64,
    },
    /// A sensor's reading.
    Sensor(Sensor),
}

impl Output {
    /// The column's unit.
    pub fn unit(&self) -> &'static str {
        match self {
            Output::Vehicle | Output::TipRel | Output::TopRel(_) | Output::Gap { .. } => "m",
            Output::ContactForce { .. } | Output::DriveForce => "N",
            Output::Moment { .. } => "N m",
            Output::Stress { .. } => "Pa",
            Output::Sensor(Sensor::FootCurvature) => "1/m",
            Output::Sensor(Sensor::LoadAcceleration) => "m/s^2",
        }
    }

    /// What the column measures, in one line.
    pub fn description(&self) -> String {
        match *self {
            Output::Vehicle => "vehicle position w_1(0,t)".into(),
            Output::TipRel => "load relative to the foot, w_n(l_n,t) - w_1(0,t)".into(),
            Output::TopRel(k) => {
                format!("top of section {k} relative to the foot, w_{k}(l_{k},t) - w_1(0,t)")
            }
            Output::Gap { overlap, point } => {
                format!("gap at contact {point} of overlap {overlap}")
            }
            Output::ContactForce { overlap, point } => {
                format!("force at contact {point} of overlap {overlap}")
            }
            Output::DriveForce => "force the prescribed motion takes (the drive's reaction)".into(),
            Output::Moment { section, x } => {
                format!("bending moment of section {section} at {x} m from its foot")
            }
            Output::Stress { section, x } => {
                format!("bending stress of section {section} at {x} m from its foot")
            }
            Output::Sensor(Sensor::FootCurvature) => {
                "bending curvature of section 1 at its foot, w_1''(0,t) (a strain gauge reads \
                 it times half the section's height)"
                    .into()
            }
            Output::Sensor(Sensor::LoadAcceleration) => {
                "absolute horizontal acceleration of the load, d^2/dt^2 w_n(l_n,t)".into()
            }
        }
    }

    /// Whether the output is a contact's gap.
    pub fn is_gap(&self) -> bool {
        matches!(self, Output::Gap { .. })
    }

    /// Whether the output is a contact's force.
    pub fn is_contact_force(&self) -> bool {
        matches!(self, Output::ContactForce { .. })
    }

    /// The output a column's name stands for; `None` for a name that is no output (a
    /// generalized coordinate, a controller's column).
    pub fn parse(name: &str) -> Option<Output> {
        let pair = |rest: &str| -> Option<(usize, usize)> {
            let (a, b) = rest.split_once('_')?;
            Some((a.parse().ok()?, b.parse().ok()?))
        };
        let station = |rest: &str| -> Option<(usize, f64)> {
            let (k, x) = rest.split_once('_')?;
            Some((k.parse().ok()?, x.parse().ok()?))
        };
        match name {
            "vehicle" => return Some(Output::Vehicle),
            "tip_rel" => return Some(Output::TipRel),
            "drive_force" => return Some(Output::DriveForce),
            _ => {}
        }
        if let Some(sensor) = Sensor::parse(name) {
            return Some(Output::Sensor(sensor));
        }
        if let Some(rest) = name.strip_prefix("xi_") {
            let (overlap, point) = pair(rest)?;
            return Some(Output::Gap { overlap, point });
        }
        if let Some(rest) = name.strip_prefix("f_") {
            let (overlap, point) = pair(rest)?;
            return Some(Output::ContactForce { overlap, point });
        }
        if let Some(rest) = name.strip_prefix("moment_") {
            let (section, x) = station(rest)?;
            return Some(Output::Moment { section, x });
        }
        if let Some(rest) = name.strip_prefix("stress_") {
            let (section, x) = station(rest)?;
            return Some(Output::Stress { section, x });
        }
        let k = name.strip_prefix("top")?.strip_suffix("_rel")?;
        k.parse().ok().map(Output::TopRel)
    }
}

impl fmt::Display for Output {
    /// The column's name.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Output::Vehicle => f.write_str("vehicle"),
            Output::TipRel => f.write_str("tip_rel"),
            Output::TopRel(k) => write!(f, "top{k}_rel"),
            Output::Gap { overlap, point } => write!(f, "xi_{overlap}_{point}"),
            Output::ContactForce { overlap, point } => write!(f, "f_{overlap}_{point}"),
            Output::DriveForce => f.write_str("drive_force"),
            Output::Moment { section, x } => write!(f, "moment_{section}_{x}"),
            Output::Stress { section, x } => write!(f, "stress_{section}_{x}"),
            Output::Sensor(s) => f.write_str(s.name()),
        }
    }
}

impl FromStr for Output {
    type Err = String;

    fn from_str(name: &str) -> Result<Self, String> {
        Output::parse(name).ok_or_else(|| {
            format!(
                "`{name}` is no output; outputs are vehicle, tip_rel, top1_rel, xi_k_j, f_k_j, \
                 drive_force, moment_k_x, stress_k_x, kappa_1_0 and acc_load"
            )
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_output_reads_back_from_its_name() {
        let outputs = [
            Output::Vehicle,
            Output::TipRel,
            Output::TopRel(1),
            Output::TopRel(12),
            Output::Gap {
                overlap: 3,
                point: 1,
            },
            Output::ContactForce {
                overlap: 2,
                point: 0,
            },
            Output::DriveForce,
            Output::Moment {
                section: 1,
                x: 0.675,
            },
            Output::Stress { section: 2, x: 1.0 },
            Output::Sensor(Sensor::FootCurvature),
            Output::Sensor(Sensor::LoadAcceleration),
        ];
        for output in outputs {
            assert_eq!(Output::parse(&output.to_string()), Some(output), "{output}");
            assert!(!output.unit().is_empty() && !output.description().is_empty());
        }
        assert_eq!(Output::TopRel(1).to_string(), "top1_rel");
        assert_eq!(
            Output::Moment {
                section: 1,
                x: 0.675
            }
            .to_string(),
            "moment_1_0.675"
        );
    }

    #[test]
    fn every_input_reads_back_from_its_name() {
        for input in LinearInput::ALL {
            assert_eq!(input.to_string().parse::<LinearInput>(), Ok(input));
        }
        assert!("G".parse::<LinearInput>().unwrap_err().contains("no input"));
    }

    #[test]
    fn names_that_are_no_output_are_none() {
        for name in [
            "u", "q_1_2", "r_2", "xi_2", "f_a_b", "top_rel", "moment_1", "F", "",
        ] {
            assert_eq!(Output::parse(name), None, "{name}");
        }
        assert!("xi_2".parse::<Output>().unwrap_err().contains("no output"));
    }
}
