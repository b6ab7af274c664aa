//! The printed shape functions (paper eqs. 16, 17) evaluated with 512-bit floats (about 154
//! significant digits; the printed forms cancel at most ~40 of them at mode 30), roots
//! included: Newton in 512 bits from the `f64` root. The reference against which the
//! `f64` forms of [`crate::shape`] are measured (feature `reference`).

use crate::shape::{SectionKind, ShapeFunction};
use astro_float::{BigFloat, Consts, Radix, RoundingMode};

const P: usize = 512;
const RM: RoundingMode = RoundingMode::ToEven;

/// 512-bit evaluation of the printed forms (keeps a constants cache).
pub struct Hp {
    cc: Consts,
}

impl Hp {
    /// A new evaluator.
    pub fn new() -> Self {
        Self {
            cc: Consts::new().expect("constants cache"),
        }
    }
    fn num(&self, v: f64) -> BigFloat {
        BigFloat::from_f64(v, P)
    }
    /// `v` rounded to `f64`.
    pub fn as_f64(&mut self, v: &BigFloat) -> f64 {
        let s = v.format(Radix::Dec, RM, &mut self.cc).expect("format");
        s.parse().unwrap_or_else(|_| panic!("cannot parse {s}"))
    }
    fn sin(&mut self, v: &BigFloat) -> BigFloat {
        v.sin(P, RM, &mut self.cc)
    }
    fn cos(&mut self, v: &BigFloat) -> BigFloat {
        v.cos(P, RM, &mut self.cc)
    }
    fn sinh(&mut self, v: &BigFloat) -> BigFloat {
        v.sinh(P, RM, &mut self.cc)
    }
    fn cosh(&mut self, v: &BigFloat) -> BigFloat {
        v.cosh(P, RM, &mut self.cc)
    }

    /// The root in 512 bits: Newton from the f64 root on the characteristic equation.
    pub fn root(&mut self, kind: SectionKind, beta0: f64) -> BigFloat {
        let mut b = self.num(beta0);
        for _ in 0..12 {
            let (s, c, sh, ch) = (self.sin(&b), self.cos(&b), self.sinh(&b), self.cosh(&b));
            let (g, dg) = match kind {
                // sin b cosh b + cos b sinh b = 0
                SectionKind::GuidedFree => (
                    s.mul(&ch, P, RM).add(&c.mul(&sh, P, RM), P, RM),
                    self.num(2.0).mul(&c, P, RM).mul(&ch, P, RM),
                ),
                // cos b cosh b - 1 = 0
                SectionKind::FreeFree => (
                    c.mul(&ch, P, RM).sub(&self.num(1.0), P, RM),
                    c.mul(&sh, P, RM).sub(&s.mul(&ch, P, RM), P, RM),
                ),
            };
            b = b.sub(&g.div(&dg, P, RM), P, RM);
        }
        b
    }

    /// The printed form (paper eqs. 16, 17) and its derivatives, times lam^deriv.
    pub fn printed(
        &mut self,
        kind: SectionKind,
        beta: &BigFloat,
        l: f64,
        x: f64,
        deriv: u8,
    ) -> f64 {
        let lam = beta.div(&self.num(l), P, RM);
        let y = lam.mul(&self.num(x), P, RM);
        let (s, c, sh, ch) = (self.sin(&y), self.cos(&y), self.sinh(&y), self.cosh(&y));
        let v = match kind {
            SectionKind::GuidedFree => {
                let k = self.cos(beta).div(&self.cosh(beta), P, RM);
                let (trig, hyp) = match deriv {
                    0 => (c.clone(), ch),
                    1 => (s.neg(), sh),
                    2 => (c.neg(), ch),
                    _ => (s.clone(), sh),
                };
                trig.add(&k.mul(&hyp, P, RM), P, RM)
            }
            SectionKind::FreeFree => {
                let num = self.cosh(beta).sub(&self.cos(beta), P, RM);
                let den = self.sinh(beta).sub(&self.sin(beta), P, RM);
                let sigma = num.div(&den, P, RM);
                let (a, b) = match deriv {
                    0 => (ch.add(&c, P, RM), sh.add(&s, P, RM)),
                    1 => (sh.sub(&s, P, RM), ch.add(&c, P, RM)),
                    2 => (ch.sub(&c, P, RM), sh.sub(&s, P, RM)),
                    _ => (sh.add(&s, P, RM), ch.sub(&c, P, RM)),
                };
                a.sub(&sigma.mul(&b, P, RM), P, RM)
            }
        };
        let mut scaled = v;
        for _ in 0..deriv {
            scaled = scaled.mul(&lam, P, RM);
        }
        self.as_f64(&scaled)
    }
}

impl Default for Hp {
    fn default() -> Self {
        Self::new()
    }
}

/// Error measure: relative to the value, or to the amplitude `lam^d` of the d-th derivative
/// where the value passes through zero (pointwise relative error at a zero is undefined for
/// any floating-point evaluation: `x` itself carries a rounding error).
pub fn scaled_error(ours: f64, exact: f64, lam: f64, deriv: u8) -> f64 {
    (ours - exact).abs() / exact.abs().max(lam.powi(deriv as i32))
}

/// Worst scaled error of the cancellation-free and of the printed `f64` form of mode `i`
/// on a section of length `l` (m), over `points` positions and derivatives 0 to 3:
/// `(cancellation_free, printed)`.
pub fn evaluation_errors(
    hp: &mut Hp,
    kind: SectionKind,
    i: usize,
    l: f64,
    points: usize,
) -> (f64, f64) {
    let f = ShapeFunction::new(kind, i, l);
    let beta = hp.root(kind, f.beta());
    let (mut free, mut printed) = (0.0f64, 0.0f64);
    for p in 0..points {
        let x = l * p as f64 / (points - 1) as f64;
        for d in 0..=3u8 {
            let exact = hp.printed(kind, &beta, l, x, d);
            free = free.max(scaled_error(f.eval(x, d), exact, f.wavenumber(), d));
            printed = printed.max(scaled_error(f.eval_printed(x, d), exact, f.wavenumber(), d));
        }
    }
    (free, printed)
}
