//! Time integration of a [`Model`] with the clearance contact law: methods, contact-switch
//! events, output sampling, statistics and failure reports.
//!
//! The driver ([`simulate`]) keeps the branch of the contact law fixed per contact between
//! switches, so the right-hand side is smooth within every step. After each accepted step
//! it evaluates a switch function per contact (positive while the contact stays in its
//! branch, see [`events`]); when one turns negative, the step is redone with shorter lengths
//! (Newton's method on the step length from the crossing of the step's cubic Hermite
//! interpolant, kept inside the bracket; each trial a full step of the method, so the state
//! at the switch has the method's own order), the contact changes branch and the method
//! restarts. Discontinuities of the drive and position profiles are step ends too.
//!
//! Samples at the scene's output times come from the cubic Hermite interpolant of each
//! accepted step (`y` and `ydot` at both ends).

pub mod bdf;
mod combine;
pub mod diagnosis;
pub mod esdirk;
pub mod events;
pub mod exact;
pub mod explicit;
pub mod extension;
mod fast_modes;
pub mod generalized_alpha;
pub mod imex;
mod integrator;
pub mod newton;
pub mod settled;
pub mod stability;
pub mod stiff_modes;
#[cfg(test)]
mod tableau;
pub mod verlet;

use crate::model::Model;
use crate::scene::TimeSpan;
use std::fmt;
use std::time::{Duration, Instant};

pub use driver::Stop;
pub use events::ContactTracker;
pub use integrator::Integrator;

/// An integration method, selectable by name (`--method`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Method {
    /// Dormand-Prince 5(4), adaptive, explicit.
    Dopri5,
    /// Dormand-Prince 8(5,3) (DOP853), adaptive, explicit.
    Dop853,
    /// ESDIRK4(3)6L\[2\]SA (Kennedy-Carpenter), adaptive, L-stable, Newton on the analytic
    /// Jacobian.
    Esdirk,
    /// Variable-order variable-step BDF (orders 1 to `max_order`), Newton on the analytic
    /// Jacobian.
    Bdf {
        /// Highest order used (1..=5; 1 and 2 are A-stable).
        max_order: usize,
        /// Adaptive step size from the local error estimate (else a fixed `dt`).
        adaptive: bool,
    },
    /// ARK4(3)6L\[2\]SA (Kennedy-Carpenter), adaptive, additive: the contact springs and
    /// dampers implicit (a low-rank solve per stage), everything else explicit.
    Imex,
    /// dop853 across contact switches, [`Method::Imex`] over closed contacts once their
    /// contact modes have rung down ([`settled`]).
    Dop853Imex,
    /// Classical Runge-Kutta 4, fixed step, explicit.
    Rk4,
    /// Exact stepping (matrix exponential per contact branch) of a scene that is linear and
    /// time-invariant between contact switches: fixed positions, piecewise-constant force.
    Exact,
    /// Stormer-Verlet (velocity form), fixed step, explicit, second order.
    Verlet,
    /// Generalized-alpha (Chung-Hulbert) with spectral radius at infinity `rho_inf` in
    /// `[0, 1]`, Newton on the analytic Jacobian; fixed step or adaptive.
    GeneralizedAlpha {
        /// Spectral radius at infinite frequency (1: no numerical damping, 0: the most).
        rho_inf: f64,
        /// Adaptive step size from the local error estimate.
        adaptive: bool,
    },
}

/// How a method sets its step size.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StepControl {
    /// Error-controlled step size (needs `rtol`, `atol`).
    Adaptive,
    /// A fixed step `dt`.
    Fixed,
    /// Steps set by the model's own frequencies, exact up to rounding (no tolerance).
    Exact,
}

