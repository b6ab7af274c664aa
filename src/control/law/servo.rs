//! The plant of a velocity servo: the scene's model following its setpoint plus the law's
//! correction, held over a tick.

use crate::Result;
use crate::run::held::HeldValue;
use telescopic_runtime::nalgebra::DMatrix;
use telescopic_runtime::{ContactState, Model, ModelParams};

/// The scene's model with its servo following the setpoint plus a velocity correction
/// interpolated linearly over each tick: the correction's acceleration is held a tick.
pub struct ServoCorrected<'m> {
    base: &'m dyn Model,
    /// Where the vehicle's acceleration goes (the vehicle follows it, the rest feels its
    /// inertia).
    response: crate::control::law::controlled::DriveResponse,
    /// The correction's acceleration over the current tick (m/s^2).
    acceleration: HeldValue,
    /// The correction reached at the end of the current tick (m/s).
    velocity: HeldValue,
    period: f64,
}

impl<'m> ServoCorrected<'m> {
    /// `base` (a prescribed-motion model) with corrections at `rate_hz`.
    ///
    /// # Errors
    /// [`crate::Error::Model`] when the mass matrix cannot be factored.
    pub fn new(base: &'m dyn Model, rate_hz: f64) -> Result<Self> {
        Ok(ServoCorrected {
            base,
            response: crate::control::law::controlled::DriveResponse::of(base)?,
            acceleration: HeldValue::new(0.0),
            velocity: HeldValue::new(0.0),
            period: 1.0 / rate_hz,
        })
    }

    /// Sets the correction (m/s) the servo reaches by the end of the next tick.
    pub fn hold(&self, velocity: f64) {
        let acceleration = (velocity - self.velocity.get()) / self.period;
        self.acceleration.set(acceleration);
        self.velocity.set(velocity);
    }

    fn wrapped(&self) -> &dyn Model {
        self.base
    }
}

impl Model for ServoCorrected<'_> {
    crate::wrapped::pass_through_model!();
    fn params(&self) -> &ModelParams {
        self.base.params()
    }
    fn rhs(&self, t: f64, y: &[f64], states: Option<&[ContactState]>, ydot: &mut [f64]) {
        self.base.rhs(t, y, states, ydot);
        let a = self.acceleration.get();
        self.response.add_input(a, ydot);
    }
    fn jacobian(&self, t: f64, y: &[f64], states: Option<&[ContactState]>, jac: &mut DMatrix<f64>) {
        // the correction's acceleration is held over a tick: no state dependence
        self.base.jacobian(t, y, states, jac);
    }
    fn outputs(&self, t: f64, y: &[f64], ydot: &[f64], out: &mut [f64]) {
        // the reaction is read from `ydot`, which carries the correction
        self.base.outputs(t, y, ydot, out);
    }
    fn output_quantities(&self) -> Vec<telescopic_runtime::Output> {
        self.base.output_quantities()
    }
}
