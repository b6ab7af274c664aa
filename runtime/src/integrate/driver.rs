//! The time loop shared by every method: step-size control, drive discontinuities, contact
//! events, sampling, divergence checks.

use super::events::{HermiteCubic, newton_in_bracket};
use super::stability::{closed_contact_step_cap, stable_h_rho, stable_step};
use super::{
    ContactTracker, Method, Observer, Progress, RunStats, SampleGrid, Settings, SimError,
    StepControl, StepFailure, Stepper, System, make_stepper,
};
use crate::analysis::eigen::{fastest_rates, modal_analysis};
use crate::model::Model;
use crate::scene::TimeSpan;

/// Consecutive Newton failures (each followed by a 4x shorter step) before giving up.
const MAX_NEWTON_FAILURES: u32 = 12;

/// What an accepted step did.
struct AcceptedStep {
    /// Its length (s), shortened to a switch it located.
    h: f64,
    /// Whether it ended on a contact switch.
    switched: bool,
    /// Whether it ended on a profile breakpoint.
    at_break: bool,
    /// Whether a contact closed at its end.
    closed_one: bool,
}

/// Largest growth of a capped step from one step to the next while a contact is closed.
/// There dop853 steps near its stability limit, where a ringing contact mode's error grows
/// far faster than `h^8`: free growth (up to 5x at small errors) is rejected from 1.2-1.5
/// times the last step on (docs/numerics.md, "Contact events").
const CAPPED_GROWTH: f64 = 1.1;

/// The first capped step after a contact closes, as a fraction of the cap: the impact sets
/// the contact mode ringing, and a step at the cap carried over from before was rejected
/// once after almost every closing (its error some 1e4 tolerances), then cut to about this.
const FIRST_STEP_AFTER_CLOSING: f64 = 0.3;

/// Where an [`Integrator::advance_to`](super::Integrator::advance_to) call ended.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Stop {
    /// At the time asked for.
    Reached,
    /// Just after a contact switch at this time (s), before the time asked for (only when
    /// asked to stop there).
    Switch(f64),
    /// The progress callback asked to stop at this time (s).
    Stopped(f64),
}

/// The step loop's memory between two [`Driver::advance_to`] calls.
#[derive(Debug, Clone, Copy)]
struct LoopMemory {
    /// Whether the first sample is out.
    started: bool,
    newton_failures: u32,
    /// After a rejection the next step may not grow (Hairer's dopri5 rule: at the stability
    /// boundary growing again at once is rejected again).
    just_rejected: bool,
    /// The last accepted step's error for the PI controller (Hairer's start value 1e-4).
    err_old: f64,
    next_break: usize,
    last_report: f64,
}

pub(super) struct Driver<'m> {
    memory: LoopMemory,
    /// Stop just after a contact switch ([`Stop::Switch`]).
    stop_on_switch: bool,
    /// Where the current [`Driver::advance_to`] call ends (s), at most the span's end.
    target: f64,
    sys: System<'m>,
    method: Method,
    stepper: Box<dyn Stepper>,
    settings: Settings,
    span: TimeSpan,
    /// Times after the start where the drive or a position profile is not smooth, sorted
    /// (those beyond the current end wait for a later [`Driver::advance_to`]).
    breakpoints: Vec<f64>,
    /// Whether a profile is not smooth exactly at the span's end.
    end_is_break: bool,
    /// `(section k, min, max)`: `a_k` must stay in `[min, max)`.
    position_ranges: Vec<(usize, f64, f64)>,
    /// A displacement coordinate beyond this (m) means divergence.
    size_limit: f64,
    t: f64,
    y: Vec<f64>,
    f0: Vec<f64>,
    y1: Vec<f64>,
    f1: Vec<f64>,
    y_trial: Vec<f64>,
    y_sample: Vec<f64>,
    ydot_sample: Vec<f64>,
    /// Switch functions (m) and rates (m/s) of every contact at a step's start and end.
    switch_start: (Vec<f64>, Vec<f64>),
    switch_end: (Vec<f64>, Vec<f64>),
    h: f64,
    next_sample: u64,
    samples: SampleGrid,
    /// Largest step (s) while a contact is closed ([`closed_contact_step_cap`]).
    step_cap: f64,
}

