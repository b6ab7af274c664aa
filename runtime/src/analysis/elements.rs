//! An independent finite-element model of the same beams and contacts: the truth the Ritz
//! models are checked against.
//!
//! Every section is cut into Hermite cubic elements (the standard Euler-Bernoulli element:
//! nodal displacement and slope, consistent mass, the prestress `P(x)` of docs/model.md
//! integrated element by element), with the vehicle and the load as point masses and the
//! contact points of docs/model.md section 3, with their law, at mesh nodes. It shares only
//! the parameters with the Ritz models: no shape function, root or quadrature rule of theirs.
//! With fixed telescopic positions the contact points are nodes of the mesh; with moving ones
//! they slide across the elements (the mesh is cut at their starting points), and a contact
//! vector is the Hermite functions of the element the point is in at that time, its rate
//! their slopes times the point's speed (docs/model.md, section 3), as in the Ritz models.
//!
//! Coordinates follow [`crate::model`]: index 0 is the vehicle position `u`, carried by the
//! unit translation of the whole telescope; every other coordinate is a nodal displacement
//! relative to it (`w - u`) or a nodal slope. Section 1's foot node has neither (its
//! displacement is `u`, its slope is held at zero).
//!
//! Its spectrum reaches far above the Ritz models' (the shortest element's modes): a scene
//! without clearance runs on it exactly with method `exact` (one matrix exponential, one
//! step per sample), and [`ElementModel::frequencies_hz`] solves the eigenproblem in inverse
//! form so that the lowest frequencies keep their digits.
//!
//! ```
//! use telescopic_runtime::{ElementModel, Scene};
//! let scene = Scene::load("../scenes/test-rig.toml".as_ref(), &[]).unwrap();
//! let beams = ElementModel::new(&scene.params, 32).unwrap();
//! let f = beams.frequencies_hz(3).unwrap();
//! // the beams' f1; the paper's 5 modes per section give 0.498 Hz (docs/numerics.md)
//! assert!((f[0] - 0.4914).abs() < 1e-3);
//! ```

use crate::contact::ContactState;
use crate::model::Model;
use crate::model::layout::{ContactPoint, Layout};
use crate::model::mass_solve::MassSolve;
use crate::model::params::StructuralDamping;
use crate::model::params::{Drive, ModelParams, SectionParams};
use crate::profile::Profile;
use nalgebra::{DMatrix, DVector, DVectorView, DVectorViewMut, SymmetricEigen};
use std::f64::consts::PI;

/// Why an element model could not be built or solved.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ElementError {
    /// The element count is out of range.
    #[error("elements per section must be 2 to {MAX_ELEMENTS} (got {0})")]
    Elements(usize),
    /// A matrix that must be positive definite is not.
    #[error("the {0} matrix is not positive definite")]
    NotPositiveDefinite(&'static str),
    /// Modal structural damping is defined on the Ritz model's modes.
    #[error(
        "the finite-element reference takes Rayleigh damping only (modal damping is defined on the Ritz model's modes)"
    )]
    ModalDamping,
    /// The eigen solver did not converge.
    #[error("the symmetric eigen solver did not converge")]
    NoConvergence,
}

/// Largest number of elements per section (the matrices are dense).
pub const MAX_ELEMENTS: usize = 512;

/// One section's mesh: node positions and the global coordinates of each node.
#[derive(Debug, Clone)]
struct SectionMesh {
    /// Node positions `x` (m) from the section's foot, ascending, `0` and `l` included.
    nodes: Vec<f64>,
    /// Global index of the node's relative displacement and slope; `None` where held.
    dofs: Vec<[Option<usize>; 2]>,
}

impl SectionMesh {
    /// The element `(index, s)` holding `x`: `s` in `[0, 1]` along it.
    fn locate(&self, x: f64) -> (usize, f64) {
        let last = self.nodes.len() - 2;
        let e = self
            .nodes
            .partition_point(|&n| n <= x)
            .saturating_sub(1)
            .min(last);
        let (a, b) = (self.nodes[e], self.nodes[e + 1]);
        (e, ((x - a) / (b - a)).clamp(0.0, 1.0))
    }

    /// The global coordinates of element `e`'s four Hermite functions.
    fn element_dofs(&self, e: usize) -> [Option<usize>; 4] {
        [
            self.dofs[e][0],
            self.dofs[e][1],
            self.dofs[e + 1][0],
            self.dofs[e + 1][1],
        ]
    }

