//! A controller file of either kind, as `simulate --controller` reads it: a designed
//! controller that drives the force ([`Controller`]), or a plan's velocity feedback that
//! corrects a prescribed motion ([`VelocityFeedback`]). The `format` field tells them apart.

use crate::control::closed_loop::comparison::{
    ControlComparison, beside_open_loop, compare_with_open_loop, comparison_options,
    simulate_controlled,
};
use crate::control::file::schema::Controller;
use crate::control::{
    closed_loop::velocity::simulate_velocity, file::velocity::VELOCITY_FEEDBACK_FORMAT,
    file::velocity::VelocityFeedback,
};
use crate::report::Reporter;
use crate::run::{Simulation, SimulationOptions};
use crate::{Error, Result};
use std::path::Path;
use telescopic_runtime::Scene;

/// A controller file of either kind.
#[derive(Debug, Clone, PartialEq)]
pub enum ControllerFile {
    /// A designed controller driving the force (`telescopic design`).
    Force(Box<Controller>),
    /// A plan's velocity feedback (`telescopic plan --feedback`).
    Velocity(Box<VelocityFeedback>),
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
            return Ok(ControllerFile::Velocity(Box::new(
                VelocityFeedback::from_json(text)?,
            )));
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
            ControllerFile::Velocity(v) => v.check_fits(scene),
        }
    }

    /// What the controller is, in a few words.
    pub fn describe(&self) -> String {
        match self {
            ControllerFile::Force(c) => c.describe(),
            ControllerFile::Velocity(v) => v.describe(),
        }
    }

    /// The drive's force limit (N) a force controller saturates at.
    pub fn force_limit(&self) -> Option<f64> {
        match self {
            ControllerFile::Force(c) => Some(c.force_limit_n),
            ControllerFile::Velocity(_) => None,
        }
    }

    /// Simulates `scene` with this controller on the full nonlinear model.
    ///
    /// # Errors
    /// As [`simulate_controlled`] and [`simulate_velocity`].
    pub fn simulate(
        &self,
        scene: &Scene,
        options: &SimulationOptions,
        reporter: &dyn Reporter,
    ) -> Result<Simulation> {
        match self {
            ControllerFile::Force(c) => simulate_controlled(scene, c, options, reporter),
            ControllerFile::Velocity(v) => {
                Ok(simulate_velocity(scene, v, options, reporter)?.simulation)
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
    let feedback = match file {
        ControllerFile::Force(c) => return compare_with_open_loop(scene, c, options, reporter),
        ControllerFile::Velocity(v) => v,
    };
    crate::run::memory::check_runs(&[scene, scene], options.memory_budget)?;
    let controlled = simulate_velocity(scene, feedback, options, reporter)?.simulation;
    beside_open_loop(scene, controlled, &comparison_options(options)?, reporter)
}
