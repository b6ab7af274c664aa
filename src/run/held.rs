//! Stepping with a held input: advance a model from `t` by `h` with whatever input it holds
//! fixed over the step. A co-simulation step of the FMU (`fmi2DoStep`, the master's input
//! held) and a sampled controller's tick (its force held by the zero-order hold) are this.

use super::plan::Plan;
use telescopic_runtime::integrate::stability::closed_contact_step_cap;
use telescopic_runtime::{Method, Model, RunStats, Settings, SimError, TimeSpan, simulate};

/// Advances a model over steps between which the caller changes its held input.
pub struct HeldInputStepper {
    method: Method,
    settings: Settings,
    /// The state at the end of a step, written by the integrator's observer.
    end: Vec<f64>,
}

impl HeldInputStepper {
    /// Steps of `model` (whose scene spans `span`) by `plan`'s method and settings. The step
    /// cap of the closed contacts is computed here, once: per step it would be a bisection of
    /// eigenvalue problems each time (a sampled run 25 times slower); exact stepping's
    /// hand-over time does not apply to steps this short.
    pub fn new(plan: &Plan, model: &dyn Model, span: &TimeSpan) -> Self {
        let known_step_cap = if plan.settings.step_cap {
            closed_contact_step_cap(model, plan.method, span)
        } else {
            None
        };
        HeldInputStepper {
            method: plan.method,
            settings: Settings {
                exact_from: None,
                known_step_cap,
                ..plan.settings
            },
            end: vec![0.0; 2 * model.dof()],
        }
    }

    /// Advances the state `y` of `model` from `t` by `h` (s) with its input held; what the
    /// step did.
    ///
    /// # Errors
    /// The integration's [`SimError`] (time, method, likely cause); `y` is then unchanged.
    pub fn advance(
        &mut self,
        model: &dyn Model,
        y: &mut [f64],
        t: f64,
        h: f64,
    ) -> Result<RunStats, SimError> {
        let span = TimeSpan {
            start: t,
            end: t + h,
            sample: h,
        };
        let end = &mut self.end;
        let stats = simulate(
            model,
            y,
            &span,
            self.method,
            &self.settings,
            &mut |_, s, _| end.copy_from_slice(s),
            None,
        )?;
        y.copy_from_slice(&self.end);
        Ok(stats)
    }
}
