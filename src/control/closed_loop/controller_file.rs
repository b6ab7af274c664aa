//! A controller file of either kind, as `simulate --controller` reads it: a designed
//! controller that drives the force ([`Controller`]), or a plan's velocity feedback that
//! corrects a prescribed motion ([`VelocityFeedback`]). The `format` field tells them apart.

use crate::control::closed_loop::comparison::{
    ControlComparison, beside_open_loop, compare_with_open_loop, comparison_options,
    simulate_controlled,
};
use crate::control::file::schema::Controller;
use crate::control::{
    closed_loop::velocity::simulate_velocity_told, file::velocity::VELOCITY_FEEDBACK_FORMAT,
    file::velocity::VelocityFeedback,
};
use crate::report::Reporter;
use crate::run::{Simulation, SimulationOptions};
use crate::{Error, OptionName, Result};
use std::path::Path;
use telescopic_runtime::Scene;

/// A controller file of either kind.
#[derive(Debug, Clone, PartialEq)]
pub enum ControllerFile {
    /// A designed controller driving the force (`telescopic design`).
    Force(Box<Controller>),
    /// A plan's velocity feedback (`telescopic plan --feedback`), told the load the machine
    /// weighs (kg; `None`: the scene's `masses.load`).
    Velocity {
        /// The feedback file.
        file: Box<VelocityFeedback>,
        /// The load the law is told (kg), if not the scene's.
        weighed_load_kg: Option<f64>,
    },
}

impl ControllerFile {
    /// Reads either kind from JSON, by its `format`.
    ///
    /// # Errors
    /// [`Error::Input`] naming what is malformed.
    pub fn from_json(text: &str) -> Result<Self> {
        crate::io::unique_keys::check_unique_keys(text)
            .map_err(|e| Error::input("controller file", e))?;
        let head: serde_json::Value =
            serde_json::from_str(text).map_err(|e| Error::input("controller file", e))?;
        if head.get("format").and_then(|f| f.as_str()) == Some(VELOCITY_FEEDBACK_FORMAT) {
            return Ok(ControllerFile::Velocity {
                file: Box::new(VelocityFeedback::from_json(text)?),
                weighed_load_kg: None,
            });
        }
        Ok(ControllerFile::Force(Box::new(Controller::from_json(
            text,
        )?)))
    }

    /// Reads either kind from `path` (size-capped like a scene).
    ///
    /// # Errors
    /// [`Error::Option`] naming the file and what is wrong.
    pub fn load(path: &Path) -> Result<Self> {
        crate::control::file::check::load_json(path, ControllerFile::from_json)
    }

    /// Checks that the file fits `scene`.
    ///
    /// # Errors
    /// As [`Controller::check_fits`] and [`VelocityFeedback::check_fits`].
    pub fn check_fits(&self, scene: &Scene) -> Result<()> {
        match self {
            ControllerFile::Force(c) => c.check_fits(scene),
            ControllerFile::Velocity { file, .. } => file.check_fits(scene),
        }
    }

    /// This controller with its velocity feedback told a load of `load_kg` (kg) whatever the
    /// scene carries: a machine that weighs its load wrongly.
    ///
    /// # Errors
    /// [`Error::Option`] ([`OptionName::WeighedLoad`]) for a force controller or a load that
    /// is not a finite mass of 0 kg or more.
    pub fn with_weighed_load(self, load_kg: f64) -> Result<Self> {
        let bad = |rule: String| Err(Error::option(OptionName::WeighedLoad, rule));
        if let Err(rule) = crate::control::file::velocity::check_weighed_load(load_kg) {
            return bad(rule);
        }
        match self {
            ControllerFile::Velocity { file, .. } => Ok(ControllerFile::Velocity {
                file,
                weighed_load_kg: Some(load_kg),
            }),
            ControllerFile::Force(_) => bad(
                "tells a plan's velocity feedback the load; a designed controller is not \
                 scheduled on it"
                    .into(),
            ),
        }
    }

    /// What the controller is, in a few words.
    pub fn describe(&self) -> String {
        match self {
            ControllerFile::Force(c) => c.describe(),
            ControllerFile::Velocity {
                file,
                weighed_load_kg,
            } => match weighed_load_kg {
                Some(load) if file.tables.len() > 1 => {
                    format!("{}, told a load of {load} kg", file.describe())
                }
                Some(load) => format!(
                    "{}, told a load of {load} kg, which its one table of design points does \
                     not use",
                    file.describe()
                ),
                None => file.describe(),
            },
        }
    }

    /// The drive's force limit (N) a force controller saturates at.
    pub fn force_limit(&self) -> Option<f64> {
        match self {
            ControllerFile::Force(c) => Some(c.force_limit_n),
            ControllerFile::Velocity { .. } => None,
        }
    }

    /// Simulates `scene` with this controller on the full nonlinear model.
    ///
    /// # Errors
    /// As [`simulate_controlled`] and [`simulate_velocity_told`].
    pub fn simulate(
        &self,
        scene: &Scene,
        options: &SimulationOptions,
        reporter: &dyn Reporter,
    ) -> Result<Simulation> {
        match self {
            ControllerFile::Force(c) => simulate_controlled(scene, c, options, reporter),
            ControllerFile::Velocity {
                file,
                weighed_load_kg,
            } => {
                let load = weighed_load_kg.unwrap_or(scene.params.load_mass);
                Ok(simulate_velocity_told(scene, file, load, options, reporter)?.simulation)
            }
        }
    }

    /// The summary sentence of `comparison`.
    pub fn summary(&self, comparison: &ControlComparison) -> String {
        comparison.summary_of(&self.describe(), self.force_limit())
    }
}

/// [`compare_with_open_loop`] for a file of either kind.
///
/// # Errors
/// The errors of the controlled and the open-loop simulation.
pub fn compare_file_with_open_loop(
    scene: &Scene,
    file: &ControllerFile,
    options: &SimulationOptions,
    reporter: &dyn Reporter,
) -> Result<ControlComparison> {
    if let ControllerFile::Force(c) = file {
        return compare_with_open_loop(scene, c, options, reporter);
    }
    crate::run::memory::check_runs(&[scene, scene], options.memory_budget)?;
    let controlled = file.simulate(scene, options, reporter)?;
    beside_open_loop(scene, controlled, &comparison_options(options)?, reporter)
}
