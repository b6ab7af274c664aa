//! The fast contact modes of an exact-stepping branch, and a bound of their share in every
//! switch function over a step: what lets method `exact` take the slow modes' step while a
//! contact is closed.
//!
//! A closed contact adds a mode of some kHz (the contact spring against the section's
//! mass) far above the beams' own modes. Its eigenvalues `lambda_k` are simple, so the flow
//! splits exactly into their modal coordinates `z_k(tau) = z_k(0) exp(lambda_k tau)`,
//! `z_k = w_k^T y + w_k^T e / lambda_k` (left eigenvector `w_k` of `A`, the second term from
//! the constant `e` of the affine flow), and the rest, whose spectral radius `omega_slow` is
//! the slow modes'. A switch function `s = sign g_c^T q + offset` is then
//! `s_slow + Re sum_k p_ck z_k`, with `p_ck = sign g_c^T v_k` (right eigenvector `v_k`),
//! and over a step `|sum_k p_ck z_k(tau)| <= sum_k |p_ck| max(|z_k(0)|, |z_k(h)|)` (each
//! `|z_k|` is exponential in `tau`). A step with `h omega_slow <= STEP_OMEGA` cannot hide a
//! crossing of `s_slow - bound` except by grazing, which the cubic Hermite check catches: the
//! same guard as the short steps', applied to the slow part with the fast part's bound as a
//! margin. Where the margin does not hold (the contact mode still rings after an impact, or
//! the contact is about to open), the step is not taken and short steps resolve it.
//!
//! Hand-written: nalgebra offers no eigenvectors of a non-symmetric matrix; the few fast ones
//! come from inverse iteration at the Schur eigenvalues.

use super::events::HermiteCubic;
use crate::contact::ContactState;
use nalgebra::{Complex, DMatrix, DVector};

type C64 = Complex<f64>;

/// Relative margin on the fast part's bound, for the rounding of the eigenvectors (whose
/// residual is checked to 1e-9).
const BOUND_MARGIN: f64 = 1.01;

/// Inverse-iteration sweeps per eigenvector (the shift is the Schur eigenvalue itself).
const SWEEPS: usize = 3;

/// Largest accepted deviation of `w_i^T v_j` from `[i = j]` over the fast modes.
const BIORTHOGONALITY: f64 = 1e-6;

/// Largest accepted eigenvector residual `|A v - lambda v| / (|lambda| |v|)`.
const RESIDUAL: f64 = 1e-9;

/// The fast modes of one branch.
pub(super) struct FastModes {
    /// Augmented left eigenvectors `[w_k; w_k^T e / lambda_k]` (`2 dof + 1` each), scaled so
    /// that `w_k^T v_k = 1`.
    left: Vec<DVector<C64>>,
    /// `g_c^T v_k` on the positions (row `c`, column `k`; m per unit modal coordinate).
    value_coupling: DMatrix<C64>,
    /// `g_c^T v_k` on the velocities (m/s per unit modal coordinate).
    rate_coupling: DMatrix<C64>,
}

/// One switch function as in [`super::exact`]: `sign xi_c + offset` (m).
#[derive(Clone, Copy)]
pub(super) struct SwitchFunction {
    pub contact: usize,
    pub sign: f64,
    pub offset: f64,
}

impl SwitchFunction {
    /// The switch functions of contacts in `states` with half band `half` (m), appended to
    /// `out`: `xi - half` for a contact pressed up, `-xi - half` pressed down, and both
    /// `half - xi` and `half + xi` for a free one.
    pub fn of_branches(states: &[ContactState], half: f64, out: &mut Vec<SwitchFunction>) {
        for (contact, state) in states.iter().enumerate() {
            let f = |sign, offset| SwitchFunction {
                contact,
                sign,
                offset,
            };
            match state {
                ContactState::Upper => out.push(f(1.0, -half)),
                ContactState::Lower => out.push(f(-1.0, -half)),
                ContactState::Free => out.extend([f(-1.0, half), f(1.0, half)]),
            }
        }
    }
}

