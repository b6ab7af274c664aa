//! `telescopic linearize`: the scene's linear model with stable names, in the formats of the
//! tools controls engineers use.

use super::{SceneArgs, check_output};
use crate::stdout::{check_stdout_open, write_to};
use clap::Args;
use std::path::PathBuf;
use telescopic::control::DesignOptions;
use telescopic::linear::{
    Format, Grid, LinearizeOptions, linearize as run_linearize, parse_positions,
};
use telescopic::run::models::ModelChoice;
use telescopic::runtime::ContactMode;

/// The operating point of a linear model: shared by `linearize` and `bode`.
#[derive(Debug, Args)]
pub struct OperatingPointArgs {
    /// Telescopic positions of the operating point, e.g. `a2=1.15` or `a2=1.0,a3=0.9` (m; at
    /// rest); the others come from the scene.
    #[arg(long, value_name = "a2=V,...", conflicts_with = "at_time")]
    pub positions: Option<String>,
    /// Take the positions and their speeds of the scene at this time (s); default: its start.
    #[arg(long, value_name = "T")]
    pub at_time: Option<f64>,
    /// Contacts: closed (every contact with the linear law f = c xi + d xi_dot) or open (the
    /// sections float free of each other).
    #[arg(long, default_value = "closed", value_name = "closed|open")]
    pub contacts: ContactMode,
}

impl OperatingPointArgs {
    /// The library's options for this point, with `model`.
    pub fn options(&self, model: ModelChoice) -> anyhow::Result<LinearizeOptions> {
        let positions = match &self.positions {
            Some(p) => parse_positions(p).map_err(|e| anyhow::anyhow!("--positions: {e}"))?,
            None => Vec::new(),
        };
        Ok(LinearizeOptions {
            positions,
            at_time: self.at_time,
            contacts: self.contacts,
            model,
            memory_budget: crate::memory_budget()?,
            ..LinearizeOptions::default()
        })
    }
}

/// Options of `telescopic linearize`.
#[derive(Debug, Args)]
pub struct LinearizeArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    #[command(flatten)]
    pub point: OperatingPointArgs,
    /// Sample the linear parameter-varying model over a grid of one position, e.g.
    /// `a2=0.35:1.15:9` (m; speeds zero).
    #[arg(long, value_name = "a2=FROM:TO:COUNT")]
    pub grid: Option<Grid>,
    /// Output format: json, matlab (an .m script), npz, python (a python-control script) or
    /// latex (small models).
    #[arg(long, default_value = "json", value_name = "FORMAT")]
    pub format: Format,
    /// Output file (written whole or not at all); default: standard output.
    #[arg(long, value_name = "FILE")]
    pub out: Option<PathBuf>,
    /// Which model's matrices: auto, generated or assembled.
    #[arg(long, default_value = "auto", value_name = "MODEL")]
    pub model: ModelChoice,
    /// Add a second input, F_load (N): a horizontal disturbance force on the load.
    #[arg(long)]
    pub disturbance: bool,
    /// Also write the zero-order-hold discrete-time model at this sample period (s): Ad, Bd
    /// with the same C, D (json, matlab, npz, python).
    #[arg(long, value_name = "DT")]
    pub discrete: Option<f64>,
}

/// Runs `telescopic linearize`.
pub fn linearize(args: &LinearizeArgs) -> anyhow::Result<()> {
    check_output("--out", args.out.as_deref(), &[&args.scene.scene])?;
    if args.out.is_none() {
        check_stdout_open()?;
    }
    let scene = args.scene.load()?;
    let options = LinearizeOptions {
        grid: args.grid.clone(),
        disturbance: args.disturbance,
        discrete: args.discrete,
        ..args.point.options(args.model)?
    };
    let mut export = run_linearize(&scene, &options)?;
    export.scene_file = args.scene.scene.display().to_string();
    export.overrides = args.scene.overrides.clone();
    export.check_format(args.format)?;
    write_to(args.out.as_deref(), |w| export.write(args.format, w))?;
    let points = export.points.len();
    eprintln!(
        "{}: {} states, {} input(s), {} outputs, contacts {}, {} operating point(s) ({})",
        export.scene,
        export.states.len(),
        export.inputs.len(),
        export.outputs.len(),
        export.contacts.name(),
        points,
        export.operating_point
    );
    if let Some(p) = &args.out {
        eprintln!("wrote {}", p.display());
    }
    Ok(())
}

