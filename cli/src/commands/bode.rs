//! `telescopic bode`: the frequency response of the linear model, as CSV and a Bode plot.

use super::control::OperatingPointArgs;
use super::{SceneArgs, check_chart, check_output};
use crate::stdout::{check_stdout_open, write_to};
use clap::Args;
use std::path::PathBuf;
use telescopic::linear::bode::{BodeOptions, DEFAULT_POINTS, frequency_response};
use telescopic::run::models::ModelChoice;
use telescopic::runtime::LinearInput;

/// Options of `telescopic bode`.
#[derive(Debug, Args)]
pub struct BodeArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    #[command(flatten)]
    pub point: OperatingPointArgs,
    /// Outputs of the linear model, comma-separated (see `telescopic linearize`).
    #[arg(
        long,
        value_name = "NAMES",
        value_delimiter = ',',
        default_value = "tip_rel"
    )]
    pub outputs: Vec<String>,
    /// Inputs: the drive (F, or a_vehicle for a prescribed motion) and/or F_load, the
    /// disturbance force at the load; default the drive.
    #[arg(long, value_name = "NAMES", value_delimiter = ',')]
    pub inputs: Vec<LinearInput>,
    /// Lowest frequency (Hz); default a tenth of the lowest natural frequency.
    #[arg(long, value_name = "HZ")]
    pub from: Option<f64>,
    /// Highest frequency (Hz); default 1.5 times the highest natural frequency.
    #[arg(long, value_name = "HZ")]
    pub to: Option<f64>,
    /// Number of frequencies, log-spaced.
    #[arg(long, value_name = "N", default_value_t = DEFAULT_POINTS)]
    pub points: usize,
    /// CSV file: f_hz, then <output>_mag and <output>_phase_deg per output (and
    /// <output>_from_F_load_... for the disturbance); default: standard output.
    #[arg(long, value_name = "FILE")]
    pub out: Option<PathBuf>,
    /// Bode plot (SVG or PNG by extension), natural frequencies marked.
    #[arg(long, value_name = "FILE.svg|FILE.png")]
    pub plot: Option<PathBuf>,
    /// Which model's matrices: auto, generated or assembled.
    #[arg(long, default_value = "auto", value_name = "MODEL")]
    pub model: ModelChoice,
}

/// Runs `telescopic bode`.
pub fn bode(args: &BodeArgs) -> anyhow::Result<()> {
    let inputs = [args.scene.scene.as_path()];
    check_output("--out", args.out.as_deref(), &inputs)?;
    check_chart("--plot", args.plot.as_deref(), &inputs)?;
    if let (Some(plot), Some(out)) = (&args.plot, &args.out) {
        telescopic::io::output::check_not_an_input(plot, &[out])
            .map_err(super::of_flag("--plot"))?;
    }
    if args.out.is_none() {
        check_stdout_open()?;
    }
    let scene = args.scene.load()?;
    let options = BodeOptions {
        linear: args.point.options(args.model)?,
        outputs: args.outputs.clone(),
        inputs: args.inputs.clone(),
        from_hz: args.from,
        to_hz: args.to,
        points: args.points,
    };
    let response = frequency_response(&scene, &options)?;
    write_to(args.out.as_deref(), |w| response.write_csv(w))?;
    eprintln!("{}", response.summary());
    if let Some(p) = &args.out {
        eprintln!("wrote {}", p.display());
    }
    if let Some(p) = &args.plot {
        telescopic::plot::save(&response, p)?;
        eprintln!("wrote {}", p.display());
    }
    Ok(())
}
