//! `telescopic converge`: the smallest model a scene needs.
//!
//! Raises the modes per section (the same number on every section) from 1 to `--max-modes`,
//! simulating the scene and computing the first three frequencies with closed contacts for
//! each. The quantities compared between models: the frequencies, and the peak and RMS of
//! `tip_rel` over the whole scene (with clearance the pointwise motion of two different
//! models parts after the first impacts, like two runs of one model beyond the
//! predictability horizon, so the pointwise difference cannot converge; for `l_S = 0` the
//! largest pointwise difference relative to the peak is compared too). The smallest model is
//! the first whose change to the next one is below `--tol` in every quantity. Then the
//! contacts per overlap are raised from 2 the same way, at that number of modes.
//!
//! Every model is the quadrature-assembled one, so costs compare like with like (a generated
//! model exists only for the configurations in generated/models.toml).

use crate::plot::{Figure, LogSeries, YAxis, log_panel, plot_error, save, titled_page};
use crate::simulate::{run_scene, write_atomically};
use anyhow::{Context, bail};
use clap::Args;
use plotters::prelude::*;
use std::path::PathBuf;
use telescopic_runtime::{AssembledModel, Model, Scene, auto_method, modal_analysis};

/// Options of `telescopic converge`.
#[derive(Debug, Args)]
pub struct ConvergeArgs {
    #[command(flatten)]
    pub scene: crate::cli::SceneArgs,
    /// Largest relative change between consecutive models that counts as converged.
    #[arg(long, value_name = "TOL")]
    pub tol: f64,
    /// Most modes per section tried.
    #[arg(long, default_value_t = 12, value_name = "N")]
    pub max_modes: usize,
    /// Most contact points per overlap tried (from 2).
    #[arg(long, default_value_t = 5, value_name = "N")]
    pub max_contacts: usize,
    /// Chart of model error against cost (SVG or PNG by extension).
    #[arg(long, value_name = "FILE.svg|FILE.png")]
    pub out: Option<PathBuf>,
    /// CSV with one row per model tried.
    #[arg(long, value_name = "FILE")]
    pub csv: Option<PathBuf>,
}

/// One model of the sweep and what it gave.
struct Trial {
    modes: usize,
    contacts: usize,
    dof: usize,
    /// Wall time of the scene (s).
    wall: f64,
    /// First three frequencies with closed contacts (Hz).
    frequencies: Vec<f64>,
    /// Peak and RMS of `tip_rel` over the scene (m).
    tip_peak: f64,
    tip_rms: f64,
    /// `tip_rel` at every sample (m).
    tip: Vec<f64>,
}

impl Trial {
    /// Wall time, frequencies and `tip_rel` statistics, for the progress lines.
    fn describe(&self) -> String {
        let frequencies: Vec<String> = self.frequencies.iter().map(|f| format!("{f:.4}")).collect();
        format!(
            "wall {:.4} s, f1..f3 {frequencies:?} Hz, tip_rel peak {:.5e} m, RMS {:.5e} m",
            self.wall, self.tip_peak, self.tip_rms
        )
    }
}

impl Trial {
    /// Largest relative difference to `other` over the compared quantities.
    fn change(&self, other: &Trial, pointwise: bool) -> f64 {
        let rel = |a: f64, b: f64| (a - b).abs() / b.abs().max(1e-300);
        let mut change = rel(self.tip_peak, other.tip_peak).max(rel(self.tip_rms, other.tip_rms));
        for (a, b) in self.frequencies.iter().zip(&other.frequencies) {
            change = change.max(rel(*a, *b));
        }
        if pointwise {
            let worst = self
                .tip
                .iter()
                .zip(&other.tip)
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max);
            change = change.max(worst / other.tip_peak.max(1e-300));
        }
        change
    }
}

