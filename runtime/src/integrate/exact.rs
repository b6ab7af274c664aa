//! Exact stepping of a scene that is linear and time-invariant between contact switches
//! (method `exact`).
//!
//! With fixed telescopic positions and a piecewise-constant drive force, every branch of
//! the clearance law (and `l_S = 0`'s single one) makes the first-order system affine and
//! constant in time: `y' = A y + e`. Its flow over a step `h` is `y(h) = Phi y + Gamma` with
//! `[[Phi, Gamma], [0, 1]] = exp([[A, e], [0, 0]] h)`, exact up to rounding. This module
//! computes `A` and `e` from the model itself (its Jacobian and its right-hand side at
//! `y = 0`, checked for affinity on a probe state), one matrix exponential per combination of
//! contact branches and drive level, cached; a regular step is then one matrix-vector
//! product.
//!
//! Regular steps are `sample / 2^m`, the largest with `h omega_b <= STEP_OMEGA` where
//! `omega_b` is the spectral radius of the branch's `A`: closed contacts get short steps,
//! free flight long ones, and sample times are step ends. A band-edge crossing is found
//! exactly: after a step whose switch function changed sign (or whose cubic Hermite
//! interpolant of it dips below zero: a double crossing inside the step), the flow from the
//! step start is expanded in its Taylor series `y(tau) = sum_j tau^j u_j`, `u_j = A^j
//! [y; 1] / j!` (`[A e]` acting on the augmented state), so each switch function is a
//! polynomial in `tau`: scanned for the first sign change, refined by Illinois to rounding.
//! Partial steps (to an event, to a sample time, to a drive step) use the same series; after
//! an event or a drive step the regular steps restart from there (the flow is
//! time-invariant), and a sample time brings them back onto the start's grid.
//!
//! While a contact is closed its mode (some kHz) sets `omega_b`. A branch whose fastest
//! eigenvalues stand well apart from the rest (the closed contacts' modes above the beams')
//! also gets a long step, set by the slow modes alone, with its own exponential. A long step
//! is taken where the fast modes' bound certifies that no switch function can cross over it
//! (see the `fast_modes` module): in lasting contact, once the impact's ringing has decayed;
//! elsewhere (ringing, a contact about to open) the short steps resolve it as before, to
//! the next long-step grid point.
//!
//! Hand-written: no ODE crate offers exponential stepping with state events.

use super::events::{HermiteCubic, first_crossing};
use super::fast_modes::{FastModes, StepEnd, SwitchFunction};
use super::{ContactTracker, Observer, Progress, RunStats, SampleGrid, Settings, SimError};
use crate::contact::ContactState;
use crate::model::Model;
use crate::model::params::{Drive, ModelParams};
use crate::profile::{Profile, ShapedProfile};
use crate::scene::TimeSpan;
use nalgebra::{Complex, DMatrix, DVector};
use std::collections::HashMap;
use std::sync::Arc;

/// Largest `h omega_b` of a regular step: below a quarter period of the fastest mode, so a
/// gap cannot cross a band edge and return unseen except by grazing it (which the cubic
/// Hermite check catches).
pub const STEP_OMEGA: f64 = 1.5;

/// Most Taylor terms of a partial step (`tau omega <= 1.5` needs about 30).
const MAX_TAYLOR_TERMS: usize = 90;

/// Points at which a switch polynomial is scanned for its first sign change.
const SCAN_POINTS: usize = 32;

/// Most contacts a branch key can encode (3^80 < 2^128).
const MAX_CONTACTS: usize = 80;

/// Why `params` cannot be stepped exactly, or `None` when it can: positions must be fixed
/// and the drive a piecewise-constant force.
pub fn lti_obstacle(params: &ModelParams) -> Option<String> {
    lti_obstacle_from(params, f64::NEG_INFINITY)
}

/// Why `params` cannot be stepped exactly from time `t0` (s) on, or `None` when it can: as
/// [`lti_obstacle`], but a position may move before `t0` (every profile holds its last value
/// after its last breakpoint).
pub fn lti_obstacle_from(params: &ModelParams, t0: f64) -> Option<String> {
    if let Some(k) = params.positions.iter().position(|p| moves_after(p, t0)) {
        return Some(format!(
            "the telescopic position a_{} moves, so the contact vectors change in time",
            k + 2
        ));
    }
    match &params.drive {
        Drive::Motion(_) => Some(
            "the vehicle motion is prescribed (its acceleration enters as a function of time)"
                .into(),
        ),
        Drive::Force(p) if !piecewise_constant(p) => {
            Some("the drive force is not piecewise constant".into())
        }
        Drive::Force(_) if params.contact_points * (params.sections.len() - 1) > MAX_CONTACTS => {
            Some(format!("more than {MAX_CONTACTS} contact points in all"))
        }
        Drive::Force(_) => None,
    }
}

/// True when the profile changes at some time after `t0` (s).
fn moves_after(p: &Profile, t0: f64) -> bool {
    !p.is_constant() && p.breakpoints().iter().any(|&b| b > t0)
}

/// The first sample time of `span` at or after which the scene can be stepped exactly while
/// it cannot be from the start: the end of the positions' motion, rounded up to the sample
/// grid. `None` when the whole span is exact, when no such time lies inside the span, or when
/// something else (a motion drive, a non-piecewise-constant force) stands in the way.
pub fn exact_tail_start(params: &ModelParams, span: &TimeSpan) -> Option<f64> {
    lti_obstacle(params)?;
    let rest = params
        .positions
        .iter()
        .flat_map(|p| p.breakpoints())
        .fold(span.start, f64::max);
    let k = ((rest - span.start) / span.sample * (1.0 - 1e-12)).ceil();
    let t = span.start + k * span.sample;
    (t > span.start && t < span.end && lti_obstacle_from(params, t).is_none()).then_some(t)
}

fn piecewise_constant(p: &Profile) -> bool {
    p.is_constant() || matches!(p, Profile::Shaped(ShapedProfile::PiecewiseConstant { .. }))
}

