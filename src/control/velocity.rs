//! Feedback through a velocity servo: the drive follows the scene's setpoint `s(t)` (its
//! prescribed motion) plus a velocity correction the law commands at every tick, from the
//! drive's encoder and a strain gauge at the foot of section 1.
//!
//! At tick `k` the law reads `u_k` (`vehicle`, m) and `kappa_k` (`kappa_1_0`, 1/m) and commands
//!
//! ```text
//! v_{k+1} = sat( g(a) h_k - k_p (u_k - s(t_k)) )
//! g(a)    = 2 zeta_d omega_1(a) r(a)
//! e_k     = kappa_k - c(a) s''(t_k)
//! h_k     = w (h_{k-1} + e_k - e_{k-1}),  w = tau_w / (tau_w + T)
//! ```
//!
//! bounded to `+-v_max` and changed by at most `a_max T` a tick. The drive interpolates its
//! velocity setpoint linearly over a tick (as drives in cyclic velocity mode do), so the
//! correction's acceleration `(v_{k+1} - v_k) / T` holds over the tick after the command:
//! one tick of computation delay, one of interpolation. `r(a)` is `tip_rel` per `kappa_1_0` in
//! the first elastic mode with the vehicle held, `omega_1(a)` that mode's angular frequency:
//! the correction's acceleration is then `2 zeta_d omega_1` times the tip's rate in that mode,
//! the base excitation that adds the damping ratio `zeta_d` to a tip mass on a spring (the
//! force-driven strain-rate law of [`super::strain`] is the same idea one derivative up). The
//! proportional loop `k_p` (a third of the lowest first mode's angular frequency) brings the
//! vehicle back to the setpoint. `c(a)` is the curvature the held structure takes at rest
//! under a unit vehicle acceleration: the law acts on the curvature's departure from the
//! quasi-static bending the setpoint's own acceleration `s''` causes, so that a move that
//! excites no vibration draws no correction (and no offset to win back after it). `h` is that
//! departure through a washout (a first-order
//! high-pass of time constant `tau_w`, the longest first-mode period: 9 degrees of
//! phase at the first mode): a telescope at rest may stay bent (an upper section leaning in
//! its guide under gravity), and a law on the curvature itself would hold the vehicle off
//! its target by `g kappa_rest / k_p`.

use super::sampled::{SampledController, default_noise};
use super::sampled_run::{SampledRun, TickSetup, check_tick_cost, finish, tick_grid, tick_loop};
use super::strain::{STRAIN_RATE_SENSORS, VEHICLE_LOOP_FRACTION, tip_per_curvature};
use crate::report::Reporter;
use crate::run::held::HeldValue;
use crate::run::models::{ModelChoice, ModelRegistry};
use crate::run::{PreparedRun, SimulationOptions};
use crate::{Error, OptionName, Result};
use serde::{Deserialize, Serialize};
use telescopic_runtime::nalgebra::DMatrix;
use telescopic_runtime::{
    ContactMode, ContactState, Drive, Lpv, Model, ModelParams, Profile, Scene, configuration_key,
};

/// The washout's time constant in periods of the lowest first mode.
pub const WASHOUT_PERIODS: f64 = 1.0;

/// The `format` of a velocity-feedback file.
pub const VELOCITY_FEEDBACK_FORMAT: &str = "telescopic velocity feedback";

/// The layout version this build writes and reads.
pub const VELOCITY_FEEDBACK_VERSION: u32 = 1;

