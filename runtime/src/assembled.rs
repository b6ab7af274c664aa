//! The quadrature-assembled model: docs/model.md section 4 for any number of sections and modes,
//! integrated with Gauss-Legendre ([`crate::quadrature`]). The generic model, and the
//! reference the generated models are tested against.

use crate::contact::ContactState;
use crate::damping::structural_damping;
use crate::layout::{ContactPoint, Layout};
use crate::model::Model;
use crate::params::{Drive, ModelParams, SectionParams};
use crate::profile::Profile;
use crate::quadrature::SectionQuadrature;
use crate::shape::{MAX_MODES, SectionKind, SectionShapes, ShapeFunction};
use nalgebra::{Cholesky, DMatrix, DVector, DVectorView, DVectorViewMut, Dyn};

/// Why a model could not be built.
#[derive(Debug, thiserror::Error)]
pub enum ModelError {
    /// The mass matrix is not positive definite (a section with no mass, or round-off with
    /// extreme parameters).
    #[error("the mass matrix is not positive definite (check masses and densities)")]
    SingularMass,
    /// The parameters do not fit the layout rules.
    #[error("invalid model parameters: {0}")]
    Invalid(String),
}

/// A basis function restricted to one section, in the computing coordinates.
#[derive(Debug, Clone, Copy)]
enum LocalBasis {
    /// The unit translation (value 1, derivatives 0).
    Translation,
    /// `phi(x) - shift`.
    Shape(ShapeFunction, f64),
}

impl LocalBasis {
    #[inline]
    fn eval(&self, x: f64, deriv: u8) -> f64 {
        match self {
            LocalBasis::Translation => {
                if deriv == 0 {
                    1.0
                } else {
                    0.0
                }
            }
            LocalBasis::Shape(f, shift) => {
                if deriv == 0 {
                    f.eval(x, 0) - shift
                } else {
                    f.eval(x, deriv)
                }
            }
        }
    }
}

/// `int rhoA psi_a psi_b` and `int (EI psi_a'' psi_b'' - P psi_a' psi_b')` over one section, for a
/// list of local basis functions; `prestress = (p0, p1)` gives `P(x) = p0 + p1 x` (N).
fn section_integrals(
    section: &SectionParams,
    quad: &SectionQuadrature,
    basis: &[LocalBasis],
    prestress: (f64, f64),
) -> (DMatrix<f64>, DMatrix<f64>) {
    let m = basis.len();
    let mut mass = DMatrix::zeros(m, m);
    let mut stiff = DMatrix::zeros(m, m);
    let (mut v, mut d1, mut d2) = (vec![0.0; m], vec![0.0; m], vec![0.0; m]);
    for (&x, &w) in quad.nodes.iter().zip(&quad.weights) {
        for (a, b) in basis.iter().enumerate() {
            v[a] = b.eval(x, 0);
            d1[a] = b.eval(x, 1);
            d2[a] = b.eval(x, 2);
        }
        let rho_a = w * section.mass_per_length;
        let ei = w * section.bending_stiffness;
        let p = w * (prestress.0 + prestress.1 * x);
        for a in 0..m {
            for b in 0..m {
                mass[(a, b)] += rho_a * v[a] * v[b];
                stiff[(a, b)] += ei * d2[a] * d2[b] - p * d1[a] * d1[b];
            }
        }
    }
    (mass, stiff)
}

/// Mass and stiffness matrices of one section in the paper's basis `phi_{k,1..N}`, without
/// point masses: `M_ij = int rhoA phi_i phi_j`, `K_ij = int EI phi_i'' phi_j'' - int P phi_i' phi_j'`.
/// `kind` picks the shape functions; `prestress = (p0, p1)`, `P(x) = p0 + p1 x` (N).
pub fn paper_section_matrices(
    section: &SectionParams,
    kind: SectionKind,
    prestress: (f64, f64),
) -> (DMatrix<f64>, DMatrix<f64>) {
    let shapes = SectionShapes::new(kind, section.modes, section.length);
    let quad = SectionQuadrature::for_modes(section.length, shapes.max_beta());
    let basis: Vec<_> = shapes
        .functions()
        .iter()
        .map(|&f| LocalBasis::Shape(f, 0.0))
        .collect();
    section_integrals(section, &quad, &basis, prestress)
}

