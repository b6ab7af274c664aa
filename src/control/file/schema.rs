//! The controller file's layout: what `design` writes and a controlled run reads, every
//! field serialized under its JSON name. [`crate::control::file::check`] checks a file against its rules and
//! its scene; [`CONTROLLER_FILE_VERSION`] changes whenever this layout does.

use crate::control::design::shaper::{ShaperKind, ShaperTiming};
use serde::{Deserialize, Serialize};
use telescopic_runtime::Profile;

/// The layout version this build writes and reads; a file of another version is refused.
pub const CONTROLLER_FILE_VERSION: u32 = 2;

/// Which controller.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum ControllerKind {
    /// The gain-scheduled LQR state feedback around the drive profile.
    #[serde(rename = "lqr")]
    Lqr,
    /// The drive profile through an input shaper, no feedback.
    #[serde(rename = "shaper")]
    Shaper,
    /// The LQR around the shaped profile.
    #[default]
    #[serde(rename = "lqr+shaper")]
    LqrShaper,
    /// The LQR around the shaped profile on the state a Kalman filter estimates from the
    /// measured `vehicle` and `tip_rel` alone.
    #[serde(rename = "lqr+shaper+kalman")]
    LqrShaperKalman,
}

impl ControllerKind {
    /// Whether the kind has the LQR feedback.
    pub fn has_lqr(self) -> bool {
        !matches!(self, ControllerKind::Shaper)
    }

    /// Whether the kind shapes the drive profile.
    pub fn has_shaper(self) -> bool {
        !matches!(self, ControllerKind::Lqr)
    }

    /// Whether the feedback acts on a Kalman filter's estimate.
    pub fn has_observer(self) -> bool {
        matches!(self, ControllerKind::LqrShaperKalman)
    }
}

crate::named::named_enum!(ControllerKind, "a controller", {
    Lqr => "lqr",
    Shaper => "shaper",
    LqrShaper => "lqr+shaper",
    LqrShaperKalman => "lqr+shaper+kalman",
});

/// The estimator of a sampled controller.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Estimator {
    /// The discrete Kalman filter of the closed-contact linear model (what the emitted C
    /// runs for the LQR law).
    #[default]
    Linear,
    /// The extended Kalman filter on the nonlinear model with the contact law
    /// ([`crate::control::law::ekf::ExtendedKalman`]).
    Extended,
    /// No estimator: the strain-rate law reads its sensors directly.
    None,
}

crate::named::named_enum!(Estimator, "an estimator", {
    Linear => "linear",
    Extended => "extended",
    None => "none",
});

/// The law of a sampled controller, as asked for in a design.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum SampledLaw {
    /// `strain-rate` when the sensors include `vehicle` and `kappa_1_0` and the estimator
    /// is linear, else `lqr`.
    #[default]
    Auto,
    /// The LQR on the estimator's state.
    Lqr,
    /// The strain gauge's rate fed to the drive and a PD on the vehicle, no estimator.
    StrainRate,
}

crate::named::named_enum!(SampledLaw, "a sampled law", {
    Auto => "auto",
    Lqr => "lqr",
    StrainRate => "strain-rate",
});

/// One design point of the schedule. The design model is the modal truncation of the
/// closed-contact linear model: modal coordinates `eta = W x` (the rigid translation and the
/// first elastic modes, mass-normalized, then their rates), `eta' = A eta + B u`; the LQR
/// gain on it is `K_modal = R^-1 B' X` with `X` the stabilizing solution of the Riccati
/// equation of `(A, B, Q, R)`, and on the full state `K = K_modal W`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SchedulePoint {
    /// Telescopic positions `a_2..a_n` (m).
    pub positions: Vec<f64>,
    /// State matrix of the design model, rows.
    #[serde(rename = "A")]
    pub a: Vec<Vec<f64>>,
    /// Input matrix of the design model, rows.
    #[serde(rename = "B")]
    pub b: Vec<Vec<f64>>,
    /// State weight on the design model's states, rows.
    #[serde(rename = "Q")]
    pub q: Vec<Vec<f64>>,
    /// Input weight, rows.
    #[serde(rename = "R")]
    pub r: Vec<Vec<f64>>,
    /// The gain on the design model's states, rows; empty for a shaper alone.
    #[serde(rename = "K_modal")]
    pub k_modal: Vec<Vec<f64>>,
    /// The projection `eta = W x` from the full state to the design model's, rows.
    #[serde(rename = "W")]
    pub w: Vec<Vec<f64>>,
    /// The gain on the full state (`u = -K x`, `K = K_modal W`), rows; empty for a shaper
    /// alone.
    #[serde(rename = "K")]
    pub k: Vec<Vec<f64>>,
    /// The Kalman filter, for the observer variant.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub observer: Option<ObserverPoint>,
    /// First elastic mode: frequency (Hz) and damping ratio, for the shaper.
    pub first_mode_hz: f64,
    /// Its damping ratio.
    pub first_mode_damping: f64,
    /// Relative residual of the Riccati solution (0 without LQR).
    pub riccati_residual: f64,
    /// Largest real part of the closed-loop eigenvalues (1/s; 0 without LQR).
    pub closed_loop_abscissa: f64,
}

