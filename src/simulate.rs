//! `telescopic simulate`: integrates a scene with the chosen method, writes the MODEL.md
//! section 5 outputs as CSV (complete or not at all) and a run summary on stderr.

use crate::choose::{ModelChoice, build_model};
use crate::cli::SceneArgs;
use anyhow::{Context, bail};
use clap::Args;
use std::io::{IsTerminal, Write};
use std::path::{Path, PathBuf};
use telescopic_runtime::{
    Method, Model, RunStats, Scene, Settings, auto_plan, model::rest_state, simulate,
    specializations,
};

/// Options of `telescopic simulate`.
#[derive(Debug, Args)]
pub struct SimulateArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Integration method: auto (default: exact for a scene that is linear and
    /// time-invariant between contact switches, else dopri5), exact, dopri5, dop853, esdirk,
    /// bdf, bdf<K>, rk4, verlet, galpha, galpha-fixed, galpha-rho<R> (see the README).
    #[arg(long, default_value = "auto", value_name = "NAME")]
    pub method: String,
    /// Relative tolerance of adaptive methods.
    #[arg(long, value_name = "R")]
    pub rtol: Option<f64>,
    /// Absolute tolerance of adaptive methods (m and m/s).
    #[arg(long, value_name = "A")]
    pub atol: Option<f64>,
    /// Step (s) of fixed-step methods; first trial step of adaptive ones.
    #[arg(long, value_name = "H")]
    pub dt: Option<f64>,
    /// Let dop853's step grow beyond its stable step while a contact is closed (the step
    /// control then hovers at the stability boundary; for comparison).
    #[arg(long)]
    pub no_step_cap: bool,
    /// CSV file for the outputs (written to a temporary file and renamed when complete);
    /// default: standard output.
    #[arg(long, value_name = "FILE")]
    pub out: Option<PathBuf>,
    /// Draw the paper's figures for this scene to an SVG or PNG file (by extension).
    #[arg(long, value_name = "FILE.svg|FILE.png")]
    pub plot: Option<PathBuf>,
    /// A second scene to simulate with the same method and overlay in the plot (e.g. the
    /// case-study without clearance).
    #[arg(long, value_name = "SCENE2", requires = "plot")]
    pub compare: Option<PathBuf>,
    /// Which model computes the right-hand side.
    #[arg(long, value_enum, default_value_t)]
    pub model: ModelChoice,
}

/// One simulated scene: the output names and the samples (time first in each row).
pub struct Trajectory {
    /// Output names, without `t`.
    pub names: Vec<String>,
    /// Rows `[t, outputs...]`.
    pub rows: Vec<Vec<f64>>,
    /// What the run did.
    pub stats: RunStats,
}

/// The method for a scene and how it was chosen (`auto` resolved on the scene's parameters),
/// and the settings, from the command line.
pub fn settings_from(
    args: &SimulateArgs,
    scene: &Scene,
) -> anyhow::Result<(Method, String, Settings)> {
    let mut settings = Settings::default();
    let (method, how) = if args.method == "auto" {
        let (m, exact_from, why) = auto_plan(&scene.params, &scene.time);
        settings.exact_from = exact_from;
        (m, format!("auto: {why}; "))
    } else {
        (
            Method::from_name(&args.method).map_err(anyhow::Error::msg)?,
            String::new(),
        )
    };
    if let Some(r) = args.rtol {
        settings.rtol = r;
    }
    if let Some(a) = args.atol {
        settings.atol = a;
    }
    settings.dt = args.dt;
    settings.step_cap = !args.no_step_cap;
    // checked whatever the method (exact and fixed-step methods do not use them)
    if !(settings.rtol > 0.0 && settings.rtol < 1.0 && settings.atol > 0.0) {
        anyhow::bail!(
            "tolerances must be positive with rtol < 1 (got --rtol {}, --atol {})",
            settings.rtol,
            settings.atol
        );
    }
    Ok((method, how, settings))
}