/// Refuses settings `method` cannot run with: a fixed step without `dt`, a step that is not
/// a positive number of seconds, tolerances that are not positive with rtol < 1, a longest
/// step that is not a positive number of seconds.
fn check_settings(method: Method, settings: &Settings) -> Result<(), SimError> {
    let control = method.step_control();
    match (control, settings.dt) {
        (StepControl::Fixed, None) => {
            return Err(SimError::Settings(format!(
                "method {method} has a fixed step: give the step dt (s)"
            )));
        }
        (_, Some(dt)) if !(dt > 0.0 && dt.is_finite()) => {
            return Err(SimError::Settings(format!(
                "the step dt must be a positive number of seconds (got {dt})"
            )));
        }
        _ => {}
    }
    if control == StepControl::Adaptive
        && !(settings.rtol > 0.0 && settings.atol > 0.0 && settings.rtol < 1.0)
    {
        return Err(SimError::Settings(format!(
            "tolerances must be positive with rtol < 1 (got rtol = {}, atol = {})",
            settings.rtol, settings.atol
        )));
    }
    if let Some(longest) = settings.longest_step
        && !(longest > 0.0 && longest.is_finite())
    {
        return Err(SimError::Settings(format!(
            "the longest step must be a positive number of seconds (got {longest})"
        )));
    }
    Ok(())
}

impl<'m> Driver<'m> {
    pub(super) fn new(
        model: &'m dyn Model,
        y0: &[f64],
        span: &TimeSpan,
        method: Method,
        settings: &Settings,
    ) -> Result<Self, SimError> {
        let n = model.dof();
        check_settings(method, settings)?;
        let params = model.params();
        let mut breakpoints: Vec<f64> = params
            .positions
            .iter()
            .flat_map(|p| p.breakpoints())
            .chain(params.drive_profile().breakpoints())
            .filter(|&b| b > span.start)
            .collect();
        breakpoints.sort_by(f64::total_cmp);
        breakpoints.dedup();
        // a profile that changes exactly at the end (a run handing over to exact stepping
        // where the positions come to rest): the last step sees its left limit too
        let end_is_break = breakpoints.contains(&span.end);
        let position_ranges = (1..params.sections.len())
            .map(|k| {
                let (below, above) = (params.sections[k - 1].length, params.sections[k].length);
                (k + 1, below - below.min(above), below)
            })
            .collect();
        let size_limit = 100.0 * params.sections.iter().map(|s| s.length).sum::<f64>();
        let tracker = ContactTracker::new(model, span.start, y0);
        let contacts = model.layout().contact_count();
        let mut sys = System {
            model,
            tracker,
            stats: RunStats::default(),
            time_cap: f64::INFINITY,
        };
        let mut f0 = vec![0.0; 2 * n];
        sys.rhs(span.start, y0, &mut f0);
        // the cap of a capped method; dop853-imex reads it even when the driver does not cap
        // (`Settings::step_cap` off)
        let cap = closed_contact_step_cap(model, method, span);
        let step_cap = cap.filter(|_| settings.step_cap);
        sys.stats.step_cap = step_cap;
        Ok(Driver {
            memory: LoopMemory {
                started: false,
                newton_failures: 0,
                just_rejected: false,
                err_old: 1e-4,
                next_break: 0,
                last_report: span.start,
            },
            stop_on_switch: false,
            target: span.end,
            stepper: make_stepper(
                method,
                n,
                settings,
                cap,
                settings.longest_step.unwrap_or(span.sample),
            ),
            sys,
            method,
            settings: *settings,
            span: *span,
            breakpoints,
            end_is_break,
            position_ranges,
            size_limit,
            t: span.start,
            y: y0.to_vec(),
            f0,
            y1: vec![0.0; 2 * n],
            f1: vec![0.0; 2 * n],
            y_trial: vec![0.0; 2 * n],
            y_sample: vec![0.0; 2 * n],
            ydot_sample: vec![0.0; 2 * n],
            switch_start: (vec![0.0; contacts], vec![0.0; contacts]),
            switch_end: (vec![0.0; contacts], vec![0.0; contacts]),
            h: 0.0,
            next_sample: 0,
            samples: SampleGrid::new(span),
            step_cap: step_cap.unwrap_or(f64::INFINITY),
        })
    }

    fn adaptive(&self) -> bool {
        self.method.step_control() == StepControl::Adaptive
    }