/// Contact vector entries of one contact: the values on the inner section `k` (`+psi(x_in)`)
/// and on the outer section `k-1` (`-psi(x_out)`), and their time derivatives. Fixed-size so
/// that evaluating them allocates nothing.
#[derive(Debug, Clone, Copy)]
struct ContactEntries {
    inner_offset: usize,
    inner_len: usize,
    outer_offset: usize,
    outer_len: usize,
    inner: [f64; MAX_MODES],
    outer: [f64; MAX_MODES],
    inner_rate: [f64; MAX_MODES],
    outer_rate: [f64; MAX_MODES],
}

impl ContactEntries {
    /// `(index, g, gdot)` for every entry.
    #[inline]
    fn entries(&self) -> impl Iterator<Item = (usize, f64, f64)> + '_ {
        let inner =
            (0..self.inner_len).map(|i| (self.inner_offset + i, self.inner[i], self.inner_rate[i]));
        let outer =
            (0..self.outer_len).map(|i| (self.outer_offset + i, self.outer[i], self.outer_rate[i]));
        inner.chain(outer)
    }

    /// `(xi, xi_dot)` at state `z`, `zd`.
    #[inline]
    fn gap(&self, z: &[f64], zd: &[f64]) -> (f64, f64) {
        self.entries().fold((0.0, 0.0), |(xi, xid), (j, g, gd)| {
            (xi + g * z[j], xid + g * zd[j] + gd * z[j])
        })
    }
}

/// The quadrature-assembled model. Built once per scene; every per-call method is
/// allocation-free.
#[derive(Debug, Clone)]
pub struct AssembledModel {
    params: ModelParams,
    layout: Layout,
    /// Local basis of each section: `(global index, function)`.
    bases: Vec<Vec<(usize, LocalBasis)>>,
    mass: DMatrix<f64>,
    stiffness: DMatrix<f64>,
    /// Structural damping `D_s` ([`crate::damping`]), when the scene has any.
    damping: Option<DMatrix<f64>>,
    drive: DVector<f64>,
    mass_factor: Cholesky<f64, Dyn>,
    /// Cholesky factor of `M` without row and column 0 (prescribed vehicle motion).
    relative_mass_factor: Option<Cholesky<f64, Dyn>>,
    /// Contact entries when every telescopic position is constant.
    fixed_contacts: Option<Vec<ContactEntries>>,
    /// `tip_rel = tip . z`, `top1_rel = top1 . z`.
    tip: DVector<f64>,
    top1: DVector<f64>,
    quadrature_points: Vec<usize>,
}