/// Names accepted by [`Method::from_name`], with a one-line description each.
pub const METHOD_NAMES: [(&str, &str); 14] = [
    (
        "dopri5",
        "Dormand-Prince 5(4), adaptive explicit Runge-Kutta",
    ),
    (
        "dop853",
        "Dormand-Prince 8(5,3), adaptive explicit Runge-Kutta of order 8",
    ),
    (
        "esdirk",
        "ESDIRK4(3)6L[2]SA, adaptive L-stable implicit Runge-Kutta, analytic Jacobian",
    ),
    (
        "imex",
        "ARK4(3)6L[2]SA, adaptive additive Runge-Kutta: contacts implicit, the rest explicit",
    ),
    (
        "dop853-imex",
        "dop853 across contact switches, imex over closed contacts once they have rung down",
    ),
    (
        "bdf",
        "BDF of variable order 1-5 and variable step, analytic Jacobian",
    ),
    (
        "bdf<K>",
        "BDF with orders up to K (1-5), e.g. bdf2 (A-stable)",
    ),
    ("bdf[K]-fixed", "BDF with a fixed step, e.g. bdf2-fixed"),
    ("rk4", "classical Runge-Kutta 4, fixed step"),
    (
        "exact",
        "matrix exponential per contact branch: exact for fixed positions and a \
         piecewise-constant force",
    ),
    ("verlet", "Stormer-Verlet (velocity form), fixed step"),
    (
        "galpha",
        "generalized-alpha (Chung-Hulbert), adaptive, Newton on the analytic Jacobian",
    ),
    ("galpha-fixed", "generalized-alpha, fixed step"),
    (
        "galpha-rho<R>",
        "generalized-alpha with spectral radius R, e.g. galpha-rho0.5 (default 0.8)",
    ),
];

/// Default spectral radius at infinity of generalized-alpha.
pub const DEFAULT_RHO_INF: f64 = 0.8;

impl Method {
    /// Parses a method name (see [`METHOD_NAMES`]); `galpha-rho0.5` and
    /// `galpha-fixed-rho0.5` set the spectral radius.
    ///
    /// # Errors
    /// A message listing the known names.
    pub fn from_name(name: &str) -> Result<Self, String> {
        let galpha = |rest: &str, adaptive: bool| -> Result<Self, String> {
            let rho_inf = match rest.strip_prefix("-rho") {
                None if rest.is_empty() => DEFAULT_RHO_INF,
                Some(r) => r.parse::<f64>().map_err(|_| {
                    format!("method `{name}`: `{r}` is not a number for the spectral radius")
                })?,
                None => return Err(unknown(name)),
            };
            if !(0.0..=1.0).contains(&rho_inf) {
                return Err(format!(
                    "method `{name}`: the spectral radius must be in [0, 1] (got {rho_inf})"
                ));
            }
            Ok(Method::GeneralizedAlpha { rho_inf, adaptive })
        };
        fn unknown(name: &str) -> String {
            let names: Vec<&str> = METHOD_NAMES.iter().map(|(n, _)| *n).collect();
            format!("unknown method `{name}`; known: {}", names.join(", "))
        }
        match name {
            "dopri5" => Ok(Method::Dopri5),
            "dop853" => Ok(Method::Dop853),
            "esdirk" => Ok(Method::Esdirk),
            "imex" => Ok(Method::Imex),
            "dop853-imex" => Ok(Method::Dop853Imex),
            "rk4" => Ok(Method::Rk4),
            "exact" => Ok(Method::Exact),
            "verlet" => Ok(Method::Verlet),
            _ => {
                if let Some(rest) = name.strip_prefix("galpha-fixed") {
                    galpha(rest, false)
                } else if let Some(rest) = name.strip_prefix("galpha") {
                    galpha(rest, true)
                } else if let Some(rest) = name.strip_prefix("bdf") {
                    let (k, adaptive) = match rest.strip_suffix("-fixed") {
                        Some(k) => (k, false),
                        None => (rest, true),
                    };
                    let max_order = if k.is_empty() {
                        Ok(bdf::MAX_ORDER)
                    } else {
                        k.parse::<usize>()
                    };
                    match max_order {
                        Ok(max_order @ 1..=bdf::MAX_ORDER) => Ok(Method::Bdf {
                            max_order,
                            adaptive,
                        }),
                        _ => Err(format!(
                            "method `{name}`: the highest BDF order must be 1 to {} \
                             (e.g. bdf2)",
                            bdf::MAX_ORDER
                        )),
                    }
                } else {
                    Err(unknown(name))
                }
            }
        }
    }