    /// Hairer & Wanner's starting step for an adaptive method.
    fn initial_step(&mut self) -> f64 {
        let (rtol, atol) = (self.settings.rtol, self.settings.atol);
        let scale = |v: f64| atol + rtol * v.abs();
        let rms = |a: &[f64], b: &[f64]| {
            (a.iter()
                .zip(b)
                .map(|(x, yv)| (x / scale(*yv)).powi(2))
                .sum::<f64>()
                / a.len() as f64)
                .sqrt()
        };
        let d0 = rms(&self.y, &self.y);
        let d1 = rms(&self.f0, &self.y);
        let h0 = if d0 < 1e-5 || d1 < 1e-5 {
            1e-6
        } else {
            0.01 * d0 / d1
        };
        for i in 0..self.y.len() {
            self.y_trial[i] = self.y[i] + h0 * self.f0[i];
        }
        self.sys.rhs(self.t + h0, &self.y_trial, &mut self.f1);
        let diff: Vec<f64> = self.f1.iter().zip(&self.f0).map(|(a, b)| a - b).collect();
        let d2 = rms(&diff, &self.y) / h0;
        let order = self.stepper.order() as f64 + 1.0;
        let h1 = if d1.max(d2) <= 1e-15 {
            (h0 * 1e-3).max(1e-6)
        } else {
            (0.01 / d1.max(d2)).powf(1.0 / order)
        };
        (100.0 * h0).min(h1).min(self.target - self.span.start)
    }

    /// Integrates over the whole span given to [`Driver::new`].
    pub(super) fn run(
        &mut self,
        mut observe: Observer,
        progress: Option<Progress>,
    ) -> Result<RunStats, SimError> {
        match self.advance_to(self.span.end, &mut observe, progress)? {
            Stop::Stopped(t) => Err(SimError::Stopped {
                t,
                method: self.method.name(),
            }),
            Stop::Reached | Stop::Switch(_) => Ok(self.sys.stats.clone()),
        }
    }

    /// Whether [`Driver::advance_to`] returns just after each contact switch.
    pub(super) fn set_stop_on_switch(&mut self, stop: bool) {
        self.stop_on_switch = stop;
    }

    /// The time reached (s), the state there and the counts so far.
    pub(super) fn now(&self) -> (f64, &[f64], &RunStats) {
        (self.t, &self.y, &self.sys.stats)
    }

    /// The model's input changed at the current time (a held force set anew): the
    /// derivative there is evaluated again and the method restarts, as at a drive
    /// discontinuity; the step size is kept.
    pub(super) fn input_changed(&mut self) {
        self.stepper.restart();
        let (t, y) = (self.t, &self.y);
        self.sys.rhs(t, y, &mut self.f0);
        self.memory.err_old = 1e-4;
    }

    /// Aims the next steps at `end` (s), moving the end of the span there when it lies
    /// beyond it (the sample grid goes on from the span's start).
    fn aim_at(&mut self, end: f64) {
        if end > self.span.end {
            let old = self.samples;
            self.span.end = end;
            self.samples = SampleGrid::new(&self.span);
            // the old end off the grid was a sample of its own: the grid point after it is not
            if self.next_sample == old.total && !old.ends_on_sample() {
                self.next_sample -= 1;
            }
        }
        self.target = end;
        self.end_is_break = self.breakpoints.contains(&end);
    }

    /// Integrates from the time reached to `end` (s), calling `observe` at every sample
    /// time on the way (the first call also at the start): the step size, the method's
    /// factorizations and the contact states carry over from the last call.
    pub(super) fn advance_to(
        &mut self,
        end: f64,
        observe: &mut Observer,
        mut progress: Option<Progress>,
    ) -> Result<Stop, SimError> {
        self.aim_at(end);
        if !self.memory.started {
            observe(self.t, &self.y, &self.f0);
            self.next_sample = 1;
            self.memory.started = true;
        }
        // the first step, once there is somewhere to go
        if self.h == 0.0 && self.t < end {
            self.h = match (self.settings.dt, self.adaptive()) {
                (Some(dt), _) => dt,
                (None, true) => self.initial_step(),
                (None, false) => unreachable!("checked in new"),
            };
            self.check_first_step()?;
        }
        while self.t < end {
            let step = self.one_step(&mut *observe)?;
            if let Some(p) = progress.as_mut()
                && self.t - self.memory.last_report >= 0.01 * (self.span.end - self.span.start)
            {
                if !p(self.t) {
                    return Ok(Stop::Stopped(self.t));
                }
                self.memory.last_report = self.t;
            }
            if step.is_some_and(|s| s.switched) && self.stop_on_switch && self.t < end {
                return Ok(Stop::Switch(self.t));
            }
        }
        Ok(Stop::Reached)
    }