/// A designed velocity-servo feedback: what `plan` writes beside a plan that uses feedback,
/// and `simulate --controller` reads.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct VelocityFeedback {
    /// `telescopic velocity feedback`.
    pub format: String,
    /// Layout version of the file.
    pub version: u32,
    /// The tool that wrote it.
    pub generator: String,
    /// The scene designed for.
    pub scene: String,
    /// Its configuration key (a scene of another configuration is refused).
    pub configuration: String,
    /// Controller rate (Hz).
    pub rate_hz: f64,
    /// The measured outputs: `vehicle` and `kappa_1_0`.
    pub sensors: Vec<String>,
    /// Their measurement noise (standard deviation, m and 1/m).
    pub noise: Vec<f64>,
    /// Seed of the simulated measurement noise.
    pub seed: u64,
    /// Damping ratio added to the first mode (the design's knob).
    pub added_damping: f64,
    /// The vehicle loop's gain `k_p` (1/s).
    pub position_gain_per_s: f64,
    /// Time constant of the curvature's washout `tau_w` (s).
    pub washout_time_constant_s: f64,
    /// Bound of the velocity correction (m/s).
    pub velocity_limit_m_per_s: f64,
    /// Bound of the correction's acceleration (m/s^2).
    pub acceleration_limit_m_per_s2: f64,
    /// The scheduled position (`a_k`), if the positions move.
    pub schedule_parameter: Option<String>,
    /// The design points, ordered by the scheduled position.
    pub points: Vec<VelocityPoint>,
}

/// The law at one design point.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct VelocityPoint {
    /// Telescopic positions `a_2..a_n` (m).
    pub positions: Vec<f64>,
    /// The first elastic mode's frequency with the vehicle held (Hz).
    pub first_mode_hz: f64,
    /// `tip_rel` per `kappa_1_0` in that mode (m^2).
    pub tip_per_curvature_m2: f64,
    /// The gain `g` on the curvature (m/s per 1/m).
    pub gain_m2_per_s: f64,
    /// `c`: `kappa_1_0` at rest under a unit vehicle acceleration, vehicle held (1/m per
    /// m/s^2).
    pub curvature_per_acceleration: f64,
}

/// Settings of [`design_velocity_feedback`].
#[derive(Debug, Clone, PartialEq)]
pub struct VelocityDesign {
    /// Damping ratio added to the first mode (default 0.3).
    pub added_damping: f64,
    /// Bound of the velocity correction (m/s, default 0.25).
    pub velocity_limit: f64,
    /// Bound of the correction's acceleration (m/s^2, default 1).
    pub acceleration_limit: f64,
    /// Controller rate (Hz, default 1000).
    pub rate_hz: f64,
    /// Design points over the moving position's range (default 9).
    pub grid_points: usize,
    /// Seed of the simulated measurement noise (default 1).
    pub seed: u64,
}

impl Default for VelocityDesign {
    fn default() -> Self {
        VelocityDesign {
            added_damping: 0.3,
            velocity_limit: 0.25,
            acceleration_limit: 1.0,
            rate_hz: super::sampled::DEFAULT_RATE_HZ,
            grid_points: 9,
            seed: 1,
        }
    }
}

fn field(name: &str, rule: impl std::fmt::Display) -> Error {
    Error::input(format!("velocity feedback `{name}`"), rule)
}

/// The moving position of `params` over `[start, end]` (its index among `a_2..`, and its
/// range), if one moves; more than one is refused.
fn moving_position(
    params: &ModelParams,
    start: f64,
    end: f64,
) -> Result<Option<(usize, f64, f64)>> {
    let moving: Vec<usize> = (0..params.positions.len())
        .filter(|&i| !params.positions[i].is_constant())
        .collect();
    match moving[..] {
        [] => Ok(None),
        [i] => {
            let (lo, hi) = params.positions[i].range(start, end);
            Ok(Some((i, lo, hi)))
        }
        _ => Err(Error::option(
            OptionName::Feedback,
            "gain scheduling over more than one moving telescopic position is not supported",
        )),
    }
}