    /// The curvature `w''` inside element `e` at `s` in `[0, 1]` for coordinates `z`.
    fn curvature(&self, e: usize, s: f64, z: &[f64]) -> f64 {
        let h = self.nodes[e + 1] - self.nodes[e];
        self.element_dofs(e)
            .into_iter()
            .zip(hermite(s, h, 2))
            .filter_map(|(d, v)| d.map(|d| v * z[d]))
            .sum()
    }

    /// `(global index, value of derivative deriv)` of the element's four Hermite functions
    /// at `x` (the translation excluded), skipping held coordinates.
    fn point_entries(&self, x: f64, deriv: u8) -> impl Iterator<Item = (usize, f64)> + '_ {
        let (e, s) = self.locate(x);
        let h = self.nodes[e + 1] - self.nodes[e];
        self.element_dofs(e)
            .into_iter()
            .zip(hermite(s, h, deriv))
            .filter_map(|(d, v)| d.map(|d| (d, v)))
    }
}

/// The Hermite cubics `[N1, N2, N3, N4]` (displacement and slope at each end) of an element
/// of length `h` at `s = (x - x_a) / h`, or their `deriv`-th derivative in `x`.
fn hermite(s: f64, h: f64, deriv: u8) -> [f64; 4] {
    let (s2, s3) = (s * s, s * s * s);
    match deriv {
        0 => [
            1.0 - 3.0 * s2 + 2.0 * s3,
            h * (s - 2.0 * s2 + s3),
            3.0 * s2 - 2.0 * s3,
            h * (s3 - s2),
        ],
        1 => [
            (6.0 * s2 - 6.0 * s) / h,
            1.0 - 4.0 * s + 3.0 * s2,
            (6.0 * s - 6.0 * s2) / h,
            3.0 * s2 - 2.0 * s,
        ],
        _ => [
            (12.0 * s - 6.0) / (h * h),
            (6.0 * s - 4.0) / h,
            (6.0 - 12.0 * s) / (h * h),
            (6.0 * s - 2.0) / h,
        ],
    }
}

/// Four-point Gauss-Legendre rule on `[0, 1]`: exact for the degree-6 mass integrands and the
/// degree-5 prestress integrands of a cubic element.
const GAUSS4: [(f64, f64); 4] = [
    (0.069_431_844_202_973_71, 0.173_927_422_568_726_93),
    (0.330_009_478_207_571_87, 0.326_072_577_431_273_07),
    (0.669_990_521_792_428_1, 0.326_072_577_431_273_07),
    (0.930_568_155_797_026_3, 0.173_927_422_568_726_93),
];

/// A contact vector's nonzero entries over the mesh, `(index, g, gdot)`: at most two nodes'
/// displacement and slope on each of the two sections.
#[derive(Debug, Clone, Copy)]
struct ContactEntries {
    len: usize,
    entries: [(usize, f64, f64); 8],
}

impl ContactEntries {
    /// `(index, g, gdot)` for every entry.
    fn iter(&self) -> impl Iterator<Item = (usize, f64, f64)> + '_ {
        self.entries[..self.len].iter().copied()
    }

    /// `(xi, xi_dot)` at state `z`, `zd` (the rate with the moving point's share).
    fn gap(&self, z: &[f64], zd: &[f64]) -> (f64, f64) {
        self.iter().fold((0.0, 0.0), |(xi, xid), (j, g, gd)| {
            (xi + g * z[j], xid + g * zd[j] + gd * z[j])
        })
    }
}

/// The finite-element model of a scene.
#[derive(Debug, Clone)]
pub struct ElementModel {
    params: ModelParams,
    layout: Layout,
    meshes: Vec<SectionMesh>,
    mass: DMatrix<f64>,
    stiffness: DMatrix<f64>,
    damping: Option<DMatrix<f64>>,
    drive: DVector<f64>,
    mass_solve: MassSolve,
    /// The contact points, in the layout's order.
    points: Vec<ContactPoint>,
    /// Each contact vector's entries when the telescopic positions are fixed (else they
    /// are made at each time).
    fixed_contacts: Option<Vec<ContactEntries>>,
    /// `tip_rel` and `top1_rel` as entries over the coordinates.
    tip: Vec<(usize, f64)>,
    top1: Vec<(usize, f64)>,
}

