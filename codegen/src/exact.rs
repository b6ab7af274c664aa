//! Shape functions as exponential-trigonometric sums, and their Galerkin integrals in closed
//! form, in high precision (no quadrature).
//!
//! On a section of length `l` with `x = l xi`, every basis function of the computing
//! coordinates (see the runtime's `model` module) is `l^e sum_j c_j xi^p_j e^(s_j beta_j xi)
//! trig_j(beta'_j xi)`: the paper's `cosh` and `sinh` split into `e^(+-beta xi)`. A product of
//! two such sums is a sum of `xi^p e^(a xi) cos|sin(b xi)`, integrated exactly on `[0, 1]` as
//! the real or imaginary part of `J_p(z) = int_0^1 xi^p e^(z xi) dxi`, `z = a + i b`:
//! `J_0 = (e^z - 1)/z`, `J_p = (e^z - p J_(p-1))/z`, and `J_p(0) = 1/(p+1)`. The terms
//! `e^(2 beta)` of size up to 1e78 cancel in these sums; at 512 bits about 75 digits survive.

use crate::precise::{Kind, Real, mode_root};

/// `cos` or `sin`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Trig {
    /// `cos(beta xi)`.
    Cos,
    /// `sin(beta xi)`.
    Sin,
}

/// One term `coef xi^power e^(sign beta_m xi) trig(beta_n xi)` (modes index the section's
/// root table).
#[derive(Debug, Clone)]
pub struct Term {
    /// Coefficient.
    pub coef: Real,
    /// Power of `xi` (0 or 1 here).
    pub power: u32,
    /// Exponential `e^(sign beta_m xi)`: `(sign, m)`.
    pub exp: Option<(i8, usize)>,
    /// Trigonometric factor `trig(beta_n xi)`: `(trig, n)`.
    pub trig: Option<(Trig, usize)>,
}

/// A basis function restricted to one section: `l^length_power sum(terms)(xi)`.
#[derive(Debug, Clone)]
pub struct Func {
    /// The terms, in `xi = x / l`.
    pub terms: Vec<Term>,
    /// Power of the section length in front (1 for the rigid mode `x = l xi`).
    pub length_power: i32,
}

/// Roots and their exponentials and trigonometric values for one section's modes.
#[derive(Debug, Clone)]
pub struct RootTable {
    /// `beta_i`, index `i - 1`.
    pub beta: Vec<Real>,
    exp_pos: Vec<Real>,
    exp_neg: Vec<Real>,
    cos: Vec<Real>,
    sin: Vec<Real>,
}

impl RootTable {
    /// The roots of modes `1..=modes` of a section of the given kind.
    pub fn new(kind: Kind, modes: usize) -> Self {
        let beta: Vec<Real> = (1..=modes).map(|i| mode_root(kind, i)).collect();
        Self {
            exp_pos: beta.iter().map(Real::exp).collect(),
            exp_neg: beta.iter().map(|b| (-b).exp()).collect(),
            cos: beta.iter().map(Real::cos).collect(),
            sin: beta.iter().map(Real::sin).collect(),
            beta,
        }
    }

    fn exp_of(&self, e: Option<(i8, usize)>) -> Real {
        match e {
            None => Real::int(1),
            Some((s, m)) if s > 0 => self.exp_pos[m].clone(),
            Some((_, m)) => self.exp_neg[m].clone(),
        }
    }

    pub(crate) fn rate(&self, e: Option<(i8, usize)>) -> Real {
        match e {
            None => Real::zero(),
            Some((s, m)) if s > 0 => self.beta[m].clone(),
            Some((_, m)) => -&self.beta[m],
        }
    }
}

impl Term {
    fn new(coef: Real, power: u32, exp: Option<(i8, usize)>, trig: Option<(Trig, usize)>) -> Self {
        Self {
            coef,
            power,
            exp,
            trig,
        }
    }

    /// `d/dxi` of the term: up to three terms.
    fn derivative(&self, roots: &RootTable) -> Vec<Term> {
        let mut out = Vec::new();
        if self.power > 0 {
            let c = &self.coef * &Real::int(self.power as i64);
            out.push(Term::new(c, self.power - 1, self.exp, self.trig));
        }
        if self.exp.is_some() {
            out.push(Term::new(
                &self.coef * &roots.rate(self.exp),
                self.power,
                self.exp,
                self.trig,
            ));
        }
        if let Some((t, n)) = self.trig {
            let b = &roots.beta[n];
            match t {
                Trig::Cos => out.push(Term::new(
                    -&(&self.coef * b),
                    self.power,
                    self.exp,
                    Some((Trig::Sin, n)),
                )),
                Trig::Sin => out.push(Term::new(
                    &self.coef * b,
                    self.power,
                    self.exp,
                    Some((Trig::Cos, n)),
                )),
            }
        }
        out
    }