/// Designs the velocity feedback for `scene` (which must have a prescribed motion).
///
/// # Errors
/// [`Error::Option`] for settings out of range or a scene the design does not cover;
/// [`Error::Model`] when the first mode does not bend section 1 at its foot.
pub fn design_velocity_feedback(
    scene: &Scene,
    design: &VelocityDesign,
) -> Result<VelocityFeedback> {
    let params = &scene.params;
    if !matches!(params.drive, Drive::Motion(_)) {
        return Err(Error::option(
            OptionName::Feedback,
            "velocity feedback acts through a servo's setpoint: the scene needs a prescribed \
             motion (drive.motion)",
        ));
    }
    check_design(design)?;
    let chosen = ModelRegistry::default().build(params, ModelChoice::Auto)?;
    let model = chosen.model.as_ref();
    let lpv = Lpv::new(model, ContactMode::Closed).map_err(|e| Error::Model(e.to_string()))?;
    let here: Vec<f64> = params
        .positions
        .iter()
        .map(|p| p.value(scene.time.start))
        .collect();
    let moving = moving_position(params, scene.time.start, scene.time.end)?;
    let grid: Vec<Vec<f64>> = match moving {
        None => vec![here],
        Some((i, lo, hi)) => (0..design.grid_points)
            .map(|j| {
                let mut p = here.clone();
                p[i] = lo + (hi - lo) * j as f64 / (design.grid_points - 1) as f64;
                p
            })
            .collect(),
    };
    let tau = std::f64::consts::TAU;
    let points = grid
        .into_iter()
        .map(|positions| {
            let (ratio, f1) = tip_per_curvature(model, &lpv, &positions)?;
            Ok(VelocityPoint {
                first_mode_hz: f1,
                tip_per_curvature_m2: ratio,
                gain_m2_per_s: 2.0 * design.added_damping * tau * f1 * ratio,
                curvature_per_acceleration: static_curvature(model, &lpv, &positions)?,
                positions,
            })
        })
        .collect::<Result<Vec<_>>>()?;
    let lowest = points
        .iter()
        .map(|p| p.first_mode_hz)
        .fold(f64::INFINITY, f64::min);
    let sensors: Vec<String> = STRAIN_RATE_SENSORS.iter().map(|s| s.to_string()).collect();
    Ok(VelocityFeedback {
        format: VELOCITY_FEEDBACK_FORMAT.into(),
        version: VELOCITY_FEEDBACK_VERSION,
        generator: format!("telescopic {}", env!("CARGO_PKG_VERSION")),
        scene: scene.name.clone(),
        configuration: configuration_key(params),
        rate_hz: design.rate_hz,
        noise: sensors.iter().map(|s| default_noise(s)).collect(),
        sensors,
        seed: design.seed,
        added_damping: design.added_damping,
        position_gain_per_s: VEHICLE_LOOP_FRACTION * tau * lowest,
        washout_time_constant_s: WASHOUT_PERIODS / lowest,
        velocity_limit_m_per_s: design.velocity_limit,
        acceleration_limit_m_per_s2: design.acceleration_limit,
        schedule_parameter: moving.map(|(i, _, _)| format!("a_{}", i + 2)),
        points,
    })
}

/// `kappa_1_0` (1/m) of the held structure at rest under a unit vehicle acceleration at
/// `positions`: the relative coordinates `p` solve `A_pp p + b_p = 0` of the closed-contact
/// linear model (`M_pp p'' + K_pp p = -M_p0 u''` at rest).
///
/// # Errors
/// [`Error::Model`] when the linear model cannot be formed or its stiffness is singular.
fn static_curvature(model: &dyn Model, lpv: &Lpv, positions: &[f64]) -> Result<f64> {
    let n = model.dof();
    let full = lpv
        .at(positions, &vec![0.0; positions.len()])
        .map_err(|e| Error::Model(e.to_string()))?;
    let r = n - 1;
    let a_pp = full.a.view((n + 1, 1), (r, r)).into_owned();
    let b_p = full.b.view((n + 1, 0), (r, 1)).into_owned();
    let p = a_pp
        .lu()
        .solve(&(-b_p))
        .ok_or_else(|| Error::Model("the held structure has no static deflection".into()))?;
    let row = lpv
        .outputs()
        .iter()
        .position(|o| o.name == "kappa_1_0")
        .ok_or_else(|| Error::Model("the linear model has no output `kappa_1_0`".into()))?;
    Ok((0..r).map(|j| full.c[(row, j + 1)] * p[j]).sum())
}

/// The design's settings against their rules.
fn check_design(design: &VelocityDesign) -> Result<()> {
    let bad = |rule: String| Err(Error::option(OptionName::Feedback, rule));
    if !(design.added_damping > 0.0 && design.added_damping <= 2.0) {
        return bad(format!(
            "the added damping must be a ratio in (0, 2] (got {})",
            design.added_damping
        ));
    }
    for (what, v) in [
        ("velocity", design.velocity_limit),
        ("acceleration", design.acceleration_limit),
    ] {
        if !(v.is_finite() && v > 0.0) {
            return Err(Error::option(
                OptionName::CorrectionLimits,
                format!("the correction's {what} bound must be > 0 (got {v})"),
            ));
        }
    }
    if design.grid_points < 2 {
        return bad(format!(
            "at least 2 design points (got {})",
            design.grid_points
        ));
    }
    super::sampled::check_rate(design.rate_hz)
}

