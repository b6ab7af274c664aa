//! `telescopic modes`: eigenfrequencies in Hz, with published reference columns beside
//! them, as a table or JSON.

use crate::choose::{ModelChoice, build_model};
use crate::cli::SceneArgs;
use clap::Args;
use serde::Serialize;
use std::fmt::Write as _;
use telescopic_runtime::{ModalAnalysis, Model, Scene, modal_analysis, sample_shape};

/// Options of `telescopic modes`.
#[derive(Debug, Args)]
pub struct ModesArgs {
    #[command(flatten)]
    scene: SceneArgs,
    /// Print JSON instead of a table.
    #[arg(long)]
    json: bool,
    /// Time (s) whose telescopic positions are used; default: the scene's start time.
    #[arg(long, value_name = "SECONDS")]
    at: Option<f64>,
    /// How many frequencies to print (default: all).
    #[arg(long, value_name = "N")]
    count: Option<usize>,
    /// Also give mode shapes, sampled at this many points per section (JSON: `mode_shapes`).
    #[arg(long, value_name = "POINTS")]
    shapes: Option<usize>,
    /// Which model computes the matrices.
    #[arg(long, value_enum, default_value_t)]
    model: ModelChoice,
}

/// The JSON document of `telescopic modes --json`.
#[derive(Debug, Serialize)]
struct ModesJson {
    scene: String,
    time_s: f64,
    model: String,
    frequencies_hz: Vec<f64>,
    rigid_modes: usize,
    unstable_growth_rates_per_s: Vec<f64>,
    modes_per_section: Vec<usize>,
    #[serde(skip_serializing_if = "Option::is_none")]
    mode_shapes: Option<Vec<ModeShapeJson>>,
}

/// One mode shape: displacement along each section, normalized to a largest value of 1.
#[derive(Debug, Serialize)]
struct ModeShapeJson {
    frequency_hz: f64,
    sections: Vec<Vec<f64>>,
}

/// Runs `telescopic modes`.
pub fn run(args: &ModesArgs) -> anyhow::Result<()> {
    let scene = args.scene.load()?;
    let t = args.at.unwrap_or(scene.time.start);
    anyhow::ensure!(
        t.is_finite() && t >= scene.time.start && t <= scene.time.end,
        "--at {t}: must lie in the scene's time span [{}, {}] s",
        scene.time.start,
        scene.time.end
    );
    if let Some(0 | 1) = args.shapes {
        anyhow::bail!("--shapes: needs at least 2 points per section");
    }
    let (model, which) = build_model(&scene.params, args.model)?;
    let model = model.as_ref();
    let modal = modal_analysis(model, t)?;
    let count = args
        .count
        .unwrap_or(modal.frequencies_hz.len())
        .min(modal.frequencies_hz.len());
    let shapes = args.shapes.map(|points| {
        modal.shapes[..count]
            .iter()
            .zip(&modal.frequencies_hz)
            .map(|(v, &f)| {
                let mut sections = sample_shape(model, v, points);
                let peak = sections
                    .iter()
                    .flatten()
                    .fold(0.0_f64, |m, w| m.max(w.abs()));
                sections.iter_mut().flatten().for_each(|w| *w /= peak);
                ModeShapeJson {
                    frequency_hz: f,
                    sections,
                }
            })
            .collect::<Vec<_>>()
    });
    if args.json {
        let doc = ModesJson {
            scene: scene.name.clone(),
            time_s: t,
            model: which.clone(),
            frequencies_hz: modal.frequencies_hz[..count].to_vec(),
            rigid_modes: modal.rigid_modes,
            unstable_growth_rates_per_s: modal.unstable_growth_rates.clone(),
            modes_per_section: scene.params.modes(),
            mode_shapes: shapes,
        };
        println!("{}", serde_json::to_string_pretty(&doc)?);
    } else {
        print!("{}", table(&scene, model, &which, &modal, count, t));
        if let Some(shapes) = shapes {
            print!("{}", shape_table(&shapes));
        }
    }
    Ok(())
}

/// The text table: ours, then each reference column with the difference in percent.
fn table(
    scene: &Scene,
    model: &dyn Model,
    which: &str,
    modal: &ModalAnalysis,
    count: usize,
    t: f64,
) -> String {
    let mut s = String::new();
    let modes = scene.params.modes();
    let _ = writeln!(
        s,
        "{}: {} section(s), modes per section {:?}, {} coordinates; contacts closed (c = {} N/m), geometry at t = {} s",
        scene.name,
        modes.len(),
        modes,
        model.dof(),
        scene.params.contact.stiffness,
        t
    );
    let _ = writeln!(s, "model: {which}");
    let _ = writeln!(s, "rigid-body modes: {} (not listed)", modal.rigid_modes);
    if !modal.unstable_growth_rates.is_empty() {
        let _ = writeln!(
            s,
            "UNSTABLE: {} mode(s) with negative stiffness (buckled under the axial load), growth rates {:?} 1/s",
            modal.unstable_growth_rates.len(),
            modal.unstable_growth_rates
        );
    }
    let mut header = format!("{:>5} {:>14}", "mode", "ours [Hz]");
    for r in &scene.references {
        let _ = write!(header, " {:>16} {:>8}", format!("{} [Hz]", r.label), "diff");
    }
    let _ = writeln!(s, "{header}");
    for (i, f) in modal.frequencies_hz[..count].iter().enumerate() {
        let mut line = format!("{:>5} {:>14.6}", format!("f{}", i + 1), f);
        for r in &scene.references {
            match r.frequencies_hz.get(i) {
                // difference as the paper's Table I states it: (reference - ours) / reference
                Some(&fr) => {
                    let _ = write!(line, " {:>16} {:>7.2}%", fr, 100.0 * (fr - f) / fr);
                }
                None => {
                    let _ = write!(line, " {:>16} {:>8}", "", "");
                }
            }
        }
        let _ = writeln!(s, "{line}");
    }
    if !scene.references.is_empty() {
        let _ = writeln!(
            s,
            "diff = (reference - ours) / reference, as in the paper's Table I"
        );
    }
    s
}

fn shape_table(shapes: &[ModeShapeJson]) -> String {
    let mut s =
        String::from("\nmode shapes (w along each section, foot to top, largest |w| = 1):\n");
    for (i, m) in shapes.iter().enumerate() {
        let _ = writeln!(s, "f{} = {:.6} Hz", i + 1, m.frequency_hz);
        for (k, w) in m.sections.iter().enumerate() {
            let vals: Vec<String> = w.iter().map(|v| format!("{v:+.3}")).collect();
            let _ = writeln!(s, "  section {}: {}", k + 1, vals.join(" "));
        }
    }
    s
}