    /// Value at `xi = 0` or `xi = 1`.
    fn value_at_end(&self, roots: &RootTable, at_one: bool) -> Real {
        if !at_one {
            return match (self.power, self.trig) {
                (p, _) if p > 0 => Real::zero(),
                (_, Some((Trig::Sin, _))) => Real::zero(),
                _ => self.coef.clone(),
            };
        }
        let trig = match self.trig {
            None => Real::int(1),
            Some((Trig::Cos, n)) => roots.cos[n].clone(),
            Some((Trig::Sin, n)) => roots.sin[n].clone(),
        };
        &(&self.coef * &roots.exp_of(self.exp)) * &trig
    }
}

impl Func {
    /// The constant `c`.
    pub fn constant(c: Real) -> Self {
        Self {
            terms: vec![Term::new(c, 0, None, None)],
            length_power: 0,
        }
    }

    /// The paper's shape function of mode `i` (1-based) of a section of the given kind.
    pub fn paper_mode(kind: Kind, i: usize, roots: &RootTable) -> Self {
        let m = i - 1;
        let half = Real::from_f64(0.5);
        match (kind, i) {
            (Kind::GuidedFree, 1) => Self::constant(Real::int(2)),
            (Kind::FreeFree, 1) => Self::constant(Real::int(1)),
            (Kind::FreeFree, 2) => Self {
                terms: vec![Term::new(Real::int(1), 1, None, None)],
                length_power: 1,
            },
            (Kind::GuidedFree, _) => {
                // cos(b xi) + (cos b / cosh b) (e^(b xi) + e^(-b xi)) / 2
                let k = &roots.cos[m] / &roots.beta[m].cosh();
                let kh = &k * &half;
                Self {
                    terms: vec![
                        Term::new(Real::int(1), 0, None, Some((Trig::Cos, m))),
                        Term::new(kh.clone(), 0, Some((1, m)), None),
                        Term::new(kh, 0, Some((-1, m)), None),
                    ],
                    length_power: 0,
                }
            }
            (Kind::FreeFree, _) => {
                // (1-s)/2 e^(b xi) + (1+s)/2 e^(-b xi) + cos(b xi) - s sin(b xi)
                let b = &roots.beta[m];
                let sigma = &(&b.cosh() - &roots.cos[m]) / &(&b.sinh() - &roots.sin[m]);
                let one = Real::int(1);
                Self {
                    terms: vec![
                        Term::new(&(&one - &sigma) * &half, 0, Some((1, m)), None),
                        Term::new(&(&one + &sigma) * &half, 0, Some((-1, m)), None),
                        Term::new(one, 0, None, Some((Trig::Cos, m))),
                        Term::new(-&sigma, 0, None, Some((Trig::Sin, m))),
                    ],
                    length_power: 0,
                }
            }
        }
    }

    /// `f - c`.
    pub fn minus_constant(mut self, c: Real) -> Self {
        self.terms.push(Term::new(-&c, 0, None, None));
        self
    }

    /// `d/dx = (1/l) d/dxi`.
    pub fn derivative(&self, roots: &RootTable) -> Self {
        Self {
            terms: self
                .terms
                .iter()
                .flat_map(|t| t.derivative(roots))
                .collect(),
            length_power: self.length_power - 1,
        }
    }

    /// The dimensionless sum at `xi = 0` (foot) or `xi = 1` (top); multiply by `l^length_power`.
    pub fn value_at_end(&self, roots: &RootTable, at_top: bool) -> Real {
        self.terms
            .iter()
            .fold(Real::zero(), |s, t| &s + &t.value_at_end(roots, at_top))
    }
}

/// A complex number of two [`Real`]s.
#[derive(Debug, Clone)]
struct Complex {
    re: Real,
    im: Real,
}

impl Complex {
    fn div(&self, o: &Complex) -> Complex {
        let d = &(&o.re * &o.re) + &(&o.im * &o.im);
        Complex {
            re: &(&(&self.re * &o.re) + &(&self.im * &o.im)) / &d,
            im: &(&(&self.im * &o.re) - &(&self.re * &o.im)) / &d,
        }
    }
    fn sub(&self, o: &Complex) -> Complex {
        Complex {
            re: &self.re - &o.re,
            im: &self.im - &o.im,
        }
    }
    fn scale(&self, s: &Real) -> Complex {
        Complex {
            re: &self.re * s,
            im: &self.im * s,
        }
    }
}