    /// The method's name, as [`Method::from_name`] reads it.
    pub fn name(&self) -> String {
        match self {
            Method::Dopri5 => "dopri5".into(),
            Method::Dop853 => "dop853".into(),
            Method::Esdirk => "esdirk".into(),
            Method::Imex => "imex".into(),
            Method::Dop853Imex => "dop853-imex".into(),
            Method::Bdf {
                max_order,
                adaptive,
            } => {
                let order = if *max_order == bdf::MAX_ORDER {
                    String::new()
                } else {
                    max_order.to_string()
                };
                let fixed = if *adaptive { "" } else { "-fixed" };
                format!("bdf{order}{fixed}")
            }
            Method::Rk4 => "rk4".into(),
            Method::Exact => "exact".into(),
            Method::Verlet => "verlet".into(),
            Method::GeneralizedAlpha { rho_inf, adaptive } => {
                let kind = if *adaptive { "galpha" } else { "galpha-fixed" };
                if *rho_inf == DEFAULT_RHO_INF {
                    kind.to_string()
                } else {
                    format!("{kind}-rho{rho_inf}")
                }
            }
        }
    }

    /// The explicit method whose steps are capped while a contact is closed
    /// ([`stability::closed_contact_step_cap`]): dop853 for itself and for dop853-imex's
    /// dop853 part, `None` for every other method.
    pub fn capped_part(&self) -> Option<Method> {
        match self {
            Method::Dop853 | Method::Dop853Imex => Some(Method::Dop853),
            _ => None,
        }
    }

    /// Adaptive or fixed step.
    pub fn step_control(&self) -> StepControl {
        match self {
            Method::Dopri5
            | Method::Dop853
            | Method::Esdirk
            | Method::Imex
            | Method::Dop853Imex
            | Method::Bdf { adaptive: true, .. }
            | Method::GeneralizedAlpha { adaptive: true, .. } => StepControl::Adaptive,
            Method::Exact => StepControl::Exact,
            _ => StepControl::Fixed,
        }
    }

    /// Explicit stability limit `h omega_max` on the imaginary axis (undamped oscillation),
    /// for the explicit fixed-step methods.
    pub fn stability_limit(&self) -> Option<f64> {
        match self {
            Method::Rk4 => Some(stability::RK4_IMAGINARY_AXIS),
            Method::Verlet => Some(stability::VERLET_LIMIT),
            _ => None,
        }
    }
}

impl fmt::Display for Method {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.name())
    }
}

/// Tolerances and step settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Settings {
    /// Relative tolerance (adaptive methods).
    pub rtol: f64,
    /// Absolute tolerance (adaptive methods; m, m/s: the units of the state).
    pub atol: f64,
    /// Step (s) of fixed-step methods; first trial step of adaptive ones if set.
    pub dt: Option<f64>,
    /// Most steps (accepted and rejected) before giving up.
    pub max_steps: u64,
    /// Most work ([`RunStats::operations`]) before the run stops with
    /// [`SimError::OverBudget`]: a caller that only wants runs cheaper than one it has
    /// stops a costlier one early (default infinite; checked by every method but `exact`,
    /// whose tail after a hand-over is not counted against it).
    pub max_operations: f64,
    /// From this time (s) on, step exactly ([`Method::Exact`]) whatever the method: for a
    /// scene whose positions come to rest (see [`exact::exact_tail_start`]). Must be a
    /// sample time inside the span.
    pub exact_from: Option<f64>,
    /// Cap dop853's step below its stable step while a contact is closed
    /// ([`stability::closed_contact_step_cap`]; other methods are never capped).
    pub step_cap: bool,
    /// Let method `exact` step over a closed contact's fast modes where their bound
    /// certifies it (`false`: its short steps throughout, for comparison).
    pub long_steps: bool,
    /// Longest step (s) of an adaptive method, whose steps then cross output samples and
    /// give them by the step's cubic Hermite interpolant (imex's stiff modes are those that
    /// turn fast over this step); `None`: steps end on every sample. Fixed-step methods
    /// ignore it.
    pub longest_step: Option<f64>,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            rtol: 1e-6,
            atol: 1e-9,
            dt: None,
            max_steps: 50_000_000,
            max_operations: f64::INFINITY,
            exact_from: None,
            step_cap: true,
            long_steps: true,
            longest_step: None,
        }
    }
}