impl AssembledModel {
    /// Assembles `M`, `K`, `b` by quadrature and prepares the per-call constants.
    ///
    /// # Errors
    /// [`ModelError`] if the parameters break the layout rules or `M` is not positive definite.
    pub fn new(params: &ModelParams) -> Result<Self, ModelError> {
        let n = params.sections.len();
        if n == 0
            || params
                .sections
                .iter()
                .any(|s| s.modes == 0 || s.modes > MAX_MODES)
        {
            return Err(ModelError::Invalid(format!(
                "every section needs 1..={MAX_MODES} modes"
            )));
        }
        if n > 1 && (params.contact_points < 2 || params.positions.len() != n - 1) {
            return Err(ModelError::Invalid(
                "need n_c >= 2 and one telescopic position per overlap".into(),
            ));
        }
        let layout = Layout::new(&params.modes(), params.contact_points);
        let dof = layout.dof();
        let mut bases = Vec::with_capacity(n);
        let mut mass = DMatrix::zeros(dof, dof);
        let mut stiffness = DMatrix::zeros(dof, dof);
        let mut quadrature_points = Vec::with_capacity(n);
        for (k0, sec) in params.sections.iter().enumerate() {
            let k = k0 + 1;
            let shapes = SectionShapes::new(SectionKind::of_section(k), sec.modes, sec.length);
            let mut basis = vec![(0, LocalBasis::Translation)];
            for f in shapes.functions() {
                match (k, f.index()) {
                    (1, 1) => {} // section 1's rigid mode is the translation, index 0
                    (1, i) => {
                        basis.push((layout.index(1, i), LocalBasis::Shape(*f, f.eval(0.0, 0))))
                    }
                    (_, i) => basis.push((layout.index(k, i), LocalBasis::Shape(*f, 0.0))),
                }
            }
            let quad = SectionQuadrature::for_modes(sec.length, shapes.max_beta());
            quadrature_points.push(quad.nodes.len());
            let local: Vec<_> = basis.iter().map(|(_, b)| *b).collect();
            let (m_loc, k_loc) = section_integrals(sec, &quad, &local, params.prestress(k));
            for (a, (ga, _)) in basis.iter().enumerate() {
                for (b, (gb, _)) in basis.iter().enumerate() {
                    mass[(*ga, *gb)] += m_loc[(a, b)];
                    stiffness[(*ga, *gb)] += k_loc[(a, b)];
                }
            }
            bases.push(basis);
        }
        // point masses: the vehicle at w_1(0) = z_0, the load at the top of section n
        mass[(0, 0)] += params.vehicle_mass;
        let tip_full = Self::point_vector(&bases[n - 1], dof, params.sections[n - 1].length);
        mass += params.load_mass * &tip_full * tip_full.transpose();
        let mut tip = tip_full;
        tip[0] = 0.0;
        let mut top1 = Self::point_vector(&bases[0], dof, params.sections[0].length);
        top1[0] = 0.0;
        // exact symmetry (the quadrature sums are symmetric, point masses too)
        let mass = 0.5 * (&mass + mass.transpose());
        let stiffness = 0.5 * (&stiffness + stiffness.transpose());
        let mut drive = DVector::zeros(dof);
        drive[0] = 1.0;
        let mass_factor = mass.clone().cholesky().ok_or(ModelError::SingularMass)?;
        let relative_mass_factor = match params.drive {
            Drive::Motion(_) if dof > 1 => Some(
                mass.view((1, 1), (dof - 1, dof - 1))
                    .into_owned()
                    .cholesky()
                    .ok_or(ModelError::SingularMass)?,
            ),
            _ => None,
        };
        let mut model = Self {
            params: params.clone(),
            layout,
            bases,
            mass,
            stiffness,
            damping: None,
            drive,
            mass_factor,
            relative_mass_factor,
            fixed_contacts: None,
            tip,
            top1,
            quadrature_points,
        };
        if params.positions.iter().all(Profile::is_constant) {
            let fixed = model
                .layout
                .contacts()
                .map(|c| model.contact_entries(c, 0.0))
                .collect();
            model.fixed_contacts = Some(fixed);
        }
        model.damping = structural_damping(&model)
            .map_err(|e| ModelError::Invalid(format!("structural damping: {e}")))?;
        Ok(model)
    }

    /// Values of a section's basis functions at `x` as a global vector.
    fn point_vector(basis: &[(usize, LocalBasis)], dof: usize, x: f64) -> DVector<f64> {
        let mut v = DVector::zeros(dof);
        for (j, b) in basis {
            v[*j] += b.eval(x, 0);
        }
        v
    }

    /// Quadrature points used on each section (see [`crate::quadrature`] for the rule).
    pub fn quadrature_points(&self) -> &[usize] {
        &self.quadrature_points
    }

    /// Contact vector entries of contact point `c` at time `t`.
    fn contact_entries(&self, c: ContactPoint, t: f64) -> ContactEntries {
        let a = &self.params.positions[c.overlap - 2];
        self.contact_entries_at(c, a.value(t), a.rate(t))
    }

