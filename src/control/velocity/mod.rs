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

mod design;
mod file;
mod law;
mod run;
mod servo;

pub use design::{VelocityDesign, WASHOUT_PERIODS, design_velocity_feedback};
pub use file::{
    VELOCITY_FEEDBACK_FORMAT, VELOCITY_FEEDBACK_VERSION, VelocityFeedback, VelocityPoint,
};
pub use law::VelocityController;
pub use run::simulate_velocity;
pub use servo::ServoCorrected;