    /// One trial step toward the span's end: the accepted step, or `None` when it was
    /// rejected (the next trial's size is set).
    #[inline]
    fn one_step(&mut self, observe: &mut Observer) -> Result<Option<AcceptedStep>, SimError> {
        self.check_step_count()?;
        let mut next_break = self.memory.next_break;
        let (t_break, t_stop) = self.next_stops(&mut next_break);
        self.memory.next_break = next_break;
        let end = self.target;
        // only dop853 (and dop853-imex's dop853 part) has a cap; skip the branch scan for
        // every other method
        let capped = self.step_cap < f64::INFINITY
            && !self.stepper.over_contact_modes()
            && self.sys.tracker.any_closed();
        if capped {
            self.h = self.h.min(self.step_cap);
        }
        if let Some(longest) = self.settings.longest_step {
            self.h = self.h.min(longest);
        }
        let remaining = t_stop - self.t;
        // never leave a sliver before a stop
        let h = if self.h >= remaining * (1.0 - 1e-9) {
            remaining
        } else {
            self.h
        };
        let to_stop = h == remaining;
        let toward_break = to_stop && t_stop == t_break && (t_break < end || self.end_is_break);
        // the profiles' left limits apply up to a discontinuity
        self.sys.time_cap = if toward_break {
            t_break.next_down()
        } else {
            f64::INFINITY
        };
        let h_min = 16.0 * f64::EPSILON * self.t.abs().max(1.0);
        let outcome = self
            .stepper
            .step(&mut self.sys, self.t, &self.y, &self.f0, h, &mut self.y1);
        let err = match outcome {
            Ok(e) => {
                self.memory.newton_failures = 0;
                e
            }
            Err(StepFailure::NewtonDiverged) => {
                self.memory.newton_failures += 1;
                self.sys.stats.rejected += 1;
                let failures = self.memory.newton_failures;
                // a fixed step does not shrink: the first failure is final
                if !self.adaptive() || failures >= MAX_NEWTON_FAILURES || h / 4.0 < h_min {
                    return Err(self.newton_failure(h, failures));
                }
                self.h = h / 4.0;
                self.memory.just_rejected = true;
                return Ok(None);
            }
        };
        let finite = self.y1.iter().all(|v| v.is_finite());
        if self.adaptive() && (!finite || err > 1.0) {
            self.reject(h, err, finite, h_min)?;
            self.memory.just_rejected = true;
            return Ok(None);
        }
        self.check_size(h, finite)?;
        let step = self.accept(h, remaining, t_stop, toward_break, observe)?;
        if self.adaptive() {
            let LoopMemory {
                err_old,
                just_rejected,
                ..
            } = self.memory;
            self.memory.err_old =
                self.next_step_size(&step, err, err_old, just_rejected, capped, to_stop);
            self.memory.just_rejected = false;
        }
        Ok(Some(step))
    }

    /// Accepts the trial step of `h` (s) in `y1`: locates a contact switch inside it (which
    /// shortens it), emits the samples it passes, moves the state to its end and switches
    /// the contacts; `remaining` is the time to `t_stop`, the step's target.
    #[inline]
    fn accept(
        &mut self,
        mut h: f64,
        remaining: f64,
        t_stop: f64,
        toward_break: bool,
        observe: &mut Observer,
    ) -> Result<AcceptedStep, SimError> {
        // contact events inside the step
        let mut switched = false;
        let model = self.sys.model;
        if self
            .sys
            .tracker
            .min_switch_value(model, self.t + h, &self.y1)
            < 0.0
        {
            h = self.locate_switch(h);
            switched = true;
        }
        let t1 = if h == remaining { t_stop } else { self.t + h };
        // toward a break, the stop is the break
        let at_break = toward_break && t1 == t_stop;
        match (switched, self.stepper.end_derivative()) {
            (false, Some(f)) => self.f1.copy_from_slice(f),
            _ => {
                let (t_eval, y1) = (t1, &self.y1);
                self.sys.rhs(t_eval, y1, &mut self.f1);
            }
        }
        self.emit_samples(t1, observe);
        self.check_positions(t1)?;
        self.sys.stats.steps += 1;
        if self.stepper.over_contact_modes() {
            self.sys.stats.long_steps += 1;
        }
        self.stepper.accepted();
        self.t = t1;
        std::mem::swap(&mut self.y, &mut self.y1);
        self.sys.time_cap = f64::INFINITY;
        let mut closed_one = false;
        if switched {
            let closed_before = self.sys.tracker.closed_count();
            self.sys.stats.switches += self.sys.tracker.switch(model, self.t, &self.y);
            closed_one = self.sys.tracker.closed_count() > closed_before;
        }
        if switched || at_break {
            self.stepper.restart();
            let (t, y) = (self.t, &self.y);
            self.sys.rhs(t, y, &mut self.f0);
        } else {
            std::mem::swap(&mut self.f0, &mut self.f1);
        }
        Ok(AcceptedStep {
            h,
            switched,
            at_break,
            closed_one,
        })
    }

