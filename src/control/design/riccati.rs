//! The continuous-time algebraic Riccati equation `A'X + XA - X B R^-1 B' X + Q = 0`, its
//! stabilizing solution and the LQR gain `K = R^-1 B' X`.
//!
//! No maintained pure-Rust solver exists, so this is written on nalgebra: the matrix sign
//! function of the Hamiltonian with determinant scaling (Byers 1987), on a state balanced by
//! powers of two, then Newton-Kleinman refinement whose Lyapunov equations are solved by the
//! sign function too (Roberts 1980). Every solution is checked: its relative residual must
//! be below [`RESIDUAL_LIMIT`] and `A - B K` stable, or the error says which check failed.

use nalgebra::{DMatrix, linalg::balancing::balance_parlett_reinsch};
use telescopic_runtime::eigenvalues;

/// Largest relative residual `|A'X + XA - XGX + Q| / (|A'X| + |XA| + |XGX| + |Q|)` accepted.
pub const RESIDUAL_LIMIT: f64 = 1e-10;

/// Most sign-function iterations.
const MAX_SIGN_ITERATIONS: usize = 100;

/// Most Newton-Kleinman refinement steps.
const MAX_NEWTON_STEPS: usize = 8;

/// Why the Riccati equation has no acceptable solution.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum RiccatiError {
    /// The matrices do not fit together.
    #[error("Riccati equation: {0}")]
    Dimensions(String),
    /// `R` is not symmetric positive definite, or `Q` not symmetric positive semidefinite.
    #[error("Riccati equation: {0}")]
    Weights(String),
    /// The Hamiltonian has eigenvalues on the imaginary axis (the system is not stabilizable,
    /// or a mode is undetectable in `Q`): the sign iteration does not converge.
    #[error(
        "Riccati equation: no stabilizing solution: {0} (is (A, B) stabilizable and every \
         unstable or undamped mode seen by Q?)"
    )]
    NoStabilizingSolution(String),
    /// The solution's relative residual is above [`RESIDUAL_LIMIT`].
    #[error(
        "Riccati equation: the residual check failed: relative residual {0:.3e} above \
         {RESIDUAL_LIMIT:e} (the problem is too ill-conditioned for double precision)"
    )]
    Residual(f64),
    /// `A - B K` is not stable.
    #[error(
        "Riccati equation: the closed-loop check failed: A - B K has an eigenvalue with real \
         part {0:.3e} >= 0"
    )]
    Unstable(f64),
    /// A decomposition failed.
    #[error("Riccati equation: {0}")]
    Numerics(String),
}

/// The stabilizing solution and what the checks found.
#[derive(Debug, Clone, PartialEq)]
pub struct Care {
    /// `X`, symmetric, positive semidefinite.
    pub x: DMatrix<f64>,
    /// The gain `K = R^-1 B' X` (`u = -K x`).
    pub k: DMatrix<f64>,
    /// The relative residual of `X`.
    pub residual: f64,
    /// The largest real part of the eigenvalues of `A - B K` (< 0).
    pub closed_loop_abscissa: f64,
}

/// Relative residual of `X` in `A'X + XA - XGX + Q = 0`.
fn residual(a: &DMatrix<f64>, g: &DMatrix<f64>, q: &DMatrix<f64>, x: &DMatrix<f64>) -> f64 {
    let atx = a.transpose() * x;
    let xa = x * a;
    let xgx = x * g * x;
    let r = &atx + &xa - &xgx + q;
    r.norm() / (atx.norm() + xa.norm() + xgx.norm() + q.norm()).max(f64::MIN_POSITIVE)
}

