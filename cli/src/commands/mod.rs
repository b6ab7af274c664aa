//! The subcommands: each parses its flags into the library's options, calls the library and
//! prints. Nothing in the library depends on this module.

mod analysis;
mod animate;
mod bode;
mod control;
mod fmu;
mod identify;
mod modes;
mod plan;
mod progress;
mod simulate;
mod sweep;

use clap::{Args, CommandFactory, FromArgMatches, Parser, Subcommand};
use std::path::{Path, PathBuf};
use telescopic::Scene;

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
    Modes(modes::ModesArgs),
    /// The derived equations of motion of the scene's generated model: M, K, b, contact
    /// terms, generalized forces and their Jacobian, with parameters by name.
    Equations(modes::EquationsArgs),
    /// Integrate the scene with the clearance contact law and write its outputs as CSV.
    Simulate(simulate::SimulateArgs),
    /// See a run move: the telescope bending and sliding, the contacts, the load and the
    /// vehicle, with tip_rel, the vehicle and the drive force against time; one
    /// self-contained HTML page (offline, from disk) or an animated GIF.
    Animate(animate::AnimateArgs),
    /// Plan the move: the shortest cycle that brings the load to rest within a tolerance,
    /// robust over a set of plants: the time-optimal S-curve, shaped by ZV/ZVD/EI/2EI
    /// (fixed and scheduled on the first mode) and optimized, on the nonlinear model.
    Plan(plan::PlanArgs),
    /// Fit scene values (stiffness, damping, load, clearance, ...) to a measured record of
    /// the machine by nonlinear least squares: the values with their standard deviations and
    /// correlations, the residual per sensor, the fitted scene and a figure.
    Identify(identify::IdentifyArgs),
    /// The stiffest frequency with closed contacts and the largest stable step of the
    /// fixed-step explicit methods (textbook limits and the model's own).
    Stability(analysis::StabilityArgs),
    /// Speed against accuracy: every method over a sweep of tolerances or steps, errors
    /// inside the predictability horizon and on statistics beyond it; chart and CSV.
    WorkPrecision(analysis::WorkPrecisionArgs),
    /// The smallest model a scene needs: modes per section (then contacts per overlap)
    /// raised until tip_rel and the first three frequencies change by less than --tol.
    Converge(analysis::ConvergeArgs),
    /// The linear model x' = A x + B u, y = C x + D u about the straight configuration, with
    /// stable state, input and output names, at one operating point or over a grid; as JSON,
    /// MATLAB/Octave, NumPy (.npz), python-control or LaTeX.
    Linearize(control::LinearizeArgs),
    /// Frequency response of the linear model from the drive (and a disturbance force at
    /// the load) to chosen outputs: magnitude and phase as CSV, and a Bode plot with the
    /// natural frequencies marked.
    Bode(bode::BodeArgs),
    /// The nonlinear model with clearance as an FMI 2.0 FMU (co-simulation and/or model
    /// exchange) for Simulink, Dymola, OpenModelica, FMPy: input F, the outputs, the scene's
    /// parameters.
    Fmu(fmu::FmuArgs),
    /// Design a vibration-suppressing controller (gain-scheduled LQR, input shaper, or both)
    /// on the linear models, write it as JSON, and compare the variants on the full model.
    Design(control::DesignArgs),
    /// A parameter study: every run of a sweep file (grid, list, Latin hypercube) on every
    /// core, one CSV row each; resumable; shardable over a Slurm job array.
    Sweep(sweep::SweepArgs),
    /// Join the shard files of one sweep, checking that every run is there exactly once.
    SweepMerge(sweep::MergeArgs),
    /// Chart a sweep's results: a metric against an override, a line per value of another,
    /// or a heat map.
    PlotSweep(sweep::PlotArgs),
    /// Evaluation error of the shape functions for modes 1..30: the paper's printed forms
    /// against the cancellation-free ones, both measured in 512-bit arithmetic.
    ShapeErrors(analysis::ShapeErrorsArgs),
}