    /// The next step size of an adaptive method after `step` with error `err` (the last
    /// accepted step's control error `err_old`); returns the control error to carry on.
    #[inline]
    fn next_step_size(
        &mut self,
        step: &AcceptedStep,
        err: f64,
        err_old: f64,
        just_rejected: bool,
        capped: bool,
        to_stop: bool,
    ) -> f64 {
        let restart = step.switched || step.at_break;
        // a step cut short by an event or a stop says nothing about the next one
        let base = if step.switched || to_stop {
            self.h.max(step.h)
        } else {
            step.h
        };
        let control = self.stepper.control_error(err);
        let factor = self.pi_factor(control, err_old, self.growth_limit(capped));
        self.h = base
            * if just_rejected {
                factor.min(1.0)
            } else {
                factor
            };
        if step.closed_one {
            self.h = self.h.min(FIRST_STEP_AFTER_CLOSING * self.step_cap);
        }
        // a restart forgets the history, as at the start
        if restart { 1e-4 } else { control }
    }

    /// The next profile breakpoint after `t` (advancing `next_break` to it) and the next
    /// time a step must end on, `(t_break, t_stop)` (s): the breakpoint or, for adaptive
    /// methods, the next sample time, whichever comes first (adaptive methods end steps on
    /// sample times, so samples carry the method's own accuracy, unless
    /// `Settings::longest_step` lets them cross samples; fixed-step methods keep their grid
    /// and interpolate).
    #[inline]
    fn next_stops(&self, next_break: &mut usize) -> (f64, f64) {
        let end = self.target;
        while *next_break < self.breakpoints.len() && self.breakpoints[*next_break] <= self.t {
            *next_break += 1;
        }
        let t_break = self
            .breakpoints
            .get(*next_break)
            .copied()
            .filter(|&b| b < end)
            .unwrap_or(end);
        let t_sample = if self.adaptive()
            && self.settings.longest_step.is_none()
            && self.next_sample < self.samples.total
        {
            self.samples.time(self.next_sample).min(end)
        } else {
            end
        };
        (t_break, t_break.min(t_sample))
    }

    /// The first step must be above the floor of `f64` at the start time.
    fn check_first_step(&self) -> Result<(), SimError> {
        let h_floor = 16.0 * f64::EPSILON * self.t.abs().max(1.0);
        if self.h >= h_floor {
            return Ok(());
        }
        Err(SimError::StepUnderflow {
            t: self.t,
            method: self.method.name(),
            h: self.h,
            h_min: h_floor,
            cause: format!(
                "the state changes too fast at the start for any step; {}",
                super::diagnosis::growth_cause(self.sys.model, self.t, &self.span)
            ),
        })
    }

    /// The run stops at the step limit, with the likely cause, or over its work budget.
    fn check_step_count(&self) -> Result<(), SimError> {
        let stats = &self.sys.stats;
        // counted only under a finite budget (the default has none)
        let operations = match self.settings.max_operations.is_finite() {
            true => stats.operations_over(self.y.len()),
            false => 0.0,
        };
        if operations > self.settings.max_operations {
            return Err(SimError::OverBudget {
                t: self.t,
                method: self.method.name(),
                operations,
                budget: self.settings.max_operations,
            });
        }
        if stats.steps + stats.rejected < self.settings.max_steps {
            return Ok(());
        }
        Err(SimError::TooManySteps {
            t: self.t,
            method: self.method.name(),
            steps: stats.steps + stats.rejected,
            cause: self.too_many_steps_cause(),
        })
    }

    /// The error of a Newton iteration that failed `attempts` times on a step of `h` (s).
    #[cold]
    fn newton_failure(&self, h: f64, attempts: u32) -> SimError {
        let remedy = if self.adaptive() {
            ""
        } else {
            "; a fixed step cannot be cut: take a smaller step dt or the adaptive galpha"
        };
        let stiffness = self
            .stiffness(h)
            .map_or("stiffness unknown".into(), |s| s.describe(self.method));
        SimError::NewtonFailure {
            t: self.t,
            method: self.method.name(),
            h,
            attempts,
            cause: format!(
                "the Jacobian does not describe the step (a contact switch inside it, or a \
                 singular iteration matrix){remedy}; {stiffness}"
            ),
        }
    }

