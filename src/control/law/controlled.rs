//! A controller applied to the full nonlinear model with clearance: a [`Model`] that wraps
//! the scene's own and replaces its drive force by the controller's saturated law, so every
//! integrator, the contact events and the outputs work unchanged. The output gains a
//! `drive_force` column: the total force the drive applies.

use crate::OptionName;
use crate::control::file::schema::Controller;
use crate::control::law::schedule::{Reference, schedule_weights};
use crate::io::rows::from_rows;
use crate::run::held::HeldValue;
use crate::{Error, Result};
use telescopic_runtime::nalgebra::{DMatrix, DVector};
use telescopic_runtime::{
    ContactState, ContactTable, Drive, Layout, Model, ModelParams, Output, Profile,
};

/// The control law, ready to evaluate: allocation-free per call.
pub struct ControlLaw {
    feedforward: Profile,
    reference: Reference,
    /// One gain row per schedule point (empty without LQR).
    gains: Vec<Vec<f64>>,
    /// Each design point's value of the scheduled position (m).
    schedule_positions: Vec<f64>,
    /// Section `k` of the scheduled position `a_k`.
    parameter: Option<usize>,
    positions: Vec<Profile>,
    limit: f64,
    /// A sampled controller's force (N), held between its ticks, replacing the continuous
    /// law.
    held: Option<HeldValue>,
}

impl ControlLaw {
    /// The law of a sampled controller: the force set by [`ControlLaw::hold`], held.
    pub(crate) fn held(
        controller: &Controller,
        params: &ModelParams,
        start: f64,
        end: f64,
    ) -> Self {
        ControlLaw {
            held: Some(HeldValue::new(0.0)),
            ..ControlLaw::new(controller, params, start, end)
        }
    }

    /// Sets the held force (N) of a sampled law.
    pub(crate) fn hold(&self, force: f64) {
        if let Some(h) = &self.held {
            h.set(force);
        }
    }

    /// The law of `controller` on `params` over `[start, end]` s.
    pub(crate) fn new(controller: &Controller, params: &ModelParams, start: f64, end: f64) -> Self {
        let parameter = controller.scheduled_section();
        ControlLaw {
            feedforward: controller.feedforward.clone(),
            reference: Reference::new(
                &controller.feedforward,
                controller.total_mass_kg,
                start,
                end,
                1e-3,
            ),
            // one row each, of the state's size (Controller::check_fits)
            gains: if controller.kind.has_lqr() {
                controller.schedule.iter().map(|p| p.k[0].clone()).collect()
            } else {
                Vec::new()
            },
            schedule_positions: controller.schedule_positions(),
            parameter,
            positions: params.positions.clone(),
            limit: controller.force_limit_n,
            held: None,
        }
    }

    /// The scheduled gains around time `t`: `(i, j, w)`.
    fn weights(&self, t: f64) -> (usize, usize, f64) {
        schedule_weights(&self.schedule_positions, self.parameter, &self.positions, t)
    }

    /// The total drive force (N) at `t`, state `y`, and whether it saturated.
    pub fn force(&self, t: f64, y: &[f64]) -> (f64, bool) {
        if let Some(h) = &self.held {
            return (h.get(), false);
        }
        let mut f = self.feedforward.value(t);
        if !self.gains.is_empty() {
            let n = y.len() / 2;
            let (u_ref, v_ref) = self.reference.at(t);
            let (i, j, w) = self.weights(t);
            let (ki, kj) = (&self.gains[i], &self.gains[j]);
            let mut feedback = 0.0;
            for (m, &ym) in y.iter().enumerate() {
                let e = if m == 0 {
                    ym - u_ref
                } else if m == n {
                    ym - v_ref
                } else {
                    ym
                };
                feedback += ((1.0 - w) * ki[m] + w * kj[m]) * e;
            }
            f -= feedback;
        }
        if f.abs() > self.limit {
            (self.limit.copysign(f), true)
        } else {
            (f, false)
        }
    }

    /// `dF/dy_m` at `t` (zero when saturated or without feedback), as a function of `m`.
    fn gradient(&self, t: f64, y: &[f64]) -> Option<impl Fn(usize) -> f64 + '_> {
        if self.held.is_some() || self.gains.is_empty() || self.force(t, y).1 {
            return None;
        }
        let (i, j, w) = self.weights(t);
        Some(move |m: usize| -((1.0 - w) * self.gains[i][m] + w * self.gains[j][m]))
    }
}

/// Where a change of the drive input goes: `M^-1 b` for a force; for a prescribed motion,
/// `[1; -M_pp^-1 M_p0]` for its acceleration (the vehicle follows it, the rest feels its
/// inertia). The one place that replaces a model's own drive by another (a controller's, a
/// held one, an estimator's).
#[derive(Debug, Clone)]
pub(crate) struct DriveResponse(Vec<f64>);

