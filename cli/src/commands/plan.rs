//! `telescopic plan`: the shortest move that brings the load to rest, robust over a set of
//! plants; the table of every candidate on every plant, and the best plan as a scene.

use super::progress::Progress;
use super::simulate::RunArgs;
use super::{SceneArgs, check_output};
use clap::Args;
use std::path::PathBuf;
use telescopic::moves::{MoveLimits, PlanOptions, RobustRange, plan_move};
use telescopic::run::SimulationOptions;
use telescopic::run::stress::Station;

/// Options of `telescopic plan`.
#[derive(Debug, Args)]
pub struct PlanArgs {
    #[command(flatten)]
    scene: SceneArgs,
    #[command(flatten)]
    run: RunArgs,
    /// Travel of the move (m; negative moves backwards).
    #[arg(long, value_name = "METRES")]
    distance: f64,
    /// The drive's velocity limit (m/s).
    #[arg(long, value_name = "M/S", default_value_t = 2.5)]
    v_max: f64,
    /// The drive's acceleration limit (m/s^2).
    #[arg(long, value_name = "M/S^2", default_value_t = 0.7)]
    a_max: f64,
    /// The drive's jerk limit (m/s^3).
    #[arg(long, value_name = "M/S^3", default_value_t = 2.0)]
    j_max: f64,
    /// How still the load must be: tip_rel within this of its final rest (m); the vehicle
    /// must be within 1 mm of its target.
    #[arg(long, value_name = "METRES", default_value_t = 0.005)]
    tolerance: f64,
    /// The robust set: scene values and their ranges, e.g.
    /// masses.load=10:30,contact.clearance=0.005:0.02; its corners and centre are evaluated.
    #[arg(long, value_name = "KEY=LOW:HIGH,...")]
    robust: Option<String>,
    /// Time simulated after the longest candidate arrives (s).
    #[arg(long, value_name = "SECONDS", default_value_t = 10.0)]
    settle: f64,
    /// Skip the optimizer (the spacing of the best scheduled shaper).
    #[arg(long)]
    no_optimize: bool,
    /// Plants inside the robust set, not evaluated by the planner, that the best plan is
    /// checked on.
    #[arg(long, value_name = "N", default_value_t = 4)]
    checks: usize,
    /// The drive's force limit (N): a candidate whose reaction exceeds it is not chosen.
    #[arg(long, value_name = "NEWTONS")]
    force_limit: Option<f64>,
    /// Stations whose stress is reported (the peak over them, e.g. 1:0 for the foot of
    /// section 1; the scene must give sections.section_modulus or sections.height).
    #[arg(long, value_name = "K:X,...")]
    stations: Option<String>,
    /// Write the best plan as a scene (its setpoint as drive.motion).
    #[arg(long, value_name = "PLAN.toml")]
    out: Option<PathBuf>,
}

/// Runs `telescopic plan`.
pub fn plan(args: &PlanArgs) -> anyhow::Result<()> {
    crate::stdout::check_stdout_open()?;
    check_output("--out", args.out.as_deref(), &[args.scene.scene.as_path()])?;
    let scene = args.scene.load()?;
    let options = PlanOptions {
        tolerance: args.tolerance,
        robust: match &args.robust {
            Some(text) => RobustRange::parse_list(text)?,
            None => Vec::new(),
        },
        settle_s: args.settle,
        optimize: !args.no_optimize,
        checks: args.checks,
        force_limit: args.force_limit,
        simulation: SimulationOptions {
            stations: match &args.stations {
                Some(text) => Station::parse_list(text)?,
                None => Vec::new(),
            },
            ..args.run.options()?
        },
        ..PlanOptions::new(MoveLimits {
            distance: args.distance,
            v_max: args.v_max,
            a_max: args.a_max,
            j_max: args.j_max,
        })
    };
    let progress = Progress::new();
    let plan = plan_move(&scene, &options, &progress)?;
    if let Some(path) = &args.out {
        let text = plan.scene_toml();
        telescopic::io::output::write_atomically(path, |w| w.write_all(text.as_bytes()))?;
        eprintln!(
            "wrote {} ({})",
            path.display(),
            plan.candidates[plan.best].name
        );
    }
    crate::stdout::write_to(None, |w| w.write_all(plan.table().as_bytes()))?;
    Ok(())
}
