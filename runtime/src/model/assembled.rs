//! The quadrature-assembled model: docs/model.md section 4 for any number of sections and modes,
//! integrated with Gauss-Legendre ([`crate::model::quadrature`]). The generic model, and the
//! reference the generated models are tested against.

use crate::analysis::damping::structural_damping;
use crate::contact::ContactState;
use crate::contact::table::ContactTable;
use crate::model::Model;
use crate::model::layout::{ContactPoint, Layout};
use crate::model::mass_solve::MassSolve;
use crate::model::params::Basis;
use crate::model::params::{Drive, ModelParams, SectionParams};
use crate::model::quadrature::SectionQuadrature;
use crate::profile::Profile;
pub use crate::shape::section_basis::MAX_SECTION_COORDINATES;

use crate::model::params::correction_knots;
use crate::shape::section_basis::SectionBasis;
use crate::shape::{MAX_MODES, SectionKind, SectionShapes};
use nalgebra::{DMatrix, DVector, DVectorView, DVectorViewMut};

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
    SectionBasis::paper_modes(section, kind).integrals(section, &quad, prestress)
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
    inner: [f64; MAX_SECTION_COORDINATES],
    outer: [f64; MAX_SECTION_COORDINATES],
    inner_rate: [f64; MAX_SECTION_COORDINATES],
    outer_rate: [f64; MAX_SECTION_COORDINATES],
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
    /// Each section's coordinate functions.
    bases: Vec<SectionBasis>,
    mass: DMatrix<f64>,
    stiffness: DMatrix<f64>,
    /// Structural damping `D_s` ([`crate::analysis::damping`]), when the scene has any.
    damping: Option<DMatrix<f64>>,
    drive: DVector<f64>,
    mass_solve: MassSolve,
    /// Contact entries when every telescopic position is constant.
    fixed_contacts: Option<Vec<ContactEntries>>,
    /// Per contact, its entries (inner section's, then outer's) tabulated in time when
    /// positions move ([`ContactTable`]): shape functions at moving points are the costly
    /// part of a right-hand side.
    moving_tables: Option<Vec<ContactTable>>,
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
        Self::build(params, true)
    }

    /// As [`AssembledModel::new`], but evaluating moving contact vectors from the shape
    /// functions at every call instead of a table: the reference the generated models'
    /// tables are tested against.
    ///
    /// # Errors
    /// As [`AssembledModel::new`].
    pub fn exact(params: &ModelParams) -> Result<Self, ModelError> {
        Self::build(params, false)
    }

    fn build(params: &ModelParams, tabulate: bool) -> Result<Self, ModelError> {
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
        let coordinates = params.coordinates();
        if let Some(k) = coordinates
            .iter()
            .position(|&c| c > MAX_SECTION_COORDINATES)
        {
            return Err(ModelError::Invalid(format!(
                "section {} has {} coordinates ({} modes and {} static correction shapes); at \
                 most {MAX_SECTION_COORDINATES}",
                k + 1,
                coordinates[k],
                params.sections[k].modes,
                coordinates[k] - params.sections[k].modes
            )));
        }
        let layout = Layout::new(&coordinates, params.contact_points);
        let dof = layout.dof();
        let mut bases = Vec::with_capacity(n);
        let mut mass = DMatrix::zeros(dof, dof);
        let mut stiffness = DMatrix::zeros(dof, dof);
        let mut quadrature_points = Vec::with_capacity(n);
        for (k0, sec) in params.sections.iter().enumerate() {
            let k = k0 + 1;
            let shapes = SectionShapes::new(SectionKind::of_section(k), sec.modes, sec.length);
            let knots = match params.basis {
                Basis::Modes => Vec::new(),
                Basis::ModesAndStatic => correction_knots(params, k),
            };
            let quad = SectionQuadrature::split_at(sec.length, shapes.max_beta(), &knots);
            quadrature_points.push(quad.nodes.len());
            let basis = SectionBasis::new(params, k, layout.offset(k), &quad)
                .map_err(ModelError::Invalid)?;
            let (m_loc, k_loc) = basis.integrals(sec, &quad, params.prestress(k));
            for (a, ga) in basis.indices().iter().enumerate() {
                for (b, gb) in basis.indices().iter().enumerate() {
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
        let mass_solve = MassSolve::new(&mass, &params.drive).ok_or(ModelError::SingularMass)?;
        let mut model = Self {
            params: params.clone(),
            layout,
            bases,
            mass,
            stiffness,
            damping: None,
            drive,
            mass_solve,
            fixed_contacts: None,
            moving_tables: None,
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
        } else if tabulate {
            model.moving_tables = model.tabulate_contacts();
        }
        model.damping = structural_damping(&model)
            .map_err(|e| ModelError::Invalid(format!("structural damping: {e}")))?;
        Ok(model)
    }

    /// Values of a section's basis functions at `x` as a global vector.
    fn point_vector(basis: &SectionBasis, dof: usize, x: f64) -> DVector<f64> {
        let mut values = vec![0.0; basis.len()];
        basis.values(x, 0, &mut values);
        let mut v = DVector::zeros(dof);
        for (j, b) in basis.indices().iter().zip(values) {
            v[*j] += b;
        }
        v
    }

    /// Quadrature points used on each section (see [`crate::model::quadrature`] for the rule).
    pub fn quadrature_points(&self) -> &[usize] {
        &self.quadrature_points
    }

    /// Contact vector entries of contact point `c` at time `t`.
    fn contact_entries(&self, c: ContactPoint, t: f64) -> ContactEntries {
        let a = &self.params.positions[c.overlap - 2];
        self.contact_entries_at(c, a.value(t), a.rate(t))
    }

    /// The entries of contact point `c` with every value zero.
    fn empty_entries(&self, c: ContactPoint) -> ContactEntries {
        let k = c.overlap;
        ContactEntries {
            inner_offset: self.layout.offset(k),
            inner_len: self.layout.modes()[k - 1],
            outer_offset: self.layout.offset(k - 1),
            outer_len: self.layout.modes()[k - 2],
            inner: [0.0; MAX_SECTION_COORDINATES],
            outer: [0.0; MAX_SECTION_COORDINATES],
            inner_rate: [0.0; MAX_SECTION_COORDINATES],
            outer_rate: [0.0; MAX_SECTION_COORDINATES],
        }
    }

    /// One [`ContactTable`] per contact over the interval where the positions move; `None`
    /// when a profile cannot be tabulated (a kink in its rate) or a table misses its
    /// tolerances.
    fn tabulate_contacts(&self) -> Option<Vec<ContactTable>> {
        let tolerances = self.params.basis.table_tolerances();
        self.layout
            .contacts()
            .map(|c| {
                let e = self.empty_entries(c);
                let (il, ol) = (e.inner_len, e.outer_len);
                ContactTable::build_to(&self.params.positions, il + ol, tolerances, |t, g, gd| {
                    let e = self.contact_entries(c, t);
                    g[..il].copy_from_slice(&e.inner[..il]);
                    g[il..].copy_from_slice(&e.outer[..ol]);
                    gd[..il].copy_from_slice(&e.inner_rate[..il]);
                    gd[il..].copy_from_slice(&e.outer_rate[..ol]);
                })
            })
            .collect()
    }

    /// The entries of contact point `c` at `t` (s) interpolated from `table`.
    #[inline]
    fn tabulated_entries(&self, c: ContactPoint, table: &ContactTable, t: f64) -> ContactEntries {
        let mut e = self.empty_entries(c);
        let (il, ol) = (e.inner_len, e.outer_len);
        let mut g = [0.0; 2 * MAX_SECTION_COORDINATES];
        let mut gd = [0.0; 2 * MAX_SECTION_COORDINATES];
        table.interpolate(t, &mut g[..il + ol], &mut gd[..il + ol]);
        e.inner[..il].copy_from_slice(&g[..il]);
        e.outer[..ol].copy_from_slice(&g[il..il + ol]);
        e.inner_rate[..il].copy_from_slice(&gd[..il]);
        e.outer_rate[..ol].copy_from_slice(&gd[il..il + ol]);
        e
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
        let mut e = self.empty_entries(c);
        // the translation (index 0) cancels between the sections and is skipped
        let (mut value, mut slope) = (
            [0.0; MAX_SECTION_COORDINATES + 1],
            [0.0; MAX_SECTION_COORDINATES + 1],
        );
        let inner = &self.bases[k - 1];
        inner.values(x_in, 0, &mut value);
        inner.values(x_in, 1, &mut slope);
        for (a, &j) in inner.indices().iter().enumerate().skip(1) {
            let i = j - e.inner_offset;
            e.inner[i] = value[a];
            e.inner_rate[i] = slope[a] * rate_in;
        }
        let outer = &self.bases[k - 2];
        outer.values(x_out, 0, &mut value);
        outer.values(x_out, 1, &mut slope);
        for (a, &j) in outer.indices().iter().enumerate().skip(1) {
            let i = j - e.outer_offset;
            e.outer[i] = -value[a];
            e.outer_rate[i] = -slope[a] * rate_out;
        }
        e
    }

    /// Runs `f(c, entries)` for every contact at time `t`, from the cache when positions are fixed.
    #[inline]
    fn for_each_contact(&self, t: f64, mut f: impl FnMut(usize, &ContactEntries)) {
        match (&self.fixed_contacts, &self.moving_tables) {
            (Some(fixed), _) => fixed.iter().enumerate().for_each(|(c, e)| f(c, e)),
            (None, Some(tables)) => {
                for ((c, p), table) in self.layout.contacts().enumerate().zip(tables) {
                    f(c, &self.tabulated_entries(p, table, t));
                }
            }
            (None, None) => {
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
        self.mass_solve.accelerations(self.drive_input(t), acc);
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
        self.mass_solve.jacobian_rows(jac);
    }

    fn shape_row(&self, section: usize, x: f64, deriv: u8) -> Vec<f64> {
        let basis = &self.bases[section - 1];
        let mut values = vec![0.0; basis.len()];
        basis.values(x, deriv, &mut values);
        let mut row = vec![0.0; self.dof()];
        for (&j, v) in basis.indices().iter().zip(values) {
            row[j] += v;
        }
        row
    }

    fn displacement(&self, section: usize, x: f64, z: &[f64]) -> f64 {
        self.bases[section - 1].combine(x, 0, z)
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
