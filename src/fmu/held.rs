//! A model whose drive force is an input set from outside between steps: what an FMU's `F`
//! input and a co-simulation master's held value are.

use crate::Result;
use crate::control::controlled::DriveResponse;
use telescopic_runtime::nalgebra::DMatrix;
use telescopic_runtime::{ContactState, Drive, Model, ModelParams, Profile};

/// `base` with its drive force replaced by a held value `F` (N): `zd' += M^-1 b (F - F_base(t))`.
/// Its parameters say `drive = F` (a constant), so exact stepping sees a time-invariant
/// scene between two settings of the force.
pub struct HeldForce {
    base: Box<dyn Model>,
    params: ModelParams,
    drive: DriveResponse,
    force: f64,
}

impl HeldForce {
    /// `base` with the force `force` (N) held.
    ///
    /// # Errors
    /// [`crate::Error::Model`] when the mass matrix cannot be factored.
    pub fn new(base: Box<dyn Model>, force: f64) -> Result<Self> {
        let mut params = base.params().clone();
        params.drive = Drive::Force(Profile::Constant(force));
        let drive = DriveResponse::of(base.as_ref())?;
        Ok(HeldForce {
            base,
            params,
            drive,
            force,
        })
    }

    /// The model whose force is held.
    pub fn wrapped(&self) -> &dyn Model {
        self.base.as_ref()
    }

    /// Holds `force` (N) from now on.
    pub fn set_force(&mut self, force: f64) {
        self.force = force;
        self.params.drive = Drive::Force(Profile::Constant(force));
    }

    /// The held force (N).
    pub fn force(&self) -> f64 {
        self.force
    }
}

impl Model for HeldForce {
    crate::wrapped::pass_through_model!();
    fn params(&self) -> &ModelParams {
        &self.params
    }
    fn rhs(&self, t: f64, y: &[f64], states: Option<&[ContactState]>, ydot: &mut [f64]) {
        self.drive
            .rhs_with(self.base.as_ref(), t, y, states, self.force, ydot);
    }
    fn jacobian(&self, t: f64, y: &[f64], states: Option<&[ContactState]>, jac: &mut DMatrix<f64>) {
        self.base.jacobian(t, y, states, jac);
    }
    fn outputs(&self, t: f64, y: &[f64], ydot: &[f64], out: &mut [f64]) {
        self.base.outputs(t, y, ydot, out)
    }
}
