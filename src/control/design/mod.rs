//! Vibration suppression for a force-driven telescope: an LQR state feedback on the
//! closed-contact linear model, gain-scheduled over the moving telescopic position, that
//! tracks the rigid travel the drive profile asks for; a ZV/ZVD input shaper of the drive
//! profile tuned to the first mode along the schedule; or both. The controller file records
//! every grid point's positions, `A`, `B`, `Q`, `R` and `K`, so anyone can check the design.
//!
//! The law applied to the full nonlinear model (with clearance) is
//!
//! ```text
//! F(t, x) = sat( F_ff(t) - K(a(t)) (x - x_ref(t)), +-F_max )
//! ```
//!
//! with `F_ff` the drive profile (shaped or not), `x_ref` the rigid motion it gives the whole
//! telescope (`u_ref'' = F_ff / m_total`, every other coordinate zero) and `K` interpolated
//! linearly in the moving position between the grid points.

pub mod riccati;
pub mod shaper;
pub mod velocity;

use crate::OptionName;
use crate::control::design::riccati::care;
use crate::control::design::shaper::{ShaperKind, ShaperTiming, jumps, shape, shape_within};
use crate::control::file::schema::{
    CONTROLLER_FILE_VERSION, Controller, ControllerKind, Estimator, ObserverPoint, SampledLaw,
    SchedulePoint,
};
use crate::control::law::schedule::schedule_weights;
use crate::io::rows::to_rows;
use crate::linear::Grid;
use crate::run::models::{ModelChoice, ModelRegistry};
use crate::{Error, Result};
use std::fmt;
use std::ops::AddAssign;
use telescopic_runtime::nalgebra::DMatrix;
use telescopic_runtime::{ContactMode, Lpv, ModalAnalysis, Model, Output, modal_analysis_with};
use telescopic_runtime::{Drive, Profile, Scene, ShapedProfile, configuration_key, eigenvalues};

/// Settings of [`design`]; the defaults are Bryson's rule with the scales below.
#[derive(Debug, Clone, PartialEq)]
pub struct DesignOptions {
    /// The controller.
    pub kind: ControllerKind,
    /// The drive's force limit (N): the total force saturates there (default 300).
    pub force_limit: f64,
    /// Acceptable `tip_rel` (m): its weight is `1 / tip^2` (default 0.01).
    pub tip_scale: f64,
    /// Acceptable deviation of the vehicle from the rigid travel asked for (m): weight
    /// `1 / vehicle^2` (default 0.01).
    pub vehicle_scale: f64,
    /// Grid points over the moving position's range (default 5; 1 for fixed positions).
    pub grid_points: usize,
    /// Elastic modes of the design model (default 3): the LQR is designed on the rigid
    /// translation and these modes (a modal truncation of the closed-contact linear model),
    /// whose Riccati equation is well conditioned; the gain acts on the full state.
    pub design_modes: usize,
    /// The shaper's kind (default ZVD).
    pub shaper: ShaperKind,
    /// Where the shaped trains sit: inside the profile's span (default) or after each jump.
    pub shaper_timing: ShaperTiming,
    /// Kalman filter: standard deviation of the measurement noise of `vehicle` and
    /// `tip_rel` (m; default 1e-3).
    pub sensor_noise: f64,
    /// Kalman filter: standard deviation of the force disturbance (N; default 0.1 of the
    /// force limit).
    pub force_noise: f64,
    /// Which model's matrices.
    pub model: ModelChoice,
    /// Where generated models come from (default: the committed ones).
    pub models: ModelRegistry,
    /// The memory a run's outputs may take (bytes,
    /// [`crate::run::memory::DEFAULT_MEMORY_BUDGET`] by default): a longer run is refused
    /// before it starts.
    pub memory_budget: u64,
    /// The measured outputs of an output-feedback controller, run sampled through a discrete
    /// Kalman filter (empty: the continuous full-state controller).
    pub sensors: Vec<String>,
    /// Their measurement noise (standard deviation, each in its output's unit; empty: the
    /// defaults of [`crate::control::law::sampled::default_noise`]).
    pub sensor_noises: Vec<f64>,
    /// The sampled controller's rate (Hz, default 1000).
    pub rate_hz: f64,
    /// The sampled controller's estimator: `linear` (default) or `extended`.
    pub estimator: Estimator,
    /// The extended filter's process-noise floor (variance per period added to every state,
    /// state units squared; default [`crate::control::law::sampled::DEFAULT_PROCESS_NOISE_FLOOR`]).
    pub process_noise_floor: f64,
    /// Seed of the simulated measurement noise (default 1): the same seed, the same run.
    pub noise_seed: u64,
    /// The sampled law: `auto` (default: `strain-rate` when the sensors include `vehicle`
    /// and `kappa_1_0`, else `lqr`), `lqr` (the LQR on the estimator's state) or
    /// `strain-rate` ([`crate::control::law::strain`]; the kind gives its feedforward, shaped or not).
    pub law: SampledLaw,
    /// The strain-rate law's damping ratio added to the first mode (default 0.15).
    pub added_damping: f64,
}

