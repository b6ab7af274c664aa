//! `telescopic identify`: scene values fitted to a measured record, with their uncertainty;
//! the fitted scene, a figure of measured against fitted, and a check on a second record.

use super::progress::Progress;
use super::{SceneArgs, check_chart, check_output};
use clap::{Args, ValueEnum};
use std::path::{Path, PathBuf};
use telescopic::identify::{
    FreeValue, IdentifyOptions, Offsets, Record, Start, identify, noise::parse_noise, validate,
};
use telescopic::run::ModelSize;

/// What becomes of each sensor's unknown offset.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum OffsetArg {
    /// A constant per sensor, fitted (its mean level then says nothing).
    Fitted,
    /// The record is zeroed as the model is (from rest at its first sample).
    Zero,
}

/// How the machine was moving at the record's first sample.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum StartArg {
    /// At rest, as the model starts.
    Rest,
    /// In motion: the free motion of the slowest modes and the vehicle's speed at the first
    /// sample are fitted too (closed contacts and fixed positions only).
    Moving,
}

/// Options of `telescopic identify`.
#[derive(Debug, Args)]
pub struct IdentifyArgs {
    #[command(flatten)]
    scene: SceneArgs,
    /// The measured record (CSV): a time column t (s), the drive force F (N) the machine
    /// applied, if the scene is force-driven, or the prescribed position s (m) of a
    /// position-controlled drive, and sensor columns by output name (vehicle, kappa_1_0,
    /// acc_load, tip_rel, ...), evenly sampled.
    #[arg(long, value_name = "RUN.csv")]
    data: PathBuf,
    /// The scene values to fit, with optional bounds: e.g.
    /// sections.youngs_modulus,masses.load=10:40,contact.damping (default bounds: the
    /// scene's value divided and multiplied by 10).
    #[arg(long, value_name = "KEY[=LOW:HIGH],...")]
    free: String,
    /// Each sensor's noise (its SI unit), instead of the estimate from the record: e.g.
    /// kappa_1_0=1e-4,tip_rel=1e-4.
    #[arg(long, value_name = "SENSOR=SIGMA,...")]
    noise: Option<String>,
    /// Each sensor's unknown offset: fitted, or zero (the record starts at the model's rest).
    #[arg(long, value_enum, default_value_t = OffsetArg::Fitted)]
    offsets: OffsetArg,
    /// The machine at the record's first sample: at rest, or moving (its free motion is
    /// fitted; the validation record's too).
    #[arg(long, value_enum, default_value_t = StartArg::Rest)]
    start: StartArg,
    /// The model's size (N or static:N modes per section); default: the smallest whose
    /// truncation is within every sensor's noise.
    #[arg(long, value_name = "SIZE")]
    size: Option<ModelSize>,
    /// Fit the record only up to this time (s); default: all of it without clearance, up to
    /// the first contact switch with it.
    #[arg(long, value_name = "SECONDS")]
    until: Option<f64>,
    /// A second record the fit does not see: the fitted scene predicts it, and the error per
    /// sensor is reported.
    #[arg(long, value_name = "OTHER.csv")]
    validate: Option<PathBuf>,
    /// Write the fitted scene (the scene with the fitted values).
    #[arg(long, value_name = "FITTED.toml")]
    out: Option<PathBuf>,
    /// Draw the record and the fitted run, one panel per sensor (SVG or PNG).
    #[arg(long, value_name = "FIG.svg")]
    plot: Option<PathBuf>,
}

/// Runs `telescopic identify`.
pub fn identify_command(args: &IdentifyArgs) -> anyhow::Result<()> {
    crate::stdout::check_stdout_open()?;
    let mut inputs: Vec<&Path> = vec![args.scene.scene.as_path(), args.data.as_path()];
    inputs.extend(args.validate.as_deref());
    check_output("--out", args.out.as_deref(), &inputs)?;
    check_chart("--plot", args.plot.as_deref(), &inputs)?;
    if let Some(until) = args.until
        && !(until.is_finite() && until > 0.0)
    {
        anyhow::bail!("--until: must be a positive number of seconds (got {until})");
    }
    let scene = args.scene.load()?;
    let record = Record::read(&args.data)?;
    let unseen = args.validate.as_deref().map(Record::read).transpose()?;
    let offsets = match args.offsets {
        OffsetArg::Fitted => Offsets::Fitted,
        OffsetArg::Zero => Offsets::Zero,
    };
    let start = match args.start {
        StartArg::Rest => Start::Rest,
        StartArg::Moving => Start::Moving,
    };
    let options = IdentifyOptions {
        free: FreeValue::parse_list(&args.free)?,
        noise: args
            .noise
            .as_deref()
            .map(parse_noise)
            .transpose()?
            .unwrap_or_default(),
        offsets,
        size: args.size,
        until: args.until,
        start,
    };
    let progress = Progress::new();
    let fit = identify(&scene, &record, &options, &progress)?;
    let mut report = fit.to_text();
    if let Some(unseen) = &unseen {
        report.push_str(&format!("validation on {} (not fitted):\n", unseen.source));
        for sensor in validate(&fit, unseen, offsets, start)? {
            report.push_str(&format!(
                "  {:<10} largest error {:.3e} ({:.2} % of its peak {:.3e}), RMS {:.3e}\n",
                sensor.output.to_string(),
                sensor.max_error,
                100.0 * sensor.relative(),
                sensor.peak,
                sensor.rms_error
            ));
        }
    }
    if let Some(path) = &args.out {
        let text = fit.scene_toml();
        telescopic::io::output::write_atomically(path, |w| w.write_all(text.as_bytes()))?;
        eprintln!("wrote {} (the fitted scene)", path.display());
    }
    if let Some(path) = &args.plot {
        fit.write_figure(path)?;
        eprintln!("wrote {} (measured and fitted)", path.display());
    }
    crate::stdout::write_to(None, |w| w.write_all(report.as_bytes()))?;
    Ok(())
}