    /// A rejected adaptive step of `h` (s) with error `err`: the next trial step, or an
    /// error when it falls below `h_min`.
    fn reject(&mut self, h: f64, err: f64, finite: bool, h_min: f64) -> Result<(), SimError> {
        self.sys.stats.rejected += 1;
        self.h = h * if finite { self.step_factor(err) } else { 0.1 };
        if self.h >= h_min {
            return Ok(());
        }
        Err(SimError::StepUnderflow {
            t: self.t,
            method: self.method.name(),
            h: self.h,
            h_min,
            cause: "the tolerance is too tight for f64 at this time, or the contacts chatter \
                    faster than any step can follow"
                .into(),
        })
    }

    /// Shortens the step `h` so that it ends just past the first band-edge crossing. Every
    /// trial is a full step of the method from the same start, so the state at the switch
    /// has the method's order. The first trial is the first root of the cubic Hermite
    /// interpolant of the switch functions (values and rates at both ends of the step); from
    /// there Newton's method on the step length, with the switch function's rate along the
    /// motion as derivative, kept inside the bracket (regula falsi where Newton does not
    /// converge). Leaves the state at the new end in `y1` and returns the new length.
    fn locate_switch(&mut self, h: f64) -> f64 {
        let model = self.sys.model;
        let (t, t1) = (self.t, self.t + h);
        let (v0, r0) = &mut self.switch_start;
        self.sys.tracker.switch_functions(model, t, &self.y, v0, r0);
        let (v1, r1) = &mut self.switch_end;
        self.sys
            .tracker
            .switch_functions(model, t1, &self.y1, v1, r1);
        let (v0, r0) = &self.switch_start;
        let (v1, r1) = &self.switch_end;
        let g_lo = v0.iter().copied().fold(f64::INFINITY, f64::min).max(0.0);
        let g_hi = v1.iter().copied().fold(f64::INFINITY, f64::min);
        // the earliest crossing of the interpolants of the contacts that end past their edge
        let first = (0..v0.len())
            .filter(|&c| v1[c] < 0.0)
            .filter_map(|c| {
                HermiteCubic::new(v0[c].max(0.0), r0[c] * h, v1[c], r1[c] * h).first_root()
            })
            .fold(f64::NAN, f64::min)
            * h;
        let tol = 4.0 * f64::EPSILON * self.t.abs().max(1.0);
        // a contact closing from a state where every contact is open is located on the
        // step's continuous extension (3 right-hand sides, then only the gaps along it,
        // instead of a whole step per trial): there the right-hand side is smooth over the
        // step and the extension lies within a thousandth of the tolerance of a trial step's
        // state; while a closed contact rings it does not (docs/benchmarks.md)
        let on_extension = !self.sys.tracker.any_closed()
            && self
                .stepper
                .prepare_extension(&mut self.sys, t, &self.y, &self.y1, h);
        let Driver {
            stepper,
            sys,
            y,
            f0,
            y1,
            y_trial,
            ..
        } = self;
        let mut trial = |tau: f64| {
            // a trial step: the result is only used through its switch functions, and kept
            // in y1 when it lands past the crossing (it is then the bracket's new end)
            if on_extension {
                stepper.extension_state(tau / h, y_trial);
            } else {
                let _ = stepper.step(sys, t, y, f0, tau, y_trial);
            }
            let (g, rate) = sys
                .tracker
                .min_switch_value_and_rate(model, t + tau, y_trial);
            if g < 0.0 {
                std::mem::swap(y1, y_trial);
            }
            (g, rate)
        };
        // a crossing within 100 rtol atol (m) past the band edge is found: it saves Newton's
        // last calls. Impacts amplify any difference tenfold every 40 ms, so how close to
        // the crossing a switch lands shows in the error: a fixed 1e-3 atol moved case-study's
        // error at rtol 1e-7 from 4e-11 to 2e-10 m inside the horizon, 0.1 atol at rtol 1e-5
        // from 7.5e-7 to 8e-6 m. Shrinking with rtol too, the location error vanishes against
        // the steps' own as the tolerance tightens: 1e-3 atol at rtol 1e-5, 1e-6 atol at
        // rtol 1e-8; below about rtol 3e-8 (atol 1e-3 rtol) it is under the switch
        // functions' rounding (1e-16 m) and the bracket's closing ends the search.
        // case-study's errors in its horizon equal those of a fixed 1e-6 atol at every
        // tolerance of the work-precision table
        let value_tol = 100.0 * self.settings.rtol * self.settings.atol;
        newton_in_bracket(&mut trial, (0.0, g_lo), (h, g_hi), first, tol, value_tol)
    }