/// The affine flow of one combination of contact branches and drive level.
struct Branch {
    /// `A` (`2 dof x 2 dof`); the matrices below it are shared with the branches of later
    /// drive steps that keep this `A` ([`ExactRun::same_flow_branch`]).
    a: Arc<DMatrix<f64>>,
    /// `e` (`2 dof`).
    e: DVector<f64>,
    /// Regular step (s).
    h: f64,
    /// `exp(A h)`.
    phi: Arc<DMatrix<f64>>,
    /// `int_0^h exp(A s) ds e`.
    gamma: DVector<f64>,
    /// `int_0^h exp(A s) ds`, `gamma` for each new `e`: built with the branch where the
    /// drive is a held input ([`ExactTicks`]), else once a later drive step keeps this `A`.
    integral: Option<Arc<DMatrix<f64>>>,
    /// The [`ExactRun::input_epoch`] whose input `e` and `gamma` hold.
    input_epoch: u64,
    /// Spectral radius of `A` (rad/s).
    omega: f64,
    /// The step over the fast contact modes, where they stand apart.
    long: Option<LongStep>,
    /// The lower half `[A_vz, A_vv]` of `A` when its upper half is `[0, I]` (positions'
    /// rates are the velocities) and `e`'s is zero, as the model's first-order form has it.
    lower: Option<Arc<DMatrix<f64>>>,
    /// Whether the branch has switch functions (its regular step is then `h omega`-bound).
    events: bool,
    /// Whether the exponential is another branch's ([`ExactRun::same_flow_branch`]).
    shared: bool,
}

impl Branch {
    /// `out = scale A x`, at half the cost where `A` has the first-order form.
    fn apply(&self, x: &DVector<f64>, out: &mut DVector<f64>, scale: f64) {
        match &self.lower {
            Some(lower) => {
                let n = lower.nrows();
                let (upper, rest) = out.as_mut_slice().split_at_mut(n);
                for (u, v) in upper.iter_mut().zip(&x.as_slice()[n..]) {
                    *u = scale * v;
                }
                mat_vec(lower, x.as_slice(), scale, rest);
            }
            None => mat_vec(&self.a, x.as_slice(), scale, out.as_mut_slice()),
        }
    }
}

/// Whether `t` (s) lies on the grid `anchor + k h` (up to rounding of the time itself), and
/// the grid's next point after `t`.
fn next_grid_point(t: f64, anchor: f64, h: f64) -> (bool, f64) {
    let k = ((t - anchor) / h).round();
    let on_grid = (t - (anchor + k * h)).abs() <= 1e-9 * h;
    let k_next = if on_grid {
        k + 1.0
    } else {
        ((t - anchor) / h).floor() + 1.0
    };
    (on_grid, anchor + k_next * h)
}

/// The lower half of `a` when `a = [[0, I], [.., ..]]` and `e`'s upper half is zero.
fn first_order_lower(a: &DMatrix<f64>, e: &DVector<f64>) -> Option<DMatrix<f64>> {
    let n = a.nrows() / 2;
    let upper = (0..n).all(|i| {
        e[i] == 0.0 && (0..2 * n).all(|j| a[(i, j)] == if j == n + i { 1.0 } else { 0.0 })
    });
    upper.then(|| a.rows(n, n).into_owned())
}

/// A regular step set by a branch's slow modes, taken where its fast modes' bound certifies
/// it (see the module documentation).
struct LongStep {
    /// Step (s): `sample / 2^m`, a multiple of the branch's short step.
    h: f64,
    /// The fast eigenvalues (rad/s).
    fast: Vec<Complex<f64>>,
    /// Its flow and fast modes, built when a long step is first tried: a branch met only
    /// between two impacts of a rattle never needs them.
    flow: Option<LongFlow>,
}

/// The exponential and the fast modes of a long step.
struct LongFlow {
    /// `exp(A h)`.
    phi: DMatrix<f64>,
    /// `int_0^h exp(A s) ds e`.
    gamma: DVector<f64>,
    modes: FastModes,
}

/// Least ratio of the slowest fast eigenvalue's modulus to the fastest slow one's for a long
/// step.
pub const LONG_STEP_SEPARATION: f64 = 2.0;

/// The regular step (s) of a branch with spectral radius `omega` (rad/s) on a grid of
/// `sample` (s): the largest `sample / 2^m` with `h omega <= STEP_OMEGA`.
pub fn regular_step(omega: f64, sample: f64) -> f64 {
    let mut h = sample;
    while h * omega > STEP_OMEGA {
        h *= 0.5;
    }
    h
}

/// The fast eigenvalues of a branch with `closed` closed contacts (its eigenvalues `eigen`,
/// rad/s) and the long step (s) its slow ones allow on a grid of `sample` (s): the largest
/// `k <= 2 x closed` eigenvalues in modulus are fast when they stand [`LONG_STEP_SEPARATION`]
/// times above the rest (so a conjugate pair is never split), the most such. `None` when no
/// `k` does.
pub fn long_step_split(
    eigen: &[Complex<f64>],
    closed: usize,
    sample: f64,
) -> Option<(Vec<Complex<f64>>, f64)> {
    if closed == 0 || eigen.len() < 2 {
        return None;
    }
    let mut sorted = eigen.to_vec();
    sorted.sort_by(|x, y| y.norm().total_cmp(&x.norm()));
    // the most fast modes that stand apart (a contact closed on a section already held by
    // others may stiffen a beam mode without making it fast)
    let k = (1..=(2 * closed).min(sorted.len() - 1))
        .rev()
        .find(|&k| sorted[k - 1].norm() >= LONG_STEP_SEPARATION * sorted[k].norm())?;
    let omega_slow = sorted[k].norm();
    sorted.truncate(k);
    Some((sorted, regular_step(omega_slow, sample)))
}

/// Method `exact`'s regular steps with every contact closed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ClosedContactSteps {
    /// The time (s) the closed-contact system is taken at.
    pub time: f64,
    /// Its spectral radius (rad/s).
    pub omega: f64,
    /// The step (s) set by the contact modes.
    pub short: f64,
    /// The step (s) set by the rest where the contact modes stand apart (taken where their
    /// bound certifies it).
    pub long: Option<f64>,
}

/// Method `exact`'s regular steps with every contact of `model` closed at `t` (s), on a grid
/// of `sample` (s).
///
/// # Errors
/// [`crate::EigenError`] when the eigenvalues of the closed-contact system do not converge.
pub fn closed_contact_steps(
    model: &dyn Model,
    t: f64,
    sample: f64,
) -> Result<ClosedContactSteps, crate::EigenError> {
    let n2 = 2 * model.dof();
    let rest = vec![0.0; n2];
    let mut tracker = ContactTracker::new(model, t, &rest);
    tracker.press_all();
    let mut a = DMatrix::zeros(n2, n2);
    model.jacobian(t, &rest, tracker.fixed_states(), &mut a);
    let eigen = crate::analysis::eigen::eigenvalues(a, "eigenvalues of the closed-contact system")?;
    let omega = eigen.iter().map(|l| l.norm()).fold(0.0, f64::max);
    let short = regular_step(omega, sample);
    let long = long_step_split(&eigen, model.layout().contact_count(), sample)
        .map(|(_, h)| h)
        .filter(|&h| h > short);
    Ok(ClosedContactSteps {
        time: t,
        omega,
        short,
        long,
    })
}