impl Default for DesignOptions {
    fn default() -> Self {
        DesignOptions {
            kind: ControllerKind::LqrShaper,
            force_limit: 300.0,
            tip_scale: 0.01,
            vehicle_scale: 0.01,
            grid_points: 5,
            design_modes: 3,
            shaper: ShaperKind::Zvd,
            shaper_timing: ShaperTiming::Within,
            sensor_noise: 1e-3,
            force_noise: 30.0,
            model: ModelChoice::Auto,
            models: ModelRegistry::default(),
            memory_budget: crate::run::memory::DEFAULT_MEMORY_BUDGET,
            sensors: Vec::new(),
            sensor_noises: Vec::new(),
            rate_hz: crate::control::law::sampled::DEFAULT_RATE_HZ,
            estimator: Estimator::Linear,
            process_noise_floor: crate::control::law::sampled::DEFAULT_PROCESS_NOISE_FLOOR,
            noise_seed: 1,
            law: SampledLaw::Auto,
            added_damping: crate::control::law::strain::DEFAULT_ADDED_DAMPING,
        }
    }
}

/// Most grid points of a schedule.
pub const MAX_GRID_POINTS: usize = 200;

/// The first elastic mode of `A`: frequency (Hz) and damping ratio, from the eigenvalue pair
/// of least magnitude with a non-zero imaginary part.
fn first_mode(a: &DMatrix<f64>) -> Result<(f64, f64)> {
    let ev = eigenvalues(a.clone(), "eigenvalues of the closed-contact linear model")?;
    let l = ev
        .iter()
        .filter(|l| l.im > 1e-9 * l.norm().max(1e-300))
        .min_by(|x, y| x.norm().total_cmp(&y.norm()))
        .ok_or_else(|| Error::Analysis("the linear model has no oscillating mode".into()))?;
    let omega = l.norm();
    Ok((omega / (2.0 * std::f64::consts::PI), -l.re / omega))
}

/// The modal design model of one grid point.
struct ModalDesign {
    /// Mass-normalized basis: the rigid translation, then the first elastic modes (columns).
    phi: DMatrix<f64>,
    /// `eta' = A eta + B u` for `eta = [coordinates, rates]`.
    a: DMatrix<f64>,
    b: DMatrix<f64>,
    /// `eta = W x`.
    w: DMatrix<f64>,
}