/// Gaps `xi_c` (m) and rates (m/s) at one end of a step, with the fast modal coordinates
/// of the state there.
pub(super) struct StepEnd<'a> {
    pub gap: &'a DVector<f64>,
    pub rate: &'a DVector<f64>,
    pub modal: &'a [C64],
}

impl FastModes {
    /// The modes of `lambdas` (the fast eigenvalues of `a`, conjugates included) with their
    /// eigenvectors, `e` the flow's constant and `g` the contact vectors (`dof x contacts`);
    /// `None` when an eigenvector does not converge (then the branch keeps short steps).
    pub fn new(
        a: &DMatrix<f64>,
        e: &DVector<f64>,
        lambdas: &[C64],
        g: &DMatrix<f64>,
    ) -> Option<Self> {
        let (n2, n) = (a.nrows(), a.nrows() / 2);
        let ac: DMatrix<C64> = a.map(|v| C64::new(v, 0.0));
        let ec: DVector<C64> = e.map(|v| C64::new(v, 0.0));
        let k = lambdas.len();
        let mut left: Vec<DVector<C64>> = Vec::with_capacity(k);
        let mut value_coupling = DMatrix::zeros(g.ncols(), k);
        let mut rate_coupling = DMatrix::zeros(g.ncols(), k);
        let act = ac.transpose();
        let mut right: Vec<DVector<C64>> = Vec::with_capacity(k);
        for (j, &lambda) in lambdas.iter().enumerate() {
            // a conjugate's eigenvectors are the conjugates of its partner's, its augmented
            // left one too (`e` is real), already scaled
            let partner =
                (0..j).find(|&i| (lambdas[i].conj() - lambda).norm() <= 1e-9 * lambda.norm());
            let (v, augmented) = match partner {
                Some(i) => (right[i].conjugate(), left[i].conjugate()),
                None => {
                    let v = inverse_iteration(&ac, lambda)?;
                    let w = inverse_iteration(&act, lambda)?;
                    let norm = w.dot(&v);
                    if norm.norm() <= 1e-12 * w.norm() * v.norm() {
                        return None;
                    }
                    let w = w / norm;
                    let mut augmented = DVector::zeros(n2 + 1);
                    augmented.rows_mut(0, n2).copy_from(&w);
                    augmented[n2] = w.dot(&ec) / lambda;
                    (v, augmented)
                }
            };
            for c in 0..g.ncols() {
                let gc = g.column(c);
                value_coupling[(c, j)] = (0..n).map(|i| v[i] * gc[i]).sum();
                rate_coupling[(c, j)] = (0..n).map(|i| v[n + i] * gc[i]).sum();
            }
            right.push(v);
            left.push(augmented);
        }
        // a (nearly) repeated eigenvalue gives inverse iteration the same vector twice: the
        // coordinates must be those of distinct modes, `w_i^T v_j = [i = j]`
        for (i, w) in left.iter().enumerate() {
            for (j, v) in right.iter().enumerate() {
                let product = w.rows(0, n2).dot(v);
                let expected = if i == j { 1.0 } else { 0.0 };
                if (product - C64::new(expected, 0.0)).norm() > BIORTHOGONALITY {
                    return None;
                }
            }
        }
        Some(FastModes {
            left,
            value_coupling,
            rate_coupling,
        })
    }

    /// How many fast modes there are.
    pub fn len(&self) -> usize {
        self.left.len()
    }

    /// Modal coordinates `z_k` of state `y` into `z`.
    pub fn coordinates(&self, y: &DVector<f64>, z: &mut [C64]) {
        let n2 = y.len();
        for (zk, w) in z.iter_mut().zip(&self.left) {
            let mut sum = w[n2];
            for i in 0..n2 {
                sum += w[i] * y[i];
            }
            *zk = sum;
        }
    }