/// `int_0^1 xi^p e^(z xi) dxi` with `e^z` given.
fn j_integral(p: u32, z: &Complex, ez: &Complex) -> Complex {
    if z.re.is_zero() && z.im.is_zero() {
        return Complex {
            re: &Real::int(1) / &Real::int(p as i64 + 1),
            im: Real::zero(),
        };
    }
    let mut j = ez
        .sub(&Complex {
            re: Real::int(1),
            im: Real::zero(),
        })
        .div(z);
    for k in 1..=p {
        j = ez.sub(&j.scale(&Real::int(k as i64))).div(z);
    }
    j
}

/// `int_0^1 xi^weight f g dxi` over the dimensionless sums (length powers not applied).
pub fn integrate_product(f: &Func, g: &Func, weight: u32, roots: &RootTable) -> Real {
    let mut total = Real::zero();
    for a in &f.terms {
        for b in &g.terms {
            let coef = &a.coef * &b.coef;
            if coef.is_zero() {
                continue;
            }
            let p = a.power + b.power + weight;
            let rate = &roots.rate(a.exp) + &roots.rate(b.exp);
            let e_rate = &roots.exp_of(a.exp) * &roots.exp_of(b.exp);
            // trig products as (scale, cos or sin, frequency, cos b, sin b)
            let parts: Vec<(Real, Trig, Real, Real, Real)> = match (a.trig, b.trig) {
                (None, None) => vec![(
                    Real::int(1),
                    Trig::Cos,
                    Real::zero(),
                    Real::int(1),
                    Real::zero(),
                )],
                (Some((t, n)), None) | (None, Some((t, n))) => {
                    vec![(
                        Real::int(1),
                        t,
                        roots.beta[n].clone(),
                        roots.cos[n].clone(),
                        roots.sin[n].clone(),
                    )]
                }
                (Some((t1, n1)), Some((t2, n2))) => {
                    let (b1, b2) = (&roots.beta[n1], &roots.beta[n2]);
                    let (c1, s1, c2, s2) = (
                        &roots.cos[n1],
                        &roots.sin[n1],
                        &roots.cos[n2],
                        &roots.sin[n2],
                    );
                    let half = Real::from_f64(0.5);
                    // angle sums: cos(b1 -+ b2) = c1 c2 +- s1 s2, sin(b1 -+ b2) = s1 c2 -+ c1 s2
                    let diff = (b1 - b2, &(c1 * c2) + &(s1 * s2), &(s1 * c2) - &(c1 * s2));
                    let sum = (b1 + b2, &(c1 * c2) - &(s1 * s2), &(s1 * c2) + &(c1 * s2));
                    match (t1, t2) {
                        // cos cos = (cos(d) + cos(s))/2, sin sin = (cos(d) - cos(s))/2
                        (Trig::Cos, Trig::Cos) | (Trig::Sin, Trig::Sin) => {
                            let sign = if t1 == Trig::Cos {
                                half.clone()
                            } else {
                                -&half
                            };
                            vec![
                                (half.clone(), Trig::Cos, diff.0, diff.1, diff.2),
                                (sign, Trig::Cos, sum.0, sum.1, sum.2),
                            ]
                        }
                        // sin1 cos2 = (sin(s) + sin(d))/2, cos1 sin2 = (sin(s) - sin(d))/2
                        (Trig::Sin, Trig::Cos) | (Trig::Cos, Trig::Sin) => {
                            let sign = if t1 == Trig::Sin {
                                half.clone()
                            } else {
                                -&half
                            };
                            vec![
                                (half.clone(), Trig::Sin, sum.0, sum.1, sum.2),
                                (sign, Trig::Sin, diff.0, diff.1, diff.2),
                            ]
                        }
                    }
                }
            };
            for (scale, trig, freq, cos_f, sin_f) in parts {
                let z = Complex {
                    re: rate.clone(),
                    im: freq,
                };
                let ez = Complex {
                    re: &e_rate * &cos_f,
                    im: &e_rate * &sin_f,
                };
                let j = j_integral(p, &z, &ez);
                let part = if trig == Trig::Cos { j.re } else { j.im };
                total = &total + &(&(&coef * &scale) * &part);
            }
        }
    }
    total
}