impl VelocityFeedback {
    /// The file (JSON).
    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(self).expect("plain data") + "\n"
    }

    /// Reads a velocity-feedback file: its format and version first.
    ///
    /// # Errors
    /// [`Error::Analysis`] naming what is malformed.
    pub fn from_json(text: &str) -> Result<Self> {
        let malformed = |e: serde_json::Error| Error::Analysis(format!("velocity feedback: {e}"));
        let head: serde_json::Value = serde_json::from_str(text).map_err(malformed)?;
        if head.get("format").and_then(|f| f.as_str()) != Some(VELOCITY_FEEDBACK_FORMAT) {
            return Err(Error::Analysis(format!(
                "velocity feedback: `format` is not \"{VELOCITY_FEEDBACK_FORMAT}\""
            )));
        }
        let version = head.get("version").and_then(|v| v.as_u64());
        if version != Some(u64::from(VELOCITY_FEEDBACK_VERSION)) {
            return Err(Error::Analysis(format!(
                "velocity feedback: layout version {}, but this build reads version \
                 {VELOCITY_FEEDBACK_VERSION}; plan again with this build",
                version.map_or("none".to_string(), |v| v.to_string())
            )));
        }
        serde_json::from_value(head).map_err(malformed)
    }

    /// In a few words, e.g. `velocity feedback (zeta 0.30) from vehicle, kappa_1_0 at 1000 Hz`.
    pub fn describe(&self) -> String {
        format!(
            "velocity feedback (zeta {:.2}) from {} at {} Hz",
            self.added_damping,
            self.sensors.join(", "),
            self.rate_hz
        )
    }

    /// Checks that the file fits `scene`: the configuration, a prescribed motion, the sensors
    /// the law reads, finite bounded settings and one position per telescopic position at
    /// every point.
    ///
    /// # Errors
    /// [`Error::Input`] naming the field and the rule; [`Error::Option`] for a scene without
    /// a prescribed motion.
    pub fn check_fits(&self, scene: &Scene) -> Result<()> {
        let params = &scene.params;
        if !matches!(params.drive, Drive::Motion(_)) {
            return Err(Error::option(
                OptionName::Controller,
                "velocity feedback corrects a prescribed motion; the scene's drive is a force",
            ));
        }
        let key = configuration_key(params);
        if key != self.configuration {
            return Err(field(
                "configuration",
                format!(
                    "designed for configuration {} (scene {}), the scene is {key}",
                    self.configuration, self.scene
                ),
            ));
        }
        if self.sensors != STRAIN_RATE_SENSORS || self.noise.len() != self.sensors.len() {
            return Err(field(
                "sensors",
                "must be [\"vehicle\", \"kappa_1_0\"] with one noise each",
            ));
        }
        if let Some(v) = self.noise.iter().find(|v| !(v.is_finite() && **v >= 0.0)) {
            return Err(field("noise", format!("must be finite and >= 0 (got {v})")));
        }
        super::sampled::check_rate(self.rate_hz).map_err(|_| {
            field(
                "rate_hz",
                format!("must be 1 to 1e6 Hz (got {})", self.rate_hz),
            )
        })?;
        for (name, v, high) in [
            ("added_damping", self.added_damping, 2.0),
            ("position_gain_per_s", self.position_gain_per_s, 1e3),
            ("washout_time_constant_s", self.washout_time_constant_s, 1e6),
            ("velocity_limit_m_per_s", self.velocity_limit_m_per_s, 1e3),
            (
                "acceleration_limit_m_per_s2",
                self.acceleration_limit_m_per_s2,
                1e4,
            ),
        ] {
            if !(v.is_finite() && v > 0.0 && v <= high) {
                return Err(field(
                    name,
                    format!("must be > 0 and at most {high} (got {v})"),
                ));
            }
        }
        self.check_points(params)
    }

    /// The design points: one or more, positions of the scene's count, finite gains.
    fn check_points(&self, params: &ModelParams) -> Result<()> {
        if self.points.is_empty() {
            return Err(field("points", "must hold at least one design point"));
        }
        for (j, p) in self.points.iter().enumerate() {
            if p.positions.len() != params.positions.len()
                || p.positions.iter().any(|a| !a.is_finite())
            {
                return Err(field(
                    &format!("points[{j}].positions"),
                    format!("must be {} finite positions", params.positions.len()),
                ));
            }
            if !(p.gain_m2_per_s.is_finite() && p.gain_m2_per_s.abs() <= 1e6) {
                return Err(field(
                    &format!("points[{j}].gain_m2_per_s"),
                    format!(
                        "must be finite, at most 1e6 in size (got {})",
                        p.gain_m2_per_s
                    ),
                ));
            }
        }
        let scheduled = self.scheduled_index();
        if self.points.len() > 1 && scheduled.is_none_or(|i| i >= params.positions.len()) {
            return Err(field(
                "schedule_parameter",
                "must name a telescopic position of the scene (a_2, ...) when there are several \
                 points",
            ));
        }
        if let Some(i) = scheduled
            && self
                .points
                .windows(2)
                .any(|w| w[1].positions[i] < w[0].positions[i])
        {
            return Err(field("points", "must ascend along the scheduled position"));
        }
        Ok(())
    }

    /// Index (among `a_2..`) of the scheduled position.
    fn scheduled_index(&self) -> Option<usize> {
        self.schedule_parameter
            .as_deref()
            .and_then(|s| s.strip_prefix("a_"))
            .and_then(|k| k.parse::<usize>().ok())
            .and_then(|k| k.checked_sub(2))
    }
}