/// Simulates `scene` with `modes` per section and `contacts` per overlap.
fn trial(scene: &Scene, modes: usize, contacts: usize) -> anyhow::Result<Trial> {
    let mut scene = scene.clone();
    for s in &mut scene.params.sections {
        s.modes = modes;
    }
    scene.params.contact_points = contacts;
    let model = AssembledModel::new(&scene.params)?;
    let modal = modal_analysis(&model, scene.time.start)?;
    let (method, _) = auto_method(&scene.params);
    let traj = run_scene(
        &scene,
        &model,
        method,
        &telescopic_runtime::Settings::default(),
    )
    .with_context(|| format!("{modes} modes per section, {contacts} contacts per overlap"))?;
    let col = traj
        .names
        .iter()
        .position(|n| n == "tip_rel")
        .expect("every model has tip_rel")
        + 1;
    let tip: Vec<f64> = traj.rows.iter().map(|r| r[col]).collect();
    let tip_peak = tip.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let tip_rms = (tip.iter().map(|v| v * v).sum::<f64>() / tip.len() as f64).sqrt();
    Ok(Trial {
        modes,
        contacts,
        dof: model.dof(),
        wall: traj.stats.wall.as_secs_f64(),
        frequencies: modal.frequencies_hz.iter().take(3).copied().collect(),
        tip_peak,
        tip_rms,
        tip,
    })
}

/// The first trial whose change to the next is below `tol` (index), if any.
fn first_converged(trials: &[Trial], tol: f64, pointwise: bool) -> Option<usize> {
    trials
        .windows(2)
        .position(|w| w[0].change(&w[1], pointwise) < tol)
}

/// Runs `telescopic converge`.
pub fn run(args: &ConvergeArgs) -> anyhow::Result<()> {
    if !(args.tol > 0.0 && args.tol < 1.0) {
        bail!(
            "--tol must be a relative change in (0, 1) (got {})",
            args.tol
        );
    }
    if !(2..=telescopic_runtime::MAX_MODES).contains(&args.max_modes) {
        bail!(
            "--max-modes must be 2 to {} (got {})",
            telescopic_runtime::MAX_MODES,
            args.max_modes
        );
    }
    if args.max_contacts < 3 {
        bail!(
            "--max-contacts must be at least 3 (got {}): contacts are raised from 2",
            args.max_contacts
        );
    }
    if let Some(p) = &args.out {
        crate::plot::check_picture_path("--out", p)?;
    }
    let scene = args.scene.load()?;
    let contacts = scene.params.contact_points;
    let pointwise = scene.params.contact.is_linear();
    let (method, _) = auto_method(&scene.params);
    eprintln!(
        "{}: modes per section 1..{} with {contacts} contacts per overlap, method {method}, \
         assembled models",
        scene.name, args.max_modes
    );
    let mut by_modes = Vec::new();
    for n in 1..=args.max_modes {
        let t = trial(&scene, n, contacts)?;
        eprintln!("  N = {n:2}: dof {:3}, {}", t.dof, t.describe());
        by_modes.push(t);
    }
    let largest = by_modes.last().expect("at least two models");
    let Some(best) = first_converged(&by_modes, args.tol, pointwise) else {
        bail!(
            "no model up to {} modes per section changes by less than {} to the next; raise \
             --max-modes or --tol",
            args.max_modes,
            args.tol
        );
    };
    let chosen = &by_modes[best];
    // contacts per overlap at the chosen modes
    eprintln!(
        "contacts per overlap 2..{} at {} modes per section",
        args.max_contacts, chosen.modes
    );
    let mut by_contacts = Vec::new();
    for c in 2..=args.max_contacts {
        let t = trial(&scene, chosen.modes, c)?;
        eprintln!("  n_c = {c}: {}", t.describe());
        by_contacts.push(t);
    }
    let contacts_needed =
        first_converged(&by_contacts, args.tol, pointwise).map(|i| by_contacts[i].contacts);
    println!(
        "smallest model for tol {}: {} modes per section ({} dof) with {contacts} contacts per \
         overlap",
        args.tol, chosen.modes, chosen.dof
    );
    println!(
        "  its change to {} modes: {:.3e}; its difference to the largest model tried ({} \
         modes): {:.3e}",
        chosen.modes + 1,
        chosen.change(&by_modes[best + 1], pointwise),
        largest.modes,
        chosen.change(largest, pointwise)
    );
    println!(
        "  wall time {:.4} s against {:.4} s: {:.1}x faster than the largest model",
        chosen.wall,
        largest.wall,
        largest.wall / chosen.wall
    );
    match contacts_needed {
        Some(c) if c == contacts => {
            println!("  contacts per overlap: {c} (the scene's) already converged to tol")
        }
        Some(c) => println!(
            "  contacts per overlap: {c} would do (the scene has {contacts}; the paper's \
             contacts are physical points, so this is for information)"
        ),
        None => println!(
            "  contacts per overlap: no count up to {} changes by less than tol to the next",
            args.max_contacts
        ),
    }
    if let Some(path) = &args.csv {
        write_atomically(path, |w| {
            writeln!(
                w,
                "modes,contacts,dof,wall_s,f1_hz,f2_hz,f3_hz,tip_peak_m,tip_rms_m,error_vs_largest"
            )?;
            for t in by_modes.iter().chain(&by_contacts) {
                let reference = if t.contacts == contacts {
                    largest
                } else {
                    by_contacts.last().expect("contacts tried")
                };
                let f = |i: usize| t.frequencies.get(i).copied().unwrap_or(f64::NAN);
                writeln!(
                    w,
                    "{},{},{},{:e},{},{},{},{:e},{:e},{:e}",
                    t.modes,
                    t.contacts,
                    t.dof,
                    t.wall,
                    f(0),
                    f(1),
                    f(2),
                    t.tip_peak,
                    t.tip_rms,
                    t.change(reference, pointwise)
                )?;
            }
            Ok(())
        })?;
        eprintln!("wrote {}", path.display());
    }
    if let Some(path) = &args.out {
        let chart = ConvergenceChart {
            scene: &scene.name,
            tol: args.tol,
            trials: &by_modes,
            pointwise,
        };
        save(&chart, path)?;
        eprintln!("wrote {}", path.display());
    }
    Ok(())
}

