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
//! Every overlap is held by contact springs, so the configuration has no further rigid mode:
//! an eigenvalue within the solver's round-off of zero (`|w^2| <= 16 r eps max|w^2|` for `r`
//! relative coordinates) means digits were lost, and the analysis refuses, as it does when
//! the lowest frequency's estimated error exceeds [`FREQUENCY_ERROR_LIMIT`]. Negative
//! eigenvalues are unstable (buckled) modes, reported as growth rates.

use crate::model::Model;
use crate::model::params::Drive;
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
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
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
    /// A matrix to decompose has entries that are not finite.
    #[error("{operation}: the matrix has entries that are not finite in double precision")]
    NonFinite {
        /// Which decomposition.
        operation: &'static str,
    },
    /// The eigenvalues span more than double precision resolves: the smallest lose their
    /// digits to the rounding of the largest.
    #[error(
        "the eigenvalues span {orders:.1} orders of magnitude (w^2 from {smallest:.3e} to \
         {largest:.3e} 1/s^2): the lowest frequency would carry a relative error of about \
         {error:.0e}{lost}; the stiffnesses and masses of the scene differ too much in scale \
         for double precision, or a mode sits at its buckling load (the gravity prestress \
         cancelling its stiffness)",
        lost = if *extra_rigid > 0 {
            format!(" and {extra_rigid} mode(s) vanish in the rounding")
        } else {
            String::new()
        }
    )]
    IllConditioned {
        /// log10 of the ratio of the largest to the smallest eigenvalue.
        orders: f64,
        /// Smallest eigenvalue magnitude, rigid modes excluded (1/s^2).
        smallest: f64,
        /// Largest eigenvalue (1/s^2).
        largest: f64,
        /// Estimated relative error of the lowest frequency.
        error: f64,
        /// Modes that came out as rigid beyond those the configuration has.
        extra_rigid: usize,
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

/// `D = D_s + d sum_c g_c g_c'` at time `t` (s): the structural damping and the closed
/// contacts' (N s/m in computing coordinates).
pub fn closed_contact_damping(model: &dyn Model, t: f64) -> DMatrix<f64> {
    let n = model.dof();
    let nc = model.layout().contact_count();
    let mut d = model
        .damping_matrix()
        .cloned()
        .unwrap_or_else(|| DMatrix::zeros(n, n));
    if nc > 0 {
        let mut g = DMatrix::zeros(n, nc);
        let mut gdot = DMatrix::zeros(n, nc);
        model.contact_vectors(t, &mut g, &mut gdot);
        d += model.params().contact.damping * &g * g.transpose();
    }
    d
}

/// Natural frequencies and mode shapes at time `t` (s) with closed contacts.
///
/// # Errors
/// [`EigenError::MassNotPositiveDefinite`] if the mass matrix cannot be factored,
/// [`EigenError::IllConditioned`] when the spectrum lost its digits (see the module docs),
/// [`EigenError::NoConvergence`] or [`EigenError::NonFinite`].
pub fn modal_analysis(model: &dyn Model, t: f64) -> Result<ModalAnalysis, EigenError> {
    solve(model, t, &closed_contact_stiffness(model, t), true)
}

/// [`modal_analysis`] of `model`'s mass matrix with a given stiffness `k` (in computing
/// coordinates, zero row and column 0): for closed-contact stiffnesses at positions other
/// than a time's (a linear parameter-varying model's).
///
/// # Errors
/// As [`modal_analysis`].
pub fn modal_analysis_with(
    model: &dyn Model,
    k: &DMatrix<f64>,
) -> Result<ModalAnalysis, EigenError> {
    solve(model, f64::NAN, k, true)
}

/// The eigenvalues `w^2` (1/s^2) of [`modal_analysis`]'s problem, ascending, without its
/// refusal of a spectrum whose smallest eigenvalues carry few digits: for following an
/// eigenvalue through zero (a buckling load), where the smallest is small by nature.
///
/// # Errors
/// As [`modal_analysis`], but never [`EigenError::IllConditioned`].
pub fn closed_contact_eigenvalues(model: &dyn Model, t: f64) -> Result<Vec<f64>, EigenError> {
    solve(model, t, &closed_contact_stiffness(model, t), false).map(|m| m.eigenvalues)
}

fn solve(
    model: &dyn Model,
    t: f64,
    k: &DMatrix<f64>,
    checked: bool,
) -> Result<ModalAnalysis, EigenError> {
    let n = model.dof();
    let m = model.mass_matrix();
    let free_vehicle = matches!(model.params().drive, Drive::Force(_));
    let r = n - 1;
    // the problem in the relative coordinates p = z[1..]
    let k_r = k.view((1, 1), (r, r)).into_owned();
    let mut m_r = m.view((1, 1), (r, r)).into_owned();
    let coupling = m.view((1, 0), (r, 1)).into_owned();
    if free_vehicle {
        m_r -= &coupling * coupling.transpose() / m[(0, 0)];
    }
    let rigid_modes = usize::from(free_vehicle);
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
    if !a.iter().all(|v| v.is_finite()) {
        return Err(EigenError::NonFinite {
            operation: "K_eff reduced by the Cholesky factor of M",
        });
    }
    let eig = SymmetricEigen::try_new(a, f64::EPSILON, 100 * r.max(10)).ok_or(
        EigenError::NoConvergence {
            operation: "symmetric eigenvalues of K_eff reduced by the Cholesky factor of M",
        },
    )?;
    let mut order: Vec<usize> = (0..r).collect();
    order.sort_by(|&i, &j| eig.eigenvalues[i].total_cmp(&eig.eigenvalues[j]));
    let scale = eig.eigenvalues.iter().fold(0.0_f64, |s, v| s.max(v.abs()));
    if checked {
        check_conditioning(eig.eigenvalues.as_slice(), scale, r)?;
    }
    for &i in &order {
        let lambda = eig.eigenvalues[i];
        analysis.eigenvalues.push(lambda);
        if lambda < 0.0 {
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
    Ok(analysis)
}

/// Largest relative error of the lowest frequency that [`modal_analysis`] reports instead of
/// refusing: a symmetric eigen solver's eigenvalues are exact to about `eps` times the
/// largest, so the lowest frequency's relative error is about `eps/2 * w_max^2 / w_min^2`.
pub const FREQUENCY_ERROR_LIMIT: f64 = 1e-3;

/// Refuses a spectrum whose small eigenvalues are lost in the rounding of its largest: when
/// any eigenvalue beyond the vehicle's translation falls within rounding of zero (the
/// configuration has no other rigid mode: every overlap is held by contact springs), or when
/// the lowest frequency's estimated relative error exceeds [`FREQUENCY_ERROR_LIMIT`].
fn check_conditioning(eigenvalues: &[f64], scale: f64, r: usize) -> Result<(), EigenError> {
    let floor = 16.0 * r as f64 * f64::EPSILON * scale;
    let extra_rigid = eigenvalues.iter().filter(|l| l.abs() <= floor).count();
    let smallest = eigenvalues
        .iter()
        .map(|l| l.abs())
        .filter(|&l| l > floor)
        .fold(f64::INFINITY, f64::min);
    let error = if smallest.is_finite() {
        0.5 * f64::EPSILON * scale / smallest
    } else {
        f64::INFINITY
    };
    if extra_rigid > 0 || error > FREQUENCY_ERROR_LIMIT {
        // all lost: the floor stands for the smallest
        let low = if smallest.is_finite() {
            smallest
        } else {
            floor.max(f64::MIN_POSITIVE)
        };
        return Err(EigenError::IllConditioned {
            orders: (scale / low).log10(),
            smallest: low,
            largest: scale,
            error,
            extra_rigid,
        });
    }
    Ok(())
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
    /// Largest `delta` of `D v = delta M v`, `D = D_s + d sum_c g_c g_c'` (1/s; `inf`
    /// likewise).
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
    let damping_rate = largest_pencil_eigenvalue(&closed_contact_damping(model, t), &l).ok_or(
        EigenError::NoConvergence {
            operation: "largest eigenvalue of (D, M)",
        },
    )?;
    Ok(FastestRates {
        time: t,
        omega_max: omega2.max(0.0).sqrt(),
        damping_rate,
    })
}

/// Eigenvalues of a real square matrix, robustly: refused when an entry is not finite,
/// computed on the balanced matrix (Parlett-Reinsch: rows and columns scaled by powers of 2,
/// which keeps a matrix mixing displacements and velocities of a stiff model within
/// rounding of its eigenvalues) by a Schur decomposition with an iteration limit.
///
/// # Errors
/// [`EigenError::NonFinite`] or [`EigenError::NoConvergence`], naming `operation`.
pub fn eigenvalues(
    mut m: DMatrix<f64>,
    operation: &'static str,
) -> Result<Vec<nalgebra::Complex<f64>>, EigenError> {
    if !m.iter().all(|v| v.is_finite()) {
        return Err(EigenError::NonFinite { operation });
    }
    let n = m.nrows();
    nalgebra::linalg::balancing::balance_parlett_reinsch(&mut m);
    let schur = nalgebra::linalg::Schur::try_new(m, f64::EPSILON, 100 * n.max(10))
        .ok_or(EigenError::NoConvergence { operation })?;
    Ok(schur.complex_eigenvalues().iter().copied().collect())
}