/// The rigid translation and the first `modes` elastic modes of the closed-contact model as
/// a design model: `M`-orthonormal basis `Phi`, `eta = Phi' M z`, and the projected
/// second-order system.
fn modal_design(
    model: &dyn Model,
    modal: &ModalAnalysis,
    k_e: &DMatrix<f64>,
    d: &DMatrix<f64>,
    modes: usize,
) -> ModalDesign {
    let n = model.dof();
    let m = model.mass_matrix();
    let keep = modes.min(modal.shapes.len());
    let mut phi = DMatrix::zeros(n, keep + 1);
    // the translation is z = e_0 in computing coordinates; the elastic modes carry no
    // momentum, so the basis is M-orthonormal
    phi[(0, 0)] = 1.0 / m[(0, 0)].sqrt();
    for (i, v) in modal.shapes.iter().take(keep).enumerate() {
        phi.column_mut(i + 1).copy_from(v);
    }
    let r = keep + 1;
    let kr = phi.transpose() * k_e * &phi;
    let dr = phi.transpose() * d * &phi;
    let br = phi.transpose() * model.drive_vector();
    let mut a = DMatrix::zeros(2 * r, 2 * r);
    a.view_mut((0, r), (r, r)).fill_with_identity();
    a.view_mut((r, 0), (r, r)).copy_from(&(-kr));
    a.view_mut((r, r), (r, r)).copy_from(&(-dr));
    let mut b = DMatrix::zeros(2 * r, 1);
    b.view_mut((r, 0), (r, 1)).copy_from(&br);
    let proj = phi.transpose() * m;
    let mut w = DMatrix::zeros(2 * r, 2 * n);
    w.view_mut((0, 0), (r, n)).copy_from(&proj);
    w.view_mut((r, n), (r, n)).copy_from(&proj);
    ModalDesign { phi, a, b, w }
}

/// The Kalman filter of one design point, from the dual Riccati equation of the modal model.
fn kalman(
    full: &telescopic_runtime::LinearModel,
    design: &ModalDesign,
    tip_row: usize,
    options: &DesignOptions,
) -> std::result::Result<ObserverPoint, String> {
    let n2 = full.a.nrows();
    let m2 = design.a.nrows();
    // y = [vehicle, tip_rel] on the full state
    let mut c_meas = DMatrix::zeros(2, n2);
    c_meas.row_mut(0).copy_from(&full.c.row(0));
    c_meas.row_mut(1).copy_from(&full.c.row(tip_row));
    // on the modal states: x = [Phi 0; 0 Phi] eta for the retained part
    let r = m2 / 2;
    let n = n2 / 2;
    let mut phi_full = DMatrix::zeros(n2, m2);
    phi_full.view_mut((0, 0), (n, r)).copy_from(&design.phi);
    phi_full.view_mut((n, r), (n, r)).copy_from(&design.phi);
    let c_modal = &c_meas * &phi_full;
    let q_noise = &design.b * design.b.transpose() * options.force_noise.powi(2);
    let r_noise = DMatrix::identity(2, 2) * options.sensor_noise.powi(2);
    let dual = care(
        &design.a.transpose(),
        &c_modal.transpose(),
        &q_noise,
        &r_noise,
    )
    .map_err(|e| format!("Kalman filter: {e}"))?;
    let l_modal = dual.k.transpose();
    let l = &phi_full * &l_modal;
    Ok(ObserverPoint {
        c_modal: to_rows(&c_modal),
        q_noise: to_rows(&q_noise),
        r_noise: to_rows(&r_noise),
        l_modal: to_rows(&l_modal),
        l: to_rows(&l),
        a_full: to_rows(&full.a),
        b_full: to_rows(&full.b),
        c_meas: to_rows(&c_meas),
    })
}