    /// Contact vector entries of contact point `c` with its overlap's foot position `a_t` (m)
    /// moving at `a_rate` (m/s).
    fn contact_entries_at(&self, c: ContactPoint, a_t: f64, a_rate: f64) -> ContactEntries {
        let k = c.overlap;
        let l_out = self.params.sections[k - 2].length;
        let s = c.fraction;
        let x_in = s * (l_out - a_t);
        let x_out = a_t + s * (l_out - a_t);
        let (rate_in, rate_out) = (-s * a_rate, (1.0 - s) * a_rate);
        let mut e = ContactEntries {
            inner_offset: self.layout.offset(k),
            inner_len: self.layout.modes()[k - 1],
            outer_offset: self.layout.offset(k - 1),
            outer_len: self.layout.modes()[k - 2],
            inner: [0.0; MAX_MODES],
            outer: [0.0; MAX_MODES],
            inner_rate: [0.0; MAX_MODES],
            outer_rate: [0.0; MAX_MODES],
        };
        // the translation (index 0) cancels between the sections and is skipped
        for &(j, b) in &self.bases[k - 1] {
            if j != 0 {
                let i = j - e.inner_offset;
                e.inner[i] = b.eval(x_in, 0);
                e.inner_rate[i] = b.eval(x_in, 1) * rate_in;
            }
        }
        for &(j, b) in &self.bases[k - 2] {
            if j != 0 {
                let i = j - e.outer_offset;
                e.outer[i] = -b.eval(x_out, 0);
                e.outer_rate[i] = -b.eval(x_out, 1) * rate_out;
            }
        }
        e
    }

    /// Runs `f(c, entries)` for every contact at time `t`, from the cache when positions are fixed.
    #[inline]
    fn for_each_contact(&self, t: f64, mut f: impl FnMut(usize, &ContactEntries)) {
        match &self.fixed_contacts {
            Some(fixed) => fixed.iter().enumerate().for_each(|(c, e)| f(c, e)),
            None => {
                for (c, p) in self.layout.contacts().enumerate() {
                    f(c, &self.contact_entries(p, t));
                }
            }
        }
    }

    fn drive_input(&self, t: f64) -> f64 {
        match &self.params.drive {
            Drive::Force(f) => f.value(t),
            Drive::Motion(s) => s.acceleration(t),
        }
    }
}

impl Model for AssembledModel {
    fn layout(&self) -> &Layout {
        &self.layout
    }

    fn params(&self) -> &ModelParams {
        &self.params
    }

    fn mass_matrix(&self) -> &DMatrix<f64> {
        &self.mass
    }

    fn stiffness_matrix(&self) -> &DMatrix<f64> {
        &self.stiffness
    }

    fn damping_matrix(&self) -> Option<&DMatrix<f64>> {
        self.damping.as_ref()
    }

    fn drive_vector(&self) -> &DVector<f64> {
        &self.drive
    }

    fn contact_vectors(&self, t: f64, g: &mut DMatrix<f64>, gdot: &mut DMatrix<f64>) {
        g.fill(0.0);
        gdot.fill(0.0);
        self.for_each_contact(t, |c, e| {
            for (j, gv, gd) in e.entries() {
                g[(j, c)] = gv;
                gdot[(j, c)] = gd;
            }
        });
    }

    fn contact_vectors_at(
        &self,
        positions: &[f64],
        rates: &[f64],
        g: &mut DMatrix<f64>,
        gdot: &mut DMatrix<f64>,
    ) {
        g.fill(0.0);
        gdot.fill(0.0);
        for (c, p) in self.layout.contacts().enumerate() {
            let e = self.contact_entries_at(p, positions[p.overlap - 2], rates[p.overlap - 2]);
            for (j, gv, gd) in e.entries() {
                g[(j, c)] = gv;
                gdot[(j, c)] = gd;
            }
        }
    }

    fn contact_gaps(&self, t: f64, y: &[f64], xi: &mut [f64], xi_dot: &mut [f64]) {
        let n = self.dof();
        let (z, zd) = y.split_at(n);
        self.for_each_contact(t, |c, e| (xi[c], xi_dot[c]) = e.gap(z, zd));
    }