/// Model error against the largest model versus cost, one point per number of modes.
struct ConvergenceChart<'a> {
    scene: &'a str,
    tol: f64,
    trials: &'a [Trial],
    pointwise: bool,
}

impl Figure for ConvergenceChart<'_> {
    fn size(&self) -> (u32, u32) {
        (1200, 500)
    }

    fn draw<DB: DrawingBackend>(
        &self,
        root: DrawingArea<DB, plotters::coord::Shift>,
    ) -> anyhow::Result<()> {
        let title = format!(
            "model error vs cost, {} (modes per section 1..{})",
            self.scene,
            self.trials.len()
        );
        let root = titled_page(root, &title)?;
        let largest = self.trials.last().expect("trials");
        let rest = &self.trials[..self.trials.len() - 1];
        let marks: Vec<String> = rest.iter().map(|t| format!("N={}", t.modes)).collect();
        let error = |t: &Trial| t.change(largest, self.pointwise).max(1e-16);
        let areas = root.split_evenly((1, 2));
        let by_wall = [LogSeries {
            label: "error vs largest model".into(),
            points: rest.iter().map(|t| (t.wall, error(t))).collect(),
            marks: marks.clone(),
        }];
        log_panel(
            &areas[0],
            (
                "error vs wall time",
                "wall time of the scene [s]",
                "relative error",
            ),
            &by_wall,
            YAxis::Log,
            Some((self.tol, "tol")),
        )?;
        let by_dof = [LogSeries {
            label: "error vs largest model".into(),
            points: rest.iter().map(|t| (t.dof as f64, error(t))).collect(),
            marks,
        }];
        log_panel(
            &areas[1],
            (
                "error vs model size",
                "degrees of freedom",
                "relative error",
            ),
            &by_dof,
            YAxis::Log,
            Some((self.tol, "tol")),
        )?;
        root.present().map_err(plot_error)
    }
}