/// Designs the controller of `options.kind` for `scene`.
///
/// # Errors
/// [`Error::Option`] for settings out of range or a scene the design does not cover (a
/// prescribed motion, more than one moving position, a shaper on a force that is not
/// piecewise constant); [`Error::Analysis`] when the Riccati equation has no acceptable
/// solution at a grid point (the message names the point and the failed check).
pub fn design(scene: &Scene, options: &DesignOptions) -> Result<Controller> {
    let Drive::Force(force) = &scene.params.drive else {
        return Err(Error::option(
            OptionName::ControllerKind,
            "the design needs a force-driven scene (the drive force is the input)",
        ));
    };
    check_options(options)?;
    let (parameter, grid) = schedule_grid(scene, options)?;
    let chosen = options.models.build(&scene.params, options.model)?;
    let model = chosen.model.as_ref();
    let lpv = Lpv::new(model, ContactMode::Closed).map_err(Error::from)?;
    let n = model.dof();
    if !(1..n).contains(&options.design_modes) {
        return Err(Error::option(
            OptionName::DesignModes,
            format!(
                "must be 1 to {} (the model's elastic modes; got {})",
                n - 1,
                options.design_modes
            ),
        ));
    }
    let here: Vec<f64> = scene
        .params
        .positions
        .iter()
        .map(|p| p.value(scene.time.start))
        .collect();
    let points: Vec<Vec<f64>> = match &grid {
        Some(g) => g
            .values()
            .into_iter()
            .map(|v| {
                let mut p = here.clone();
                p[g.section - 2] = v;
                p
            })
            .collect(),
        None => vec![here],
    };
    let tip_row = lpv
        .outputs()
        .iter()
        .position(|s| Output::parse(&s.name) == Some(Output::TipRel))
        .expect("tip_rel");
    let mut schedule = Vec::new();
    for (j, positions) in points.iter().enumerate() {
        let point =
            design_point(model, &lpv, positions, tip_row, options).map_err(|e| Error::Trial {
                what: format!("grid point {} (positions {positions:?} m)", j + 1),
                error: Box::new(e),
            })?;
        schedule.push(point);
    }
    let states: Vec<String> = lpv.states().iter().map(|s| s.name.clone()).collect();
    let (feedforward, shaper_timing) = feedforward(scene, force, &schedule, parameter, options)?;
    let mut controller = Controller {
        format: "telescopic controller".into(),
        version: CONTROLLER_FILE_VERSION,
        generator: format!("telescopic {}", env!("CARGO_PKG_VERSION")),
        scene: scene.name.clone(),
        configuration: configuration_key(&scene.params),
        states,
        kind: options.kind,
        force_limit_n: options.force_limit,
        tip_scale_m: options.tip_scale,
        vehicle_scale_m: options.vehicle_scale,
        total_mass_kg: scene.params.total_mass(),
        schedule_parameter: parameter.map(|k| format!("a_{k}")),
        schedule,
        shaper: options.kind.has_shaper().then_some(options.shaper),
        shaper_timing,
        feedforward,
        sampled: None,
    };
    if !options.sensors.is_empty() {
        controller.sampled = Some(sampled_part(&controller, model, options)?);
    }
    Ok(controller)
}

/// The sampled output-feedback part of a design with sensors.
fn sampled_part(
    controller: &Controller,
    model: &dyn Model,
    options: &DesignOptions,
) -> Result<crate::control::file::schema::SampledDesign> {
    if !options.kind.has_lqr() || options.kind.has_observer() {
        return Err(Error::option(
            OptionName::Sensors,
            "an output-feedback controller is an LQR on a sampled Kalman filter: take \
             the controller lqr or lqr+shaper with sensors",
        ));
    }
    let noise: Vec<f64> = if options.sensor_noises.is_empty() {
        options
            .sensors
            .iter()
            .map(|s| crate::control::law::sampled::default_noise(s))
            .collect()
    } else if options.sensor_noises.len() == options.sensors.len() {
        options.sensor_noises.clone()
    } else {
        return Err(Error::option(
            OptionName::SensorNoises,
            format!(
                "gives {} noise level(s) for {} sensor(s)",
                options.sensor_noises.len(),
                options.sensors.len()
            ),
        ));
    };
    if let Some(bad) = noise.iter().find(|v| !(v.is_finite() && **v > 0.0)) {
        return Err(Error::option(
            OptionName::SensorNoises,
            format!("must be finite numbers > 0 (got {bad})"),
        ));
    }
    if options.estimator == Estimator::None {
        return Err(Error::option(
            OptionName::Estimator,
            "`none` is the strain-rate law's (no estimator); choose linear or extended",
        ));
    }
    if sampled_law(options) == SampledLaw::StrainRate {
        return strain_rate_part(controller, model, options, noise);
    }
    let mut sampled = crate::control::law::sampled::design_sampled(
        controller,
        model,
        &options.sensors,
        &noise,
        options.force_noise,
        options.rate_hz,
    )?;
    sampled.estimator = options.estimator;
    sampled.seed = options.noise_seed;
    if options.estimator == Estimator::Extended {
        sampled.process_noise_floor = Some(options.process_noise_floor);
        sampled.model = Some(crate::control::law::estimator_model::EstimatorModel::of(
            model,
        )?);
    }
    Ok(sampled)
}

