//! `telescopic plan`: the shortest move that brings the load to rest, robust over a set of
//! plants; the table of every candidate on every plant, and the best plan as a scene.

use super::progress::Progress;
use super::simulate::RunArgs;
use super::{SceneArgs, check_output};
use clap::Args;
use std::path::{Path, PathBuf};
use telescopic::control::design::velocity::VelocityDesign;
use telescopic::control::emit::velocity::FEEDBACK_FILES;
use telescopic::plan;
use telescopic::plan::emit::{
    DEFAULT_FILTER_RATE_HZ, FILTER_FILES, check_filter_rate, write_plan_c,
};
use telescopic::plan::{MoveLimits, MovePlan, PlanOptions, RobustRange, plan_move};
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
    #[arg(long, value_name = "M/S", default_value_t = plan::DEFAULT_V_MAX)]
    v_max: f64,
    /// The drive's acceleration limit (m/s^2).
    #[arg(long, value_name = "M/S^2", default_value_t = plan::DEFAULT_A_MAX)]
    a_max: f64,
    /// The drive's jerk limit (m/s^3).
    #[arg(long, value_name = "M/S^3", default_value_t = plan::DEFAULT_J_MAX)]
    j_max: f64,
    /// How still the load must be: tip_rel within this of its final rest (m); the vehicle
    /// must be within 1 mm of its target.
    #[arg(long, value_name = "METRES", default_value_t = plan::DEFAULT_TOLERANCE_M)]
    tolerance: f64,
    /// The share of the tolerance the pick keeps in reserve (0 to 0.9): the best plan is the
    /// one with the shortest worst cycle within (1 - MARGIN) times the tolerance.
    #[arg(long, value_name = "SHARE", default_value_t = plan::DEFAULT_MARGIN)]
    margin: f64,
    /// The robust set: scene values and their ranges, e.g.
    /// masses.load=10:30,contact.clearance=0.005:0.02; its corners and centre are evaluated.
    #[arg(long, value_name = "KEY=LOW:HIGH,...")]
    robust: Option<String>,
    /// Time simulated after the longest candidate arrives (s).
    #[arg(long, value_name = "SECONDS", default_value_t = plan::DEFAULT_SETTLE_S)]
    settle: f64,
    /// Skip the optimizer (the spacing of the best scheduled shaper).
    #[arg(long)]
    no_optimize: bool,
    /// Plants inside the robust set, not evaluated by the planner, that the best plan is
    /// checked on; without --robust the best is checked on the scene's neighbours (load, E
    /// and clearance each 1 % down and up), and 0 skips them.
    #[arg(long, value_name = "N", default_value_t = plan::DEFAULT_CHECKS)]
    checks: usize,
    /// The drive's force limit (N): a candidate whose reaction exceeds it is not chosen.
    #[arg(long, value_name = "NEWTONS")]
    force_limit: Option<f64>,
    /// Stations whose stress is reported (the peak over them, e.g. 1:0 for the foot of
    /// section 1; the scene must give sections.section_modulus or sections.height).
    #[arg(long, value_name = "K:X,...")]
    stations: Option<String>,
    /// Evaluate velocity feedback on top of the S-curve and of the best open-loop move:
    /// the servo's velocity setpoint corrected from the encoder and a strain gauge at the
    /// foot of section 1, a state feedback that damps the first mode by this ratio (e.g.
    /// 0.5); with a masses.load range in --robust, scheduled on the load the machine
    /// weighs.
    #[arg(long, value_name = "ZETA")]
    feedback: Option<f64>,
    /// Bound of the feedback's velocity correction (m/s).
    #[arg(
        long,
        value_name = "M/S",
        default_value_t = VelocityDesign::default().velocity_limit,
        requires = "feedback"
    )]
    correction_v_max: f64,
    /// Bound of the feedback correction's acceleration (m/s^2).
    #[arg(
        long,
        value_name = "M/S^2",
        default_value_t = VelocityDesign::default().acceleration_limit,
        requires = "feedback"
    )]
    correction_a_max: f64,
    /// Write this candidate (a name from the table) instead of the best (with --out or
    /// --emit-c).
    #[arg(long, value_name = "CANDIDATE")]
    pick: Option<String>,
    /// Write the written candidate's shaper as a C99 setpoint filter (telescopic_setpoint.h
    /// and .c) and, when it uses feedback, its feedback law (telescopic_feedback.h and .c)
    /// into this existing directory.
    #[arg(long, value_name = "DIR")]
    emit_c: Option<PathBuf>,
    /// The emitted filter's tick rate (Hz).
    #[arg(long, value_name = "HZ", default_value_t = DEFAULT_FILTER_RATE_HZ, requires = "emit_c")]
    filter_rate: f64,
    /// Write the best plan as a scene (its setpoint as drive.motion); a plan with feedback
    /// also writes its feedback file beside it (PLAN.json).
    #[arg(long, value_name = "PLAN.toml")]
    out: Option<PathBuf>,
}