impl DriveResponse {
    /// The response of `model`'s drive input: force or prescribed acceleration.
    ///
    /// # Errors
    /// [`Error::Model`] when the mass matrix cannot be factored.
    pub(crate) fn of(model: &dyn Model) -> Result<Self> {
        let not_definite = || Error::Model("the mass matrix is not positive definite".into());
        let m = model.mass_matrix();
        let response = match model.params().drive {
            Drive::Force(_) => m
                .clone()
                .cholesky()
                .ok_or_else(not_definite)?
                .solve(model.drive_vector()),
            Drive::Motion(_) => {
                let n = model.dof();
                let inertia = m
                    .view((1, 1), (n - 1, n - 1))
                    .into_owned()
                    .cholesky()
                    .ok_or_else(not_definite)?
                    .solve(&m.view((1, 0), (n - 1, 1)).into_owned());
                let mut r = telescopic_runtime::nalgebra::DVector::zeros(n);
                r[0] = 1.0;
                for j in 1..n {
                    r[j] = -inertia[(j - 1, 0)];
                }
                r
            }
        };
        Ok(DriveResponse(response.iter().copied().collect()))
    }

    /// The entries of the response.
    pub(crate) fn entries(&self) -> &[f64] {
        &self.0
    }

    /// `ydot` of `model` at `t`, `y` with the drive input `input` (N, or m/s^2 for a
    /// prescribed motion) in place of the scene's.
    pub(crate) fn rhs_with(
        &self,
        model: &dyn Model,
        t: f64,
        y: &[f64],
        states: Option<&[ContactState]>,
        input: f64,
        ydot: &mut [f64],
    ) {
        model.rhs(t, y, states, ydot);
        let own = match &model.params().drive {
            Drive::Force(f) => f.value(t),
            Drive::Motion(s) => s.acceleration(t),
        };
        self.add_input(input - own, ydot);
    }

    /// Adds to the accelerations in `ydot` (`[zd, zdd]`) what a change `change` of the drive
    /// input (N, or m/s^2 for a prescribed motion) makes of them.
    pub(crate) fn add_input(&self, change: f64, ydot: &mut [f64]) {
        let n = self.0.len();
        for (a, r) in ydot[n..].iter_mut().zip(&self.0) {
            *a += r * change;
        }
    }
}

/// The scene's model with its drive replaced by a controller.
pub struct Controlled<'m> {
    base: &'m dyn Model,
    law: ControlLaw,
    /// The base parameters with the feedforward profile as the drive (its breakpoints end
    /// the integrator's steps).
    params: ModelParams,
    /// Where a change of the drive force goes in the accelerations.
    drive: DriveResponse,
}

impl<'m> Controlled<'m> {
    /// Wraps `base` with `controller` over `[start, end]` s.
    ///
    /// # Errors
    /// [`Error::Option`] when the controller does not fit the model (see
    /// [`Controller::check_fits`]); [`Error::Model`] when the mass matrix cannot be factored.
    pub fn new(base: &'m dyn Model, controller: &Controller, start: f64, end: f64) -> Result<Self> {
        controller.check_params(base.params())?;
        let drive = DriveResponse::of(base)?;
        let mut params = base.params().clone();
        params.drive = Drive::Force(controller.feedforward.clone());
        Ok(Controlled {
            base,
            law: ControlLaw::new(controller, base.params(), start, end),
            params,
            drive,
        })
    }

    /// `base` driven by a sampled controller's held force (set at every tick).
    ///
    /// # Errors
    /// As [`Controlled::new`].
    pub fn sampled(
        base: &'m dyn Model,
        controller: &Controller,
        start: f64,
        end: f64,
    ) -> Result<Self> {
        let mut wrapped = Controlled::new(base, controller, start, end)?;
        wrapped.law = ControlLaw::held(controller, base.params(), start, end);
        Ok(wrapped)
    }

    /// The control law.
    pub fn law(&self) -> &ControlLaw {
        &self.law
    }
}

impl Controlled<'_> {
    /// The model the controller drives.
    fn wrapped(&self) -> &dyn Model {
        self.base
    }
}