/// The sampled law `options` ask for, `auto` resolved: `strain-rate` when the sensors include
/// `vehicle` and `kappa_1_0` and the estimator is the default, else `lqr`.
pub fn sampled_law(options: &DesignOptions) -> SampledLaw {
    if options.law != SampledLaw::Auto {
        return options.law;
    }
    let reads = |s: &str| options.sensors.iter().any(|o| o == s);
    let strain = crate::control::law::strain::STRAIN_RATE_SENSORS
        .iter()
        .all(|s| reads(s));
    if strain && options.estimator == Estimator::Linear {
        SampledLaw::StrainRate
    } else {
        SampledLaw::Lqr
    }
}

/// The sampled part of a strain-rate design: the law, no estimator.
fn strain_rate_part(
    controller: &Controller,
    model: &dyn Model,
    options: &DesignOptions,
    noise: Vec<f64>,
) -> Result<crate::control::file::schema::SampledDesign> {
    use crate::control::law::strain::STRAIN_RATE_SENSORS;
    if let Some(missing) = STRAIN_RATE_SENSORS
        .iter()
        .find(|s| !options.sensors.iter().any(|o| o == *s))
    {
        return Err(Error::option(
            OptionName::Sensors,
            format!(
                "the strain-rate law reads {}; `{missing}` is missing",
                STRAIN_RATE_SENSORS.join(" and ")
            ),
        ));
    }
    if options.estimator != Estimator::Linear {
        return Err(Error::option(
            OptionName::Estimator,
            "the strain-rate law has no estimator; leave the estimator at its default (linear)",
        ));
    }
    crate::control::law::sampled::check_rate(options.rate_hz)?;
    let law =
        crate::control::law::strain::design_strain_rate(controller, model, options.added_damping)?;
    Ok(crate::control::file::schema::SampledDesign {
        rate_hz: options.rate_hz,
        sensors: options.sensors.clone(),
        noise,
        force_noise: options.force_noise,
        seed: options.noise_seed,
        estimator: Estimator::None,
        process_noise_floor: None,
        points: Vec::new(),
        strain_rate: Some(law),
        model: None,
    })
}

/// The usable range of the force limit (N): the Riccati equation's weight `1 / F^2` must
/// stay within double precision's reach of the state weights.
pub const FORCE_LIMIT_RANGE: (f64, f64) = (1e-3, 1e4);

/// The usable range of the weight scales `tip_scale` and `vehicle_scale` (m).
pub const SCALE_RANGE: (f64, f64) = (1e-4, 1e3);

/// The usable range of the Kalman filter's measurement noise (m).
pub const SENSOR_NOISE_RANGE: (f64, f64) = (1e-12, 1e3);

/// The usable range of the extended filter's process-noise floor (variance per period).
pub const PROCESS_NOISE_FLOOR_RANGE: (f64, f64) = (1e-20, 1.0);

