//! Command-line interface: the subcommands and the options they share.

use clap::{Args, Parser, Subcommand};
use std::path::PathBuf;
use telescopic_runtime::Scene;

/// Telescopic multi-section beams with clearance (Barthelis & Wauer 2005): derived Galerkin
/// equations, eigenfrequencies and simulation.
#[derive(Debug, Parser)]
#[command(name = "telescopic", version, about, long_about = None)]
pub struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Natural frequencies and mode shapes, linearized about the straight state with closed
    /// contacts (clearance and contact damping ignored, as for the paper's Table I).
    Modes(crate::modes::ModesArgs),
    /// The derived equations of motion of the scene's generated model: M, K, b, contact
    /// terms, generalized forces and their Jacobian, with parameters by name.
    Equations(crate::equations::EquationsArgs),
    /// Integrate the scene with the clearance contact law and write its outputs as CSV.
    Simulate(crate::simulate::SimulateArgs),
    /// The stiffest frequency with closed contacts and the largest stable step of the
    /// fixed-step explicit methods (textbook limits and the model's own).
    Stability(crate::stability::StabilityArgs),
    /// Speed against accuracy: every method over a sweep of tolerances or steps, errors
    /// inside the predictability horizon and on statistics beyond it; chart and CSV.
    WorkPrecision(crate::work_precision::WorkPrecisionArgs),
    /// The smallest model a scene needs: modes per section (then contacts per overlap)
    /// raised until tip_rel and the first three frequencies change by less than --tol.
    Converge(crate::converge::ConvergeArgs),
    /// Evaluation error of the shape functions for modes 1..30: the paper's printed forms
    /// against the cancellation-free ones, both measured in 512-bit arithmetic.
    ShapeErrors(crate::shape_errors::ShapeErrorsArgs),
}

/// A scene file and its overrides: shared by every command that reads a scene.
#[derive(Debug, Args)]
pub struct SceneArgs {
    /// Scene file (TOML); the schema is in the README.
    pub scene: PathBuf,
    /// Override one scene value by its dotted TOML key, e.g. `--set contact.clearance=0.01`
    /// or `--set sections.modes=[6,4]`; repeatable. Validated like the file.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub overrides: Vec<String>,
}

impl SceneArgs {
    /// Loads and validates the scene with its overrides.
    pub fn load(&self) -> anyhow::Result<Scene> {
        Ok(Scene::load(&self.scene, &self.overrides)?)
    }
}

impl Cli {
    /// Runs the chosen command.
    pub fn run(self) -> anyhow::Result<()> {
        match self.command {
            Command::Modes(args) => crate::modes::run(&args),
            Command::Equations(args) => crate::equations::run(&args),
            Command::Simulate(args) => crate::simulate::run(&args),
            Command::Stability(args) => crate::stability::run(&args),
            Command::WorkPrecision(args) => crate::work_precision::run(&args),
            Command::Converge(args) => crate::converge::run(&args),
            Command::ShapeErrors(args) => crate::shape_errors::run(&args),
        }
    }
}