    /// True when switch function `f` stays positive over a step of `h` (s) from `start` to
    /// `end`, certified as in the module documentation.
    pub fn certifies(&self, f: SwitchFunction, h: f64, start: &StepEnd, end: &StepEnd) -> bool {
        let c = f.contact;
        let mut bound = 0.0;
        let slow = |at: &StepEnd| {
            let (mut value, mut rate) = (at.gap[c], at.rate[c]);
            for (k, z) in at.modal.iter().enumerate() {
                value -= (self.value_coupling[(c, k)] * z).re;
                rate -= (self.rate_coupling[(c, k)] * z).re;
            }
            (f.sign * value + f.offset, f.sign * rate)
        };
        for k in 0..self.len() {
            let size = start.modal[k].norm_sqr().max(end.modal[k].norm_sqr());
            bound += (self.value_coupling[(c, k)].norm_sqr() * size).sqrt();
        }
        bound *= BOUND_MARGIN;
        let ((s0, d0), (s1, d1)) = (slow(start), slow(end));
        let (m0, m1) = (s0 - bound, s1 - bound);
        m0 > 0.0 && m1 > 0.0 && !HermiteCubic::new(m0, d0 * h, m1, d1 * h).dips()
    }
}

/// The eigenvector of `a` for its eigenvalue `lambda` by inverse iteration, or `None` when
/// it does not converge to [`RESIDUAL`].
fn inverse_iteration(a: &DMatrix<C64>, lambda: C64) -> Option<DVector<C64>> {
    let n = a.nrows();
    // a shift a hair off the eigenvalue keeps the factorization regular
    let shift = lambda + C64::new(1e-10 * lambda.norm(), 0.0);
    let lu = (a - DMatrix::from_diagonal_element(n, n, shift)).lu();
    let mut v = DVector::from_fn(n, |i, _| C64::new(1.0 + 0.1 * i as f64, 0.3));
    for _ in 0..SWEEPS {
        v = lu.solve(&v)?;
        let size = v.norm();
        if !size.is_finite() || size == 0.0 {
            return None;
        }
        v /= C64::new(size, 0.0);
    }
    let residual = (a * &v - &v * lambda).norm();
    (residual <= RESIDUAL * lambda.norm()).then_some(v)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two equal, uncoupled stiff oscillators share one eigenvalue pair: inverse iteration
    /// cannot tell their modes apart, so no coordinates (and no long step) come out.
    #[test]
    fn a_repeated_fast_eigenvalue_gives_no_modes() {
        let mut a = DMatrix::zeros(4, 4);
        a[(0, 2)] = 1.0;
        a[(1, 3)] = 1.0;
        a[(2, 0)] = -1e6;
        a[(3, 1)] = -1e6;
        a[(2, 2)] = -1.0;
        a[(3, 3)] = -1.0;
        let eig = crate::analysis::eigen::eigenvalues(a.clone(), "test").unwrap();
        let g = DMatrix::from_column_slice(2, 1, &[1.0, -1.0]);
        assert!(FastModes::new(&a, &DVector::zeros(4), &eig, &g).is_none());
        // split them by 10 %: four distinct modes
        a[(3, 1)] = -1.21e6;
        let eig = crate::analysis::eigen::eigenvalues(a.clone(), "test").unwrap();
        assert_eq!(
            FastModes::new(&a, &DVector::zeros(4), &eig, &g)
                .unwrap()
                .len(),
            4
        );
    }

    /// A 2-dof chain with a stiff and a soft spring: the fast mode's coordinates evolve as
    /// `exp(lambda t)` under the exact flow, and the slow remainder of a gap carries none of
    /// the fast frequency.
    #[test]
    fn modal_coordinates_follow_their_eigenvalue() {
        // x'' = -K x - D x', K = [[1e6 + 1, -1e6], [-1e6, 1e6 + 1]]: fast mode ~1414 rad/s
        let (kf, ks, d) = (1e6, 1.0, 2.0);
        let mut a = DMatrix::zeros(4, 4);
        a[(0, 2)] = 1.0;
        a[(1, 3)] = 1.0;
        a[(2, 0)] = -(kf + ks);
        a[(2, 1)] = kf;
        a[(3, 0)] = kf;
        a[(3, 1)] = -(kf + ks);
        a[(2, 2)] = -d;
        a[(3, 3)] = -d;
        let e = DVector::from_vec(vec![0.0, 0.0, 0.5, 0.0]);
        let eig = crate::analysis::eigen::eigenvalues(a.clone(), "test").unwrap();
        let fast: Vec<C64> = eig.into_iter().filter(|l| l.norm() > 100.0).collect();
        assert_eq!(fast.len(), 2);
        let g = DMatrix::from_column_slice(2, 1, &[1.0, -1.0]);
        let modes = FastModes::new(&a, &e, &fast, &g).unwrap();
        let y0 = DVector::from_vec(vec![1e-3, -2e-3, 0.3, 0.1]);
        let h = 1.3e-3;
        let mut aug = DMatrix::zeros(5, 5);
        aug.view_mut((0, 0), (4, 4)).copy_from(&(&a * h));
        aug.view_mut((0, 4), (4, 1)).copy_from(&(&e * h));
        let flow = aug.exp();
        let y1 = flow.view((0, 0), (4, 4)) * &y0 + flow.view((0, 4), (4, 1));
        let (mut z0, mut z1) = ([C64::default(); 2], [C64::default(); 2]);
        modes.coordinates(&y0, &mut z0);
        modes.coordinates(&y1, &mut z1);
        for k in 0..2 {
            let expected = z0[k] * (fast[k] * h).exp();
            assert!((z1[k] - expected).norm() <= 1e-9 * z0[k].norm(), "{k}");
        }
        // the gap x0 - x1 lives in the fast (antisymmetric) mode and the static deflection
        // under the constant force: removing the fast part leaves the static gap
        // 0.5 / (2 kf + ks), whatever the state
        let static_gap = 0.5 / (2.0 * kf + ks);
        for (y, z) in [(&y0, &z0), (&y1, &z1)] {
            let gap = y[0] - y[1];
            let fast_part: f64 = (0..2)
                .map(|k| (modes.value_coupling[(0, k)] * z[k]).re)
                .sum();
            let slow = gap - fast_part;
            assert!(
                (slow - static_gap).abs() <= 1e-9 * static_gap,
                "{slow} {static_gap}"
            );
        }
    }

    /// The certificate against the flow itself: from states of adams-clearance's lasting
    /// contact (t = 0.8 s) with perturbations from 1e-12 to 1e-5 m, every long step it
    /// certifies keeps every switch function positive at 400 points inside the step (the
    /// flow composed from `exp(A h / 400)`, an independent path); among the refused are
    /// steps that end positive but cross inside, which a check of the ends would pass.
    /// `y` (coordinates then rates, `n` each) moved by a wave of a size between 1e-12 and
    /// 1e-5 that depends on `case`, its rates scaled by the fastest rate `omega` (1/s).
    fn perturbed(y: &[f64], case: usize, n: usize, omega: f64) -> DVector<f64> {
        let size = 10f64.powf(-12.0 + 7.0 * (case % 40) as f64 / 39.0);
        DVector::from_fn(y.len(), |i, _| {
            let wave = (1.3 * i as f64 + 0.77 * case as f64).sin();
            let scale = if i < n {
                1.0
            } else {
                omega / (1 + case % 3) as f64
            };
            y[i] + size * wave * scale
        })
    }

    /// `y0` and `steps` applications of the affine flow `y -> phi y + gamma`.
    fn flow_path(
        phi: &DMatrix<f64>,
        gamma: &DVector<f64>,
        y0: &DVector<f64>,
        steps: usize,
    ) -> Vec<DVector<f64>> {
        let mut path = vec![y0.clone()];
        for _ in 0..steps {
            let next = phi * path.last().unwrap() + gamma;
            path.push(next);
        }
        path
    }

    #[test]
    fn a_certified_step_never_crosses_inside() {
        use crate::integrate::{Method, Settings, events::ContactTracker, simulate};
        use crate::model::Model;
        let path = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../scenes/adams-clearance.toml"
        );
        let scene = crate::Scene::load(path.as_ref(), &[]).unwrap();
        let model = crate::AssembledModel::new(&scene.params).unwrap();
        let (n, nc) = (model.dof(), model.layout().contact_count());
        let n2 = 2 * n;
        let t = 0.8;
        let mut y = vec![0.0; n2];
        let span = crate::scene::TimeSpan {
            start: 0.0,
            end: t,
            sample: 1e-3,
        };
        let mut observe = |_: f64, state: &[f64], _: &[f64]| y.copy_from_slice(state);
        simulate(
            &model,
            &vec![0.0; n2],
            &span,
            Method::Exact,
            &Settings::default(),
            &mut observe,
            None,
        )
        .unwrap();
        let tracker = ContactTracker::new(&model, t, &y);
        let states = tracker.states().to_vec();
        let closed = states.iter().filter(|&&s| s != ContactState::Free).count();
        assert!(closed >= 2, "{states:?}");
        let mut a = DMatrix::zeros(n2, n2);
        let mut e = DVector::zeros(n2);
        model.jacobian(t, &y, Some(&states), &mut a);
        model.rhs(t, &vec![0.0; n2], Some(&states), e.as_mut_slice());
        let eig = crate::analysis::eigen::eigenvalues(a.clone(), "test").unwrap();
        let (fast, h) = super::super::exact::long_step_split(&eig, closed, 1e-3).unwrap();
        let (mut g, mut gdot) = (DMatrix::zeros(n, nc), DMatrix::zeros(n, nc));
        model.contact_vectors(t, &mut g, &mut gdot);
        let modes = FastModes::new(&a, &e, &fast, &g).unwrap();
        // the switch functions of the branch, as method exact builds them
        let mut functions = Vec::new();
        SwitchFunction::of_branches(&states, scene.params.contact.half_band(), &mut functions);
        // the affine flow over h / 400
        let omega = eig.iter().map(|l| l.norm()).fold(0.0, f64::max);
        let (phi, gamma) = super::super::exact::balanced_flow(&a, &e, h / 400.0, omega);
        let gaps = |y: &DVector<f64>| {
            let (value, rate): (Vec<f64>, Vec<f64>) = (0..nc)
                .map(|c| {
                    let gc = g.column(c);
                    (gc.dot(&y.rows(0, n)), gc.dot(&y.rows(n, n)))
                })
                .unzip();
            (DVector::from_vec(value), DVector::from_vec(rate))
        };
        let (mut certified, mut refused, mut hidden) = (0, 0, 0);
        let k = modes.len();
        for case in 0..240 {
            let y0 = perturbed(&y, case, n, omega);
            let path = flow_path(&phi, &gamma, &y0, 400);
            let y1 = path.last().unwrap();
            let (v0, r0) = gaps(&y0);
            let (v1, r1) = gaps(y1);
            let (mut z0, mut z1) = (vec![C64::default(); k], vec![C64::default(); k]);
            modes.coordinates(&y0, &mut z0);
            modes.coordinates(y1, &mut z1);
            let start = StepEnd {
                gap: &v0,
                rate: &r0,
                modal: &z0,
            };
            let end = StepEnd {
                gap: &v1,
                rate: &r1,
                modal: &z1,
            };
            for &f in &functions {
                let value = |y: &DVector<f64>| f.sign * gaps(y).0[f.contact] + f.offset;
                let lowest = path.iter().map(value).fold(f64::INFINITY, f64::min);
                if modes.certifies(f, h, &start, &end) {
                    certified += 1;
                    assert!(
                        lowest > 0.0,
                        "case {case}: certified, but reaches {lowest:e} m"
                    );
                } else {
                    refused += 1;
                    if value(&y0) > 0.0 && value(y1) > 0.0 && lowest < 0.0 {
                        hidden += 1;
                    }
                }
            }
        }
        eprintln!(
            "{certified} certified, {refused} refused ({hidden} with a crossing hidden inside)"
        );
        assert!(certified > 100 && refused > 100 && hidden > 0);
    }
}