/// The law of a velocity-feedback file, ready to step: allocation-free per tick.
pub struct VelocityController {
    file: VelocityFeedback,
    /// The scheduled positions of the points.
    positions: Vec<f64>,
    /// The setpoint `s(t)` (m): the scene's prescribed motion.
    setpoint: Profile,
    period: f64,
    /// The washout's weight per tick.
    washout: f64,
    /// The previous tick's departure from the quasi-static curvature (1/m), once there is
    /// one, and the washed-out departure.
    curvature: (Option<f64>, f64),
    /// The previous command (m/s).
    last: f64,
}

impl VelocityController {
    /// The law of `file` around the setpoint `setpoint`.
    pub fn new(file: &VelocityFeedback, setpoint: Profile) -> Self {
        let positions = match file.scheduled_index() {
            Some(i) => file.points.iter().map(|p| p.positions[i]).collect(),
            None => vec![0.0; file.points.len()],
        };
        let period = 1.0 / file.rate_hz;
        VelocityController {
            positions,
            setpoint,
            period,
            washout: file.washout_time_constant_s / (file.washout_time_constant_s + period),
            curvature: (None, 0.0),
            last: 0.0,
            file: file.clone(),
        }
    }
}

impl SampledController for VelocityController {
    fn step(&mut self, t: f64, y: &[f64], a: f64) -> f64 {
        let (u, kappa) = (y[0], y[1]);
        let f = &self.file;
        let (i, j, w) = super::schedule::bracket(&self.positions, a);
        let between = |x: f64, y: f64| x + w * (y - x);
        let gain = between(f.points[i].gain_m2_per_s, f.points[j].gain_m2_per_s);
        let c = between(
            f.points[i].curvature_per_acceleration,
            f.points[j].curvature_per_acceleration,
        );
        let (s, _, s_acceleration) = self.setpoint.state(t);
        // the departure from the quasi-static bending of the setpoint's acceleration
        let departure = kappa - c * s_acceleration;
        let (previous, washed) = self.curvature;
        let washed = previous.map_or(0.0, |p| self.washout * (washed + departure - p));
        self.curvature = (Some(departure), washed);
        let wanted = gain * washed - f.position_gain_per_s * (u - s);
        let step = f.acceleration_limit_m_per_s2 * self.period;
        let v = wanted
            .clamp(-f.velocity_limit_m_per_s, f.velocity_limit_m_per_s)
            .clamp(self.last - step, self.last + step);
        self.last = v;
        v
    }
}