impl ElementModel {
    /// Meshes every section with about `elements` elements (more where contact points cut
    /// it), assembles `M` and `K`, and places the contacts.
    ///
    /// # Errors
    /// [`ElementError`] for an element count outside `2..=MAX_ELEMENTS`, or a mass matrix
    /// that is not positive definite.
    pub fn new(params: &ModelParams, elements: usize) -> Result<Self, ElementError> {
        if !(2..=MAX_ELEMENTS).contains(&elements) {
            return Err(ElementError::Elements(elements));
        }
        let meshes = number_nodes(params, elements);
        let counts: Vec<usize> = meshes
            .iter()
            .enumerate()
            .map(|(k0, m)| m.dofs.iter().flatten().flatten().count() + usize::from(k0 == 0))
            .collect();
        let layout = Layout::new(&counts, params.contact_points);
        let dof = layout.dof();
        let mut mass = DMatrix::zeros(dof, dof);
        let mut stiffness = DMatrix::zeros(dof, dof);
        for (k0, (mesh, section)) in meshes.iter().zip(&params.sections).enumerate() {
            let prestress = params.prestress(k0 + 1);
            assemble_section(mesh, section, prestress, &mut mass, &mut stiffness);
        }
        let n = params.sections.len();
        let top = |k: usize| {
            let mesh = &meshes[k - 1];
            mesh.point_entries(params.sections[k - 1].length, 0)
                .collect::<Vec<_>>()
        };
        let (tip, top1) = (top(n), top(1));
        // point masses: the vehicle at u, the load at u + w_rel(top of section n)
        mass[(0, 0)] += params.vehicle_mass;
        let mut load = DVector::zeros(dof);
        load[0] = 1.0;
        for &(j, v) in &tip {
            load[j] += v;
        }
        mass += params.load_mass * &load * load.transpose();
        let mass = 0.5 * (&mass + mass.transpose());
        let stiffness = 0.5 * (&stiffness + stiffness.transpose());
        let points: Vec<ContactPoint> = layout.contacts().collect();
        let mass_solve = MassSolve::new(&mass, &params.drive)
            .ok_or(ElementError::NotPositiveDefinite("mass"))?;
        let damping = match params.damping {
            _ if params.damping.is_none() => None,
            StructuralDamping::Rayleigh { alpha, beta } => Some(alpha * &mass + beta * &stiffness),
            StructuralDamping::Modal { .. } => return Err(ElementError::ModalDamping),
            StructuralDamping::None => None,
        };
        let mut drive = DVector::zeros(dof);
        drive[0] = 1.0;
        let mut model = ElementModel {
            params: params.clone(),
            layout,
            meshes,
            mass,
            stiffness,
            damping,
            drive,
            mass_solve,
            points,
            fixed_contacts: None,
            tip,
            top1,
        };
        if params.positions.iter().all(Profile::is_constant) {
            let fixed = (0..model.points.len())
                .map(|c| model.contact_at(c, 0.0))
                .collect();
            model.fixed_contacts = Some(fixed);
        }
        Ok(model)
    }

    /// Number of elements of section `k` (1-based).
    pub fn elements(&self, k: usize) -> usize {
        self.meshes[k - 1].nodes.len() - 1
    }

    /// Bending moment `EI w''(x)` (N m) of section `k` (1-based) at `x` (m) for coordinates
    /// `z`: at an inner node, the mean of its two elements' curvatures.
    pub fn moment(&self, k: usize, x: f64, z: &[f64]) -> f64 {
        let mesh = &self.meshes[k - 1];
        let ei = self.params.sections[k - 1].bending_stiffness;
        let (e, s) = mesh.locate(x);
        let curvature = if s == 1.0 && e + 2 < mesh.nodes.len() {
            0.5 * (mesh.curvature(e, 1.0, z) + mesh.curvature(e + 1, 0.0, z))
        } else if s == 0.0 && e > 0 {
            0.5 * (mesh.curvature(e - 1, 1.0, z) + mesh.curvature(e, 0.0, z))
        } else {
            mesh.curvature(e, s, z)
        };
        ei * curvature
    }