    /// Step-size factor from a scaled error estimate (1 = at tolerance), in `[0.2, 5]`.
    fn step_factor(&self, err: f64) -> f64 {
        self.pi_factor(err, 1.0, self.growth_limit(false))
    }

    /// Largest factor by which the next step may grow: the stepper's, and at most
    /// [`CAPPED_GROWTH`] for a step held under the closed-contact cap.
    fn growth_limit(&self, capped: bool) -> f64 {
        let growth = self.stepper.growth_limit();
        if capped {
            growth.min(CAPPED_GROWTH)
        } else {
            growth
        }
    }

    /// Step-size factor of a PI controller (Gustafsson; Hairer's dopri5 form
    /// `0.9 err^-(1/(p+1) - 0.75 beta) err_old^beta`) from this step's error and the last
    /// accepted one's (both scaled, 1 = at tolerance, `err_old` at least 1e-4), in
    /// `[0.2, growth]`.
    fn pi_factor(&self, err: f64, err_old: f64, growth: f64) -> f64 {
        if err <= 0.0 {
            return growth;
        }
        let beta = self.stepper.pi_beta();
        let alpha = 1.0 / (self.stepper.order() as f64 + 1.0) - 0.75 * beta;
        (0.9 * err.powf(-alpha) * err_old.max(1e-4).powf(beta)).clamp(0.2, growth)
    }

    /// Samples at output times in `(t, t1]` from the cubic Hermite interpolant of the step.
    fn emit_samples(&mut self, t1: f64, observe: &mut Observer) {
        let (t0, h) = (self.t, t1 - self.t);
        while self.next_sample < self.samples.total && self.samples.time(self.next_sample) <= t1 {
            let ts = self.samples.time(self.next_sample);
            let th = (ts - t0) / h;
            let (th2, th3) = (th * th, th * th * th);
            let (h00, h10, h01, h11) = (
                2.0 * th3 - 3.0 * th2 + 1.0,
                th3 - 2.0 * th2 + th,
                -2.0 * th3 + 3.0 * th2,
                th3 - th2,
            );
            let (d00, d10, d01, d11) = (
                6.0 * th2 - 6.0 * th,
                3.0 * th2 - 4.0 * th + 1.0,
                -6.0 * th2 + 6.0 * th,
                3.0 * th2 - 2.0 * th,
            );
            for i in 0..self.y.len() {
                let (y0, f0, y1, f1) = (self.y[i], self.f0[i], self.y1[i], self.f1[i]);
                self.y_sample[i] = h00 * y0 + h10 * h * f0 + h01 * y1 + h11 * h * f1;
                self.ydot_sample[i] = (d00 * y0 + d01 * y1) / h + d10 * f0 + d11 * f1;
            }
            observe(ts, &self.y_sample, &self.ydot_sample);
            self.next_sample += 1;
        }
    }

    fn check_size(&self, h: f64, finite: bool) -> Result<(), SimError> {
        let n = self.sys.dof();
        let too_big = self.y1[1..n].iter().any(|v| v.abs() > self.size_limit);
        if finite && !too_big {
            return Ok(());
        }
        let what = if finite {
            format!(
                "a displacement coordinate exceeded {:.0} m (100 times the telescope's length)",
                self.size_limit
            )
        } else {
            "the state became non-finite".to_string()
        };
        let cause = match self.method.stability_limit() {
            Some(textbook) => {
                let omega_max = modal_analysis(self.sys.model, self.t)
                    .ok()
                    .and_then(|m| m.frequencies_hz.last().copied())
                    .map(|f| 2.0 * std::f64::consts::PI * f);
                let limit = omega_max.and_then(|w| {
                    stable_step(self.sys.model, self.method, self.t, w, self.span.sample)
                        .ok()
                        .map(|l| (w, l))
                });
                match limit {
                    Some((w, limit)) => {
                        if h > limit {
                            format!(
                                "{what}; the step {h:.3e} s is above the stability limit of {}: \
                                 the largest stable step on this model with closed contacts is \
                                 {limit:.3e} s (h omega_max = {:.3} for omega_max = {w:.4e} rad/s; \
                                 {textbook:.3} without damping); see `telescopic stability`",
                                self.method.name(),
                                limit * w
                            )
                        } else {
                            format!(
                                "{what}; the step is below the linear stability limit ({limit:.3e} s \
                                 for omega_max = {w:.4e} rad/s), so the blow-up comes from the \
                                 nonlinear contact law: take a smaller step or an adaptive method"
                            )
                        }
                    }
                    None => format!("{what}; take a smaller step"),
                }
            }
            None if matches!(
                self.method,
                Method::Bdf {
                    max_order: 3..,
                    adaptive: false
                }
            ) =>
            {
                format!(
                    "{what}; BDF of order 3 to 5 is not A-stable: with a fixed step, modes with \
                     h omega near the imaginary axis grow; take bdf2-fixed, galpha-fixed or a \
                     smaller step"
                )
            }
            None => format!(
                "{what}; {}",
                super::diagnosis::growth_cause(self.sys.model, self.t, &self.span)
            ),
        };
        Err(SimError::Diverged {
            t: self.t,
            method: self.method.name(),
            h,
            cause,
        })
    }