struct ExactRun<'m> {
    model: &'m dyn Model,
    n: usize,
    span: TimeSpan,
    samples: SampleGrid,
    /// Contact vectors `g_c` as columns (`dof x contacts`), constant.
    g: DMatrix<f64>,
    tracker: ContactTracker,
    functionals: Vec<SwitchFunction>,
    /// Drive steps inside the span, sorted.
    breakpoints: Vec<f64>,
    branches: Vec<Branch>,
    index: HashMap<(usize, u128), usize>,
    /// The first branch built afresh for each contact code and presence of switch
    /// functions: the donor a later drive segment's branch takes its flow from when the
    /// model's right-hand side is the donor's affine map with the segment's own `e`.
    donors: HashMap<(u128, bool), usize>,
    stats: RunStats,
    size_limit: f64,
    y: DVector<f64>,
    y1: DVector<f64>,
    ydot: DVector<f64>,
    /// Taylor vectors `u_j` of the flow from the current step start.
    taylor: Vec<DVector<f64>>,
    taylor_len: usize,
    coefficients: Vec<f64>,
    gaps0: Gaps,
    gaps1: Gaps,
    /// `gaps0` holds the gaps of `y` (carried over from the last step's end).
    gaps0_current: bool,
    /// Whether branches get long steps ([`Settings::long_steps`]).
    long_steps: bool,
    /// Which switch functions a step's end values or Hermite check flag.
    suspects: Vec<bool>,
    /// Fast modal coordinates at a long step's start and end.
    modal0: Vec<Complex<f64>>,
    modal1: Vec<Complex<f64>>,
    /// The branch and time whose state `modal0` holds the coordinates of: the end of the
    /// last long step, so that consecutive long steps compute them once.
    modal0_at: Option<(usize, f64)>,
    /// Whether the drive is a held input set between ticks ([`ExactTicks`]): a branch then
    /// keeps `int exp(A s) ds` to take each new input's `e` by superposition.
    held: bool,
    /// Counts the held input's changes.
    input_epoch: u64,
}

/// Gap `xi_c` (m) and rate `xi_dot_c` (m/s) of every contact.
struct Gaps {
    value: DVector<f64>,
    rate: DVector<f64>,
}

impl Gaps {
    fn new(contacts: usize) -> Self {
        Gaps {
            value: DVector::zeros(contacts),
            rate: DVector::zeros(contacts),
        }
    }
}

/// Integrates an LTI scene exactly (see the module documentation).
///
/// # Errors
/// [`SimError::Settings`] when the scene is not linear and time-invariant between switches;
/// [`SimError::Diverged`] for a growing mode; [`SimError::TooManySteps`].
pub(super) fn run(
    model: &dyn Model,
    y0: &[f64],
    span: &TimeSpan,
    settings: &Settings,
    mut observe: Observer,
    mut progress: Option<Progress>,
) -> Result<RunStats, SimError> {
    let params = model.params();
    if let Some(why) = lti_obstacle_from(params, span.start) {
        return Err(SimError::Settings(format!(
            "method exact needs a scene that is linear and time-invariant between contact \
             switches, but {why}; take dopri5 or another method"
        )));
    }
    let mut run = ExactRun::new(model, y0, span, settings);
    run.breakpoints = params
        .drive_profile()
        .breakpoints()
        .into_iter()
        .filter(|&b| b > span.start && b < span.end)
        .collect();
    run.breakpoints.sort_by(f64::total_cmp);
    run.breakpoints.dedup();
    run.integrate(settings, &mut observe, &mut progress)?;
    Ok(run.stats)
}

/// Exact stepping of a model whose drive force is an input held between ticks (a sampled
/// controller's zero-order hold), advanced tick by tick: its branches' exponentials are
/// built once, with `int_0^h exp(A s) ds`, so that a new input costs one evaluation of the
/// right-hand side and one matrix-vector product (superposition) instead of a run of its
/// own. The positions must rest from the start on and the model's right-hand side must not
/// change in time at a fixed state (checked per branch). Regular steps only: the long steps'
/// bound would need the fast modes anew at every tick.
pub struct ExactTicks<'m> {
    run: ExactRun<'m>,
    settings: Settings,
    /// The ticks' nominal interval (s): it sets the branches' regular steps.
    tick: f64,
    /// The time reached (s).
    t: f64,
}

impl<'m> ExactTicks<'m> {
    /// Ticks of `model` from `y0` at `t0` (s), `tick` (s) apart, with `settings`' step limit.
    ///
    /// # Errors
    /// [`SimError::Settings`] for a state of the wrong length, a tick that is not positive
    /// and finite, and where exact stepping does not apply: a position moving after `t0`, a
    /// prescribed vehicle motion, too many contact points.
    pub fn new(
        model: &'m dyn Model,
        t0: f64,
        y0: &[f64],
        tick: f64,
        settings: &Settings,
    ) -> Result<Self, SimError> {
        super::check_state_len(model, y0)?;
        if !(tick > 0.0 && tick.is_finite() && t0.is_finite()) {
            return Err(SimError::Settings(format!(
                "exact ticks need a finite start and a positive finite tick (got t0 = {t0} s, \
                 tick = {tick} s)"
            )));
        }
        let params = model.params();
        let why = match &params.drive {
            Drive::Motion(_) => Some("the vehicle motion is prescribed".to_owned()),
            Drive::Force(_) => lti_obstacle_from(
                &ModelParams {
                    drive: Drive::Force(Profile::Constant(0.0)),
                    ..params.clone()
                },
                t0,
            ),
        };
        if let Some(why) = why {
            return Err(SimError::Settings(format!(
                "method exact with a held input needs a scene that is linear and \
                 time-invariant between contact switches from t = {t0} s on, but {why}"
            )));
        }
        let span = TimeSpan {
            start: t0,
            end: t0 + tick,
            sample: tick,
        };
        let mut run = ExactRun::new(model, y0, &span, settings);
        run.held = true;
        Ok(ExactTicks {
            run,
            settings: *settings,
            tick,
            t: t0,
        })
    }

    /// The model's held input changed: each branch takes its new `e` when next used.
    pub fn input_changed(&mut self) {
        self.run.input_epoch += 1;
    }