impl Model for Controlled<'_> {
    crate::wrapped::pass_through_model!();
    fn params(&self) -> &ModelParams {
        &self.params
    }
    fn rhs(&self, t: f64, y: &[f64], states: Option<&[ContactState]>, ydot: &mut [f64]) {
        let force = self.law.force(t, y).0;
        self.drive.rhs_with(self.base, t, y, states, force, ydot);
    }
    fn jacobian(&self, t: f64, y: &[f64], states: Option<&[ContactState]>, jac: &mut DMatrix<f64>) {
        self.base.jacobian(t, y, states, jac);
        let n = self.dof();
        if let Some(grad) = self.law.gradient(t, y) {
            for (i, r) in self.drive.entries().iter().enumerate() {
                for j in 0..2 * n {
                    jac[(n + i, j)] += r * grad(j);
                }
            }
        }
    }
    fn outputs(&self, t: f64, y: &[f64], ydot: &[f64], out: &mut [f64]) {
        let last = out.len() - 1;
        self.base.outputs(t, y, ydot, &mut out[..last]);
        out[last] = self.law.force(t, y).0;
    }
    fn output_quantities(&self) -> Vec<Output> {
        let mut outputs = self.base.output_quantities();
        outputs.push(Output::DriveForce);
        outputs
    }
}

/// One design point's Kalman filter as matrices.
struct ObserverMatrices {
    a: DMatrix<f64>,
    b: DMatrix<f64>,
    l: DMatrix<f64>,
    c: DMatrix<f64>,
}

/// The scene's model driven by a controller whose feedback acts on a Kalman filter's
/// estimate: the state is the model's `[z, zd]` and the estimate `x_hat = [x_z, x_zd]`,
/// stacked as `[z, x_z, zd, x_zd]`. For explicit methods (the stacked system is not of the
/// second-order form the implicit methods use).
pub struct Observed<'m> {
    inner: Controlled<'m>,
    points: Vec<ObserverMatrices>,
    /// `[z, zd]`, its rate and `x_hat`, gathered from the stacked state (no allocation per
    /// call).
    scratch: std::cell::RefCell<(Vec<f64>, Vec<f64>, Vec<f64>)>,
}

impl<'m> Observed<'m> {
    /// Wraps `base` with `controller`, whose design points must carry Kalman filters.
    ///
    /// # Errors
    /// As [`Controlled::new`]; [`Error::Option`] for a controller without filters or with
    /// filter matrices of the wrong size.
    pub fn new(base: &'m dyn Model, controller: &Controller, start: f64, end: f64) -> Result<Self> {
        let inner = Controlled::new(base, controller, start, end)?;
        let n = base.dof();
        let matrix = |rows: &[Vec<f64>], name: &str, shape: (usize, usize)| {
            from_rows(rows, Some(shape)).map_err(|e| {
                Error::option(OptionName::Controller, format!("Kalman filter: {name} {e}"))
            })
        };
        let points = controller
            .schedule
            .iter()
            .map(|p| {
                let o = p.observer.as_ref().ok_or_else(|| {
                    Error::option(
                        OptionName::Controller,
                        "the controller has no Kalman filter",
                    )
                })?;
                Ok(ObserverMatrices {
                    a: matrix(&o.a_full, "A_full", (2 * n, 2 * n))?,
                    b: matrix(&o.b_full, "B_full", (2 * n, 1))?,
                    l: matrix(&o.l, "L", (2 * n, 2))?,
                    c: matrix(&o.c_meas, "C_meas", (2, 2 * n))?,
                })
            })
            .collect::<Result<Vec<_>>>()?;
        Ok(Observed {
            inner,
            points,
            scratch: std::cell::RefCell::new((
                vec![0.0; 2 * n],
                vec![0.0; 2 * n],
                vec![0.0; 2 * n],
            )),
        })
    }

    fn n(&self) -> usize {
        self.inner.base.dof()
    }

    /// Copies `[z, zd]` out of the stacked state into `out`.
    fn gather(&self, y: &[f64], out: &mut [f64]) {
        let n = self.n();
        out[..n].copy_from_slice(&y[..n]);
        out[n..].copy_from_slice(&y[2 * n..3 * n]);
    }

    /// Entry `i` of the estimate `x_hat = [x_z, x_zd]` in the stacked state.
    fn estimate(&self, y: &[f64], i: usize) -> f64 {
        let n = self.n();
        if i < n { y[n + i] } else { y[2 * n + i] }
    }
}