/// What a run did.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct RunStats {
    /// Accepted steps (partial steps to an event count).
    pub steps: u64,
    /// Rejected steps (error too large, or Newton not converged).
    pub rejected: u64,
    /// Right-hand side evaluations.
    pub rhs_evals: u64,
    /// Jacobian evaluations.
    pub jacobian_evals: u64,
    /// LU factorizations.
    pub factorizations: u64,
    /// Contact branch switches (band-edge crossings).
    pub switches: u64,
    /// Matrix exponentials (method `exact`: one per contact-branch combination met, two
    /// for a branch with a long step over its contact modes; drive steps that leave `A`
    /// unchanged share one, plus one integral of it for their inputs).
    pub exponentials: u64,
    /// Steps over closed contacts' fast modes (counted in `steps` too): method `exact`'s long
    /// steps, `dop853-imex`'s imex steps.
    pub long_steps: u64,
    /// Matrix-vector products of method `exact`'s partial steps off its regular grid (the
    /// terms of their Taylor sums).
    pub taylor_terms: u64,
    /// The step cap (s) applied while a contact was closed, if any.
    pub step_cap: Option<f64>,
    /// Wall-clock time of the integration.
    pub wall: Duration,
    /// Entries of the integrated state (twice the model's coordinates).
    pub state_len: usize,
}

impl RunStats {
    /// The run's work in floating-point operations, roughly, for its state of
    /// [`RunStats::state_len`] entries: a step or a right-hand side costs a matrix-vector
    /// product, a Jacobian, a factorization or a matrix exponential a matrix-matrix one. A
    /// count, not a wall time: a choice ranked by it does not depend on how busy the machine
    /// is.
    pub fn operations(&self) -> f64 {
        self.operations_over(self.state_len)
    }

    /// [`RunStats::operations`] over a state of `state_len` entries (for a run under way,
    /// whose [`RunStats::state_len`] is set when it ends).
    pub fn operations_over(&self, state_len: usize) -> f64 {
        let n2 = (state_len * state_len) as f64;
        let n3 = n2 * state_len as f64;
        (self.steps + self.rhs_evals) as f64 * n2
            + (self.jacobian_evals + self.factorizations + self.exponentials) as f64 * n3
    }

    /// Adds the counts of `other` (a later part of the same run); wall times add too.
    pub fn add(&mut self, other: &RunStats) {
        self.steps += other.steps;
        self.rejected += other.rejected;
        self.rhs_evals += other.rhs_evals;
        self.jacobian_evals += other.jacobian_evals;
        self.factorizations += other.factorizations;
        self.switches += other.switches;
        self.exponentials += other.exponentials;
        self.long_steps += other.long_steps;
        self.taylor_terms += other.taylor_terms;
        self.step_cap = self.step_cap.or(other.step_cap);
        self.wall += other.wall;
        self.state_len = self.state_len.max(other.state_len);
    }
}

/// Why a run stopped early. Every message names the time, the method and the likely cause.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SimError {
    /// The state stopped being finite or grew beyond any physical size.
    #[error("the solution diverged at t = {t:.6} s (method {method}, step {h:.3e} s): {cause}")]
    Diverged {
        /// Time of the last good state (s).
        t: f64,
        /// Method name.
        method: String,
        /// Step that failed (s).
        h: f64,
        /// The likely cause.
        cause: String,
    },
    /// The adaptive step size fell below the floor.
    #[error(
        "step size underflow at t = {t:.6} s (method {method}): the step {h:.3e} s fell below {h_min:.3e} s; \
         likely cause: {cause}"
    )]
    StepUnderflow {
        /// Time (s).
        t: f64,
        /// Method name.
        method: String,
        /// The rejected step (s).
        h: f64,
        /// The floor (s).
        h_min: f64,
        /// The likely cause.
        cause: String,
    },
    /// Newton's method failed repeatedly.
    #[error(
        "Newton iteration failed at t = {t:.6} s (method {method}, step {h:.3e} s) {attempts} times in a row; \
         likely cause: {cause}"
    )]
    NewtonFailure {
        /// Time (s).
        t: f64,
        /// Method name.
        method: String,
        /// Last step tried (s).
        h: f64,
        /// Consecutive failures.
        attempts: u32,
        /// The likely cause.
        cause: String,
    },
    /// A telescopic position left the range where the overlap is valid.
    #[error(
        "telescopic position a_{section} = {value:.6} m at t = {t:.6} s (method {method}) leaves its valid range \
         [{min:.6}, {max:.6}) m: the overlap of sections {} and {section} would vanish or exceed a section",
        section - 1
    )]
    PositionOutOfRange {
        /// Time (s).
        t: f64,
        /// Method name.
        method: String,
        /// Section `k` (1-based) whose foot position `a_k` is out of range.
        section: usize,
        /// `a_k(t)` (m).
        value: f64,
        /// Smallest valid value (m).
        min: f64,
        /// Valid values are below this (m).
        max: f64,
    },
    /// The run cost more than [`Settings::max_operations`].
    #[error(
        "stopped at t = {t:.6} s (method {method}) after {operations:.2e} operations, above \
         the budget of {budget:.2e} it was given; likely cause: a costlier run than the one \
         the caller compares it with"
    )]
    OverBudget {
        /// Time reached (s).
        t: f64,
        /// Method name.
        method: String,
        /// Operations counted so far.
        operations: f64,
        /// [`Settings::max_operations`].
        budget: f64,
    },
    /// Too many steps.
    #[error("gave up after {steps} steps at t = {t:.6} s (method {method}); likely cause: {cause}")]
    TooManySteps {
        /// Time reached (s).
        t: f64,
        /// Method name.
        method: String,
        /// Steps taken.
        steps: u64,
        /// The likely cause.
        cause: String,
    },
    /// Settings that cannot work.
    #[error("{0}")]
    Settings(String),
    /// The caller asked the run to stop (its progress callback returned false).
    #[error("stopped on request at t = {t:.6} s (method {method})")]
    Stopped {
        /// Time reached (s).
        t: f64,
        /// Method name.
        method: String,
    },
}