/// The scene's model with its servo following the setpoint plus a velocity correction
/// interpolated linearly over each tick: the correction's acceleration is held a tick.
pub struct ServoCorrected<'m> {
    base: &'m dyn Model,
    /// Where the vehicle's acceleration goes (the vehicle follows it, the rest feels its
    /// inertia).
    response: super::controlled::DriveResponse,
    /// The correction's acceleration over the current tick (m/s^2).
    acceleration: HeldValue,
    /// The correction reached at the end of the current tick (m/s).
    velocity: HeldValue,
    period: f64,
}

impl<'m> ServoCorrected<'m> {
    /// `base` (a prescribed-motion model) with corrections at `rate_hz`.
    ///
    /// # Errors
    /// [`Error::Model`] when the mass matrix cannot be factored.
    pub fn new(base: &'m dyn Model, rate_hz: f64) -> Result<Self> {
        Ok(ServoCorrected {
            base,
            response: super::controlled::DriveResponse::of(base)?,
            acceleration: HeldValue::new(0.0),
            velocity: HeldValue::new(0.0),
            period: 1.0 / rate_hz,
        })
    }

    /// Sets the correction (m/s) the servo reaches by the end of the next tick.
    pub fn hold(&self, velocity: f64) {
        let acceleration = (velocity - self.velocity.get()) / self.period;
        self.acceleration.set(acceleration);
        self.velocity.set(velocity);
    }

    fn wrapped(&self) -> &dyn Model {
        self.base
    }
}

impl Model for ServoCorrected<'_> {
    crate::wrapped::pass_through_model!();
    fn params(&self) -> &ModelParams {
        self.base.params()
    }
    fn rhs(&self, t: f64, y: &[f64], states: Option<&[ContactState]>, ydot: &mut [f64]) {
        self.base.rhs(t, y, states, ydot);
        let a = self.acceleration.get();
        self.response.add_input(a, ydot);
    }
    fn jacobian(&self, t: f64, y: &[f64], states: Option<&[ContactState]>, jac: &mut DMatrix<f64>) {
        // the correction's acceleration is held over a tick: no state dependence
        self.base.jacobian(t, y, states, jac);
    }
    fn outputs(&self, t: f64, y: &[f64], ydot: &[f64], out: &mut [f64]) {
        // the reaction is read from `ydot`, which carries the correction
        self.base.outputs(t, y, ydot, out);
    }
    fn output_names(&self) -> Vec<String> {
        self.base.output_names()
    }
}

/// Simulates `scene` with the velocity feedback of `file` on the full nonlinear model,
/// sampled at its rate with seeded measurement noise. `auto` is dopri5.
///
/// # Errors
/// [`Error::Input`]/[`Error::Option`] when the file does not fit the scene; the errors of a
/// simulation.
pub fn simulate_velocity(
    scene: &Scene,
    file: &VelocityFeedback,
    options: &SimulationOptions,
    reporter: &dyn Reporter,
) -> Result<SampledRun> {
    file.check_fits(scene)?;
    let Drive::Motion(setpoint) = &scene.params.drive else {
        unreachable!("check_fits refuses a force drive")
    };
    let run = PreparedRun::new(scene, &super::comparison_options(options)?, reporter)?;
    tick_grid(file.rate_hz, &scene.time)?;
    check_tick_cost(scene, file.rate_hz, run.model().dof(), 50.0)?;
    let model = ServoCorrected::new(run.model(), file.rate_hz)?;
    let mut controller = VelocityController::new(file, setpoint.clone());
    let setup = TickSetup {
        rate_hz: file.rate_hz,
        sensors: &file.sensors,
        noise: &file.noise,
        seed: file.seed,
        scheduled: file.scheduled_index().map(|i| i + 2),
    };
    let (trajectory, commands) = tick_loop(
        &run,
        &model,
        &|v| model.hold(v),
        &setup,
        &mut controller,
        reporter,
    )?;
    Ok(finish(run, file.rate_hz, trajectory, commands))
}