/// Refuses options of a sampled controller given without its sensors (they would be
/// ignored) and a sensor named twice.
fn check_sampled_options(options: &DesignOptions) -> Result<()> {
    if options.sensors.is_empty() {
        let needs = |option: OptionName, what: &str| {
            Err(Error::option_see(
                option,
                format!("{what} is of a sampled controller: name its sensors"),
                OptionName::Sensors,
            ))
        };
        if options.law != SampledLaw::Auto {
            return needs(OptionName::Law, &format!("the law `{}`", options.law));
        }
        if options.estimator != Estimator::Linear {
            return needs(
                OptionName::Estimator,
                &format!("the estimator `{}`", options.estimator),
            );
        }
        if !options.sensor_noises.is_empty() {
            return needs(OptionName::SensorNoises, "a measurement noise");
        }
    }
    for (k, sensor) in options.sensors.iter().enumerate() {
        if options.sensors[..k].contains(sensor) {
            return Err(Error::option(
                OptionName::Sensors,
                format!("`{sensor}` is named twice"),
            ));
        }
    }
    Ok(())
}

/// Checks the design settings' ranges.
fn check_options(options: &DesignOptions) -> Result<()> {
    check_sampled_options(options)?;
    for (name, v, (low, high), unit) in [
        (
            OptionName::ForceLimit,
            options.force_limit,
            FORCE_LIMIT_RANGE,
            "N",
        ),
        (OptionName::TipScale, options.tip_scale, SCALE_RANGE, "m"),
        (
            OptionName::VehicleScale,
            options.vehicle_scale,
            SCALE_RANGE,
            "m",
        ),
        (
            OptionName::SensorNoise,
            options.sensor_noise,
            SENSOR_NOISE_RANGE,
            "m",
        ),
        (
            OptionName::ForceNoise,
            options.force_noise,
            FORCE_LIMIT_RANGE,
            "N",
        ),
        (
            OptionName::ProcessNoiseFloor,
            options.process_noise_floor,
            PROCESS_NOISE_FLOOR_RANGE,
            "(state units squared per period)",
        ),
    ] {
        if !(low..=high).contains(&v) {
            return Err(Error::option(
                name,
                format!(
                    "must be {low:e} to {high:e} {unit}, the range a design resolves in double \
                     precision (got {v:e})"
                ),
            ));
        }
    }
    if !(1..=MAX_GRID_POINTS).contains(&options.grid_points) {
        return Err(Error::option(
            OptionName::GridPoints,
            format!(
                "must be 1 to {MAX_GRID_POINTS} (got {})",
                options.grid_points
            ),
        ));
    }
    Ok(())
}

/// The schedule's parameter (`k` of the moving `a_k`) and its grid over the range the scene
/// moves it through; `None` for fixed positions (one design point).
fn schedule_grid(scene: &Scene, options: &DesignOptions) -> Result<(Option<usize>, Option<Grid>)> {
    let moving: Vec<usize> = scene
        .params
        .positions
        .iter()
        .enumerate()
        .filter(|(_, p)| !p.is_constant())
        .map(|(i, _)| i)
        .collect();
    if moving.len() > 1 {
        return Err(Error::option(
            OptionName::ControllerKind,
            "gain scheduling over more than one moving telescopic position is not supported; \
         design at fixed positions (telescope.positions = [...])",
        ));
    }
    // the schedule: the moving position over its range in the span, else one point
    Ok(match moving.first() {
        Some(&i) => {
            let (lo, hi) = scene.params.positions[i].range(scene.time.start, scene.time.end);
            let count = options.grid_points.max(2);
            (
                Some(i + 2),
                Some(Grid {
                    section: i + 2,
                    from: lo,
                    to: hi,
                    count,
                }),
            )
        }
        None => (None, None),
    })
}