    /// Advances to `t_end` (s) with the input held.
    ///
    /// # Errors
    /// As [`super::simulate`] with method `exact`; the run cannot go on after one.
    pub fn advance_to(&mut self, t_end: f64) -> Result<(), SimError> {
        if !t_end.is_finite() {
            return Err(SimError::Settings(format!(
                "exact ticks advance to a finite time (got {t_end} s)"
            )));
        }
        if t_end <= self.t {
            return Ok(());
        }
        // a tick of any length: samples (unobserved) at the nominal interval, then its end
        let span = TimeSpan {
            start: self.t,
            end: t_end,
            sample: self.tick,
        };
        let run = &mut self.run;
        run.span = span;
        run.samples = SampleGrid::new(&span);
        run.gaps0_current = false;
        run.modal0_at = None;
        let mut ignore = |_: f64, _: &[f64], _: &[f64]| {};
        let mut observe: Observer = &mut ignore;
        run.integrate(&self.settings, &mut observe, &mut None)?;
        self.t = t_end;
        Ok(())
    }

    /// The time reached (s).
    pub fn time(&self) -> f64 {
        self.t
    }

    /// The state reached, `[z, zdot]`.
    pub fn state(&self) -> &[f64] {
        self.run.y.as_slice()
    }

    /// The counts so far.
    pub fn stats(&self) -> RunStats {
        self.run.stats.clone()
    }
}

impl<'m> ExactRun<'m> {
    /// A run of `model` from `y0` over `span` with `settings`, without drive steps.
    fn new(model: &'m dyn Model, y0: &[f64], span: &TimeSpan, settings: &Settings) -> Self {
        let n = model.dof();
        let nc = model.layout().contact_count();
        let (mut g, mut gdot) = (DMatrix::zeros(n, nc), DMatrix::zeros(n, nc));
        model.contact_vectors(span.start, &mut g, &mut gdot);
        let params = model.params();
        ExactRun {
            model,
            n,
            span: *span,
            samples: SampleGrid::new(span),
            g,
            tracker: ContactTracker::new(model, span.start, y0),
            functionals: Vec::with_capacity(2 * nc),
            breakpoints: Vec::new(),
            branches: Vec::new(),
            index: HashMap::new(),
            donors: HashMap::new(),
            stats: RunStats::default(),
            size_limit: 100.0 * params.sections.iter().map(|s| s.length).sum::<f64>(),
            y: DVector::from_column_slice(y0),
            y1: DVector::zeros(2 * n),
            ydot: DVector::zeros(2 * n),
            taylor: vec![DVector::zeros(2 * n); MAX_TAYLOR_TERMS],
            taylor_len: 0,
            coefficients: vec![0.0; MAX_TAYLOR_TERMS],
            gaps0: Gaps::new(nc),
            gaps1: Gaps::new(nc),
            gaps0_current: false,
            suspects: vec![false; 2 * nc],
            long_steps: settings.long_steps,
            modal0: vec![Complex::default(); 2 * n],
            modal1: vec![Complex::default(); 2 * n],
            modal0_at: None,
            held: false,
            input_epoch: 0,
        }
    }

    fn integrate(
        &mut self,
        settings: &Settings,
        observe: &mut Observer,
        progress: &mut Option<Progress>,
    ) -> Result<(), SimError> {
        let (start, end) = (self.span.start, self.span.end);
        let mut t = start;
        let mut segment = 0usize;
        let mut current = self.branch(t, segment)?;
        self.emit(current, t, observe);
        let mut next_sample = 1u64;
        let mut last_report = t;
        // regular steps run on the grid `anchor + k h`: from the start, and from each event
        // or drive step (the flow is time-invariant, so a regular step is exact from any
        // time); back on the start's grid at the next sample time, which lies on it. Without
        // the re-anchoring every event would need a partial step back onto the start's grid.
        let mut anchor = start;
        // a long step found uncertified is not tried again before this time
        let mut short_until = start;
        while t < end {
            self.check_step_count(t, settings)?;
            let t_sample = if next_sample < self.samples.total {
                self.samples.time(next_sample)
            } else {
                end
            };
            let t_break = self.breakpoints.get(segment).copied().unwrap_or(end);
            let limit = t_sample.min(t_break).min(end);
            let mut long = None;
            if t >= short_until
                && let Some(stop) = self.long_stop(current, t, anchor, limit)
            {
                if self.long_step(current, t, stop)? {
                    long = Some(stop);
                } else {
                    short_until = stop;
                }
            }
            let stop = match long {
                Some(stop) => stop,
                None => {
                    let stop = self.regular_step(current, t, anchor, limit)?;
                    if let Some(tau_event) = self.find_event(current, t, stop - t)? {
                        // y1 holds the state just past the crossing
                        t += tau_event;
                        std::mem::swap(&mut self.y, &mut self.y1);
                        let y = self.y.as_slice();
                        self.stats.switches += self.tracker.switch(self.model, t, y);
                        current = self.branch(t, segment)?;
                        self.gaps0_current = false;
                        anchor = t;
                        short_until = t;
                        continue;
                    }
                    stop
                }
            };
            t = stop;
            std::mem::swap(&mut self.y, &mut self.y1);
            std::mem::swap(&mut self.gaps0, &mut self.gaps1);
            self.gaps0_current = !self.functionals.is_empty();
            let on_sample = t == t_sample && next_sample < self.samples.total;
            if on_sample {
                self.emit(current, t, observe);
                next_sample += 1;
                anchor = start;
            }
            if t == t_break && t < end {
                segment += 1;
                current = self.branch(t, segment)?;
                // a drive step within rounding of the start's grid (a record's force, held
                // between samples, steps at its own time stamps, a few ulps off the run's
                // samples) stays on that grid: the next step ends on the next sample (one
                // matrix-vector product), not a Taylor sum of nearly a sample short of it
                let h = self.branches[current].h;
                if !(on_sample || next_grid_point(t, start, h).0) {
                    anchor = t;
                }
            }
            if let Some(p) = progress.as_mut()
                && t - last_report >= 0.01 * (end - start)
            {
                if !p(t) {
                    return Err(SimError::Stopped {
                        t,
                        method: "exact".into(),
                    });
                }
                last_report = t;
            }
        }
        Ok(())
    }

    /// Refuses another step past the step limit.
    fn check_step_count(&self, t: f64, settings: &Settings) -> Result<(), SimError> {
        if self.stats.steps >= settings.max_steps {
            return Err(SimError::TooManySteps {
                t,
                method: "exact".into(),
                steps: self.stats.steps,
                cause: "the contacts chatter without end at this time, or the step limit is too \
                        low"
                .into(),
            });
        }
        Ok(())
    }