/// The matrix sign function by Newton's iteration with determinant scaling. It stops when
/// the change falls below `1e-13` of the iterate, or when, already below `1e-6`, it stops
/// falling (rounding dominates: an ill-conditioned `H` stagnates there; the refinement and
/// the residual check that follow judge the result).
fn sign(mut z: DMatrix<f64>) -> Result<DMatrix<f64>, RiccatiError> {
    let n = z.nrows() as f64;
    let mut previous = f64::INFINITY;
    for _ in 0..MAX_SIGN_ITERATIONS {
        let lu = z.clone().lu();
        let log_det: f64 = lu.u().diagonal().iter().map(|u| u.abs().ln()).sum();
        let inv = lu.try_inverse().ok_or_else(|| {
            RiccatiError::NoStabilizingSolution(
                "the Hamiltonian is singular (an eigenvalue at zero)".into(),
            )
        })?;
        if !log_det.is_finite() || !inv.iter().all(|v| v.is_finite()) {
            return Err(RiccatiError::NoStabilizingSolution(
                "the sign iteration met a singular matrix".into(),
            ));
        }
        let c = (-log_det / n).exp();
        let next = 0.5 * (&z * c + inv / c);
        let change = (&next - &z).norm();
        z = next;
        let size = z.norm();
        if change <= 1e-13 * size || (change <= 1e-6 * size && change >= previous) {
            return Ok(z);
        }
        previous = change;
    }
    Err(RiccatiError::NoStabilizingSolution(format!(
        "the sign iteration did not converge in {MAX_SIGN_ITERATIONS} steps (eigenvalues on or \
         near the imaginary axis)"
    )))
}

/// Solves `F'X + XF + W = 0` for stable `F` by the sign function of `[[F', W], [0, -F]]`,
/// which is `[[-I, 2X], [0, I]]`.
fn lyapunov(f: &DMatrix<f64>, w: &DMatrix<f64>) -> Result<DMatrix<f64>, RiccatiError> {
    let n = f.nrows();
    let mut m = DMatrix::zeros(2 * n, 2 * n);
    m.view_mut((0, 0), (n, n)).copy_from(&f.transpose());
    m.view_mut((0, n), (n, n)).copy_from(w);
    m.view_mut((n, n), (n, n)).copy_from(&(-f));
    let s = sign(m)?;
    let x = 0.5 * s.view((0, n), (n, n)).into_owned();
    Ok(0.5 * (&x + x.transpose()))
}

/// The stabilizing solution of `A'X + XA - X B R^-1 B' X + Q = 0` and the LQR gain.
///
/// # Errors
/// [`RiccatiError`] naming the check that failed.
// NaN fails every comparison: the negated ones below reject it
#[allow(clippy::neg_cmp_op_on_partial_ord)]
pub fn care(
    a: &DMatrix<f64>,
    b: &DMatrix<f64>,
    q: &DMatrix<f64>,
    r: &DMatrix<f64>,
) -> Result<Care, RiccatiError> {
    let (n, m) = (a.nrows(), b.ncols());
    let r_chol = check_problem(a, b, q, r)?;
    let r_inv = r_chol.inverse();
    // balance the state by powers of two: x = D x~, A~ = D^-1 A D, B~ = D^-1 B, Q~ = D Q D
    let mut at = a.clone();
    let d = balance_parlett_reinsch(&mut at);
    let bt = DMatrix::from_fn(n, m, |i, j| b[(i, j)] / d[i]);
    let qt = DMatrix::from_fn(n, n, |i, j| q[(i, j)] * d[i] * d[j]);
    let gt = &bt * &r_inv * bt.transpose();
    let mut h = DMatrix::zeros(2 * n, 2 * n);
    h.view_mut((0, 0), (n, n)).copy_from(&at);
    h.view_mut((0, n), (n, n)).copy_from(&(-&gt));
    h.view_mut((n, 0), (n, n)).copy_from(&(-&qt));
    h.view_mut((n, n), (n, n)).copy_from(&(-at.transpose()));
    let w = sign(h)?;
    // [W12; W22 + I] X = -[W11 + I; W21], in the least-squares sense
    let mut lhs = DMatrix::zeros(2 * n, n);
    let mut rhs = DMatrix::zeros(2 * n, n);
    lhs.view_mut((0, 0), (n, n))
        .copy_from(&w.view((0, n), (n, n)));
    lhs.view_mut((n, 0), (n, n))
        .copy_from(&(w.view((n, n), (n, n)) + DMatrix::identity(n, n)));
    rhs.view_mut((0, 0), (n, n))
        .copy_from(&(-(w.view((0, 0), (n, n)) + DMatrix::identity(n, n))));
    rhs.view_mut((n, 0), (n, n))
        .copy_from(&(-w.view((n, 0), (n, n))));
    let svd = lhs.svd(true, true);
    let x = svd
        .solve(&rhs, 1e-14)
        .map_err(|e| RiccatiError::Numerics(format!("least squares: {e}")))?;
    let (x, res) = newton_kleinman(0.5 * (&x + x.transpose()), &at, &bt, &gt, &qt, r, &r_inv);
    if !(res <= RESIDUAL_LIMIT) {
        return Err(RiccatiError::Residual(res));
    }
    // back to the original state
    let x = DMatrix::from_fn(n, n, |i, j| x[(i, j)] / (d[i] * d[j]));
    let k = &r_inv * b.transpose() * &x;
    let closed = a - b * &k;
    let abscissa = eigenvalues(closed, "eigenvalues of A - B K")
        .map_err(|e| RiccatiError::Numerics(e.to_string()))?
        .iter()
        .map(|l| l.re)
        .fold(f64::NEG_INFINITY, f64::max);
    if !(abscissa < 0.0) {
        return Err(RiccatiError::Unstable(abscissa));
    }
    Ok(Care {
        residual: residual(a, &(b * &r_inv * b.transpose()), q, &x),
        x,
        k,
        closed_loop_abscissa: abscissa,
    })
}

