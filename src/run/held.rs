//! Stepping with a held input: a model advanced tick by tick while the caller changes an
//! input it holds fixed over each tick. A co-simulation step of the FMU (`fmi2DoStep`, the
//! master's input held) and a sampled controller's tick (its force or servo correction held
//! by the zero-order hold) are this.
//!
//! The run is one [`Integrator`] advanced from tick to tick: its step size, its method's
//! prepared data (imex's contact compliance and stiff modes, dop853's closed-contact step
//! cap) and its contact states carry over, and a changed input restarts the method at the
//! tick as a drive step would. Where the plan steps exactly (method `exact`, or its
//! hand-over once the positions rest), the ticks are [`ExactTicks`]: a held force keeps
//! the scene linear and time-invariant over a tick, and each new one is taken by
//! superposition on the exponentials built once.

use super::method::Plan;
use std::sync::atomic::{AtomicU64, Ordering};
use telescopic_runtime::integrate::Integrator;
use telescopic_runtime::integrate::exact::ExactTicks;
use telescopic_runtime::{Method, Model, RunStats, Settings, SimError, TimeSpan};

/// An `f64` a model reads in its right-hand side and its caller sets between ticks, through
/// a shared reference (the run borrows the model while the caller holds it).
#[derive(Debug, Default)]
pub struct HeldValue(AtomicU64);

impl HeldValue {
    /// Holding `value`.
    pub fn new(value: f64) -> Self {
        HeldValue(AtomicU64::new(value.to_bits()))
    }

    /// The value held.
    pub fn get(&self) -> f64 {
        f64::from_bits(self.0.load(Ordering::Relaxed))
    }

    /// Holds `value` from now on.
    pub fn set(&self, value: f64) {
        self.0.store(value.to_bits(), Ordering::Relaxed);
    }
}

/// How the ticks are integrated.
enum Ticks<'m> {
    /// One run advanced from tick to tick.
    Advancing(Box<Integrator<'m>>),
    /// Exact stepping, each new input taken by superposition.
    Exact(Box<ExactTicks<'m>>),
}

/// Advances a model over ticks between which the caller changes its held input.
pub struct HeldInputStepper<'m> {
    ticks: Ticks<'m>,
    model: &'m dyn Model,
    settings: Settings,
    /// The ticks' interval (s).
    tick: f64,
    /// Where the plan's method hands over to exact stepping (s), until it has.
    exact_from: Option<f64>,
    /// The counts of the plan's method before the hand-over.
    before: RunStats,
}

impl<'m> HeldInputStepper<'m> {
    /// Ticks of `model` from `y0` at `span.start` by `plan`'s method and settings (`span`
    /// is the planned run: its sample interval the ticks', its end the horizon of the
    /// closed-contact step cap), exact stepping from the plan's hand-over on.
    ///
    /// # Errors
    /// [`SimError::Settings`] for a state or span a run refuses, or a model exact stepping
    /// does not apply to.
    pub fn new(
        plan: &Plan,
        model: &'m dyn Model,
        span: &TimeSpan,
        y0: &[f64],
    ) -> Result<Self, SimError> {
        // the hand-over is this stepper's: the integrator runs the plan's method alone
        let settings = Settings {
            exact_from: None,
            ..plan.settings
        };
        let ticks = if plan.method == Method::Exact {
            let exact = ExactTicks::new(model, span.start, y0, span.sample, &settings)?;
            Ticks::Exact(Box::new(exact))
        } else {
            let mut run = Integrator::new(model, y0, span, plan.method, &settings)?;
            // the first call emits the start: make it now
            run.advance_to(span.start, &mut |_, _, _| {})?;
            Ticks::Advancing(Box::new(run))
        };
        Ok(HeldInputStepper {
            ticks,
            model,
            settings,
            tick: span.sample,
            exact_from: plan.settings.exact_from,
            before: RunStats::default(),
        })
    }

    /// The model's held input changed at the time reached: the next tick restarts there.
    pub fn input_changed(&mut self) {
        match &mut self.ticks {
            Ticks::Advancing(run) => run.input_changed(),
            Ticks::Exact(run) => run.input_changed(),
        }
    }

    /// Advances to `t_end` (s) with the input held, handing over to exact stepping on the
    /// way where the plan does.
    ///
    /// # Errors
    /// The integration's [`SimError`] (time, method, likely cause); the stepper cannot go
    /// on after it.
    pub fn advance_to(&mut self, t_end: f64) -> Result<(), SimError> {
        if let Some(t_exact) = self.exact_from
            && t_end > t_exact
        {
            self.advance_ticks(t_exact)?;
            self.hand_over()?;
        }
        self.advance_ticks(t_end)
    }

    /// Advances the current way of stepping to `t_end` (s).
    fn advance_ticks(&mut self, t_end: f64) -> Result<(), SimError> {
        match &mut self.ticks {
            Ticks::Advancing(run) => run.advance_to(t_end, &mut |_, _, _| {}).map(|_| ()),
            Ticks::Exact(run) => run.advance_to(t_end),
        }
    }

    /// Continues by exact stepping from the state reached; where exact stepping refuses the
    /// model there (its right-hand side still changes in time, [`ExactTicks::new`]), the
    /// plan's method goes on: the hand-over saves work and is never worth failing a run.
    fn hand_over(&mut self) -> Result<(), SimError> {
        self.exact_from = None;
        if let Ticks::Advancing(run) = &self.ticks {
            let exact = match ExactTicks::new(
                self.model,
                run.time(),
                run.state(),
                self.tick,
                &self.settings,
            ) {
                Ok(exact) => exact,
                Err(SimError::Settings(_)) => return Ok(()),
                Err(e) => return Err(e),
            };
            self.before = run.stats();
            self.ticks = Ticks::Exact(Box::new(exact));
        }
        Ok(())
    }

    /// Whether the ticks are stepped exactly now.
    pub fn is_exact(&self) -> bool {
        matches!(self.ticks, Ticks::Exact(_))
    }

    /// The time reached (s).
    pub fn time(&self) -> f64 {
        match &self.ticks {
            Ticks::Advancing(run) => run.time(),
            Ticks::Exact(run) => run.time(),
        }
    }

    /// The state reached, `[z, zdot]`.
    pub fn state(&self) -> &[f64] {
        match &self.ticks {
            Ticks::Advancing(run) => run.state(),
            Ticks::Exact(run) => run.state(),
        }
    }

    /// The counts so far.
    pub fn stats(&self) -> RunStats {
        let mut stats = self.before.clone();
        match &self.ticks {
            Ticks::Advancing(run) => stats.add(&run.stats()),
            Ticks::Exact(run) => stats.add(&run.stats()),
        }
        stats
    }
}