    /// One regular step from `t` on branch `current` into `y1`: to the next point of the
    /// grid `anchor + k h` (a matrix-vector product), or a shorter one to `limit` (a Taylor
    /// sum). Its end time (s).
    fn regular_step(
        &mut self,
        current: usize,
        t: f64,
        anchor: f64,
        limit: f64,
    ) -> Result<f64, SimError> {
        let h = self.branches[current].h;
        let (on_grid, t_grid) = next_grid_point(t, anchor, h);
        let stop = t_grid.min(limit);
        let tau = stop - t;
        // a stop within rounding of the grid point (a drive step stamped a few ulps before a
        // sample) is taken as it, as `next_grid_point` takes a start within rounding of it
        if on_grid && t_grid - stop <= 1e-9 * h {
            let b = &self.branches[current];
            mat_vec(&b.phi, self.y.as_slice(), 1.0, self.y1.as_mut_slice());
            self.y1 += &b.gamma;
            self.taylor_len = 0;
        } else {
            self.taylor_step(current, tau)?;
        }
        self.check_size(t, tau)?;
        self.stats.steps += 1;
        Ok(stop)
    }

    /// A step of `tau` off the grid from `y` into `y1` by Taylor sums: one, or where `tau`
    /// is longer than [`STEP_OMEGA`] over the fastest mode (a branch without switch events
    /// steps the whole sample) as many equal pieces as keep each within it.
    fn taylor_step(&mut self, current: usize, tau: f64) -> Result<(), SimError> {
        let omega = self.branches[current].omega;
        let pieces = ((tau * omega / STEP_OMEGA).ceil() as usize).max(1);
        let piece = tau / pieces as f64;
        for i in 0..pieces {
            self.expand(current, piece)?;
            self.sum_taylor(piece);
            if i + 1 < pieces {
                std::mem::swap(&mut self.y, &mut self.y1);
            }
        }
        if pieces > 1 {
            // the step's start state was overwritten: nothing of it may be reused
            self.taylor_len = 0;
            self.gaps0_current = false;
            self.modal0_at = None;
        }
        Ok(())
    }

    /// The branch for the current contact states and drive `segment`, built on first use.
    fn branch(&mut self, t: f64, segment: usize) -> Result<usize, SimError> {
        self.functionals.clear();
        if !self.tracker.is_linear() {
            let half = self.model.params().contact.half_band();
            SwitchFunction::of_branches(self.tracker.states(), half, &mut self.functionals);
        }
        let key = (segment, self.branch_code());
        if let Some(&i) = self.index.get(&key) {
            if self.branches[i].input_epoch != self.input_epoch {
                self.take_held_input(i, t);
            }
            return Ok(i);
        }
        let branch = self.build_branch(t)?;
        let fresh = !branch.shared;
        let events = branch.events;
        self.branches.push(branch);
        let i = self.branches.len() - 1;
        self.index.insert(key, i);
        if fresh {
            self.donors.entry((key.1, events)).or_insert(i);
        }
        Ok(i)
    }

    fn branch_code(&self) -> u128 {
        if self.tracker.is_linear() {
            return 0;
        }
        self.tracker.states().iter().fold(0u128, |code, s| {
            3 * code
                + match s {
                    ContactState::Lower => 0,
                    ContactState::Free => 1,
                    ContactState::Upper => 2,
                }
        })
    }

    /// The held input's `e` and `gamma` in `branch` at `t`, by superposition: one evaluation
    /// of the right-hand side and one product with `int exp(A s) ds`.
    fn take_held_input(&mut self, branch: usize, t: f64) {
        let states = self.tracker.fixed_states();
        let b = &mut self.branches[branch];
        self.y1.fill(0.0);
        self.model
            .rhs(t, self.y1.as_slice(), states, b.e.as_mut_slice());
        self.stats.rhs_evals += 1;
        if let Some(integral) = &b.integral {
            mat_vec(integral, b.e.as_slice(), 1.0, b.gamma.as_mut_slice());
        }
        b.input_epoch = self.input_epoch;
    }

    /// Refuses a held-input model whose right-hand side changes in time at a fixed state
    /// (`e` at `t` against `e` a tick later): its drive is more than the held input.
    fn check_time_invariant(&mut self, t: f64, e: &DVector<f64>) -> Result<(), SimError> {
        let mut later = DVector::zeros(e.len());
        let states = self.tracker.fixed_states();
        self.y1.fill(0.0);
        let t_later = t + self.span.sample;
        self.model
            .rhs(t_later, self.y1.as_slice(), states, later.as_mut_slice());
        self.stats.rhs_evals += 1;
        let mismatch = (&later - e).amax();
        if mismatch.is_nan() || mismatch > 1e-9 * e.amax().max(f64::MIN_POSITIVE) {
            return Err(SimError::Settings(format!(
                "method exact with a held input: at a fixed state the model's right-hand side \
                 changes between t = {t} s and {t_later} s (by {mismatch:.3e}), so its drive is \
                 more than the held input; take dopri5"
            )));
        }
        Ok(())
    }

    /// Refuses a model whose right-hand side is not affine in the state within the current
    /// branches at `t` (`A`, `e` as evaluated there), checked on a probe state of the size of
    /// the current one.
    fn check_affine(&mut self, t: f64, a: &DMatrix<f64>, e: &DVector<f64>) -> Result<(), SimError> {
        let (mismatch, allowed) = self.affine_mismatch(t, a, e);
        if mismatch.is_nan() || mismatch > allowed {
            return Err(SimError::Settings(format!(
                "method exact: the model's right-hand side is not affine in the state within a \
                 contact branch at t = {t} s (mismatch {mismatch:.3e}); take dopri5"
            )));
        }
        Ok(())
    }

    /// How far the model's right-hand side at `t` on a probe state of the size of the
    /// current one is from `A probe + e`, and the mismatch allowed (1e-9 of their size).
    fn affine_mismatch(&mut self, t: f64, a: &DMatrix<f64>, e: &DVector<f64>) -> (f64, f64) {
        let (n2, states) = (2 * self.n, self.tracker.fixed_states());
        let scale = self.y.amax().max(1e-6);
        let probe = DVector::from_fn(n2, |i, _| scale * (1.7 * i as f64 + 0.3).sin());
        let mut f = DVector::zeros(n2);
        self.model
            .rhs(t, probe.as_slice(), states, f.as_mut_slice());
        let predicted = a * &probe + e;
        self.stats.rhs_evals += 1;
        let mismatch = (&f - &predicted).amax();
        let allowed = 1e-9 * (predicted.amax() + f.amax()).max(f64::MIN_POSITIVE);
        (mismatch, allowed)
    }