/// A scene file and its overrides: shared by every command that reads a scene.
#[derive(Debug, Args)]
pub struct SceneArgs {
    /// Scene file (TOML); the schema is in docs/scenes.md.
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

/// Checks an output file's path before any work (`option` names the flag): writable, and
/// none of the command's `inputs`.
pub fn check_output(option: &str, path: Option<&Path>, inputs: &[&Path]) -> anyhow::Result<()> {
    if let Some(p) = path {
        crate::signals::watch_output(p);
        telescopic::io::output::check_writable(p).map_err(of_flag(option))?;
        telescopic::io::output::check_not_an_input(p, inputs).map_err(of_flag(option))?;
    }
    Ok(())
}

/// Checks a directory C files are emitted into before any work: it exists, and none of the
/// files `names` written there is one of the command's `inputs` (or another of its outputs).
pub fn check_emit_dir(
    option: &str,
    dir: Option<&Path>,
    names: &[&str],
    inputs: &[&Path],
) -> anyhow::Result<()> {
    let Some(dir) = dir else {
        return Ok(());
    };
    if !dir.is_dir() {
        anyhow::bail!("{option} {}: not an existing directory", dir.display());
    }
    for name in names {
        check_output(option, Some(&dir.join(name)), inputs)?;
    }
    crate::signals::watch_output_dir(dir.to_path_buf());
    Ok(())
}

/// A library error about the path that `flag` gives, told as that flag's.
pub fn of_flag(flag: &str) -> impl Fn(telescopic::Error) -> anyhow::Error + '_ {
    move |e| anyhow::Error::new(e).context(flag.to_string())
}

/// Checks a chart's path before any work: .svg or .png in a writable directory, and none of
/// the command's `inputs`.
pub fn check_chart(option: &str, path: Option<&Path>, inputs: &[&Path]) -> anyhow::Result<()> {
    if let Some(p) = path {
        crate::signals::watch_output(p);
        telescopic::plot::check_picture_path(p).map_err(of_flag(option))?;
        telescopic::io::output::check_not_an_input(p, inputs).map_err(of_flag(option))?;
    }
    Ok(())
}

/// `command` and every subcommand below it: an option that takes one value takes a value
/// that starts with `-` (a negative number such as `-1e-6`, which clap's own negative-number
/// setting does not recognize), so the option's check judges it.
fn with_negative_numbers(command: clap::Command) -> clap::Command {
    command
        .mut_args(|arg| {
            let one_value = arg.get_num_args().is_none_or(|n| n.max_values() == 1);
            if arg.get_action().takes_values() && one_value && !arg.is_positional() {
                arg.allow_hyphen_values(true)
            } else {
                arg
            }
        })
        .mut_subcommands(with_negative_numbers)
}

impl Cli {
    /// Parses the process's arguments (exits with clap's message on a parse error). A
    /// negative number is an option's value, so `--rtol -1` reaches the option's own check,
    /// which names the rule, instead of clap's "unexpected argument".
    pub fn parse_arguments() -> Self {
        let matches = with_negative_numbers(Cli::command()).get_matches();
        Cli::from_arg_matches(&matches).unwrap_or_else(|e| e.exit())
    }

    /// Runs the chosen command.
    pub fn run(self) -> anyhow::Result<()> {
        match self.command {
            Command::Modes(args) => modes::modes(&args),
            Command::Equations(args) => modes::equations(&args),
            Command::Simulate(args) => simulate::simulate(&args),
            Command::Animate(args) => animate::animate(&args),
            Command::Plan(args) => plan::plan(&args),
            Command::Identify(args) => identify::identify_command(&args),
            Command::Stability(args) => analysis::stability(&args),
            Command::WorkPrecision(args) => analysis::work_precision(&args),
            Command::Converge(args) => analysis::converge(&args),
            Command::ShapeErrors(args) => analysis::shape_errors(&args),
            Command::Linearize(args) => control::linearize(&args),
            Command::Bode(args) => bode::bode(&args),
            Command::Fmu(args) => fmu::fmu(&args),
            Command::Design(args) => control::design(&args),
            Command::Sweep(args) => sweep::sweep(&args),
            Command::SweepMerge(args) => sweep::merge(&args),
            Command::PlotSweep(args) => sweep::plot(&args),
        }
    }
}