/// Integrates `scene` on `model`, collecting every output sample.
pub fn run_scene(
    scene: &Scene,
    model: &dyn Model,
    method: Method,
    settings: &Settings,
) -> anyhow::Result<Trajectory> {
    let names = model.output_names();
    let mut rows: Vec<Vec<f64>> = Vec::new();
    let mut out = vec![0.0; names.len()];
    let mut bad_output: Option<(f64, String)> = None;
    let mut observe = |t: f64, y: &[f64], ydot: &[f64]| {
        model.outputs(t, y, ydot, &mut out);
        if bad_output.is_none()
            && let Some(i) = out.iter().position(|v| !v.is_finite())
        {
            bad_output = Some((t, names[i].clone()));
        }
        let mut row = Vec::with_capacity(out.len() + 1);
        row.push(t);
        row.extend_from_slice(&out);
        rows.push(row);
    };
    let bar = progress_bar(scene);
    let mut tick = |t: f64| {
        if let Some(b) = &bar {
            b.set_position(
                ((t - scene.time.start) / (scene.time.end - scene.time.start) * 1000.0) as u64,
            );
        }
    };
    let y0 = rest_state(model, scene.time.start);
    let result = simulate(
        model,
        &y0,
        &scene.time,
        method,
        settings,
        &mut observe,
        Some(&mut tick),
    );
    if let Some(b) = &bar {
        b.finish_and_clear();
    }
    let stats = result.with_context(|| format!("scene {} could not be simulated", scene.name))?;
    if let Some((t, name)) = bad_output {
        bail!("output `{name}` is not finite at t = {t} s (method {method}); no output written");
    }
    Ok(Trajectory { names, rows, stats })
}

/// A progress bar on stderr when it is a terminal (0..1000 over the span).
fn progress_bar(scene: &Scene) -> Option<indicatif::ProgressBar> {
    if !std::io::stderr().is_terminal() {
        return None;
    }
    let bar = indicatif::ProgressBar::new(1000);
    bar.set_style(
        indicatif::ProgressStyle::with_template("{msg} [{bar:40}] {percent}% ({elapsed})")
            .expect("a valid template")
            .progress_chars("=> "),
    );
    bar.set_message(format!("simulating {}", scene.name));
    Some(bar)
}

/// Writes the trajectory as CSV: to `path` via a temporary file renamed when complete, or to
/// standard output.
pub fn write_csv(traj: &Trajectory, path: Option<&Path>) -> anyhow::Result<()> {
    let write_rows = |w: &mut dyn Write| -> std::io::Result<()> {
        writeln!(w, "t,{}", traj.names.join(","))?;
        for row in &traj.rows {
            let cells: Vec<String> = row.iter().map(|&v| csv_number(v)).collect();
            writeln!(w, "{}", cells.join(","))?;
        }
        w.flush()
    };
    match path {
        None => {
            let stdout = std::io::stdout();
            let mut lock = std::io::BufWriter::new(stdout.lock());
            write_rows(&mut lock).context("writing CSV to standard output")
        }
        Some(path) => write_atomically(path, |w| write_rows(w)),
    }
}

/// A number as CSV text: shortest round-trip digits, positional for moderate magnitudes and
/// with an exponent for tiny or huge ones.
fn csv_number(v: f64) -> String {
    let a = v.abs();
    if a == 0.0 || (1e-4..1e7).contains(&a) {
        format!("{v}")
    } else {
        format!("{v:e}")
    }
}