    fn check_positions(&self, t: f64) -> Result<(), SimError> {
        for (i, p) in self.sys.model.params().positions.iter().enumerate() {
            let (section, min, max) = self.position_ranges[i];
            let a = p.value(t);
            if !(a >= min && a < max) {
                return Err(SimError::PositionOutOfRange {
                    t,
                    method: self.method.name(),
                    section,
                    value: a,
                    min,
                    max,
                });
            }
        }
        Ok(())
    }

    fn too_many_steps_cause(&self) -> String {
        let steps = (self.sys.stats.steps + self.sys.stats.rejected).max(1);
        let mean = (self.t - self.span.start).max(0.0) / steps as f64;
        match self.stiffness(mean) {
            Some(s) if s.too_stiff() => s.describe(self.method),
            Some(s) if self.adaptive() => format!(
                "{}, so stiffness is not the cause: the tolerance is too tight or the contacts \
                 chatter; loosen the tolerances rtol/atol",
                s.describe(self.method)
            ),
            _ if self.adaptive() => "the tolerance is too tight or the contacts chatter; loosen \
                                     the tolerances rtol/atol"
                .into(),
            _ => "the fixed step is too small for the span; take a larger step dt".into(),
        }
    }

    /// The stiffest rate of the closed-contact system at the current time against a step `h`
    /// (s); `None` when the eigen analysis fails.
    fn stiffness(&self, h: f64) -> Option<StiffnessCheck> {
        let rates = fastest_rates(self.sys.model, self.t).ok()?;
        let source = if rates.damping_rate > rates.omega_max {
            format!("the contact damping rate {:.3e} 1/s", rates.damping_rate)
        } else {
            format!(
                "the stiffest mode with closed contacts, omega_max = {:.3e} rad/s",
                rates.omega_max
            )
        };
        Some(StiffnessCheck {
            rho: rates.spectral_radius(),
            source,
            h,
            limit: stable_h_rho(self.method),
        })
    }
}

/// A step against the stiffest rate `rho` of the closed-contact system.
struct StiffnessCheck {
    /// Spectral radius estimate (1/s).
    rho: f64,
    /// What sets it.
    source: String,
    /// The step (s).
    h: f64,
    /// The method's stable `h rho`, if it has one (explicit methods, exact stepping).
    limit: Option<f64>,
}

impl StiffnessCheck {
    /// The step sits at the method's stability limit: the model is too stiff for it.
    fn too_stiff(&self) -> bool {
        self.limit.is_some_and(|l| self.h * self.rho > 0.3 * l)
    }

    /// `h rho` beyond `1e-6 / eps`: an implicit method's iteration matrix `I - h gamma J`
    /// keeps fewer than six digits.
    fn beyond_double_precision(&self) -> bool {
        self.limit.is_none() && self.h * self.rho > 1e-6 / f64::EPSILON
    }

    fn describe(&self, method: Method) -> String {
        let (h, source) = (self.h, &self.source);
        match self.limit {
            Some(limit) if self.too_stiff() => format!(
                "too stiff for this method: {source} allows {} steps of at most about {:.3e} s \
                 (h rho <= {limit}), and the steps were {h:.3e} s on average; an implicit \
                 method (esdirk, bdf) is not bound by it, or check the stiffnesses and masses",
                method.name(),
                limit / self.rho
            ),
            Some(limit) => format!(
                "the steps ({h:.3e} s on average) stayed far below the stability limit of about \
                 {:.3e} s set by {source}",
                limit / self.rho
            ),
            None if self.beyond_double_precision() => format!(
                "too stiff for this method in double precision: the step {h:.3e} s against \
                 {source} gives h rho = {:.3e}, and the iteration matrix keeps too few digits",
                h * self.rho
            ),
            None => format!(
                "the step {h:.3e} s against {source}: h rho = {:.3e}",
                h * self.rho
            ),
        }
    }
}