    /// The lowest `count` natural frequencies (Hz) with closed contacts (rigid modes
    /// excluded), from the eigenproblem in inverse form: `K_eff^-1 M` reduced by the Cholesky
    /// factor of `K_eff`, whose largest eigenvalues `1/w^2` the solver gets to full relative
    /// precision however stiff the finest element is.
    ///
    /// # Errors
    /// [`ElementError::NotPositiveDefinite`] when `K_eff` is not (buckled, or a mechanism),
    /// [`ElementError::NoConvergence`].
    pub fn frequencies_hz(&self, count: usize) -> Result<Vec<f64>, ElementError> {
        let (k_r, m_r) = self.relative_problem();
        let r = k_r.nrows();
        let chol = k_r.cholesky().ok_or(ElementError::NotPositiveDefinite(
            "closed-contact stiffness",
        ))?;
        let l = chol.l();
        let a = l.solve_lower_triangular(&m_r).expect("invertible");
        let a = l
            .solve_lower_triangular(&a.transpose())
            .expect("invertible");
        let a = 0.5 * (&a + a.transpose());
        let eig = SymmetricEigen::try_new(a, f64::EPSILON, 100 * r.max(10))
            .ok_or(ElementError::NoConvergence)?;
        let mut inverse: Vec<f64> = eig
            .eigenvalues
            .iter()
            .copied()
            .filter(|&v| v > 0.0)
            .collect();
        inverse.sort_by(|a, b| b.total_cmp(a));
        Ok(inverse
            .iter()
            .take(count)
            .map(|mu| (1.0 / mu).sqrt() / (2.0 * PI))
            .collect())
    }

    /// The closed-contact problem in the relative coordinates `z[1..]`: stiffness and mass
    /// (with the free vehicle's translation condensed out of the mass, as in
    /// [`crate::analysis::eigen`]).
    fn relative_problem(&self) -> (DMatrix<f64>, DMatrix<f64>) {
        let n = self.dof();
        let r = n - 1;
        let k = crate::analysis::eigen::closed_contact_stiffness(self, 0.0);
        let k_r = k.view((1, 1), (r, r)).into_owned();
        let mut m_r = self.mass.view((1, 1), (r, r)).into_owned();
        if matches!(self.params.drive, Drive::Force(_)) {
            let coupling = self.mass.view((1, 0), (r, 1)).into_owned();
            m_r -= &coupling * coupling.transpose() / self.mass[(0, 0)];
        }
        (k_r, m_r)
    }

    fn drive_input(&self, t: f64) -> f64 {
        match &self.params.drive {
            Drive::Force(f) => f.value(t),
            Drive::Motion(s) => s.acceleration(t),
        }
    }

    /// Contact `c`'s vector and its rate at time `t` (s).
    fn contact_at(&self, c: usize, t: f64) -> ContactEntries {
        if let Some(fixed) = &self.fixed_contacts {
            return fixed[c];
        }
        let position = &self.params.positions[self.points[c].overlap - 2];
        self.entries_at(self.points[c], position.value(t), position.rate(t))
    }

    /// The entries of contact point `p`'s vector with its overlap's telescopic position at
    /// `a` (m) moving at `a_rate` (m/s): `+psi(x_in)` on the inner section, `-psi(x_out)` on
    /// the outer one (the translation cancels), the rates from the slopes.
    fn entries_at(&self, p: ContactPoint, a: f64, a_rate: f64) -> ContactEntries {
        let k = p.overlap;
        let s = p.fraction;
        let overlap = self.params.sections[k - 2].length - a;
        let (x_in, x_out) = (s * overlap, a + s * overlap);
        let (rate_in, rate_out) = (-s * a_rate, (1.0 - s) * a_rate);
        let mut e = ContactEntries {
            len: 0,
            entries: [(0, 0.0, 0.0); 8],
        };
        for (mesh, x, rate, sign) in [
            (&self.meshes[k - 1], x_in, rate_in, 1.0),
            (&self.meshes[k - 2], x_out, rate_out, -1.0),
        ] {
            for ((j, v), (_, d)) in mesh.point_entries(x, 0).zip(mesh.point_entries(x, 1)) {
                if v != 0.0 || d != 0.0 {
                    e.entries[e.len] = (j, sign * v, sign * d * rate);
                    e.len += 1;
                }
            }
        }
        e
    }
}

