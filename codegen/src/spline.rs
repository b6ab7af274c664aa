//! The static correction shapes in high precision: the cubic B-splines on a section's knots
//! as polynomial pieces in `xi`, their Galerkin integrals with each other and with the modes
//! in closed form, and their Gram-Schmidt orthonormalization against the modes.
//!
//! The runtime's basis `modes+static` (its `shape::section_basis`) is the same: the clamped
//! cubic B-splines on `0, 0, 0, 0, xi_1, ..., xi_m, 1, 1, 1, 1` without the first two, made
//! orthogonal to the section's modes and orthonormal among themselves in `int_0^1 f g dxi`,
//! each correction the Cholesky factor's (positive-diagonal) column. Here every integral is
//! exact (piecewise polynomials against the modes' exponential-trigonometric sums), so the
//! emitted matrices carry no quadrature error.

use crate::exact::{Func, RootTable, galerkin_tables, integrate_product, term_moment};
use crate::precise::Real;

/// A polynomial in `xi`: the coefficients of `xi^0, xi^1, ...`.
#[derive(Debug, Clone)]
struct Poly(Vec<Real>);

impl Poly {
    fn constant(c: Real) -> Self {
        Poly(vec![c])
    }

    /// `(c0 + c1 xi) p`.
    fn times_linear(&self, c0: &Real, c1: &Real) -> Poly {
        let mut out = vec![Real::zero(); self.0.len() + 1];
        for (n, c) in self.0.iter().enumerate() {
            out[n] = &out[n] + &(c * c0);
            out[n + 1] = &out[n + 1] + &(c * c1);
        }
        Poly(out)
    }

    fn plus(&self, o: &Poly) -> Poly {
        let n = self.0.len().max(o.0.len());
        let at = |p: &Poly, i: usize| p.0.get(i).cloned().unwrap_or_else(Real::zero);
        Poly((0..n).map(|i| &at(self, i) + &at(o, i)).collect())
    }

    fn times(&self, o: &Poly) -> Poly {
        let mut out = vec![Real::zero(); self.0.len() + o.0.len()];
        for (i, a) in self.0.iter().enumerate() {
            for (j, b) in o.0.iter().enumerate() {
                out[i + j] = &out[i + j] + &(a * b);
            }
        }
        Poly(out)
    }

    fn derivative(&self) -> Poly {
        Poly(
            self.0
                .iter()
                .enumerate()
                .skip(1)
                .map(|(n, c)| c * &Real::int(n as i64))
                .collect(),
        )
    }

    fn eval(&self, x: &Real) -> Real {
        self.0
            .iter()
            .rev()
            .fold(Real::zero(), |acc, c| &(&acc * x) + c)
    }

    /// `int_a^b xi^weight p dxi`.
    fn integral(&self, weight: u32, (a, b): (&Real, &Real)) -> Real {
        let mut total = Real::zero();
        for (n, c) in self.0.iter().enumerate() {
            let e = n as u32 + weight + 1;
            let power = |x: &Real| (0..e).fold(Real::int(1), |acc, _| &acc * x);
            let span = &power(b) - &power(a);
            total = &total + &(&(c * &span) / &Real::int(i64::from(e)));
        }
        total
    }
}

/// A function given by polynomial pieces on the intervals `[a, b]` of its support.
#[derive(Debug, Clone)]
pub struct Piecewise {
    pieces: Vec<(Real, Real, Poly)>,
}

impl Piecewise {
    fn derivative(&self) -> Piecewise {
        Piecewise {
            pieces: self
                .pieces
                .iter()
                .map(|(a, b, p)| (a.clone(), b.clone(), p.derivative()))
                .collect(),
        }
    }

    /// The value at `xi = 1` (the last piece's end).
    pub fn top(&self) -> Real {
        match self.pieces.last() {
            Some((_, b, p)) if *b == Real::int(1) => p.eval(b),
            _ => Real::zero(),
        }
    }
}

/// `a / b` with the B-spline convention `0 / 0 = 0` for repeated knots.
fn ratio(a: &Real, b: &Real) -> Real {
    if b.is_zero() { Real::zero() } else { a / b }
}

/// The cubic B-spline on the five knots `t[j..j + 5]`, piece by piece (Cox-de Boor on
/// polynomials restricted to each knot interval).
fn bspline(t: &[Real], j: usize) -> Piecewise {
    let mut pieces = Vec::new();
    for s in j..j + 4 {
        if t[s] == t[s + 1] {
            continue;
        }
        // degree 0 on interval s, then up: N_i,p = w_i,p N_i,p-1 + (1 - w_i+1,p) N_i+1,p-1
        let mut level: Vec<Poly> = (j..j + 4)
            .map(|i| Poly::constant(Real::int(i64::from(i == s))))
            .collect();
        for p in 1..=3 {
            level = (0..level.len() - 1)
                .map(|r| {
                    let i = j + r;
                    let left = ratio(&Real::int(1), &(&t[i + p] - &t[i]));
                    let right = ratio(&Real::int(1), &(&t[i + p + 1] - &t[i + 1]));
                    // (xi - t_i) / (t_i+p - t_i) and (t_i+p+1 - xi) / (t_i+p+1 - t_i+1)
                    let up = level[r].times_linear(&-&(&t[i] * &left), &left);
                    let down = level[r + 1].times_linear(&(&t[i + p + 1] * &right), &-&right);
                    up.plus(&down)
                })
                .collect();
        }
        let poly = level.pop().expect("one spline of degree 3");
        pieces.push((t[s].clone(), t[s + 1].clone(), poly));
    }
    Piecewise { pieces }
}