/// Options of `telescopic design`.
#[derive(Debug, Args)]
pub struct DesignArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    /// The controller to write: lqr (gain-scheduled state feedback around the drive
    /// profile), shaper (a ZV/ZVD input shaper of the profile), lqr+shaper, or
    /// lqr+shaper+kalman (the feedback on a Kalman filter's estimate from vehicle and
    /// tip_rel).
    #[arg(long, default_value = "lqr+shaper", value_name = "KIND")]
    pub controller: telescopic::control::ControllerKind,
    /// The drive's force limit (N): the total force saturates there.
    #[arg(long, default_value_t = DesignOptions::default().force_limit, value_name = "N")]
    pub force_limit: f64,
    /// Acceptable tip_rel (m): the LQR weighs it by 1/scale^2.
    #[arg(long, default_value_t = DesignOptions::default().tip_scale, value_name = "M")]
    pub tip_scale: f64,
    /// Acceptable deviation of the vehicle from the rigid travel asked for (m).
    #[arg(long, default_value_t = DesignOptions::default().vehicle_scale, value_name = "M")]
    pub vehicle_scale: f64,
    /// Design points over the moving telescopic position (1 to 200).
    #[arg(long, default_value_t = DesignOptions::default().grid_points, value_name = "N")]
    pub grid_points: usize,
    /// Elastic modes of the LQR's design model (the rigid translation and these modes).
    #[arg(long, default_value_t = DesignOptions::default().design_modes, value_name = "N")]
    pub design_modes: usize,
    /// The shaper: zv or zvd.
    #[arg(long, default_value_t = DesignOptions::default().shaper, value_name = "KIND")]
    pub shaper: telescopic::control::ShaperKind,
    /// Where the shaper's trains sit: within (inside the profile's span, its rest-to-rest
    /// travel kept) or delayed (after each jump, ending up to a period late).
    #[arg(long, default_value_t = DesignOptions::default().shaper_timing, value_name = "TIMING")]
    pub shaper_timing: telescopic::control::ShaperTiming,
    /// Kalman filter (lqr+shaper+kalman): measurement noise of vehicle and tip_rel (m).
    #[arg(long, default_value_t = DesignOptions::default().sensor_noise, value_name = "M")]
    pub sensor_noise: f64,
    /// Kalman filter: the force disturbance (N).
    #[arg(long, default_value_t = DesignOptions::default().force_noise, value_name = "N")]
    pub force_noise: f64,
    /// The controller file (JSON) to write.
    #[arg(long, value_name = "FILE")]
    pub out: PathBuf,
    /// Output feedback from these measured outputs (e.g. `vehicle,kappa_1_0` or
    /// `vehicle,acc_load`), run sampled through a discrete Kalman filter (default: the
    /// continuous full-state controller).
    #[arg(long, value_name = "OUTPUT,...", value_delimiter = ',')]
    pub sensors: Vec<String>,
    /// Measurement noise of each sensor (standard deviation in its unit), as many as
    /// --sensors (default: vehicle 1e-4 m, kappa_1_0 1e-5 1/m, acc_load 0.01 m/s^2).
    #[arg(long, value_name = "SIGMA,...", value_delimiter = ',')]
    pub measurement_noise: Vec<f64>,
    /// Also write the sampled controller as C99 into this directory
    /// (telescopic_controller.h and .c); needs --sensors.
    #[arg(long, value_name = "DIR", requires = "sensors")]
    pub emit_c: Option<PathBuf>,
    /// The sampled controller's estimator: linear (a discrete Kalman filter of the
    /// closed-contact model) or extended (an extended Kalman filter on the design scene's
    /// nonlinear model with the contact law, recorded in the file); --emit-c writes either.
    #[arg(long, default_value_t = DesignOptions::default().estimator, value_name = "linear|extended")]
    pub estimator: telescopic::control::Estimator,
    /// The extended filter's process-noise floor: a variance added to every state per
    /// period (state units squared).
    #[arg(long, default_value_t = DesignOptions::default().process_noise_floor, value_name = "VAR")]
    pub process_noise_floor: f64,
    /// The sampled law: auto (strain-rate when the sensors include vehicle and kappa_1_0,
    /// else lqr), lqr (the LQR on the estimator's state) or strain-rate (the strain gauge's
    /// rate fed to the drive and a PD on the vehicle, no estimator; --controller then only
    /// chooses the feedforward, shaped or not).
    #[arg(long, default_value_t = DesignOptions::default().law, value_name = "auto|lqr|strain-rate")]
    pub law: telescopic::control::SampledLaw,
    /// The strain-rate law's damping ratio added to the first mode.
    #[arg(long, default_value_t = DesignOptions::default().added_damping, value_name = "ZETA")]
    pub added_damping: f64,
    /// Seed of the simulated measurement noise (the same seed, the same run).
    #[arg(long, default_value_t = 1, value_name = "N")]
    pub noise_seed: u64,
    /// The sampled controller's rate (Hz).
    #[arg(long, default_value_t = DesignOptions::default().rate_hz, value_name = "HZ")]
    pub rate: f64,
    /// Skip the table of variants (four simulations of the scene).
    #[arg(long)]
    pub no_table: bool,
    /// Which model's matrices: auto, generated or assembled.
    #[arg(long, default_value = "auto", value_name = "MODEL")]
    pub model: ModelChoice,
}