/// The meshes of every section with their global coordinates: nodes at both ends and at every
/// contact point, about `elements` elements per section in between.
fn number_nodes(params: &ModelParams, elements: usize) -> Vec<SectionMesh> {
    let n = params.sections.len();
    let mut next = 1;
    (1..=n)
        .map(|k| {
            let nodes = section_nodes(params, k, elements);
            let dofs = nodes
                .iter()
                .enumerate()
                .map(|(i, _)| {
                    if k == 1 && i == 0 {
                        [None, None]
                    } else {
                        next += 2;
                        [Some(next - 2), Some(next - 1)]
                    }
                })
                .collect();
            SectionMesh { nodes, dofs }
        })
        .collect()
}

/// Node positions of section `k`: its ends and contact points as breakpoints, each interval
/// between them cut into elements of about `l_k / elements`.
fn section_nodes(params: &ModelParams, k: usize, elements: usize) -> Vec<f64> {
    let n = params.sections.len();
    let l = params.sections[k - 1].length;
    let fractions: Vec<f64> = (0..params.contact_points)
        .map(|j| j as f64 / (params.contact_points - 1).max(1) as f64)
        .collect();
    let mut breaks = vec![0.0, l];
    if k >= 2 {
        let overlap = params.sections[k - 2].length - params.positions[k - 2].value(0.0);
        breaks.extend(fractions.iter().map(|s| s * overlap));
    }
    if k < n {
        let a = params.positions[k - 1].value(0.0);
        breaks.extend(fractions.iter().map(|s| a + s * (l - a)));
    }
    breaks.retain(|x| (0.0..=l).contains(x));
    breaks.sort_by(f64::total_cmp);
    breaks.dedup_by(|a, b| (*a - *b).abs() <= 1e-12 * l);
    let mut nodes = vec![0.0];
    for pair in breaks.windows(2) {
        let (a, b) = (pair[0], pair[1]);
        let pieces = ((b - a) / l * elements as f64).round().max(1.0) as usize;
        nodes.extend((1..=pieces).map(|i| {
            if i == pieces {
                b
            } else {
                a + (b - a) * i as f64 / pieces as f64
            }
        }));
    }
    nodes
}

/// Adds section `section`'s element integrals `int rhoA psi_a psi_b` and `int (EI psi_a''
/// psi_b'' - P psi_a' psi_b')` over the translation and the Hermite functions of every
/// element, `P(x) = p0 + p1 x`.
fn assemble_section(
    mesh: &SectionMesh,
    section: &SectionParams,
    (p0, p1): (f64, f64),
    mass: &mut DMatrix<f64>,
    stiffness: &mut DMatrix<f64>,
) {
    for e in 0..mesh.nodes.len() - 1 {
        let (a, b) = (mesh.nodes[e], mesh.nodes[e + 1]);
        let h = b - a;
        let dofs = [
            Some(0),
            mesh.dofs[e][0],
            mesh.dofs[e][1],
            mesh.dofs[e + 1][0],
            mesh.dofs[e + 1][1],
        ];
        for &(s, w) in &GAUSS4 {
            let x = a + s * h;
            let (v, d1, d2) = (hermite(s, h, 0), hermite(s, h, 1), hermite(s, h, 2));
            // basis 0 is the translation: value 1, no slope or curvature
            let value = |i: usize| if i == 0 { 1.0 } else { v[i - 1] };
            let slope = |i: usize| if i == 0 { 0.0 } else { d1[i - 1] };
            let curve = |i: usize| if i == 0 { 0.0 } else { d2[i - 1] };
            let rho_a = w * h * section.mass_per_length;
            let ei = w * h * section.bending_stiffness;
            let p = w * h * (p0 + p1 * x);
            for (i, gi) in dofs.iter().enumerate() {
                let Some(gi) = *gi else { continue };
                for (j, gj) in dofs.iter().enumerate() {
                    let Some(gj) = *gj else { continue };
                    mass[(gi, gj)] += rho_a * value(i) * value(j);
                    stiffness[(gi, gj)] += ei * curve(i) * curve(j) - p * slope(i) * slope(j);
                }
            }
        }
    }
}

