//! The interface every model implements: the quadrature-assembled reference model
//! ([`crate::AssembledModel`]) and the generated ones.
//!
//! # Computing coordinates
//!
//! docs/model.md section 4 writes `w_k(x,t) = sum_i q_{k,i}(t) phi_{k,i}(x)` with the paper's shape
//! functions (`phi_{1,1} = 2`, `phi_{k,1} = 1`). The vehicle travels metres while contact gaps
//! live at micrometres, so a model works in an exactly equivalent Ritz basis that carries the
//! vehicle position as a coordinate of its own and measures everything else relative to it:
//!
//! * `z_0 = u = w_1(0, t)`, the vehicle position; its basis function is the unit rigid
//!   translation of the whole telescope (`1` on every section);
//! * section 1, `i >= 2`: basis `phi_{1,i}(x) - phi_{1,i}(0)` (zero at the vehicle), same
//!   coefficient as the paper's `q_{1,i}`;
//! * section `k >= 2`: basis `phi_{k,i}(x)`, coefficient `z_{k,i} = q_{k,i}` except
//!   `z_{k,1} = q_{k,1} - u`, the section's rigid offset from the vehicle.
//!
//! Index positions are those of the paper's `q` ([`crate::Layout::index`]); index 0 holds
//! `u`. The change of variables `q = T z` is linear and exact: `q_{1,1} = (u - sum_{i>=2}
//! q_{1,i} phi_{1,i}(0)) / 2`, `q_{k,1} = z_{k,1} + u`. In these coordinates the drive vector
//! is `b = e_0`, `K` has a zero row and column 0 (translation stores no energy), every contact
//! vector has `g_c[0] = 0` (translation opens no gap), and the outputs `vehicle = z_0`,
//! `tip_rel` and `top1_rel` are sums over small relative coordinates only.
//!
//! The first-order state is `y = [z, zd]` (length `2 dof`). Matrices are `nalgebra`
//! column-major `DMatrix<f64>`.

pub mod assembled;
pub mod configuration;
pub mod layout;
pub(crate) mod mass_solve;
pub mod output;
pub mod params;
pub mod quadrature;
pub mod sensors;

use crate::contact::{ContactForce, ContactState};
use crate::model::layout::Layout;
use crate::model::output::Output;
use crate::model::params::{Drive, ModelParams};
use crate::shape::{SectionKind, SectionShapes};
use nalgebra::{DMatrix, DVector};

/// A discretized telescope: matrices, contact geometry, right-hand side and Jacobian of the
/// first-order system, and outputs. All per-call methods are allocation-free.
pub trait Model {
    /// Sizes and index layout.
    fn layout(&self) -> &Layout;

    /// The physical parameters the model was prepared with.
    fn params(&self) -> &ModelParams;

    /// Mass matrix `M` in computing coordinates (kg, kg m, ...: units of the coordinates).
    fn mass_matrix(&self) -> &DMatrix<f64>;

    /// Stiffness matrix `K` (elastic minus prestress) in computing coordinates.
    fn stiffness_matrix(&self) -> &DMatrix<f64>;

    /// Structural damping matrix `D_s` in computing coordinates ([`crate::analysis::damping`]); `None`
    /// without structural damping (the contacts' damping is not part of it).
    fn damping_matrix(&self) -> Option<&DMatrix<f64>>;

    /// Drive vector `b` (the force `F` enters as `b F`); `e_0` in computing coordinates.
    fn drive_vector(&self) -> &DVector<f64>;

    /// Contact vectors at time `t` (s): column `c` of `g` is `g_c(t)`, of `gdot` its time
    /// derivative; both `dof x contact_count`. `xi_c = g_c . z`, `xi_dot_c = g_c . zd + gdot_c . z`.
    fn contact_vectors(&self, t: f64, g: &mut DMatrix<f64>, gdot: &mut DMatrix<f64>);

    /// Contact vectors for telescopic positions `positions` (m, `a_2..a_n`) moving at `rates`
    /// (m/s), whatever the scene's profiles say: what a linear parameter-varying model is
    /// evaluated with. Same layout as [`Model::contact_vectors`].
    fn contact_vectors_at(
        &self,
        positions: &[f64],
        rates: &[f64],
        g: &mut DMatrix<f64>,
        gdot: &mut DMatrix<f64>,
    );

    /// The table the model interpolates its contact vectors from when positions move
    /// ([`crate::ContactTable`]); `None` when it evaluates them exactly.
    fn contact_table(&self) -> Option<&crate::ContactTable> {
        None
    }

    /// Gaps `xi_c` (m) and gap rates `xi_dot_c` (m/s) of every contact at time `t`, state `y`.
    fn contact_gaps(&self, t: f64, y: &[f64], xi: &mut [f64], xi_dot: &mut [f64]);