    fn rhs(&self, t: f64, y: &[f64], states: Option<&[ContactState]>, ydot: &mut [f64]) {
        let n = self.dof();
        let (z, zd) = y.split_at(n);
        let (vel, acc) = ydot.split_at_mut(n);
        vel.copy_from_slice(zd);
        acc.fill(0.0);
        let mut acc = DVectorViewMut::from_slice(acc, n);
        acc.gemv(-1.0, &self.stiffness, &DVectorView::from_slice(z, n), 0.0);
        if let Some(d) = &self.damping {
            acc.gemv(-1.0, d, &DVectorView::from_slice(zd, n), 1.0);
        }
        self.for_each_contact(t, |c, e| {
            let (xi, xid) = e.gap(z, zd);
            let f = self.contact_force(c, xi, xid, states).force;
            for (j, g, _) in e.entries() {
                acc[j] -= f * g;
            }
        });
        let input = self.drive_input(t);
        match &self.relative_mass_factor {
            None => {
                acc[0] += input;
                self.mass_factor.solve_mut(&mut acc);
            }
            Some(factor) => {
                // u'' = s''(t) is given; the other rows carry -M_p0 s'' and drop the reaction
                for j in 1..n {
                    acc[j] -= self.mass[(j, 0)] * input;
                }
                factor.solve_mut(&mut acc.rows_mut(1, n - 1));
                acc[0] = input;
            }
        }
    }

    fn jacobian(&self, t: f64, y: &[f64], states: Option<&[ContactState]>, jac: &mut DMatrix<f64>) {
        let n = self.dof();
        let (z, zd) = y.split_at(n);
        jac.fill(0.0);
        for j in 0..n {
            jac[(j, n + j)] = 1.0;
        }
        // lower rows first hold [K + sum f_xi g g' + f_xidot g gdot' | sum f_xidot g g'] ...
        jac.view_mut((n, 0), (n, n)).copy_from(&self.stiffness);
        if let Some(d) = &self.damping {
            jac.view_mut((n, n), (n, n)).copy_from(d);
        }
        self.for_each_contact(t, |c, e| {
            let (xi, xid) = e.gap(z, zd);
            let f = self.contact_force(c, xi, xid, states);
            if f.d_gap == 0.0 && f.d_rate == 0.0 {
                return;
            }
            for (i, gi, _) in e.entries() {
                for (j, gj, gdj) in e.entries() {
                    jac[(n + i, j)] += gi * (f.d_gap * gj + f.d_rate * gdj);
                    jac[(n + i, n + j)] += f.d_rate * gi * gj;
                }
            }
        });
        // ... then become -M^-1 times that
        match &self.relative_mass_factor {
            None => self
                .mass_factor
                .solve_mut(&mut jac.view_mut((n, 0), (n, 2 * n))),
            Some(factor) => {
                jac.row_mut(n).fill(0.0);
                factor.solve_mut(&mut jac.view_mut((n + 1, 0), (n - 1, 2 * n)));
            }
        }
        jac.view_mut((n, 0), (n, 2 * n)).neg_mut();
    }

    fn displacement(&self, section: usize, x: f64, z: &[f64]) -> f64 {
        self.bases[section - 1]
            .iter()
            .map(|(j, b)| z[*j] * b.eval(x, 0))
            .sum()
    }

    fn outputs(&self, t: f64, y: &[f64], ydot: &[f64], out: &mut [f64]) {
        let n = self.dof();
        let (z, zd) = y.split_at(n);
        out[0] = z[0];
        out[1] = self.tip.iter().zip(z).map(|(a, b)| a * b).sum();
        out[2] = self.top1.iter().zip(z).map(|(a, b)| a * b).sum();
        let nc = self.layout.contact_count();
        self.for_each_contact(t, |c, e| {
            let (xi, xid) = e.gap(z, zd);
            out[3 + c] = xi;
            out[3 + nc + c] = self.contact_force(c, xi, xid, None).force;
        });
        if matches!(self.params.drive, Drive::Motion(_)) {
            // reaction: row 0 of M zdd + D_s zd = F (K's row 0 and every g_c[0] vanish)
            let row = |m: &DMatrix<f64>, v: &[f64]| -> f64 {
                m.row(0).iter().zip(v).map(|(a, b)| a * b).sum()
            };
            out[3 + 2 * nc] =
                row(&self.mass, &ydot[n..]) + self.damping.as_ref().map_or(0.0, |d| row(d, zd));
        }
    }
}