/// A section's correction B-splines on its interior knots `knots` (fractions of its length):
/// the clamped cubic B-splines without the first two (the only ones with a value or slope at
/// the foot), `knots.len() + 2` of them.
pub fn correction_splines(knots: &[f64]) -> Vec<Piecewise> {
    let mut t = vec![Real::zero(); 4];
    t.extend(knots.iter().map(|&x| Real::from_f64(x)));
    t.extend((0..4).map(|_| Real::int(1)));
    (2..t.len() - 4).map(|j| bspline(&t, j)).collect()
}

/// A function of the section's coordinates before the orthogonalization: a mode's (or the
/// translation's) sum, or a B-spline.
#[derive(Debug, Clone)]
pub enum Primitive {
    /// An exponential-trigonometric sum.
    Sum(Func),
    /// A cubic B-spline.
    Spline(Piecewise),
}

impl Primitive {
    fn derivative(&self, roots: &RootTable) -> Primitive {
        match self {
            Primitive::Sum(f) => Primitive::Sum(f.derivative(roots)),
            Primitive::Spline(s) => Primitive::Spline(s.derivative()),
        }
    }

    /// The value at `xi = 1`.
    pub fn top(&self, roots: &RootTable) -> Real {
        match self {
            Primitive::Sum(f) => f.value_at_end(roots, true),
            Primitive::Spline(s) => s.top(),
        }
    }
}

/// `int_0^1 xi^weight f g dxi`.
fn inner(f: &Primitive, g: &Primitive, weight: u32, roots: &RootTable) -> Real {
    match (f, g) {
        (Primitive::Sum(a), Primitive::Sum(b)) => integrate_product(a, b, weight, roots),
        (Primitive::Spline(s), Primitive::Sum(a)) | (Primitive::Sum(a), Primitive::Spline(s)) => {
            let mut total = Real::zero();
            for (lo, hi, poly) in &s.pieces {
                for (n, c) in poly.0.iter().enumerate() {
                    for t in &a.terms {
                        let m = term_moment(t, n as u32 + weight, (lo, hi), roots);
                        total = &total + &(c * &m);
                    }
                }
            }
            total
        }
        (Primitive::Spline(a), Primitive::Spline(b)) => {
            let mut total = Real::zero();
            for (lo, hi, p) in &a.pieces {
                if let Some((_, _, q)) = b.pieces.iter().find(|(l, h, _)| l == lo && h == hi) {
                    total = &total + &p.times(q).integral(weight, (lo, hi));
                }
            }
            total
        }
    }
}

/// The four Galerkin tables (`int f g`, `int f'' g''`, `int f' g'`, `int xi f' g'`, with
/// `' = d/dxi`) over `functions`.
pub fn tables(functions: &[Primitive], roots: &RootTable) -> [Vec<Vec<Real>>; 4] {
    galerkin_tables(
        functions,
        |f| f.derivative(roots),
        |a, b, w| inner(a, b, w, roots),
    )
}