    /// `A`, `e`, the regular step and its exponential for the current branches at `t`.
    fn build_branch(&mut self, t: f64) -> Result<Branch, SimError> {
        let (model, n2) = (self.model, 2 * self.n);
        let mut e = DVector::zeros(n2);
        let zero = vec![0.0; n2];
        model.rhs(t, &zero, self.tracker.fixed_states(), e.as_mut_slice());
        self.stats.rhs_evals += 1;
        // a drive step on contacts as before: the donor's `A`, if the model agrees, without
        // a Jacobian of its own (a record's force changes at every sample)
        let events = !self.functionals.is_empty();
        if let Some(&donor) = self.donors.get(&(self.branch_code(), events)) {
            let a = self.branches[donor].a.clone();
            let (mismatch, allowed) = self.affine_mismatch(t, &a, &e);
            if mismatch <= allowed {
                if self.held {
                    self.check_time_invariant(t, &e)?;
                }
                return Ok(self.shared_branch(donor, e));
            }
        }
        let mut a = DMatrix::zeros(n2, n2);
        model.jacobian(t, self.y.as_slice(), self.tracker.fixed_states(), &mut a);
        self.stats.jacobian_evals += 1;
        self.check_affine(t, &a, &e)?;
        if self.held {
            self.check_time_invariant(t, &e)?;
        }
        if let Some(branch) = self.same_flow_branch(&a, &e) {
            return Ok(branch);
        }
        let eigen =
            crate::analysis::eigen::eigenvalues(a.clone(), "eigenvalues of a branch's Jacobian")
                .map_err(|e| {
                    SimError::Settings(format!("method exact at t = {t} s: {e}; take dopri5"))
                })?;
        let omega = eigen.iter().map(|l| l.norm()).fold(0.0, f64::max);
        // without switch functions (l_S = 0) the step is exact at any length: one per sample
        let h = if self.functionals.is_empty() {
            self.span.sample
        } else {
            regular_step(omega, self.span.sample)
        };
        // with a held input the input at build is taken as a run without ticks takes it (the
        // same flow to the last bit while the input stays), later ones through the integral
        let (phi, gamma) = balanced_flow(&a, &e, h, omega);
        let integral = self
            .held
            .then(|| Arc::new(balanced_input_flow(&a, h, omega)));
        self.stats.exponentials += 1 + u64::from(self.held);
        // a held input's long steps would need the fast modes' bound anew at every tick
        let long = if self.long_steps && !self.held {
            self.long_step_of(&eigen, h)
        } else {
            None
        };
        let lower = first_order_lower(&a, &e).map(Arc::new);
        Ok(Branch {
            phi: Arc::new(phi),
            gamma,
            integral,
            input_epoch: self.input_epoch,
            a: Arc::new(a),
            e,
            h,
            omega,
            long,
            lower,
            events: !self.functionals.is_empty(),
            shared: false,
        })
    }

    /// A branch whose `A` equals that of one built before with as many switch functions (the
    /// drive stepped, the contacts and positions did not): that one's exponential, step and
    /// spectral radius, and `gamma` as `int_0^h exp(A s) ds e` with the integral built once
    /// for all such branches. `None` when no branch has this `A`. The earliest such branch
    /// is taken, so a run's result does not depend on the order of a hash map.
    fn same_flow_branch(&mut self, a: &DMatrix<f64>, e: &DVector<f64>) -> Option<Branch> {
        let code = self.branch_code();
        let events = !self.functionals.is_empty();
        // only branches built afresh: a shared one has its donor's `A`
        let donor = self
            .index
            .iter()
            .filter(|((_, c), i)| *c == code && !self.branches[**i].shared)
            .map(|(_, &i)| i)
            .filter(|&i| self.branches[i].events == events && *self.branches[i].a == *a)
            .min()?;
        Some(self.shared_branch(donor, e.clone()))
    }

    /// A branch with the `donor`'s `A`, exponential, step and spectral radius and its own
    /// `e`: `gamma` is `int_0^h exp(A s) ds e`, the integral built once for all of them.
    fn shared_branch(&mut self, donor: usize, e: DVector<f64>) -> Branch {
        let integral = match self.branches[donor].integral.clone() {
            Some(integral) => integral,
            None => {
                let d = &self.branches[donor];
                let integral = Arc::new(balanced_input_flow(&d.a, d.h, d.omega));
                self.stats.exponentials += 1;
                self.branches[donor].integral = Some(integral.clone());
                integral
            }
        };
        let d = &self.branches[donor];
        let mut gamma = DVector::zeros(e.len());
        mat_vec(&integral, e.as_slice(), 1.0, gamma.as_mut_slice());
        // the same `A`: first-order form as the donor's, if `e`'s upper half is zero too
        let upper_free = e.rows(0, e.len() / 2).iter().all(|&v| v == 0.0);
        Branch {
            phi: d.phi.clone(),
            gamma,
            integral: Some(integral),
            input_epoch: self.input_epoch,
            a: d.a.clone(),
            e,
            h: d.h,
            omega: d.omega,
            long: d.long.as_ref().map(|l| LongStep {
                h: l.h,
                fast: l.fast.clone(),
                flow: None,
            }),
            lower: d.lower.clone().filter(|_| upper_free),
            events: d.events,
            shared: true,
        }
    }

    /// The long step of a branch with closed contacts (its eigenvalues, its short step `h`),
    /// as [`long_step_split`] gives it; `None` where that gives no longer step. Its flow is
    /// built on first use ([`Self::long_flow`]).
    fn long_step_of(&self, eigen: &[Complex<f64>], h: f64) -> Option<LongStep> {
        if self.functionals.is_empty() {
            return None;
        }
        let closed = self
            .tracker
            .states()
            .iter()
            .filter(|&&s| s != ContactState::Free)
            .count();
        let (fast, long) = long_step_split(eigen, closed, self.span.sample)?;
        (long > h).then_some(LongStep {
            h: long,
            fast,
            flow: None,
        })
    }

    /// Builds the flow and fast modes of `branch`'s long step if not yet built; drops the
    /// long step when its eigenvectors do not converge. True when the branch has one.
    fn long_flow(&mut self, branch: usize) -> bool {
        let b = &self.branches[branch];
        let Some(long) = &b.long else {
            return false;
        };
        if long.flow.is_some() {
            return true;
        }
        let flow = FastModes::new(&b.a, &b.e, &long.fast, &self.g).map(|modes| {
            let (phi, gamma) = balanced_flow(&b.a, &b.e, long.h, b.omega);
            LongFlow { phi, gamma, modes }
        });
        self.stats.exponentials += u64::from(flow.is_some());
        let b = &mut self.branches[branch];
        match flow {
            Some(flow) => {
                b.long.as_mut().expect("checked above").flow = Some(flow);
                true
            }
            None => {
                b.long = None;
                false
            }
        }
    }