/// Runs `telescopic plan`.
pub fn plan(args: &PlanArgs) -> anyhow::Result<()> {
    crate::stdout::check_stdout_open()?;
    check_output("--out", args.out.as_deref(), &[args.scene.scene.as_path()])?;
    if let (Some(out), Some(_)) = (&args.out, args.feedback) {
        let beside = out.with_extension("json");
        if beside == *out {
            anyhow::bail!(
                "--out {}: a plan with --feedback writes its feedback file beside the scene as \
                 .json; give the scene another extension (plan.toml)",
                out.display()
            );
        }
        check_output("--out", Some(&beside), &[args.scene.scene.as_path()])?;
    }
    let mut inputs: Vec<&Path> = vec![args.scene.scene.as_path()];
    inputs.extend(args.out.as_deref());
    let emitted = [FILTER_FILES, FEEDBACK_FILES].concat();
    super::check_emit_dir("--emit-c", args.emit_c.as_deref(), &emitted, &inputs)?;
    if args.emit_c.is_some() {
        check_filter_rate(args.filter_rate)?;
    }
    let scene = args.scene.load()?;
    let options = PlanOptions {
        tolerance: args.tolerance,
        margin: args.margin,
        robust: match &args.robust {
            Some(text) => RobustRange::parse_list(text)?,
            None => Vec::new(),
        },
        settle_s: args.settle,
        optimize: !args.no_optimize,
        checks: args.checks,
        force_limit: args.force_limit,
        feedback: args.feedback.map(|zeta| VelocityDesign {
            added_damping: zeta,
            velocity_limit: args.correction_v_max,
            acceleration_limit: args.correction_a_max,
            ..VelocityDesign::default()
        }),
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
    options.check()?;
    if let Some(name) = &args.pick {
        MovePlan::check_pick(name, &options, args.emit_c.is_some())?;
    }
    let progress = Progress::new();
    let plan = plan_move(&scene, &options, &progress)?;
    write_outputs(args, &plan)?;
    crate::stdout::write_to(None, |w| w.write_all(plan.table().as_bytes()))?;
    Ok(())
}

/// Writes the chosen candidate (the best, or --pick) as C (--emit-c) and as a scene (--out)
/// with its feedback file beside it; before the table, so that a refusal leaves no stdout.
fn write_outputs(args: &PlanArgs, plan: &MovePlan) -> anyhow::Result<()> {
    let chosen = match &args.pick {
        Some(name) => plan.candidate_named(name)?,
        None => plan.best,
    };
    if let Some(dir) = &args.emit_c {
        for files in write_plan_c(plan, chosen, args.filter_rate, dir)? {
            eprintln!("wrote {} ({files})", dir.display());
        }
    }
    if let Some(path) = &args.out {
        let text = plan.scene_toml_of(chosen);
        telescopic::io::output::write_atomically(path, |w| w.write_all(text.as_bytes()))?;
        eprintln!(
            "wrote {} ({})",
            path.display(),
            plan.candidates[chosen].name
        );
        if let Some(json) = plan.feedback_json_of(chosen) {
            let beside = path.with_extension("json");
            telescopic::io::output::write_atomically(&beside, |w| w.write_all(json.as_bytes()))?;
            eprintln!(
                "wrote {} (its velocity feedback: simulate {} --controller {})",
                beside.display(),
                path.display(),
                beside.display()
            );
        } else {
            remove_stale_feedback(&path.with_extension("json"))?;
        }
    }
    Ok(())
}

/// Removes the velocity-feedback file an earlier plan wrote beside this plan's scene: this
/// plan uses none, and a stale one would run with it unnoticed. Any other file is left.
fn remove_stale_feedback(beside: &Path) -> anyhow::Result<()> {
    // a regular file of a feedback file's size only (a FIFO would block the read)
    let small_file =
        std::fs::symlink_metadata(beside).is_ok_and(|m| m.is_file() && m.len() < 1 << 20);
    if !small_file {
        return Ok(());
    }
    let Ok(text) = std::fs::read_to_string(beside) else {
        return Ok(());
    };
    if telescopic::control::file::velocity::VelocityFeedback::is_feedback_file(&text) {
        std::fs::remove_file(beside)
            .map_err(|e| anyhow::anyhow!("--out: removing the stale {}: {e}", beside.display()))?;
        eprintln!(
            "removed {}: an earlier plan's velocity feedback; this plan uses none",
            beside.display()
        );
    }
    Ok(())
}