/// Writes `path` through a temporary file in the same directory, renamed when `fill`
/// succeeded; removed otherwise, so no partial file is left.
pub fn write_atomically(
    path: &Path,
    fill: impl FnOnce(&mut dyn Write) -> std::io::Result<()>,
) -> anyhow::Result<()> {
    let dir = path
        .parent()
        .filter(|d| !d.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let file_name = path
        .file_name()
        .with_context(|| format!("{} is not a file path", path.display()))?;
    let tmp = dir.join(format!(
        ".{}.tmp-{}",
        file_name.to_string_lossy(),
        std::process::id()
    ));
    let result = (|| -> std::io::Result<()> {
        let file = std::fs::File::create(&tmp)?;
        let mut w = std::io::BufWriter::new(file);
        fill(&mut w)?;
        w.into_inner().map_err(|e| e.into_error())?.sync_all()?;
        std::fs::rename(&tmp, path)
    })();
    if let Err(e) = result {
        let _ = std::fs::remove_file(&tmp);
        return Err(e).with_context(|| format!("writing {}", path.display()));
    }
    Ok(())
}

/// The run summary printed on stderr: scene, model, method (and why, for `auto`), the
/// specializations in use, and what the run did.
pub fn summary(
    scene: &Scene,
    model: &dyn Model,
    model_word: &str,
    (method, how): (Method, &str),
    settings: &Settings,
    traj: &Trajectory,
) -> String {
    let s = &traj.stats;
    let cap = s.step_cap.map_or(String::new(), |c| {
        format!("; step capped at {c:.3e} s while a contact is closed (its stable step)")
    });
    let tol = match method.step_control() {
        telescopic_runtime::integrate::StepControl::Adaptive if s.exponentials > 0 => format!(
            "rtol {:e}, atol {:e}{cap}; {} matrix exponentials",
            settings.rtol, settings.atol, s.exponentials
        ),
        telescopic_runtime::integrate::StepControl::Adaptive => {
            format!("rtol {:e}, atol {:e}{cap}", settings.rtol, settings.atol)
        }
        telescopic_runtime::integrate::StepControl::Fixed => {
            format!("dt {:e} s", settings.dt.unwrap_or(f64::NAN))
        }
        telescopic_runtime::integrate::StepControl::Exact => {
            format!("{} matrix exponentials", s.exponentials)
        }
    };
    let special = specializations(model, &scene.time);
    let special = if special.is_empty() {
        "none".to_string()
    } else {
        special.join("; ")
    };
    format!(
        "{} on the {model_word}: method {method} ({how}{tol}), t = {} .. {} s, {} samples\n\
         specializations: {special}\n\
         steps {} (rejected {}), rhs evaluations {}, Jacobian evaluations {}, factorizations {}, \
         contact switches {}, wall time {:.3} s",
        scene.name,
        scene.time.start,
        scene.time.end,
        traj.rows.len(),
        s.steps,
        s.rejected,
        s.rhs_evals,
        s.jacobian_evals,
        s.factorizations,
        s.switches,
        s.wall.as_secs_f64()
    )
}

/// Runs `telescopic simulate`.
pub fn run(args: &SimulateArgs) -> anyhow::Result<()> {
    if let Some(p) = &args.plot {
        crate::plot::check_picture_path("--plot", p)?;
    }
    let scene = args.scene.load()?;
    let (method, how, settings) = settings_from(args, &scene)?;
    let (model, word) = build_model(&scene.params, args.model)?;
    let traj = run_scene(&scene, model.as_ref(), method, &settings)?;
    write_csv(&traj, args.out.as_deref())?;
    eprintln!(
        "{}",
        summary(
            &scene,
            model.as_ref(),
            &word,
            (method, &how),
            &settings,
            &traj
        )
    );
    if let Some(p) = &args.out {
        eprintln!("wrote {} ({} rows)", p.display(), traj.rows.len());
    }
    if let Some(plot_path) = &args.plot {
        let mut curves = vec![crate::plot::Curve {
            label: &scene.name,
            traj: &traj,
            half_band: scene.params.contact.half_band(),
        }];
        let compared;
        let other;
        if let Some(path) = &args.compare {
            other = Scene::load(path, &args.scene.overrides)?;
            let (method2, how2, settings2) = settings_from(args, &other)?;
            let (model2, word2) = build_model(&other.params, args.model)?;
            compared = run_scene(&other, model2.as_ref(), method2, &settings2)?;
            eprintln!(
                "{}",
                summary(
                    &other,
                    model2.as_ref(),
                    &word2,
                    (method2, &how2),
                    &settings2,
                    &compared
                )
            );
            curves.push(crate::plot::Curve {
                label: &other.name,
                traj: &compared,
                half_band: other.params.contact.half_band(),
            });
        }
        crate::plot::plot(&scene.name, &curves, plot_path)?;
        eprintln!("wrote {}", plot_path.display());
    }
    Ok(())
}