/// Checks the problem's shapes, finiteness, symmetry and definiteness: `R`'s Cholesky
/// factor.
fn check_problem(
    a: &DMatrix<f64>,
    b: &DMatrix<f64>,
    q: &DMatrix<f64>,
    r: &DMatrix<f64>,
) -> Result<nalgebra::Cholesky<f64, nalgebra::Dyn>, RiccatiError> {
    let (n, m) = (a.nrows(), b.ncols());
    if a.ncols() != n || b.nrows() != n || q.shape() != (n, n) || r.shape() != (m, m) {
        return Err(RiccatiError::Dimensions(format!(
            "A is {}x{}, B {}x{}, Q {}x{}, R {}x{}: need A n x n, B n x m, Q n x n, R m x m",
            a.nrows(),
            a.ncols(),
            b.nrows(),
            b.ncols(),
            q.nrows(),
            q.ncols(),
            r.nrows(),
            r.ncols()
        )));
    }
    if [a, b, q, r]
        .iter()
        .any(|x| !x.iter().all(|v| v.is_finite()))
    {
        return Err(RiccatiError::Dimensions("an entry is not finite".into()));
    }
    let symmetric = |x: &DMatrix<f64>| (x - x.transpose()).norm() <= 1e-12 * x.norm().max(1e-300);
    if !symmetric(q) || !symmetric(r) {
        return Err(RiccatiError::Weights("Q and R must be symmetric".into()));
    }
    let r_chol = r
        .clone()
        .cholesky()
        .ok_or_else(|| RiccatiError::Weights("R must be positive definite".into()))?;
    let q_min = nalgebra::SymmetricEigen::try_new(q.clone(), f64::EPSILON, 100 * n.max(10))
        .ok_or_else(|| RiccatiError::Numerics("eigenvalues of Q did not converge".into()))?
        .eigenvalues
        .min();
    if q_min < -1e-12 * q.norm() {
        return Err(RiccatiError::Weights(format!(
            "Q must be positive semidefinite (smallest eigenvalue {q_min:.3e})"
        )));
    }
    Ok(r_chol)
}

