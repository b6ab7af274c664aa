//! The strain-rate law: output feedback from the drive's encoder and a strain gauge at the
//! foot of section 1, with no model-based estimator.
//!
//! At tick `k` the law reads `u_k` (`vehicle`, m) and `kappa_k` (`kappa_1_0`, 1/m), forms their
//! rates by first-order filtered differences (time constant `tau`), and commands
//!
//! ```text
//! F_{k+1} = sat( F_ff(t_{k+1}) - k_p (u_k - u_ref) - k_d (v_hat - v_ref) + g(a) kappa_dot_hat, +-F_max )
//! g(a)    = m_total * 2 zeta_d * omega_1(a) * r(a)
//! ```
//!
//! `r(a)` is `tip_rel` per `kappa_1_0` in the first elastic mode at the scheduled position,
//! `omega_1(a)` that mode's angular frequency: `r kappa_dot` is the tip's rate in that mode,
//! and a vehicle accelerated by `2 zeta_d omega_1` times it adds the damping ratio `zeta_d` to
//! a tip mass on a spring (the vehicle's acceleration is the tip's base excitation). The PD on
//! the vehicle (natural frequency a third of the lowest first mode's, damping ratio one half)
//! keeps the travel of the rigid reference. No part of it models the contacts: while the
//! upper section moves freely in its clearance the law waits, and when a contact closes the
//! impact bends section 1, which the gauge sees and the law damps.

use crate::OptionName;
use crate::control::file::schema::{Controller, StrainRateLaw, StrainRatePoint};
use crate::control::law::sampled::SampledController;
use crate::{Error, Result};
use telescopic_runtime::{ContactMode, Lpv, Model, Sensor, modal_analysis_with};

/// Default damping ratio the strain-rate law adds to the first mode.
pub const DEFAULT_ADDED_DAMPING: f64 = 0.15;

/// Damping ratio of the vehicle's position loop.
pub const VEHICLE_LOOP_DAMPING: f64 = 0.5;

/// The vehicle loop's natural frequency as a fraction of the lowest first mode's.
pub const VEHICLE_LOOP_FRACTION: f64 = 1.0 / 3.0;

/// The sensors the strain-rate law reads.
pub const STRAIN_RATE_SENSORS: [&str; 2] = ["vehicle", Sensor::FootCurvature.name()];

/// `tip_rel` per `kappa_1_0` (m^2) in the first elastic mode of the closed-contact linear model
/// `lpv` of `model` at `positions`, and that mode's frequency (Hz).
///
/// # Errors
/// [`Error::Linear`] when the linear model cannot be formed, [`Error::Modes`] when its modes
/// cannot, [`Error::Model`] when no mode a strain gauge at the foot sees.
pub fn tip_per_curvature(model: &dyn Model, lpv: &Lpv, positions: &[f64]) -> Result<(f64, f64)> {
    let rates = vec![0.0; positions.len()];
    let full = lpv.at(positions, &rates)?;
    let (k_e, _) = lpv.second_order_at(positions, &rates)?;
    let modal = modal_analysis_with(model, &k_e)?;
    let (Some(shape), Some(&f1)) = (modal.shapes.first(), modal.frequencies_hz.first()) else {
        return Err(Error::Model("the linear model has no elastic mode".into()));
    };
    let row = |name: &str| {
        lpv.outputs()
            .iter()
            .position(|o| o.name == name)
            .ok_or_else(|| Error::Model(format!("the linear model has no output `{name}`")))
    };
    let along = |r: usize| {
        (0..model.dof())
            .map(|j| full.c[(r, j)] * shape[j])
            .sum::<f64>()
    };
    let (tip, kappa) = (along(row("tip_rel")?), along(row("kappa_1_0")?));
    if kappa.abs() <= 1e-12 * tip.abs() || !(tip / kappa).is_finite() {
        return Err(Error::Model(
            "the first mode does not bend section 1 at its foot: a strain gauge there cannot \
             see it"
                .into(),
        ));
    }
    Ok((tip / kappa, f1))
}