/// The LQR (and Kalman filter) designed at one operating point on the modal model.
fn design_point(
    model: &dyn Model,
    lpv: &Lpv,
    positions: &[f64],
    tip_row: usize,
    options: &DesignOptions,
) -> Result<SchedulePoint> {
    let (n, npos) = (model.dof(), positions.len());
    // the caller names the grid point
    let at = |e: &dyn fmt::Display| Error::Analysis(e.to_string());
    let full = lpv.at(positions, &vec![0.0; npos])?;
    let (f1, zeta1) = first_mode(&full.a)?;
    let (k_e, d) = lpv.second_order_at(positions, &vec![0.0; npos])?;
    let modal = modal_analysis_with(model, &k_e)?;
    let design = modal_design(model, &modal, &k_e, &d, options.design_modes);
    let c_tip = full.c.view((tip_row, 0), (1, n)).into_owned() * &design.phi;
    let m2 = design.a.nrows();
    let mut q = DMatrix::zeros(m2, m2);
    q.view_mut((0, 0), (m2 / 2, m2 / 2))
        .copy_from(&(c_tip.transpose() * &c_tip / (options.tip_scale * options.tip_scale)));
    let u_row = design.phi.row(0).into_owned();
    q.view_mut((0, 0), (m2 / 2, m2 / 2)).add_assign(
        &(u_row.transpose() * &u_row / (options.vehicle_scale * options.vehicle_scale)),
    );
    let r = DMatrix::from_element(1, 1, 1.0 / (options.force_limit * options.force_limit));
    let (k_modal, k_full, residual, abscissa) = if options.kind.has_lqr() {
        let solution = care(&design.a, &design.b, &q, &r).map_err(|e| {
            let ratio = options.force_limit / options.tip_scale.min(options.vehicle_scale);
            at(&format!(
                "{e}; the weights are out of balance when the force limit over the smaller \
                 scale is large (here {ratio:.1e} N/m; designs resolve to about 1e6 N/m): lower \
                 the force limit or raise the tip or vehicle scale"
            ))
        })?;
        let k_full = &solution.k * &design.w;
        (
            to_rows(&solution.k),
            to_rows(&k_full),
            solution.residual,
            solution.closed_loop_abscissa,
        )
    } else {
        (Vec::new(), Vec::new(), 0.0, 0.0)
    };
    let observer = if options.kind.has_observer() {
        Some(kalman(&full, &design, tip_row, options).map_err(|e| at(&e))?)
    } else {
        None
    };
    Ok(SchedulePoint {
        observer,
        positions: positions.to_vec(),
        a: to_rows(&design.a),
        b: to_rows(&design.b),
        q: to_rows(&q),
        r: to_rows(&r),
        k_modal,
        w: to_rows(&design.w),
        k: k_full,
        first_mode_hz: f1,
        first_mode_damping: zeta1,
        riccati_residual: residual,
        closed_loop_abscissa: abscissa,
    })
}

/// The shaped feed-forward force (the scene's force when the variant has no shaper), the
/// shaper tuned to the scheduled first mode, and the timing its trains got (`within` falls
/// back to `delayed` where [`shape_within`] says the trains cannot sit within the span).
fn feedforward(
    scene: &Scene,
    force: &Profile,
    schedule: &[SchedulePoint],
    parameter: Option<usize>,
    options: &DesignOptions,
) -> Result<(Profile, ShaperTiming)> {
    if !options.kind.has_shaper() {
        return Ok((force.clone(), options.shaper_timing));
    }
    let j =
        jumps(force, scene.time.start).map_err(|e| Error::option(OptionName::ControllerKind, e))?;
    let scheduled: Vec<f64> = parameter.map_or_else(
        || vec![0.0; schedule.len()],
        |k| schedule.iter().map(|p| p.positions[k - 2]).collect(),
    );
    let at = |t: f64| -> (f64, f64) {
        let (a, b, w) = schedule_weights(&scheduled, parameter, &scene.params.positions, t);
        let lerp = |x: f64, y: f64| x + w * (y - x);
        let (pa, pb) = (&schedule[a], &schedule[b]);
        (
            2.0 * std::f64::consts::PI * lerp(pa.first_mode_hz, pb.first_mode_hz),
            lerp(pa.first_mode_damping, pb.first_mode_damping),
        )
    };
    if options.shaper_timing == ShaperTiming::Within
        && let Ok(profile) = shape_within(&j, options.shaper, at)
    {
        return Ok((profile, ShaperTiming::Within));
    }
    Ok((shape(&j, options.shaper, at), ShaperTiming::Delayed))
}