/// Newton-Kleinman refinement of a stabilizing `x` of the balanced problem (`at`, `bt`,
/// `gt = bt R^-1 bt'`, `qt`): each step solves a Lyapunov equation, kept while the residual
/// falls. The refined solution and its residual.
fn newton_kleinman(
    mut x: DMatrix<f64>,
    at: &DMatrix<f64>,
    bt: &DMatrix<f64>,
    gt: &DMatrix<f64>,
    qt: &DMatrix<f64>,
    r: &DMatrix<f64>,
    r_inv: &DMatrix<f64>,
) -> (DMatrix<f64>, f64) {
    let mut res = residual(at, gt, qt, &x);
    for _ in 0..MAX_NEWTON_STEPS {
        if res <= 1e-15 {
            break;
        }
        let k = r_inv * bt.transpose() * &x;
        let f = at - bt * &k;
        let wq = qt + k.transpose() * r * &k;
        let Ok(next) = lyapunov(&f, &wq) else { break };
        let next_res = residual(at, gt, qt, &next);
        // stop unless the residual fell (a NaN residual stops too)
        if next_res.partial_cmp(&res) != Some(std::cmp::Ordering::Less) {
            break;
        }
        x = next;
        res = next_res;
    }
    (x, res)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_scalar_equation_has_its_closed_form() {
        // a x^2 term: X = r (a + sqrt(a^2 + q / r)) for b = 1
        for (a, q, r) in [
            (1.0, 1.0, 1.0),
            (-2.0, 3.0, 0.5),
            (0.0, 4.0, 2.0),
            (10.0, 1e-3, 7.0),
        ] {
            let c = care(
                &DMatrix::from_element(1, 1, a),
                &DMatrix::from_element(1, 1, 1.0),
                &DMatrix::from_element(1, 1, q),
                &DMatrix::from_element(1, 1, r),
            )
            .unwrap();
            let x = r * (a + (a * a + q / r).sqrt());
            assert!(
                (c.x[(0, 0)] - x).abs() <= 1e-12 * x,
                "a {a} q {q} r {r}: {} vs {x}",
                c.x
            );
            assert!((c.k[(0, 0)] - x / r).abs() <= 1e-12 * x / r);
            assert!(c.residual < RESIDUAL_LIMIT);
        }
    }

    #[test]
    fn the_double_integrator_has_the_textbook_gain() {
        // A = [[0, 1], [0, 0]], B = [0, 1]', Q = I, R = 1: X = [[sqrt 3, 1], [1, sqrt 3]],
        // K = [1, sqrt 3]
        let a = DMatrix::from_row_slice(2, 2, &[0.0, 1.0, 0.0, 0.0]);
        let b = DMatrix::from_row_slice(2, 1, &[0.0, 1.0]);
        let c = care(&a, &b, &DMatrix::identity(2, 2), &DMatrix::identity(1, 1)).unwrap();
        let s3 = 3f64.sqrt();
        let x = DMatrix::from_row_slice(2, 2, &[s3, 1.0, 1.0, s3]);
        assert!((&c.x - x).norm() < 1e-12, "{}", c.x);
        assert!((c.k[(0, 0)] - 1.0).abs() < 1e-12 && (c.k[(0, 1)] - s3).abs() < 1e-12);
        // the closed loop's poles: s^2 + sqrt 3 s + 1
        assert!((c.closed_loop_abscissa + s3 / 2.0).abs() < 1e-12);
    }

    #[test]
    fn an_unstabilizable_system_is_refused_by_name() {
        // an unstable mode the input cannot reach
        let a = DMatrix::from_row_slice(2, 2, &[1.0, 0.0, 0.0, -1.0]);
        let b = DMatrix::from_row_slice(2, 1, &[0.0, 1.0]);
        let err = care(&a, &b, &DMatrix::identity(2, 2), &DMatrix::identity(1, 1)).unwrap_err();
        assert!(
            matches!(
                err,
                RiccatiError::NoStabilizingSolution(_)
                    | RiccatiError::Residual(_)
                    | RiccatiError::Unstable(_)
            ),
            "{err}"
        );
        let err = care(
            &a,
            &b,
            &DMatrix::identity(2, 2),
            &DMatrix::from_element(1, 1, -1.0),
        )
        .unwrap_err();
        assert!(
            err.to_string().contains("R must be positive definite"),
            "{err}"
        );
    }

    #[test]
    fn lyapunov_by_the_sign_function_solves_its_equation() {
        let f = DMatrix::from_row_slice(3, 3, &[-1.0, 2.0, 0.0, 0.0, -3.0, 1.0, 0.5, 0.0, -2.0]);
        let w = DMatrix::from_row_slice(3, 3, &[2.0, 0.5, 0.0, 0.5, 1.0, 0.2, 0.0, 0.2, 3.0]);
        let x = lyapunov(&f, &w).unwrap();
        let r = f.transpose() * &x + &x * &f + &w;
        assert!(r.norm() < 1e-12 * w.norm(), "residual {}", r.norm());
    }
}
