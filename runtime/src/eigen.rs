//! Eigenfrequencies and mode shapes, linearized about `q = 0` with closed contacts
//! (`f = c xi`: clearance and damping ignored, as the paper does for Table I).
//!
//! The generalized symmetric problem `K_eff v = w^2 M v`, `K_eff = K + c sum_c g_c g_c'`, is
//! reduced to a standard one by the Cholesky factor of `M` and solved with nalgebra's
//! symmetric eigensolver. The vehicle translation is handled exactly rather than by a
//! threshold: in computing coordinates `K_eff` has a zero row and column 0, so
//!
//! * with a force drive the vehicle is free: the translation is a rigid mode (counted) and
//!   is removed by condensing `u` out of the mass matrix (the other modes have zero
//!   momentum, `u = -M_0p p / M_00`);
//! * with a prescribed motion the vehicle is held: `u = 0`, no rigid mode.
//!
//! Any further eigenvalue within the solver's round-off, `|w^2| <= 16 r eps max|w^2|` for `r`
//! relative coordinates, also counts as rigid (with contacts on every overlap there is none);
//! negative ones are unstable (buckled) and reported as growth rates.

use crate::model::Model;
use crate::params::Drive;
use nalgebra::{DMatrix, DVector, SymmetricEigen};
use std::f64::consts::PI;

/// Result of [`modal_analysis`].
#[derive(Debug, Clone, PartialEq)]
pub struct ModalAnalysis {
    /// Time at which the contact geometry was taken (s).
    pub time: f64,
    /// Natural frequencies (Hz), ascending, rigid and unstable modes excluded.
    pub frequencies_hz: Vec<f64>,
    /// Mode shapes in computing coordinates, one per frequency, mass-normalized
    /// (`v' M v = 1`).
    pub shapes: Vec<DVector<f64>>,
    /// Number of rigid-body modes (zero frequency).
    pub rigid_modes: usize,
    /// Growth rates (1/s) of unstable modes (`w^2 < 0`, e.g. buckling under self-weight),
    /// ascending.
    pub unstable_growth_rates: Vec<f64>,
    /// All eigenvalues `w^2` (1/s^2) of the problem after the exact removal of the vehicle
    /// translation, ascending (rigid and unstable ones included).
    pub eigenvalues: Vec<f64>,
}

/// Why the eigen analysis failed.
#[derive(Debug, thiserror::Error)]
pub enum EigenError {
    /// The (condensed) mass matrix is not positive definite.
    #[error("the mass matrix is not positive definite; no eigen analysis is possible")]
    MassNotPositiveDefinite,
    /// An eigenvalue iteration did not converge within its iteration limit.
    #[error("the eigen solver did not converge ({operation}) within its iteration limit")]
    NoConvergence {
        /// Which decomposition.
        operation: &'static str,
    },
}

/// `K_eff = K + c sum_c g_c g_c'` at time `t` (s).
pub fn closed_contact_stiffness(model: &dyn Model, t: f64) -> DMatrix<f64> {
    let n = model.dof();
    let nc = model.layout().contact_count();
    let mut g = DMatrix::zeros(n, nc);
    let mut gdot = DMatrix::zeros(n, nc);
    model.contact_vectors(t, &mut g, &mut gdot);
    let c = model.params().contact.stiffness;
    let mut k = model.stiffness_matrix().clone();
    if nc > 0 {
        k += c * &g * g.transpose();
    }
    k
}

/// Natural frequencies and mode shapes at time `t` (s) with closed contacts.
///
/// # Errors
/// [`EigenError::MassNotPositiveDefinite`] if the mass matrix cannot be factored.
pub fn modal_analysis(model: &dyn Model, t: f64) -> Result<ModalAnalysis, EigenError> {
    let n = model.dof();
    let m = model.mass_matrix();
    let k = closed_contact_stiffness(model, t);
    let free_vehicle = matches!(model.params().drive, Drive::Force(_));
    let r = n - 1;
    // the problem in the relative coordinates p = z[1..]
    let k_r = k.view((1, 1), (r, r)).into_owned();
    let mut m_r = m.view((1, 1), (r, r)).into_owned();
    let coupling = m.view((1, 0), (r, 1)).into_owned();
    if free_vehicle {
        m_r -= &coupling * coupling.transpose() / m[(0, 0)];
    }
    let mut rigid_modes = usize::from(free_vehicle);
    let mut analysis = ModalAnalysis {
        time: t,
        frequencies_hz: Vec::new(),
        shapes: Vec::new(),
        rigid_modes,
        unstable_growth_rates: Vec::new(),
        eigenvalues: Vec::new(),
    };
    if r == 0 {
        return Ok(analysis);
    }
    let chol = m_r.cholesky().ok_or(EigenError::MassNotPositiveDefinite)?;
    let l = chol.l();
    // A = L^-1 K L^-T, symmetric
    let mut a = l
        .solve_lower_triangular(&k_r)
        .expect("Cholesky factor is invertible");
    a = l
        .solve_lower_triangular(&a.transpose())
        .expect("Cholesky factor is invertible");
    a = 0.5 * (&a + a.transpose());
    let eig = SymmetricEigen::new(a);
    let mut order: Vec<usize> = (0..r).collect();
    order.sort_by(|&i, &j| eig.eigenvalues[i].total_cmp(&eig.eigenvalues[j]));
    let scale = eig.eigenvalues.iter().fold(0.0_f64, |s, v| s.max(v.abs()));
    for &i in &order {
        let lambda = eig.eigenvalues[i];
        analysis.eigenvalues.push(lambda);
        if lambda.abs() <= 16.0 * r as f64 * f64::EPSILON * scale {
            rigid_modes += 1;
        } else if lambda < 0.0 {
            analysis.unstable_growth_rates.push((-lambda).sqrt());
        } else {
            // v = L^-T w gives v' M_r v = 1
            let w = eig.eigenvectors.column(i).into_owned();
            let p = l
                .transpose()
                .solve_upper_triangular(&w)
                .expect("Cholesky factor is invertible");
            let mut shape = DVector::zeros(n);
            shape.rows_mut(1, r).copy_from(&p);
            if free_vehicle {
                shape[0] = -coupling.dot(&p) / m[(0, 0)];
            }
            analysis.frequencies_hz.push(lambda.sqrt() / (2.0 * PI));
            analysis.shapes.push(shape);
        }
    }
    analysis.unstable_growth_rates.sort_by(f64::total_cmp);
    analysis.rigid_modes = rigid_modes;
    Ok(analysis)
}