impl Controller {
    /// The sampled part.
    ///
    /// # Errors
    /// [`Error::Option`] when the controller has none (a continuous full-state design).
    pub fn sampled_part(&self) -> Result<&crate::control::file::schema::SampledDesign> {
        self.sampled.as_ref().ok_or_else(|| {
            Error::option(
                OptionName::Controller,
                "has no sampled part (design it with sensors)",
            )
        })
    }

    /// The controller file (JSON).
    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(self).expect("plain data") + "\n"
    }

    /// Reads a controller file.
    ///
    /// # Errors
    /// [`Error::Input`] naming what is malformed.
    pub fn from_json(text: &str) -> Result<Self> {
        let malformed = |e: serde_json::Error| Error::input("controller file", e);
        // the format and version first: a file of another layout is refused as such, not
        // for the first field the layouts disagree on
        let head: serde_json::Value = serde_json::from_str(text).map_err(malformed)?;
        if head.get("format").and_then(|f| f.as_str()) != Some("telescopic controller") {
            return Err(Error::input(
                "controller file",
                "not a telescopic controller (`format` is not \"telescopic controller\")",
            ));
        }
        let version = head.get("version").and_then(|v| v.as_u64());
        if version != Some(u64::from(CONTROLLER_FILE_VERSION)) {
            let found = version.map_or("none".to_string(), |v| v.to_string());
            return Err(Error::input(
                "controller file",
                format!(
                    "layout version {found}, but this build reads version \
                     {CONTROLLER_FILE_VERSION}; design the controller again with this build"
                ),
            ));
        }
        serde_json::from_value(head).map_err(malformed)
    }

    /// What the controller is, in a few words: its kind, and for a sampled one its law,
    /// sensors and rate (e.g. `strain-rate + shaper from vehicle, kappa_1_0 at 1000 Hz`).
    pub fn describe(&self) -> String {
        let Some(sampled) = &self.sampled else {
            return self.kind.to_string();
        };
        let sensors = sampled.sensors.join(", ");
        let rate = sampled.rate_hz;
        if sampled.strain_rate.is_some() {
            let shaped = if self.kind.has_shaper() {
                " + shaper"
            } else {
                ""
            };
            format!("strain-rate{shaped} from {sensors} at {rate} Hz")
        } else {
            let estimator = &sampled.estimator;
            format!(
                "{} on a {estimator} filter from {sensors} at {rate} Hz",
                self.kind
            )
        }
    }

    /// Each design point's value of the scheduled position (m), zeros for a schedule at fixed
    /// positions.
    pub fn schedule_positions(&self) -> Vec<f64> {
        let k = self.scheduled_section();
        self.schedule
            .iter()
            .map(|p| k.map_or(0.0, |k| p.positions[k - 2]))
            .collect()
    }

    /// Section `k` of the scheduled position `a_k`, if the schedule runs over one.
    pub fn scheduled_section(&self) -> Option<usize> {
        self.schedule_parameter
            .as_ref()
            .and_then(|name| name.strip_prefix("a_")?.parse().ok())
    }

    /// The feedforward profile as a piecewise-constant one, if it is (for the summary).
    pub fn feedforward_steps(&self) -> Option<(&[f64], &[f64])> {
        match &self.feedforward {
            Profile::Shaped(ShapedProfile::PiecewiseConstant { times, values }) => {
                Some((times, values))
            }
            _ => None,
        }
    }
}
