//! A model whose drive input is set from outside between steps: what an FMU's input (`F`, or
//! `a_vehicle` for a prescribed motion) and a co-simulation master's held value are.

use crate::Result;
use crate::control::law::controlled::DriveResponse;
use crate::run::held::HeldValue;
use telescopic_runtime::nalgebra::DMatrix;
use telescopic_runtime::{ContactState, Drive, Model, ModelParams, Profile};

/// `base` with its drive input replaced by a held value: a force `F` (N) for a force-driven
/// model (`zd' += M^-1 b (F - F_base(t))`), the vehicle's acceleration `a` (m/s^2) for a
/// prescribed motion (`u'' = a`, the other coordinates feel `-M_p0 a`). Its parameters say
/// `drive = F` (a constant, the input at construction) for a force, so exact stepping sees a
/// time-invariant scene between two settings of the input (it takes the force from the
/// right-hand side); for a motion they keep the base's profile, and `auto` never picks exact
/// stepping for a prescribed motion.
pub struct HeldDrive {
    base: Box<dyn Model>,
    params: ModelParams,
    drive: DriveResponse,
    input: HeldValue,
}

impl HeldDrive {
    /// `base` with `input` held (N, or m/s^2 for a prescribed motion).
    ///
    /// # Errors
    /// [`crate::Error::Model`] when the mass matrix cannot be factored.
    pub fn new(base: Box<dyn Model>, input: f64) -> Result<Self> {
        let params = base.params().clone();
        let drive = DriveResponse::of(base.as_ref())?;
        let mut params = params;
        if let Drive::Force(_) = params.drive {
            // a constant: what the force is between two settings (its value is in `input`)
            params.drive = Drive::Force(Profile::Constant(input));
        }
        Ok(HeldDrive {
            base,
            params,
            drive,
            input: HeldValue::new(input),
        })
    }

    /// Holds `input` from now on (a run that advances the model restarts at its next step:
    /// [`crate::run::HeldInputStepper::input_changed`]).
    pub fn set_input(&self, input: f64) {
        self.input.set(input);
    }

    /// The held input (N or m/s^2).
    pub fn input(&self) -> f64 {
        self.input.get()
    }

    /// The model whose input is held.
    pub fn wrapped(&self) -> &dyn Model {
        self.base.as_ref()
    }
}

impl Model for HeldDrive {
    crate::wrapped::pass_through_model!();
    fn params(&self) -> &ModelParams {
        &self.params
    }
    fn rhs(&self, t: f64, y: &[f64], states: Option<&[ContactState]>, ydot: &mut [f64]) {
        self.drive
            .rhs_with(self.base.as_ref(), t, y, states, self.input.get(), ydot);
    }
    fn jacobian(&self, t: f64, y: &[f64], states: Option<&[ContactState]>, jac: &mut DMatrix<f64>) {
        self.base.jacobian(t, y, states, jac);
    }
    fn outputs(&self, t: f64, y: &[f64], ydot: &[f64], out: &mut [f64]) {
        self.base.outputs(t, y, ydot, out)
    }
}