impl SimError {
    /// Where a numerical failure happened: its time (s) and method; `None` for bad settings.
    pub fn at(&self) -> Option<(f64, &str)> {
        match self {
            SimError::Diverged { t, method, .. }
            | SimError::StepUnderflow { t, method, .. }
            | SimError::NewtonFailure { t, method, .. }
            | SimError::PositionOutOfRange { t, method, .. }
            | SimError::TooManySteps { t, method, .. }
            | SimError::OverBudget { t, method, .. }
            | SimError::Stopped { t, method } => Some((*t, method.as_str())),
            SimError::Settings(_) => None,
        }
    }
}

/// The right-hand side with the contact branches held fixed, and its evaluation counts.
pub struct System<'m> {
    /// The model.
    pub model: &'m dyn Model,
    /// Contact branches (ignored for the linear law).
    pub tracker: ContactTracker,
    /// Evaluation counts so far.
    pub stats: RunStats,
    /// Times are clamped to this (s): just before a drive discontinuity, so a step that ends
    /// on it sees the profile's left limit.
    pub time_cap: f64,
}

impl System<'_> {
    /// `ydot = f(t, y)` in the current contact branches.
    #[inline]
    pub fn rhs(&mut self, t: f64, y: &[f64], ydot: &mut [f64]) {
        self.stats.rhs_evals += 1;
        self.model
            .rhs(t.min(self.time_cap), y, self.tracker.fixed_states(), ydot);
    }

    /// `d ydot / d y` in the current contact branches.
    pub fn jacobian(&mut self, t: f64, y: &[f64], jac: &mut nalgebra::DMatrix<f64>) {
        self.stats.jacobian_evals += 1;
        self.model
            .jacobian(t.min(self.time_cap), y, self.tracker.fixed_states(), jac);
    }

    /// Number of generalized coordinates.
    pub fn dof(&self) -> usize {
        self.model.dof()
    }
}

/// Why a single step could not be taken (the driver turns it into a retry or a [`SimError`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum StepFailure {
    /// Newton did not converge within its iteration limit.
    NewtonDiverged,
}

/// One step of a method. `f0 = f(t, y)` in the current branches is given; the method writes
/// `y1` at `t + h` and returns the scaled local error estimate (1 = at tolerance) when it
/// has one, else 0.
pub trait Stepper {
    /// Order used for step-size control (`err ~ h^(order+1)`).
    fn order(&self) -> u32;

    /// Takes one step.
    ///
    /// # Errors
    /// [`StepFailure`] when the step cannot be completed (the driver retries shorter).
    fn step(
        &mut self,
        sys: &mut System,
        t: f64,
        y: &[f64],
        f0: &[f64],
        h: f64,
        y1: &mut [f64],
    ) -> Result<f64, StepFailure>;

    /// `f(t + h, y1)` of the last step, when the method computed it (first-same-as-last).
    fn end_derivative(&self) -> Option<&[f64]> {
        None
    }

    /// The last step taken was accepted (commit any carried history).
    fn accepted(&mut self) {}

    /// Forget history after a contact switch or a drive discontinuity.
    fn restart(&mut self) {}

    /// The error estimate that sets the next step after an accepted one with estimate `err`
    /// (a variable-order method returns the estimate of the order it chose).
    fn control_error(&self, err: f64) -> f64 {
        err
    }