    /// The end of a long step of `branch` from `t`, when `t` lies on its grid from `anchor`
    /// and the step ends no later than `limit` (a sample, a drive step, the end; s).
    fn long_stop(&self, branch: usize, t: f64, anchor: f64, limit: f64) -> Option<f64> {
        let h = self.branches[branch].long.as_ref()?.h;
        let (on_grid, stop) = next_grid_point(t, anchor, h);
        if !on_grid {
            return None;
        }
        if stop > limit + 1e-9 * h {
            None
        } else if stop >= limit - 1e-9 * h {
            Some(limit)
        } else {
            Some(stop)
        }
    }

    /// A long step of `branch` from `t` to `stop`: true, with the state and gaps at its end
    /// in `y1` and `gaps1`, when every switch function is certified to stay positive over
    /// it; false (nothing taken) otherwise.
    fn long_step(&mut self, branch: usize, t: f64, stop: f64) -> Result<bool, SimError> {
        if !self.long_flow(branch) {
            return Ok(false);
        }
        let Some(LongStep {
            h,
            flow: Some(long),
            ..
        }) = self.branches[branch].long.as_ref()
        else {
            return Ok(false);
        };
        let h = *h;
        mat_vec(&long.phi, self.y.as_slice(), 1.0, self.y1.as_mut_slice());
        self.y1 += &long.gamma;
        self.check_size(t, stop - t)?;
        if !self.gaps0_current {
            Self::gaps(&self.g, self.n, &self.y, &mut self.gaps0);
            self.gaps0_current = true;
        }
        Self::gaps(&self.g, self.n, &self.y1, &mut self.gaps1);
        let k = long.modes.len();
        // (time only moves forward: the same branch and time means the same state)
        if self.modal0_at != Some((branch, t)) {
            long.modes.coordinates(&self.y, &mut self.modal0[..k]);
        }
        long.modes.coordinates(&self.y1, &mut self.modal1[..k]);
        let start = StepEnd {
            gap: &self.gaps0.value,
            rate: &self.gaps0.rate,
            modal: &self.modal0[..k],
        };
        let end = StepEnd {
            gap: &self.gaps1.value,
            rate: &self.gaps1.rate,
            modal: &self.modal1[..k],
        };
        let certified = self
            .functionals
            .iter()
            .all(|&f| long.modes.certifies(f, h, &start, &end));
        if certified {
            self.stats.steps += 1;
            self.stats.long_steps += 1;
            self.taylor_len = 0;
            std::mem::swap(&mut self.modal0, &mut self.modal1);
            self.modal0_at = Some((branch, stop));
        }
        Ok(certified)
    }

    /// Taylor vectors `u_j` of the flow of `branch` from `y`, enough for steps up to `tau`.
    fn expand(&mut self, branch: usize, tau: f64) -> Result<(), SimError> {
        let b = &self.branches[branch];
        self.taylor[0].copy_from(&self.y);
        {
            let (first, rest) = self.taylor.split_at_mut(1);
            b.apply(&first[0], &mut rest[0], 1.0);
            rest[0] += &b.e;
        }
        let size = self.taylor[0].amax().max(tau * self.taylor[1].amax());
        let mut power = tau;
        let mut small_terms = 0;
        for j in 2..MAX_TAYLOR_TERMS {
            let (done, rest) = self.taylor.split_at_mut(j);
            b.apply(&done[j - 1], &mut rest[0], 1.0 / j as f64);
            power *= tau;
            if power * rest[0].amax() <= 1e-18 * size {
                small_terms += 1;
                if small_terms == 2 {
                    self.taylor_len = j + 1;
                    self.stats.taylor_terms += j as u64;
                    return Ok(());
                }
            } else {
                small_terms = 0;
            }
        }
        Err(SimError::Settings(format!(
            "method exact: the Taylor series of a partial step of {tau:.3e} s did not converge \
             in {MAX_TAYLOR_TERMS} terms (spectral radius {:.3e} rad/s)",
            b.omega
        )))
    }

    /// `y1 = sum_j tau^j u_j` (Horner).
    fn sum_taylor(&mut self, tau: f64) {
        let last = self.taylor_len - 1;
        self.y1.copy_from(&self.taylor[last]);
        for j in (0..last).rev() {
            self.y1 *= tau;
            self.y1 += &self.taylor[j];
        }
    }

    /// Gaps and gap rates of every contact at `y` (m, m/s), into `xi`.
    fn gaps(g: &DMatrix<f64>, n: usize, y: &DVector<f64>, xi: &mut Gaps) {
        xi.value.gemv_tr(1.0, g, &y.rows(0, n), 0.0);
        xi.rate.gemv_tr(1.0, g, &y.rows(n, n), 0.0);
    }

    /// Looks for the first band-edge crossing in the step `[t, t + tau]` from `y` to `y1`.
    /// On a crossing, leaves the state just past it in `y1` and returns its offset from `t`.
    fn find_event(&mut self, branch: usize, t: f64, tau: f64) -> Result<Option<f64>, SimError> {
        if self.functionals.is_empty() {
            return Ok(None);
        }
        if !self.gaps0_current {
            Self::gaps(&self.g, self.n, &self.y, &mut self.gaps0);
        }
        Self::gaps(&self.g, self.n, &self.y1, &mut self.gaps1);
        let (g0, g1) = (&self.gaps0, &self.gaps1);
        // the switch functions whose end value or Hermite interpolant says they cross: the
        // others are taken not to, as on a step without any (the step length's guarantee)
        let mut any = false;
        for (f, suspect) in self.functionals.iter().zip(self.suspects.iter_mut()) {
            let c = f.contact;
            let f1 = f.sign * g1.value[c] + f.offset;
            let (f0, d0) = (f.sign * g0.value[c] + f.offset, f.sign * g0.rate[c]);
            *suspect = f1 < 0.0
                || (d0 < 0.0
                    && HermiteCubic::new(f0, d0 * tau, f1, f.sign * g1.rate[c] * tau).dips());
            any |= *suspect;
        }
        if !any {
            return Ok(None);
        }
        if self.taylor_len == 0 {
            self.expand(branch, tau)?;
        }
        // the earliest first sign change over the suspect switch functions
        let mut best: Option<f64> = None;
        let tol = 4.0 * f64::EPSILON * t.abs().max(1.0);
        for i in 0..self.functionals.len() {
            if !self.suspects[i] {
                continue;
            }
            let f = self.functionals[i];
            self.switch_polynomial(f);
            let mut p = |x: f64| horner(&self.coefficients[..self.taylor_len], x);
            let limit = best.unwrap_or(tau);
            if let Some(root) = first_crossing(&mut p, limit, SCAN_POINTS, tol) {
                best = Some(root);
            }
        }
        let Some(mut tau_hi) = best else {
            // a false alarm of the Hermite check, or rounding at the step end
            return Ok(None);
        };
        // the state just past the crossing: the switch function must be negative there
        let mut nudge = 4.0 * f64::EPSILON * t.abs().max(1.0);
        for _ in 0..64 {
            self.sum_taylor(tau_hi);
            let y1 = self.y1.as_slice();
            if self.tracker.min_switch_value(self.model, t + tau_hi, y1) < 0.0 {
                return Ok(Some(tau_hi));
            }
            tau_hi += nudge;
            nudge *= 2.0;
        }
        Ok(Some(tau_hi))
    }