/// Designs the strain-rate law over `controller`'s schedule, adding the damping ratio
/// `added_damping` to the first mode.
///
/// # Errors
/// [`Error::Option`] for a damping ratio outside (0, 2]; the errors of [`tip_per_curvature`].
pub fn design_strain_rate(
    controller: &Controller,
    model: &dyn Model,
    added_damping: f64,
) -> Result<StrainRateLaw> {
    if !(added_damping > 0.0 && added_damping <= 2.0) {
        return Err(Error::option(
            OptionName::AddedDamping,
            format!("must be a damping ratio in (0, 2] (got {added_damping})"),
        ));
    }
    let mass = controller.total_mass_kg;
    let tau = std::f64::consts::TAU;
    let lpv = Lpv::new(model, ContactMode::Closed).map_err(Error::from)?;
    let mut points = Vec::with_capacity(controller.schedule.len());
    for p in &controller.schedule {
        let (ratio, f1) = tip_per_curvature(model, &lpv, &p.positions)?;
        points.push(StrainRatePoint {
            tip_per_curvature_m2: ratio,
            first_mode_hz: f1,
            gain: mass * 2.0 * added_damping * tau * f1 * ratio,
        });
    }
    let lowest = points
        .iter()
        .map(|p| p.first_mode_hz)
        .fold(f64::INFINITY, f64::min);
    let highest = points.iter().map(|p| p.first_mode_hz).fold(0.0, f64::max);
    let omega_v = VEHICLE_LOOP_FRACTION * tau * lowest;
    Ok(StrainRateLaw {
        added_damping,
        vehicle_stiffness_n_per_m: mass * omega_v * omega_v,
        vehicle_damping_n_s_per_m: 2.0 * VEHICLE_LOOP_DAMPING * mass * omega_v,
        // the rate filters pass the first mode (phase lag under 45 degrees at the highest)
        // and cut the contact modes' aliases
        filter_time_constant_s: 1.0 / (tau * highest),
        points,
    })
}

/// The strain-rate law of a controller file, ready to step: allocation-free per tick.
pub struct StrainRateController {
    law: StrainRateLaw,
    positions: Vec<f64>,
    reference: crate::control::law::schedule::Reference,
    feedforward: telescopic_runtime::Profile,
    period: f64,
    /// The rate filters' weight per tick.
    alpha: f64,
    limit: f64,
    /// Where `vehicle` and `kappa_1_0` are among the measurements.
    columns: (usize, usize),
    /// The previous tick's measurements, once there is one.
    previous: Option<(f64, f64)>,
    /// The filtered rates of the vehicle (m/s) and the curvature (1/(m s)).
    rates: (f64, f64),
}

impl StrainRateController {
    /// The law of `file` (which must have a strain-rate sampled part) over `[start, end]` s.
    ///
    /// # Errors
    /// [`Error::Option`] naming what the file lacks.
    pub fn new(file: &Controller, start: f64, end: f64) -> Result<Self> {
        let lacks = |what: &str| Error::input("controller `sampled.strain_rate`", what);
        let sampled = file.sampled.as_ref().ok_or_else(|| lacks("is absent"))?;
        let law = sampled
            .strain_rate
            .clone()
            .ok_or_else(|| lacks("is absent"))?;
        if law.points.len() != file.schedule.len() {
            return Err(lacks("needs one point per design point"));
        }
        let column = |name: &str| {
            sampled
                .sensors
                .iter()
                .position(|s| s == name)
                .ok_or_else(|| {
                    Error::input(
                        "controller `sampled.sensors`",
                        format!("the strain-rate law reads `{name}`, which is not among them"),
                    )
                })
        };
        Ok(StrainRateController {
            positions: file.schedule_positions(),
            reference: crate::control::law::schedule::reference(file, start, end),
            feedforward: file.feedforward.clone(),
            period: 1.0 / sampled.rate_hz,
            alpha: law.filter_weight(sampled.rate_hz),
            limit: file.force_limit_n,
            columns: (column("vehicle")?, column("kappa_1_0")?),
            previous: None,
            rates: (0.0, 0.0),
            law,
        })
    }
}

impl SampledController for StrainRateController {
    fn step(&mut self, t: f64, y: &[f64], a: f64) -> f64 {
        let (u, kappa) = (y[self.columns.0], y[self.columns.1]);
        let alpha = self.alpha;
        if let Some((u_prev, kappa_prev)) = self.previous {
            let v = (u - u_prev) / self.period;
            let kappa_dot = (kappa - kappa_prev) / self.period;
            self.rates.0 += alpha * (v - self.rates.0);
            self.rates.1 += alpha * (kappa_dot - self.rates.1);
        }
        self.previous = Some((u, kappa));
        let next = t + self.period;
        let (u_ref, v_ref) = self.reference.at(next);
        let (i, j, w) = crate::control::law::schedule::bracket(&self.positions, a);
        let (gi, gj) = (self.law.points[i].gain, self.law.points[j].gain);
        let gain = gi + w * (gj - gi);
        let vehicle = self.law.vehicle_stiffness_n_per_m * (u - u_ref)
            + self.law.vehicle_damping_n_s_per_m * (self.rates.0 - v_ref);
        let f = self.feedforward.value(next) - vehicle + gain * self.rates.1;
        f.clamp(-self.limit, self.limit)
    }
}