    /// Weight `beta` of the previous error in the PI step controller (0: plain I control).
    fn pi_beta(&self) -> f64 {
        0.0
    }

    /// Whether the method's next steps step over the closed contacts' modes: the driver then
    /// lifts the closed-contact step cap and counts them in [`RunStats::long_steps`].
    fn over_contact_modes(&self) -> bool {
        false
    }

    /// Largest factor by which the step may grow from one step to the next.
    fn growth_limit(&self) -> f64 {
        5.0
    }

    /// Prepares the continuous extension of the step just taken, of length `h` (s) from
    /// `(t, y)` to `y1`, when the method has one (its extra right-hand sides are evaluated
    /// here); false when it has none.
    fn prepare_extension(
        &mut self,
        _sys: &mut System,
        _t: f64,
        _y: &[f64],
        _y1: &[f64],
        _h: f64,
    ) -> bool {
        false
    }

    /// The state at `t + theta h` of the step whose extension was prepared, into `out`.
    fn extension_state(&self, _theta: f64, _out: &mut [f64]) {}
}

/// Scaled RMS norm of an error vector against `atol + rtol max(|y0|, |y1|)`.
pub fn error_norm(err: &[f64], y0: &[f64], y1: &[f64], rtol: f64, atol: f64) -> f64 {
    let n = err.len() as f64;
    let sum: f64 = err
        .iter()
        .zip(y0.iter().zip(y1))
        .map(|(e, (a, b))| {
            let sc = atol + rtol * a.abs().max(b.abs());
            (e / sc).powi(2)
        })
        .sum();
    (sum / n).sqrt()
}

/// The stepper of `method`; `step_cap` is dop853's step cap with closed contacts (s), when
/// the model has contacts (read by `dop853-imex`); `longest_step` the run's longest step
/// (s: the output sample interval, or `Settings::longest_step`), which sets imex's stiff modes.
fn make_stepper(
    method: Method,
    dof: usize,
    settings: &Settings,
    step_cap: Option<f64>,
    longest_step: f64,
) -> Box<dyn Stepper> {
    match method {
        Method::Dopri5 => Box::new(explicit::ExplicitRk::new(
            &explicit::DOPRI5,
            2 * dof,
            settings,
        )),
        Method::Dop853 => Box::new(explicit::ExplicitRk::new(
            &explicit::DOP853,
            2 * dof,
            settings,
        )),
        Method::Esdirk => Box::new(esdirk::Esdirk::new(dof, settings)),
        Method::Imex => Box::new(imex::Imex::new(dof, settings, longest_step)),
        Method::Dop853Imex => Box::new(settled::SettledSteps::new(
            dof,
            settings,
            step_cap.unwrap_or(f64::INFINITY),
            longest_step,
        )),
        Method::Bdf { max_order, .. } => Box::new(bdf::Bdf::new(dof, max_order, settings)),
        Method::Rk4 => Box::new(explicit::ExplicitRk::new(&explicit::RK4, 2 * dof, settings)),
        Method::Exact => unreachable!("method exact has its own loop (exact.rs)"),
        Method::Verlet => Box::new(verlet::StormerVerlet::new(dof)),
        Method::GeneralizedAlpha { rho_inf, adaptive } => Box::new(
            generalized_alpha::GeneralizedAlpha::new(dof, rho_inf, adaptive, settings),
        ),
    }
}

/// The output times of a span: `start + k sample`, then `end` if the span is not a whole
/// number of samples.
#[derive(Debug, Clone, Copy)]
pub(crate) struct SampleGrid {
    start: f64,
    end: f64,
    sample: f64,
    /// Number of output samples, the one at `start` included.
    pub total: u64,
}

impl SampleGrid {
    pub(crate) fn new(span: &TimeSpan) -> Self {
        // whole samples in the span (a last one within 1e-9 of a sample of the end counts)
        let whole = ((span.end - span.start) / span.sample * (1.0 + 1e-9)).floor() as u64;
        let ends_on_sample =
            (span.start + whole as f64 * span.sample - span.end).abs() <= 1e-9 * span.sample;
        SampleGrid {
            start: span.start,
            end: span.end,
            sample: span.sample,
            total: whole + 1 + u64::from(!ends_on_sample),
        }
    }

    /// Whether the span's end is a grid time (else it is a sample of its own).
    pub(crate) fn ends_on_sample(&self) -> bool {
        let whole = self.total - 1;
        (self.start + whole as f64 * self.sample - self.end).abs() <= 1e-9 * self.sample
    }

