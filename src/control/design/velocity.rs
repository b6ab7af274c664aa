//! The design of a velocity feedback on the scene's scheduled linear model.

use crate::control::file::velocity::{
    VELOCITY_FEEDBACK_FORMAT, VELOCITY_FEEDBACK_VERSION, VelocityFeedback, VelocityPoint,
    VelocityTable,
};
use crate::control::law::sampled::default_noise;
use crate::control::law::strain::{STRAIN_RATE_SENSORS, tip_per_curvature};
use crate::run::models::{ModelChoice, ModelRegistry};
use crate::{Error, OptionName, Result};
use telescopic_runtime::{
    ContactMode, Drive, Lpv, Model, ModelParams, Output, Scene, Sensor, configuration_key,
};

/// The vehicle's two closed-loop poles in units of the first mode's angular frequency.
///
/// They and the observer's poles below were chosen on the single-mode loop (a tip mass on a
/// spring on the vehicle, the law of [`crate::control::law::velocity`] with its observer):
/// from a residual of 30 mm and a vehicle 10 mm off, the vehicle within 1 mm and the tip
/// within 5 mm soonest over plants whose first mode is 0.8 to 1.2 times the one designed
/// for and whose participation is 0.8 to 1.3 times. Not tuned on any scene.
pub const VEHICLE_POLES_PER_MODE: [f64; 2] = [0.64, 0.8];

/// The damping ratio of the observer's oscillatory pair.
pub const OBSERVER_DAMPING: f64 = 0.5;

/// The observer pair's natural frequency in units of the first mode's.
pub const OBSERVER_FREQUENCY_PER_MODE: f64 = 1.5;

/// The observer's real pole (the curvature at rest) in units of the first mode's angular
/// frequency.
pub const OBSERVER_BIAS_POLE_PER_MODE: f64 = 0.64;

/// Settings of [`design_velocity_feedback`].
#[derive(Debug, Clone, PartialEq)]
pub struct VelocityDesign {
    /// The first mode's damping ratio with the loop closed (default 0.5).
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
    /// The loads the law is scheduled on (kg, ascending; default none: the scene's load
    /// alone, a law used unchanged whatever the load).
    pub loads_kg: Vec<f64>,
}

impl Default for VelocityDesign {
    fn default() -> Self {
        VelocityDesign {
            added_damping: 0.5,
            velocity_limit: 0.25,
            acceleration_limit: 1.0,
            rate_hz: crate::control::law::sampled::DEFAULT_RATE_HZ,
            grid_points: 9,
            seed: 1,
            loads_kg: Vec::new(),
        }
    }
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
    let moving = moving_position(params, scene.time.start, scene.time.end)?;
    let tables = match &design.loads_kg[..] {
        [] => vec![VelocityTable {
            load_kg: params.load_mass,
            points: design_points(scene, design, moving)?,
        }],
        loads => loads
            .iter()
            .map(|&load_kg| {
                let loaded = scene.with_values(&[("masses.load", load_kg)])?;
                Ok(VelocityTable {
                    load_kg,
                    points: design_points(&loaded, design, moving)?,
                })
            })
            .collect::<Result<Vec<_>>>()?,
    };
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
        vehicle_poles_per_mode: VEHICLE_POLES_PER_MODE,
        observer_damping: OBSERVER_DAMPING,
        observer_frequency_per_mode: OBSERVER_FREQUENCY_PER_MODE,
        observer_bias_pole_per_mode: OBSERVER_BIAS_POLE_PER_MODE,
        velocity_limit_m_per_s: design.velocity_limit,
        acceleration_limit_m_per_s2: design.acceleration_limit,
        schedule_parameter: moving.map(|(i, _, _)| format!("a_{}", i + 2)),
        tables,
    })
}

/// The design points of `scene` over the `moving` position's range (`design.grid_points` of
/// them), or at its positions when none moves.
fn design_points(
    scene: &Scene,
    design: &VelocityDesign,
    moving: Option<(usize, f64, f64)>,
) -> Result<Vec<VelocityPoint>> {
    let params = &scene.params;
    let chosen = ModelRegistry::default().build(params, ModelChoice::Auto)?;
    let model = chosen.model.as_ref();
    let lpv = Lpv::new(model, ContactMode::Closed).map_err(Error::from)?;
    let here: Vec<f64> = params
        .positions
        .iter()
        .map(|p| p.value(scene.time.start))
        .collect();
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
    grid.into_iter()
        .map(|positions| {
            let (ratio, f1) = tip_per_curvature(model, &lpv, &positions)?;
            Ok(VelocityPoint {
                first_mode_hz: f1,
                tip_per_curvature_m2: ratio,
                curvature_per_acceleration: static_curvature(model, &lpv, &positions)?,
                positions,
            })
        })
        .collect()
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
        .map_err(Error::from)?;
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
        .position(|o| Output::parse(&o.name) == Some(Output::Sensor(Sensor::FootCurvature)))
        .ok_or_else(|| Error::Model("the linear model has no output `kappa_1_0`".into()))?;
    Ok((0..r).map(|j| full.c[(row, j + 1)] * p[j]).sum())
}

impl VelocityDesign {
    /// The settings against their rules, before any work (the bounds a feedback file
    /// accepts).
    ///
    /// # Errors
    /// [`Error::Option`] naming the setting.
    pub fn check(&self) -> Result<()> {
        check_design(self)
    }
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
    // the file's own bounds (`check_fits`), so that a design is never refused when read
    for (what, v, high) in [
        ("velocity", design.velocity_limit, 1e3),
        ("acceleration", design.acceleration_limit, 1e4),
    ] {
        if !(v.is_finite() && v > 0.0 && v <= high) {
            return Err(Error::option(
                OptionName::CorrectionLimits,
                format!("the correction's {what} bound must be > 0 and at most {high} (got {v})"),
            ));
        }
    }
    if design
        .loads_kg
        .iter()
        .any(|m| !(m.is_finite() && *m > 0.0 && *m <= 1e9))
        || design.loads_kg.windows(2).any(|w| w[1] <= w[0])
    {
        return bad(format!(
            "the loads scheduled on must be ascending masses > 0 and at most 1e9 kg (got {:?})",
            design.loads_kg
        ));
    }
    if design.grid_points < 2 {
        return bad(format!(
            "at least 2 design points (got {})",
            design.grid_points
        ));
    }
    crate::control::law::sampled::check_rate(design.rate_hz)
}