/// Runs `telescopic design`.
pub fn design(args: &DesignArgs) -> anyhow::Result<()> {
    check_output("--out", Some(&args.out), &[&args.scene.scene])?;
    check_stdout_open()?;
    let scene = args.scene.load()?;
    let options = DesignOptions {
        kind: args.controller,
        force_limit: args.force_limit,
        tip_scale: args.tip_scale,
        vehicle_scale: args.vehicle_scale,
        grid_points: args.grid_points,
        design_modes: args.design_modes,
        shaper: args.shaper,
        shaper_timing: args.shaper_timing,
        sensor_noise: args.sensor_noise,
        force_noise: args.force_noise,
        sensors: args.sensors.clone(),
        sensor_noises: args.measurement_noise.clone(),
        rate_hz: args.rate,
        estimator: args.estimator,
        process_noise_floor: args.process_noise_floor,
        noise_seed: args.noise_seed,
        law: args.law,
        added_damping: args.added_damping,
        model: args.model,
        models: Default::default(),
        memory_budget: crate::memory_budget()?,
    };
    super::check_emit_dir(
        "--emit-c",
        args.emit_c.as_deref(),
        &telescopic::control::emit::C_FILES,
        &[&args.scene.scene, &args.out],
    )?;
    let controller = telescopic::control::design(&scene, &options)?;
    if controller.shaper.is_some() && controller.shaper_timing != options.shaper_timing {
        eprintln!(
            "note: the shaper's trains are {} (asked: {}): the drive profile is not rest to rest \
             (force and velocity back at zero) or too short for its trains",
            controller.shaper_timing, options.shaper_timing
        );
    }
    if let Some(dir) = &args.emit_c {
        telescopic::control::emit::write_c(&controller, scene.time.start, scene.time.end, dir)?;
        eprintln!(
            "wrote {} and {} in {}",
            telescopic::control::emit::C_FILES[0],
            telescopic::control::emit::C_FILES[1],
            dir.display()
        );
    }
    write_to(Some(&args.out), |w| {
        w.write_all(controller.to_json().as_bytes())
    })?;
    eprintln!(
        "{}: controller {} with {} design point(s){}; wrote {}",
        scene.name,
        controller.describe(),
        controller.schedule.len(),
        controller
            .schedule_parameter
            .as_ref()
            .map_or(String::new(), |p| format!(" over {p}")),
        args.out.display()
    );
    if !args.no_table {
        let rows = telescopic::control::compare_variants(
            &scene,
            &options,
            &super::progress::Progress::new(),
        )?;
        let text = format!(
            "residual vibration: standard deviation of tip_rel from t = {} s (the drive's last \
             change) to the end\n{}",
            rows[0].metrics.window_start,
            telescopic::control::variants_table(&rows)
        );
        write_to(None, |w| w.write_all(text.as_bytes()))?;
    }
    Ok(())
}