    /// Time of output sample `k` (s).
    pub(crate) fn time(&self, k: u64) -> f64 {
        (self.start + k as f64 * self.sample).min(self.end)
    }
}

/// Sample callback: `(t, y, ydot)` at each output time.
pub type Observer<'a> = &'a mut dyn FnMut(f64, &[f64], &[f64]);

/// Progress callback: called now and then (every 1 % of the span) with the current time (s);
/// returns whether to go on (false stops the run with [`SimError::Stopped`]).
pub type Progress<'a> = &'a mut dyn FnMut(f64) -> bool;

/// Refuses an initial state `y0` that is not `[z, zdot]` of `model`.
fn check_state_len(model: &dyn Model, y0: &[f64]) -> Result<(), SimError> {
    if y0.len() == 2 * model.dof() {
        return Ok(());
    }
    Err(SimError::Settings(format!(
        "initial state has {} entries, the model needs 2 dof = {}",
        y0.len(),
        2 * model.dof()
    )))
}

/// Integrates `model` from `y0` at `span.start` to `span.end`, calling `observe(t, y, ydot)`
/// at every sample time `start + k sample` (and at `end`).
///
/// # Errors
/// [`SimError`] naming the time, method and likely cause; `observe` has then seen only the
/// samples before the failure.
pub fn simulate(
    model: &dyn Model,
    y0: &[f64],
    span: &TimeSpan,
    method: Method,
    settings: &Settings,
    observe: Observer,
    progress: Option<Progress>,
) -> Result<RunStats, SimError> {
    let started = Instant::now();
    check_state_len(model, y0)?;
    let mut stats = match settings.exact_from {
        _ if method == Method::Exact => exact::run(model, y0, span, settings, observe, progress)?,
        Some(t_exact) => method_then_exact(
            model, y0, span, method, settings, t_exact, observe, progress,
        )?,
        None => Driver::new(model, y0, span, method, settings)?.run(observe, progress)?,
    };
    stats.wall = started.elapsed();
    stats.state_len = y0.len();
    Ok(stats)
}

/// `method` on `[start, t_exact]`, exact stepping on `[t_exact, end]` from the state reached;
/// one stream of samples on the span's grid (the sample at `t_exact` once).
#[allow(clippy::too_many_arguments)]
fn method_then_exact(
    model: &dyn Model,
    y0: &[f64],
    span: &TimeSpan,
    method: Method,
    settings: &Settings,
    t_exact: f64,
    observe: Observer,
    mut progress: Option<Progress>,
) -> Result<RunStats, SimError> {
    let grid = SampleGrid::new(span);
    let k_exact = ((t_exact - span.start) / span.sample).round();
    if !(t_exact > span.start && t_exact < span.end)
        || (grid.time(k_exact as u64) - t_exact).abs() > 1e-9 * span.sample
    {
        return Err(SimError::Settings(format!(
            "exact stepping from t = {t_exact} s needs a sample time inside ({}, {}) s",
            span.start, span.end
        )));
    }
    let head = TimeSpan {
        end: t_exact,
        ..*span
    };
    let tail = TimeSpan {
        start: t_exact,
        ..*span
    };
    let mut y_exact = y0.to_vec();
    let mut stats = {
        let mut keep_last = |t: f64, y: &[f64], ydot: &[f64]| {
            observe(t, y, ydot);
            y_exact.copy_from_slice(y);
        };
        let head_progress = progress
            .as_mut()
            .map(|p| &mut **p as &mut dyn FnMut(f64) -> bool);
        Driver::new(model, y0, &head, method, settings)?.run(&mut keep_last, head_progress)?
    };
    // the tail's samples are t_exact + k sample; report them as the span's own grid times
    let mut first = true;
    let mut on_grid = |t: f64, y: &[f64], ydot: &[f64]| {
        if std::mem::take(&mut first) {
            return;
        }
        let k = ((t - span.start) / span.sample).round();
        let t_grid = grid.time(k as u64);
        let t = if (t_grid - t).abs() <= 1e-9 * span.sample {
            t_grid
        } else {
            t
        };
        observe(t, y, ydot);
    };
    let tail_stats = exact::run(model, &y_exact, &tail, settings, &mut on_grid, progress)?;
    stats.add(&tail_stats);
    Ok(stats)
}

mod driver;
use driver::Driver;