impl Model for ElementModel {
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
        for c in 0..self.points.len() {
            for (j, v, d) in self.contact_at(c, t).iter() {
                g[(j, c)] = v;
                gdot[(j, c)] = d;
            }
        }
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
        for (c, &p) in self.points.iter().enumerate() {
            let e = self.entries_at(p, positions[p.overlap - 2], rates[p.overlap - 2]);
            for (j, v, d) in e.iter() {
                g[(j, c)] = v;
                gdot[(j, c)] = d;
            }
        }
    }

    fn contact_gaps(&self, t: f64, y: &[f64], xi: &mut [f64], xi_dot: &mut [f64]) {
        let (z, zd) = y.split_at(self.dof());
        for c in 0..self.points.len() {
            (xi[c], xi_dot[c]) = self.contact_at(c, t).gap(z, zd);
        }
    }

    fn rhs(&self, t: f64, y: &[f64], states: Option<&[ContactState]>, ydot: &mut [f64]) {
        let n = self.dof();
        let (z, zd) = y.split_at(n);
        let (vel, acc) = ydot.split_at_mut(n);
        vel.copy_from_slice(zd);
        let mut acc = DVectorViewMut::from_slice(acc, n);
        acc.gemv(-1.0, &self.stiffness, &DVectorView::from_slice(z, n), 0.0);
        if let Some(d) = &self.damping {
            acc.gemv(-1.0, d, &DVectorView::from_slice(zd, n), 1.0);
        }
        for c in 0..self.points.len() {
            let entries = self.contact_at(c, t);
            let (xi, xid) = entries.gap(z, zd);
            let f = self.contact_force(c, xi, xid, states).force;
            for (j, g, _) in entries.iter() {
                acc[j] -= f * g;
            }
        }
        self.mass_solve.accelerations(self.drive_input(t), acc);
    }

    fn jacobian(&self, t: f64, y: &[f64], states: Option<&[ContactState]>, jac: &mut DMatrix<f64>) {
        let n = self.dof();
        let (z, zd) = y.split_at(n);
        jac.fill(0.0);
        for j in 0..n {
            jac[(j, n + j)] = 1.0;
        }
        jac.view_mut((n, 0), (n, n)).copy_from(&self.stiffness);
        if let Some(d) = &self.damping {
            jac.view_mut((n, n), (n, n)).copy_from(d);
        }
        for c in 0..self.points.len() {
            let entries = self.contact_at(c, t);
            let (xi, xid) = entries.gap(z, zd);
            let f = self.contact_force(c, xi, xid, states);
            for (i, gi, _) in entries.iter() {
                for (j, gj, gdj) in entries.iter() {
                    // xi_dot = g . zd + gdot . z
                    jac[(n + i, j)] += gi * (f.d_gap * gj + f.d_rate * gdj);
                    jac[(n + i, n + j)] += f.d_rate * gi * gj;
                }
            }
        }
        self.mass_solve.jacobian_rows(jac);
    }

    fn shape_row(&self, section: usize, x: f64, deriv: u8) -> Vec<f64> {
        let mut row = vec![0.0; self.dof()];
        row[0] = f64::from(u8::from(deriv == 0));
        for (j, v) in self.meshes[section - 1].point_entries(x, deriv) {
            row[j] += v;
        }
        row
    }

    fn displacement(&self, section: usize, x: f64, z: &[f64]) -> f64 {
        z[0] + self.meshes[section - 1]
            .point_entries(x, 0)
            .map(|(j, v)| v * z[j])
            .sum::<f64>()
    }

    fn outputs(&self, t: f64, y: &[f64], ydot: &[f64], out: &mut [f64]) {
        let n = self.dof();
        let (z, zd) = y.split_at(n);
        let dot = |entries: &[(usize, f64)]| entries.iter().map(|&(j, v)| v * z[j]).sum::<f64>();
        out[0] = z[0];
        out[1] = dot(&self.tip);
        out[2] = dot(&self.top1);
        let nc = self.points.len();
        for c in 0..nc {
            let (xi, xid) = self.contact_at(c, t).gap(z, zd);
            out[3 + c] = xi;
            out[3 + nc + c] = self.contact_force(c, xi, xid, None).force;
        }
        if matches!(self.params.drive, Drive::Motion(_)) {
            let row = |m: &DMatrix<f64>, v: &[f64]| -> f64 {
                m.row(0).iter().zip(v).map(|(a, b)| a * b).sum()
            };
            out[3 + 2 * nc] =
                row(&self.mass, &ydot[n..]) + self.damping.as_ref().map_or(0.0, |d| row(d, zd));
        }
    }
}
