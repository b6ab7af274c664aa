//! An integration that can be advanced: created from a model, a method, settings and a
//! state, then moved on by [`Integrator::advance_to`] as often as the caller likes, keeping
//! its step size, its method's prepared data (factorizations, stiff modes, step cap) and its
//! contact states between calls. [`super::simulate`] is one call of it over a whole span; a
//! sampled controller or a co-simulation step is one call per tick, with
//! [`Integrator::input_changed`] after the caller sets the model's held input.
//!
//! ```
//! use telescopic_runtime::integrate::{Integrator, Stop};
//! use telescopic_runtime::{AssembledModel, Method, Scene, Settings, rest_state};
//!
//! let scene = Scene::load("../scenes/adams-linear.toml".as_ref(), &[]).unwrap();
//! let model = AssembledModel::new(&scene.params).unwrap();
//! let y0 = rest_state(&model, 0.0);
//! // a run planned over the scene's span (0 to 5 s), sampled every millisecond
//! let mut run = Integrator::new(&model, &y0, &scene.time, Method::Dopri5, &Settings::default())
//!     .unwrap();
//! let mut samples = 0;
//! for tick in 1..=10 {
//!     let stop = run.advance_to(tick as f64 * 0.01, &mut |_t, _y, _ydot| samples += 1).unwrap();
//!     assert_eq!(stop, Stop::Reached);
//! }
//! assert!((run.time() - 0.1).abs() < 1e-12);
//! assert_eq!(samples, 101); // t = 0, 0.001, ..., 0.1
//! ```

use super::driver::{Driver, Stop};
use super::{Method, Observer, Progress, RunStats, Settings, SimError};
use crate::model::Model;
use crate::scene::TimeSpan;

/// A run of a model that the caller advances piece by piece.
pub struct Integrator<'m> {
    driver: Driver<'m>,
}

impl<'m> Integrator<'m> {
    /// A run of `model` from state `y0` at `span.start` with `method` and `settings`,
    /// sampled every `span.sample` seconds from there (adaptive methods end their steps on
    /// samples, and imex sets its stiff modes by it). `span.end` is the planned end: the
    /// closed-contact step cap is computed over the span once, and progress is reported in
    /// its hundredths; the run may be advanced beyond it.
    ///
    /// # Errors
    /// [`SimError::Settings`] for a state of the wrong length, a span that does not go
    /// forward by positive samples, method `exact` or a hand-over to it (`exact_from`),
    /// which integrate whole spans only ([`super::simulate`]), and the settings a run
    /// refuses (tolerances, a fixed step's `dt`).
    pub fn new(
        model: &'m dyn Model,
        y0: &[f64],
        span: &TimeSpan,
        method: Method,
        settings: &Settings,
    ) -> Result<Self, SimError> {
        super::check_state_len(model, y0)?;
        let TimeSpan { start, end, sample } = *span;
        if !(sample > 0.0 && sample.is_finite() && start.is_finite() && end.is_finite())
            || end <= start
        {
            return Err(SimError::Settings(format!(
                "the span must run forward from a finite start by a positive sample interval \
                 (got {start} to {end} s by {sample} s)"
            )));
        }
        if method == Method::Exact || settings.exact_from.is_some() {
            return Err(SimError::Settings(
                "method exact (and a hand-over to it) integrates whole spans only: use \
                 simulate, or another method to advance a run piece by piece"
                    .into(),
            ));
        }
        Ok(Integrator {
            driver: Driver::new(model, y0, span, method, settings)?,
        })
    }

    /// Integrates to `t` (s), calling `observe(t, y, ydot)` at every sample time passed (on
    /// the first call, at the start too; the span's end when it is off the grid); a `t` off
    /// the grid is reached exactly ([`Integrator::state`]). A `t` at or before the time
    /// reached does nothing but emit the start on a first call.
    ///
    /// # Errors
    /// [`SimError`] naming the time, method and likely cause; the run cannot go on after it.
    pub fn advance_to(&mut self, t: f64, observe: Observer) -> Result<Stop, SimError> {
        self.advance_with_progress(t, observe, None)
    }

    /// [`Integrator::advance_to`] with a progress callback (called every 1 % of the span
    /// from the start to `t`; returning false ends the call with [`Stop::Stopped`]; a later
    /// call goes on from there).
    ///
    /// # Errors
    /// As [`Integrator::advance_to`].
    pub fn advance_with_progress(
        &mut self,
        t: f64,
        mut observe: Observer,
        progress: Option<Progress>,
    ) -> Result<Stop, SimError> {
        if !t.is_finite() {
            return Err(SimError::Settings(format!(
                "advance to a finite time (got {t} s)"
            )));
        }
        self.driver.advance_to(t, &mut observe, progress)
    }

    /// Whether [`Integrator::advance_to`] returns just after each contact switch
    /// ([`Stop::Switch`]) instead of going on to the time asked for.
    pub fn stop_on_switch(&mut self, stop: bool) {
        self.driver.set_stop_on_switch(stop);
    }

    /// The model's input changed at the time reached (a held force or correction set anew
    /// through the model's shared state): the derivative is evaluated again and the method
    /// restarts as at a drive discontinuity; the step size is kept.
    pub fn input_changed(&mut self) {
        self.driver.input_changed();
    }

    /// The time reached (s).
    pub fn time(&self) -> f64 {
        self.driver.now().0
    }

    /// The state reached, `[z, zdot]`.
    pub fn state(&self) -> &[f64] {
        self.driver.now().1
    }

    /// The counts so far (steps, right-hand sides, switches, ...; the wall time is not
    /// measured here).
    pub fn stats(&self) -> RunStats {
        let mut stats = self.driver.now().2.clone();
        stats.state_len = self.state().len();
        stats
    }
}