/// The corrections as combinations of `gram`'s functions: row `e` holds correction `e`'s
/// coefficients (zero past its own function), for the functions from `first` on, made
/// orthogonal to those before them and orthonormal among themselves (Cholesky `G = R^T R`,
/// the columns of `R^-1`).
///
/// # Errors
/// A message naming the correction that lies within rounding of the span before it.
pub fn orthonormal_corrections(
    gram: &[Vec<Real>],
    first: usize,
    k: usize,
) -> Result<Vec<Vec<Real>>, String> {
    let n = gram.len();
    // the upper Cholesky factor R, row by row
    let mut r = vec![vec![Real::zero(); n]; n];
    let largest = (0..n).fold(Real::zero(), |m, i| {
        let d = gram[i][i].sqrt();
        if d > m { d } else { m }
    });
    for i in 0..n {
        let mut d = gram[i][i].clone();
        for row in r.iter().take(i) {
            d = &d - &(&row[i] * &row[i]);
        }
        let pivot = if d > Real::zero() {
            d.sqrt()
        } else {
            Real::zero()
        };
        if pivot <= &Real::from_f64(1e-12) * &largest {
            return Err(format!(
                "section {k}: static correction shape {} lies within rounding of the span of \
                 the modes and the other shapes; give the section fewer modes",
                i + 1 - first
            ));
        }
        for j in i + 1..n {
            let mut v = gram[i][j].clone();
            for row in r.iter().take(i) {
                v = &v - &(&row[i] * &row[j]);
            }
            r[i][j] = &v / &pivot;
        }
        r[i][i] = pivot;
    }
    // column c of R^-1 by back substitution of R x = e_c
    let column = |c: usize| {
        let mut x = vec![Real::zero(); n];
        for i in (0..=c).rev() {
            let mut v = Real::int(i64::from(i == c));
            for j in i + 1..=c {
                v = &v - &(&r[i][j] * &x[j]);
            }
            x[i] = &v / &r[i][i];
        }
        x
    };
    Ok((first..n).map(column).collect())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::precise::Kind;

    #[test]
    fn the_full_spline_basis_is_a_partition_of_unity_and_integrates_exactly() {
        let knots = [0.25, 0.5];
        let mut t = vec![Real::zero(); 4];
        t.extend(knots.iter().map(|&x| Real::from_f64(x)));
        t.extend((0..4).map(|_| Real::int(1)));
        let all: Vec<Piecewise> = (0..t.len() - 4).map(|j| bspline(&t, j)).collect();
        for x in [0.0, 0.1, 0.3, 0.5, 0.77, 0.99] {
            let xr = Real::from_f64(x);
            let sum = all.iter().fold(Real::zero(), |acc, s| {
                let v = s
                    .pieces
                    .iter()
                    .find(|(a, b, _)| *a <= xr && xr < *b)
                    .map_or(Real::zero(), |(_, _, p)| p.eval(&xr));
                &acc + &v
            });
            assert!(
                (sum.to_f64() - 1.0).abs() < 1e-30,
                "at {x}: {}",
                sum.to_f64()
            );
        }
        // the integrals of a partition of unity sum to 1 (and its moments to 1/2)
        let roots = RootTable::new(Kind::FreeFree, 2);
        let one = Primitive::Sum(Func::constant(Real::int(1)));
        let (mut area, mut moment) = (0.0, 0.0);
        for s in all {
            let s = Primitive::Spline(s);
            area += inner(&s, &one, 0, &roots).to_f64();
            moment += inner(&one, &s, 1, &roots).to_f64();
        }
        assert!((area - 1.0).abs() < 1e-15 && (moment - 0.5).abs() < 1e-15);
    }

    /// `f(xi)` of an exponential-trigonometric sum, by its terms.
    fn value(f: &Func, x: &Real, roots: &RootTable) -> Real {
        use crate::exact::Trig;
        f.terms.iter().fold(Real::zero(), |acc, t| {
            let mut v = t.coef.clone();
            for _ in 0..t.power {
                v = &v * x;
            }
            if let Some((sign, m)) = t.exp {
                let e = (&roots.beta[m] * x).exp();
                v = if sign > 0 { &v * &e } else { &v / &e };
            }
            if let Some((trig, n)) = t.trig {
                let a = &roots.beta[n] * x;
                v = &v * &(if trig == Trig::Cos { a.cos() } else { a.sin() });
            }
            &acc + &v
        })
    }

    #[test]
    fn spline_integrals_against_the_modes_agree_with_a_quadrature() {
        // composite Simpson on a fine grid that holds the knots (the integrand is smooth
        // between them): an independent path to the closed form
        let roots = RootTable::new(Kind::FreeFree, 6);
        let splines = correction_splines(&[0.3, 0.6]);
        for i in [3, 6] {
            let mode = Func::paper_mode(Kind::FreeFree, i, &roots);
            let slope = mode.derivative(&roots);
            for s in &splines {
                let ds = s.derivative();
                let at = |p: &Piecewise, x: f64| {
                    let xr = Real::from_f64(x);
                    p.pieces
                        .iter()
                        .find(|(a, b, _)| *a <= xr && xr <= *b)
                        .map_or(0.0, |(_, _, q)| q.eval(&xr).to_f64())
                };
                let n = 600;
                let h = 1.0 / n as f64;
                let (mut plain, mut weighted) = (0.0, 0.0);
                for j in 0..=n {
                    let x = j as f64 * h;
                    let w = if j == 0 || j == n {
                        1.0
                    } else if j % 2 == 1 {
                        4.0
                    } else {
                        2.0
                    };
                    let xr = Real::from_f64(x);
                    plain += w * at(s, x) * value(&mode, &xr, &roots).to_f64();
                    weighted += w * x * at(&ds, x) * value(&slope, &xr, &roots).to_f64();
                }
                let (plain, weighted) = (plain * h / 3.0, weighted * h / 3.0);
                let exact = inner(
                    &Primitive::Spline(s.clone()),
                    &Primitive::Sum(mode.clone()),
                    0,
                    &roots,
                );
                let exact_w = inner(
                    &Primitive::Spline(ds),
                    &Primitive::Sum(slope.clone()),
                    1,
                    &roots,
                );
                assert!(
                    (exact.to_f64() - plain).abs() < 1e-9,
                    "mode {i}: {} {plain}",
                    exact.to_f64()
                );
                assert!(
                    (exact_w.to_f64() - weighted).abs() < 1e-7,
                    "mode {i}: {} {weighted}",
                    exact_w.to_f64()
                );
            }
        }
    }
}