/// `int_a^b xi^p e^(z xi) dxi` (the recursion of [`j_integral`] between two bounds).
fn j_between(p: u32, z: &Complex, (a, b): (&Real, &Real)) -> Complex {
    let power = |x: &Real, n: u32| (0..n).fold(Real::int(1), |acc, _| &acc * x);
    if z.re.is_zero() && z.im.is_zero() {
        let n = Real::int(i64::from(p) + 1);
        return Complex {
            re: &(&power(b, p + 1) - &power(a, p + 1)) / &n,
            im: Real::zero(),
        };
    }
    let at = |x: &Real| {
        let (grow, turn) = ((&z.re * x).exp(), &z.im * x);
        Complex {
            re: &grow * &turn.cos(),
            im: &grow * &turn.sin(),
        }
    };
    let (ea, eb) = (at(a), at(b));
    let mut j = eb.sub(&ea).div(z);
    for k in 1..=p {
        let ends = eb.scale(&power(b, k)).sub(&ea.scale(&power(a, k)));
        j = ends.sub(&j.scale(&Real::int(i64::from(k)))).div(z);
    }
    j
}

/// `int_a^b xi^power t(xi) dxi` of one term `t` (its coefficient and power included).
pub(crate) fn term_moment(t: &Term, power: u32, (a, b): (&Real, &Real), roots: &RootTable) -> Real {
    let z = Complex {
        re: roots.rate(t.exp),
        im: t.trig.map_or(Real::zero(), |(_, n)| roots.beta[n].clone()),
    };
    let j = j_between(power + t.power, &z, (a, b));
    let part = match t.trig {
        Some((Trig::Sin, _)) => j.im,
        _ => j.re,
    };
    &t.coef * &part
}

/// The integrals of one section over its local basis (dimensionless; the symbolic layer adds
/// the length powers and parameters): `mass = int f_a f_b`, `bending = int f_a'' f_b''`,
/// `axial = int f_a' f_b'`, `axial_x = int xi f_a' f_b'`, with `' = d/dxi`.
#[derive(Debug, Clone)]
pub struct SectionIntegrals {
    /// `int_0^1 f_a f_b dxi`.
    pub mass: Vec<Vec<Real>>,
    /// `int_0^1 f_a'' f_b'' dxi`.
    pub bending: Vec<Vec<Real>>,
    /// `int_0^1 f_a' f_b' dxi`.
    pub axial: Vec<Vec<Real>>,
    /// `int_0^1 xi f_a' f_b' dxi`.
    pub axial_x: Vec<Vec<Real>>,
}

impl SectionIntegrals {
    /// All four integrals for every pair of `basis` functions.
    pub fn new(basis: &[Func], roots: &RootTable) -> Self {
        let [mass, bending, axial, axial_x] = galerkin_tables(
            basis,
            |f| f.derivative(roots),
            |a, b, w| integrate_product(a, b, w, roots),
        );
        Self {
            mass,
            bending,
            axial,
            axial_x,
        }
    }
}

/// The four Galerkin tables of `functions` (`int f g`, `int f'' g''`, `int f' g'`,
/// `int xi f' g'` over `xi` in `[0, 1]`), each symmetric, from how to differentiate a
/// function and how to integrate a product weighted by `xi^w`.
pub fn galerkin_tables<F>(
    functions: &[F],
    derivative: impl Fn(&F) -> F,
    integrate: impl Fn(&F, &F, u32) -> Real,
) -> [Vec<Vec<Real>>; 4] {
    let d1: Vec<F> = functions.iter().map(&derivative).collect();
    let d2: Vec<F> = d1.iter().map(&derivative).collect();
    let table = |fs: &[F], w: u32| {
        let n = fs.len();
        let mut m = vec![vec![Real::zero(); n]; n];
        for a in 0..n {
            for b in a..n {
                let v = integrate(&fs[a], &fs[b], w);
                m[b][a] = v.clone();
                m[a][b] = v;
            }
        }
        m
    };
    [
        table(functions, 0),
        table(&d2, 0),
        table(&d1, 0),
        table(&d1, 1),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn closed_forms_of_simple_integrals() {
        let roots = RootTable::new(Kind::FreeFree, 6);
        // int_0^1 xi^2 = 1/3
        let x = Func::paper_mode(Kind::FreeFree, 2, &roots);
        assert!((integrate_product(&x, &x, 0, &roots).to_f64() - 1.0 / 3.0).abs() < 1e-16);
        // the free-free normalisation: int phi^2 = 1 (in xi), int phi''^2 = beta^4
        for i in 3..=6 {
            let f = Func::paper_mode(Kind::FreeFree, i, &roots);
            let d2 = f.derivative(&roots).derivative(&roots);
            let b = roots.beta[i - 1].to_f64();
            assert!((integrate_product(&f, &f, 0, &roots).to_f64() - 1.0).abs() < 1e-15);
            assert!(
                (integrate_product(&d2, &d2, 0, &roots).to_f64() / b.powi(4) - 1.0).abs() < 1e-15
            );
            // orthogonal to the rigid modes, exactly up to round-off of 512 bits
            assert!(integrate_product(&f, &x, 0, &roots).abs() < Real::from_f64(1e-60));
        }
    }
}