/// A mode shape sampled along every section: `points` evenly spaced values of `w_k(x)` per
/// section (m per unit modal coordinate), from the foot to the top.
pub fn sample_shape(model: &dyn Model, shape: &DVector<f64>, points: usize) -> Vec<Vec<f64>> {
    let params = model.params();
    (1..=params.sections.len())
        .map(|k| {
            let l = params.sections[k - 1].length;
            (0..points)
                .map(|s| {
                    let x = if points > 1 {
                        l * s as f64 / (points - 1) as f64
                    } else {
                        0.0
                    };
                    model.displacement(k, x, shape.as_slice())
                })
                .collect()
        })
        .collect()
}

/// The fastest rates of the closed-contact system at one time: its largest natural circular
/// frequency and its largest contact damping rate, from two symmetric generalized eigen
/// problems (robust, iteration-limited). Together they bound the spectral radius of the
/// first-order system's Jacobian to within a factor 2 (`|lambda| <= omega + delta`), which is
/// what an explicit method's stable step is set by.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FastestRates {
    /// Time of the contact geometry (s).
    pub time: f64,
    /// Largest `omega` of `K_eff v = omega^2 M v` (rad/s; `inf` when it does not fit in
    /// double precision).
    pub omega_max: f64,
    /// Largest `delta` of `D v = delta M v`, `D = d sum_c g_c g_c'` (1/s; `inf` likewise).
    pub damping_rate: f64,
}

impl FastestRates {
    /// The estimate of the Jacobian's spectral radius: `max(omega_max, damping_rate)` (1/s).
    pub fn spectral_radius(&self) -> f64 {
        self.omega_max.max(self.damping_rate)
    }
}

/// Largest eigenvalue of the symmetric pencil `(a, M)` with `M = L L'`, scaled so that no
/// intermediate overflows: `inf` when the answer does not fit in double precision, `None`
/// when the iteration does not converge.
fn largest_pencil_eigenvalue(a: &DMatrix<f64>, l: &DMatrix<f64>) -> Option<f64> {
    let scale = a.abs().max();
    if scale == 0.0 {
        return Some(0.0);
    }
    if !scale.is_finite() {
        return Some(f64::INFINITY);
    }
    let mut s = a / scale;
    s = l.solve_lower_triangular(&s)?;
    s = l.solve_lower_triangular(&s.transpose())?;
    s = 0.5 * (&s + s.transpose());
    if !s.iter().all(|v| v.is_finite()) {
        return Some(f64::INFINITY);
    }
    let eig = SymmetricEigen::try_new(s, f64::EPSILON, 100 * a.nrows().max(10))?;
    let largest = eig.eigenvalues.iter().fold(0.0_f64, |m, &v| m.max(v));
    Some(largest * scale)
}

/// The [`FastestRates`] of `model` at time `t` (s), contacts closed.
///
/// # Errors
/// [`EigenError::MassNotPositiveDefinite`], or [`EigenError::NoConvergence`].
pub fn fastest_rates(model: &dyn Model, t: f64) -> Result<FastestRates, EigenError> {
    let n = model.dof();
    let nc = model.layout().contact_count();
    let chol = model
        .mass_matrix()
        .clone()
        .cholesky()
        .ok_or(EigenError::MassNotPositiveDefinite)?;
    let l = chol.l();
    let k = closed_contact_stiffness(model, t);
    let omega2 = largest_pencil_eigenvalue(&k, &l).ok_or(EigenError::NoConvergence {
        operation: "largest eigenvalue of (K_eff, M)",
    })?;
    let mut damping_rate = 0.0;
    let d = model.params().contact.damping;
    if nc > 0 && d > 0.0 {
        let mut g = DMatrix::zeros(n, nc);
        let mut gdot = DMatrix::zeros(n, nc);
        model.contact_vectors(t, &mut g, &mut gdot);
        let ggt = &g * g.transpose();
        let rate = largest_pencil_eigenvalue(&ggt, &l).ok_or(EigenError::NoConvergence {
            operation: "largest eigenvalue of (D, M)",
        })?;
        damping_rate = d * rate;
    }
    Ok(FastestRates {
        time: t,
        omega_max: omega2.max(0.0).sqrt(),
        damping_rate,
    })
}
