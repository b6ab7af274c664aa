//! Stepping with a held input: a model advanced tick by tick while the caller changes an
//! input it holds fixed over each tick. A co-simulation step of the FMU (`fmi2DoStep`, the
//! master's input held) and a sampled controller's tick (its force or servo correction held
//! by the zero-order hold) are this.
//!
//! The run is one [`Integrator`] advanced from tick to tick: its step size, its method's
//! prepared data (imex's contact compliance and stiff modes, dop853's closed-contact step
//! cap) and its contact states carry over, and a changed input restarts the method at the
//! tick as a drive step would. Method `exact` integrates whole spans only; with it each tick
//! is a run of its own.

use super::method::Plan;
use std::sync::atomic::{AtomicU64, Ordering};
use telescopic_runtime::integrate::Integrator;
use telescopic_runtime::{Method, Model, RunStats, Settings, SimError, TimeSpan, simulate};

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
    /// Method exact: each tick a run of its own from the state reached.
    EachTick(Box<EachTick<'m>>),
}

/// Method exact's ticks: the model, the settings and the state reached.
struct EachTick<'m> {
    model: &'m dyn Model,
    settings: Settings,
    t: f64,
    y: Vec<f64>,
    end: Vec<f64>,
    stats: RunStats,
}

/// Advances a model over ticks between which the caller changes its held input.
pub struct HeldInputStepper<'m> {
    ticks: Ticks<'m>,
}

impl<'m> HeldInputStepper<'m> {
    /// Ticks of `model` from `y0` at `span.start` by `plan`'s method and settings (`span`
    /// is the planned run: its sample interval the output grid, its end the horizon of the
    /// closed-contact step cap).
    ///
    /// # Errors
    /// [`SimError::Settings`] for a state or span a run refuses.
    pub fn new(
        plan: &Plan,
        model: &'m dyn Model,
        span: &TimeSpan,
        y0: &[f64],
    ) -> Result<Self, SimError> {
        // exact stepping's hand-over time does not apply to ticks
        let settings = Settings {
            exact_from: None,
            ..plan.settings
        };
        let ticks = if plan.method == Method::Exact {
            Ticks::EachTick(Box::new(EachTick {
                model,
                settings,
                t: span.start,
                y: y0.to_vec(),
                end: y0.to_vec(),
                stats: RunStats::default(),
            }))
        } else {
            let mut run = Integrator::new(model, y0, span, plan.method, &settings)?;
            // the first call emits the start: make it now
            run.advance_to(span.start, &mut |_, _, _| {})?;
            Ticks::Advancing(Box::new(run))
        };
        Ok(HeldInputStepper { ticks })
    }

    /// The model's held input changed at the time reached: the next tick restarts there.
    pub fn input_changed(&mut self) {
        if let Ticks::Advancing(run) = &mut self.ticks {
            run.input_changed();
        }
    }

    /// Advances to `t_end` (s) with the input held.
    ///
    /// # Errors
    /// The integration's [`SimError`] (time, method, likely cause); the stepper cannot go
    /// on after it.
    pub fn advance_to(&mut self, t_end: f64) -> Result<(), SimError> {
        match &mut self.ticks {
            Ticks::Advancing(run) => {
                run.advance_to(t_end, &mut |_, _, _| {})?;
            }
            Ticks::EachTick(tick) => {
                let EachTick {
                    model,
                    settings,
                    t,
                    y,
                    end,
                    stats,
                } = tick.as_mut();
                if t_end <= *t {
                    return Ok(());
                }
                let span = TimeSpan {
                    start: *t,
                    end: t_end,
                    sample: t_end - *t,
                };
                let tick = simulate(
                    *model,
                    y,
                    &span,
                    Method::Exact,
                    settings,
                    &mut |_, s, _| end.copy_from_slice(s),
                    None,
                )?;
                y.copy_from_slice(end);
                stats.add(&tick);
                *t = span.end;
            }
        }
        Ok(())
    }

    /// The time reached (s).
    pub fn time(&self) -> f64 {
        match &self.ticks {
            Ticks::Advancing(run) => run.time(),
            Ticks::EachTick(tick) => tick.t,
        }
    }

    /// The state reached, `[z, zdot]`.
    pub fn state(&self) -> &[f64] {
        match &self.ticks {
            Ticks::Advancing(run) => run.state(),
            Ticks::EachTick(tick) => &tick.y,
        }
    }

    /// The counts so far.
    pub fn stats(&self) -> RunStats {
        match &self.ticks {
            Ticks::Advancing(run) => run.stats(),
            Ticks::EachTick(tick) => tick.stats.clone(),
        }
    }
}