/// The Kalman filter of one design point: designed on the modal model from the measured
/// `vehicle` and `tip_rel` (`y = C_meas x`), run on the full linear model
/// `x_hat' = A x_hat + B F + L (y - C_meas x_hat)` with `L = [Phi 0; 0 Phi] L_modal`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ObserverPoint {
    /// Measurement rows on the design model's states.
    #[serde(rename = "C_modal")]
    pub c_modal: Vec<Vec<f64>>,
    /// Process noise on the design model's states (`sigma_F^2 B B'`).
    #[serde(rename = "Q_noise")]
    pub q_noise: Vec<Vec<f64>>,
    /// Measurement noise.
    #[serde(rename = "R_noise")]
    pub r_noise: Vec<Vec<f64>>,
    /// The Kalman gain on the design model (`L_modal = P C' R^-1`), rows.
    #[serde(rename = "L_modal")]
    pub l_modal: Vec<Vec<f64>>,
    /// The gain on the full state, rows (`2 dof x 2`).
    #[serde(rename = "L")]
    pub l: Vec<Vec<f64>>,
    /// The full closed-contact linear model the filter runs on, rows.
    #[serde(rename = "A_full")]
    pub a_full: Vec<Vec<f64>>,
    /// Its input matrix, rows.
    #[serde(rename = "B_full")]
    pub b_full: Vec<Vec<f64>>,
    /// Measurement rows on the full state (`vehicle`, `tip_rel`).
    #[serde(rename = "C_meas")]
    pub c_meas: Vec<Vec<f64>>,
}

/// A designed controller: what `design` writes and `simulate --controller` reads.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Controller {
    /// `telescopic controller`.
    pub format: String,
    /// Layout version of the file.
    pub version: u32,
    /// The tool that wrote it.
    pub generator: String,
    /// The scene designed for.
    pub scene: String,
    /// Its configuration key (a scene of another configuration is refused).
    pub configuration: String,
    /// The state names, in the order of the gains.
    pub states: Vec<String>,
    /// The controller.
    pub kind: ControllerKind,
    /// Force limit (N).
    pub force_limit_n: f64,
    /// `tip_rel` scale of the weights (m).
    pub tip_scale_m: f64,
    /// Vehicle scale of the weights (m).
    pub vehicle_scale_m: f64,
    /// Total mass of the telescope, vehicle and load (kg): the rigid reference's.
    pub total_mass_kg: f64,
    /// The scheduled position (`a_k`), if the positions move.
    pub schedule_parameter: Option<String>,
    /// The design points, ordered by the scheduled position.
    pub schedule: Vec<SchedulePoint>,
    /// The shaper, if any.
    pub shaper: Option<ShaperKind>,
    /// Where its trains sit.
    pub shaper_timing: ShaperTiming,
    /// The feedforward force: the drive profile, shaped or not.
    pub feedforward: Profile,
    /// The sampled output-feedback part: sensors, rate and discrete Kalman filters (absent
    /// for a continuous full-state controller).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sampled: Option<SampledDesign>,
}

/// The sampled output-feedback part of a controller file: what a machine needs to run it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SampledDesign {
    /// Controller rate (Hz).
    pub rate_hz: f64,
    /// The measured outputs, in the order of `C`'s rows.
    pub sensors: Vec<String>,
    /// Their measurement noise (standard deviation, in each output's unit).
    pub noise: Vec<f64>,
    /// The force disturbance of the filter's model (N, standard deviation).
    pub force_noise: f64,
    /// Seed of the simulated measurement noise.
    pub seed: u64,
    /// The estimator.
    pub estimator: Estimator,
    /// The extended filter's process-noise floor: a variance added to every state per
    /// period (state units squared); the extended estimator's only.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub process_noise_floor: Option<f64>,
    /// One discrete filter per design point, in the schedule's order (none for the
    /// strain-rate law).
    pub points: Vec<DiscretePoint>,
    /// The strain-rate law, replacing the LQR on a filter's estimate (estimator `none`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub strain_rate: Option<StrainRateLaw>,
    /// The extended filter's model of the plant: the design scene's.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub model: Option<crate::control::law::estimator_model::EstimatorModel>,
}

/// The discrete model and Kalman gain of one design point.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DiscretePoint {
    /// `Ad = exp(A T)`, rows.
    #[serde(rename = "Ad")]
    pub ad: Vec<Vec<f64>>,
    /// `Bd = int_0^T exp(A s) ds B`, rows.
    #[serde(rename = "Bd")]
    pub bd: Vec<Vec<f64>>,
    /// Measurement rows on the full state.
    #[serde(rename = "C")]
    pub c: Vec<Vec<f64>>,
    /// Kalman gain (predictor form), rows (`states x sensors`).
    #[serde(rename = "L")]
    pub l: Vec<Vec<f64>>,
}

/// The strain-rate law of a controller file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StrainRateLaw {
    /// Damping ratio added to the first mode (the design's knob).
    pub added_damping: f64,
    /// Vehicle loop stiffness `k_p` (N/m).
    pub vehicle_stiffness_n_per_m: f64,
    /// Vehicle loop damping `k_d` (N s/m).
    pub vehicle_damping_n_s_per_m: f64,
    /// Time constant of the rate filters (s).
    pub filter_time_constant_s: f64,
    /// One entry per design point, in the schedule's order.
    pub points: Vec<StrainRatePoint>,
}

impl StrainRateLaw {
    /// The rate filters' weight per tick at `rate_hz`: `T / (tau + T)` (first-order low-pass
    /// by backward Euler), the same number in the library and the emitted C.
    pub fn filter_weight(&self, rate_hz: f64) -> f64 {
        let period = 1.0 / rate_hz;
        period / (self.filter_time_constant_s + period)
    }
}

/// The strain-rate law at one design point.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StrainRatePoint {
    /// `tip_rel` per `kappa_1_0` in the first elastic mode (m^2).
    pub tip_per_curvature_m2: f64,
    /// The first elastic mode's frequency (Hz).
    pub first_mode_hz: f64,
    /// The gain `g` on the curvature's rate (N per 1/(m s)).
    pub gain: f64,
}