    /// Coefficients of switch function `f` along the expanded flow.
    fn switch_polynomial(&mut self, f: SwitchFunction) {
        let gc = self.g.column(f.contact);
        for j in 0..self.taylor_len {
            self.coefficients[j] = f.sign * gc.dot(&self.taylor[j].rows(0, self.n));
        }
        self.coefficients[0] += f.offset;
    }

    /// Output sample at `t` from the state `y` of `branch`.
    fn emit(&mut self, branch: usize, t: f64, observe: &mut Observer) {
        let b = &self.branches[branch];
        b.apply(&self.y, &mut self.ydot, 1.0);
        self.ydot += &b.e;
        observe(t, self.y.as_slice(), self.ydot.as_slice());
    }

    fn check_size(&self, t: f64, tau: f64) -> Result<(), SimError> {
        // one pass: NaN fails the comparison, an infinity exceeds the limit
        let (z, zd) = self.y1.as_slice().split_at(self.n);
        let within = |v: &f64| v.abs() <= self.size_limit;
        if z[0].is_finite() && z[1..].iter().all(within) && zd.iter().all(|v| v.is_finite()) {
            return Ok(());
        }
        Err(SimError::Diverged {
            t,
            method: "exact".into(),
            h: tau,
            cause: format!(
                "the exact solution grows beyond any physical size; {}",
                super::diagnosis::growth_cause(self.model, t, &self.span)
            ),
        })
    }
}

/// `exp(A h)` and `int_0^h exp(A s) ds e` for `A = [[0, I], [A_vz, A_vv]]`-shaped systems,
/// computed on velocities scaled by `1 / omega`: the similarity `D A D^-1` with
/// `D = diag(I, I / omega)` has norm ~`omega` instead of ~`omega^2`, and the rounding error
/// of scaling and squaring grows with that norm (measured on adams-linear: 5e-10 m of
/// `tip_rel` over 2 s unscaled).
pub(super) fn balanced_flow(
    a: &DMatrix<f64>,
    e: &DVector<f64>,
    h: f64,
    omega: f64,
) -> (DMatrix<f64>, DVector<f64>) {
    let n2 = a.nrows();
    let n = n2 / 2;
    let s = omega.max(1.0);
    let scale = |i: usize| if i < n { 1.0 } else { 1.0 / s };
    let mut aug = DMatrix::zeros(n2 + 1, n2 + 1);
    for j in 0..n2 {
        for i in 0..n2 {
            aug[(i, j)] = scale(i) * a[(i, j)] / scale(j) * h;
        }
        aug[(j, n2)] = scale(j) * e[j] * h;
    }
    let flow = aug.exp();
    let phi = DMatrix::from_fn(n2, n2, |i, j| flow[(i, j)] / scale(i) * scale(j));
    let gamma = DVector::from_fn(n2, |i, _| flow[(i, n2)] / scale(i));
    (phi, gamma)
}

/// `int_0^h exp(A s) ds`, the flow of every constant input at once, from the exponential of
/// `[[A, I], [0, 0]] h` balanced as [`balanced_flow`] balances its own.
fn balanced_input_flow(a: &DMatrix<f64>, h: f64, omega: f64) -> DMatrix<f64> {
    let n2 = a.nrows();
    let n = n2 / 2;
    let s = omega.max(1.0);
    let scale = |i: usize| if i < n { 1.0 } else { 1.0 / s };
    let mut aug = DMatrix::zeros(2 * n2, 2 * n2);
    for j in 0..n2 {
        for i in 0..n2 {
            aug[(i, j)] = scale(i) * a[(i, j)] / scale(j) * h;
        }
        aug[(j, n2 + j)] = h;
    }
    let flow = aug.exp();
    DMatrix::from_fn(n2, n2, |i, j| flow[(i, n2 + j)] * scale(j) / scale(i))
}

/// `out = scale a x` for a column-major `a`, four columns per pass over `out`: the exact
/// stepper's hot loop (the flow of a regular step, each Taylor term).
///
/// Hand-written: nalgebra's `gemv` on these dynamically sized 10-40 row matrices and vector
/// views took about 1500 instructions for a 10 x 20 product against 930 here (cachegrind, the
/// whole CLI run: adams-clearance 207 -> 184 million instructions, three-section 1607 -> 1501
/// million).
fn mat_vec(a: &DMatrix<f64>, x: &[f64], scale: f64, out: &mut [f64]) {
    let rows = a.nrows();
    out.fill(0.0);
    let mut columns = a.as_slice().chunks_exact(4 * rows);
    let mut j = 0;
    for block in columns.by_ref() {
        let (c0, rest) = block.split_at(rows);
        let (c1, rest) = rest.split_at(rows);
        let (c2, c3) = rest.split_at(rows);
        let s = [
            scale * x[j],
            scale * x[j + 1],
            scale * x[j + 2],
            scale * x[j + 3],
        ];
        for ((((o, a0), a1), a2), a3) in out.iter_mut().zip(c0).zip(c1).zip(c2).zip(c3) {
            *o += (a0 * s[0] + a1 * s[1]) + (a2 * s[2] + a3 * s[3]);
        }
        j += 4;
    }
    for column in columns.remainder().chunks_exact(rows) {
        let s = scale * x[j];
        for (o, &aij) in out.iter_mut().zip(column) {
            *o += aij * s;
        }
        j += 1;
    }
}

fn horner(c: &[f64], x: f64) -> f64 {
    c.iter().rev().fold(0.0, |acc, &cj| acc * x + cj)
}