    /// Right-hand side `ydot = f(t, y)` of the first-order system
    /// `zd' = M^-1 (b F(t) - K z - D_s zd - sum_c f_c g_c)` (or, for a prescribed motion, `u'' = s''(t)`
    /// and the rest with the reaction eliminated). `states`: `None` lets the contact law pick
    /// each branch from the gap; `Some` fixes the branch per contact (event-driven
    /// integration keeps the law smooth within a step).
    fn rhs(&self, t: f64, y: &[f64], states: Option<&[ContactState]>, ydot: &mut [f64]);

    /// Jacobian `d ydot / d y` (`2 dof x 2 dof`), exact within the contact branches chosen as in
    /// [`Model::rhs`].
    fn jacobian(&self, t: f64, y: &[f64], states: Option<&[ContactState]>, jac: &mut DMatrix<f64>);

    /// Absolute transverse displacement `w_k(x, t)` (m) of section `k` (1-based) at `x` (m).
    fn displacement(&self, section: usize, x: f64, z: &[f64]) -> f64;

    /// The row `r` with `w_k^(deriv)(x) = r . z`: the value (`deriv = 0`, m), slope (1) or
    /// curvature (2, 1/m) of section `k` (1-based) at `x` (m from its foot) per unit of each
    /// coordinate. The default evaluates the paper's shape functions, the basis of every
    /// generated model; a model with other coordinates overrides it.
    fn shape_row(&self, section: usize, x: f64, deriv: u8) -> Vec<f64> {
        paper_shape_row(self.layout(), self.params(), section, x, deriv)
    }

    /// Output quantities (docs/model.md section 5, names from [`Model::output_names`]) at `t`,
    /// state `y` and its derivative `ydot` (for `drive_force`).
    fn outputs(&self, t: f64, y: &[f64], ydot: &[f64], out: &mut [f64]);

    /// Number of generalized coordinates.
    fn dof(&self) -> usize {
        self.layout().dof()
    }

    /// What [`Model::outputs`] computes, in order.
    fn output_quantities(&self) -> Vec<Output> {
        self.layout()
            .outputs(matches!(self.params().drive, Drive::Motion(_)))
    }

    /// Names of [`Model::outputs`] ([`Model::output_quantities`]' names).
    fn output_names(&self) -> Vec<String> {
        self.output_quantities()
            .iter()
            .map(Output::to_string)
            .collect()
    }

    /// The contact force and partials at contact `c` for gap `xi`, rate `xi_dot`, in the branch
    /// `states[c]` if given.
    fn contact_force(
        &self,
        c: usize,
        xi: f64,
        xi_dot: f64,
        states: Option<&[ContactState]>,
    ) -> ContactForce {
        let law = &self.params().contact;
        match states {
            Some(s) => law.force_in_state(s[c], xi, xi_dot),
            None => law.force(xi, xi_dot),
        }
    }
}

/// [`Model::shape_row`] in the paper's basis: the translation (index 0, value 1) and each
/// section's modes (section 1's shifted to vanish at the vehicle).
pub fn paper_shape_row(
    layout: &Layout,
    params: &ModelParams,
    section: usize,
    x: f64,
    deriv: u8,
) -> Vec<f64> {
    let s = &params.sections[section - 1];
    let shapes = SectionShapes::new(SectionKind::of_section(section), s.modes, s.length);
    let mut row = vec![0.0; layout.dof()];
    row[0] = f64::from(u8::from(deriv == 0));
    for f in shapes.functions() {
        // section 1's first function is the vehicle's translation
        match (section, f.index()) {
            (1, 1) => {}
            (1, i) if deriv == 0 => row[layout.index(1, i)] = f.eval(x, 0) - f.eval(0.0, 0),
            (k, i) => row[layout.index(k, i)] = f.eval(x, deriv),
        }
    }
    row
}

/// The state at rest and straight at time `t0` (s): `z = 0` except the vehicle, which sits at
/// `s(t0)` with speed `s'(t0)` for a prescribed motion.
pub fn rest_state(model: &dyn Model, t0: f64) -> Vec<f64> {
    let n = model.dof();
    let mut y = vec![0.0; 2 * n];
    if let Drive::Motion(s) = &model.params().drive {
        y[0] = s.value(t0);
        y[n] = s.rate(t0);
    }
    y
}

/// Total mechanical energy (J) at state `y`: kinetic `1/2 zd' M zd`, elastic and prestress
/// `1/2 z' K z`, and the contact springs. Allocates; for tests and run summaries.
pub fn mechanical_energy(model: &dyn Model, t: f64, y: &[f64]) -> f64 {
    let n = model.dof();
    let z = DVector::from_column_slice(&y[..n]);
    let zd = DVector::from_column_slice(&y[n..]);
    let kinetic = 0.5 * zd.dot(&(model.mass_matrix() * &zd));
    let potential = 0.5 * z.dot(&(model.stiffness_matrix() * &z));
    let nc = model.layout().contact_count();
    let (mut xi, mut xid) = (vec![0.0; nc], vec![0.0; nc]);
    model.contact_gaps(t, y, &mut xi, &mut xid);
    let springs: f64 = xi
        .iter()
        .map(|&x| model.params().contact.spring_energy(x))
        .sum();
    kinetic + potential + springs
}