impl Model for Observed<'_> {
    fn layout(&self) -> &Layout {
        self.inner.layout()
    }
    fn params(&self) -> &ModelParams {
        self.inner.params()
    }
    fn mass_matrix(&self) -> &DMatrix<f64> {
        self.inner.mass_matrix()
    }
    fn stiffness_matrix(&self) -> &DMatrix<f64> {
        self.inner.stiffness_matrix()
    }
    fn damping_matrix(&self) -> Option<&DMatrix<f64>> {
        self.inner.damping_matrix()
    }
    fn drive_vector(&self) -> &DVector<f64> {
        self.inner.drive_vector()
    }
    fn dof(&self) -> usize {
        2 * self.n()
    }
    fn contact_vectors(&self, t: f64, g: &mut DMatrix<f64>, gdot: &mut DMatrix<f64>) {
        self.inner.contact_vectors(t, g, gdot)
    }
    fn contact_vectors_at(
        &self,
        positions: &[f64],
        rates: &[f64],
        g: &mut DMatrix<f64>,
        gdot: &mut DMatrix<f64>,
    ) {
        self.inner.contact_vectors_at(positions, rates, g, gdot)
    }
    fn contact_table(&self) -> Option<&ContactTable> {
        self.inner.contact_table()
    }
    fn contact_gaps(&self, t: f64, y: &[f64], xi: &mut [f64], xi_dot: &mut [f64]) {
        let mut s = self.scratch.borrow_mut();
        self.gather(y, &mut s.0);
        self.inner.base.contact_gaps(t, &s.0, xi, xi_dot)
    }
    fn rhs(&self, t: f64, y: &[f64], states: Option<&[ContactState]>, ydot: &mut [f64]) {
        let n = self.n();
        let mut guard = self.scratch.borrow_mut();
        let (yb, ydb, xhat) = &mut *guard;
        self.gather(y, yb);
        // the law on the estimate
        for (i, x) in xhat.iter_mut().enumerate() {
            *x = self.estimate(y, i);
        }
        let force = self.inner.law.force(t, xhat).0;
        self.inner
            .drive
            .rhs_with(self.inner.base, t, yb, states, force, ydb);
        // the filter: x_hat' = A x_hat + B F + L (y_meas - C x_hat), interpolated
        let (i, j, w) = self.inner.law.weights(t);
        let (pi, pj) = (&self.points[i], &self.points[j]);
        let blend = |a: f64, b: f64| (1.0 - w) * a + w * b;
        let mut innovation = [0.0f64; 2];
        for (k, inn) in innovation.iter_mut().enumerate() {
            let mut measured = 0.0;
            let mut estimated = 0.0;
            for (m, &ybm) in yb.iter().enumerate().take(2 * n) {
                let c = blend(pi.c[(k, m)], pj.c[(k, m)]);
                measured += c * ybm;
                estimated += c * self.estimate(y, m);
            }
            *inn = measured - estimated;
        }
        for r in 0..2 * n {
            let mut v = blend(pi.b[(r, 0)], pj.b[(r, 0)]) * force
                + blend(pi.l[(r, 0)], pj.l[(r, 0)]) * innovation[0]
                + blend(pi.l[(r, 1)], pj.l[(r, 1)]) * innovation[1];
            for m in 0..2 * n {
                v += blend(pi.a[(r, m)], pj.a[(r, m)]) * self.estimate(y, m);
            }
            // x_hat' into its place of the stacked rate
            if r < n {
                ydot[n + r] = v;
            } else {
                ydot[2 * n + r] = v;
            }
        }
        ydot[..n].copy_from_slice(&ydb[..n]);
        ydot[2 * n..3 * n].copy_from_slice(&ydb[n..]);
    }
    fn jacobian(&self, t: f64, y: &[f64], states: Option<&[ContactState]>, jac: &mut DMatrix<f64>) {
        // central differences: the stacked system is for explicit methods; this serves the
        // analyses that linearize it
        let len = y.len();
        let mut yp = y.to_vec();
        let (mut fp, mut fm) = (vec![0.0; len], vec![0.0; len]);
        for j in 0..len {
            let h = 1e-7 * y[j].abs().max(1e-6);
            yp[j] = y[j] + h;
            self.rhs(t, &yp, states, &mut fp);
            yp[j] = y[j] - h;
            self.rhs(t, &yp, states, &mut fm);
            yp[j] = y[j];
            for i in 0..len {
                jac[(i, j)] = (fp[i] - fm[i]) / (2.0 * h);
            }
        }
    }
    fn displacement(&self, section: usize, x: f64, z: &[f64]) -> f64 {
        self.inner.base.displacement(section, x, &z[..self.n()])
    }
    fn outputs(&self, t: f64, y: &[f64], ydot: &[f64], out: &mut [f64]) {
        let n = self.n();
        let last = out.len() - 1;
        let mut s = self.scratch.borrow_mut();
        let (yb, ydb, xhat) = &mut *s;
        self.gather(y, yb);
        ydb[..n].copy_from_slice(&ydot[..n]);
        ydb[n..].copy_from_slice(&ydot[2 * n..3 * n]);
        self.inner.base.outputs(t, yb, ydb, &mut out[..last]);
        for (i, x) in xhat.iter_mut().enumerate() {
            *x = self.estimate(y, i);
        }
        out[last] = self.inner.law.force(t, xhat).0;
    }
    fn output_quantities(&self) -> Vec<Output> {
        self.inner.output_quantities()
    }
}
