//! Shape functions in `f64` (cancellation-free forms) against the printed forms evaluated
//! with 512-bit floats (about 154 significant digits; the printed forms cancel at most
//! ~40 of them at mode 30), roots included: Newton in 512 bits from the `f64` root.

use astro_float::{BigFloat, Consts, Radix, RoundingMode};
use telescopic_runtime::shape::{MAX_MODES, SectionKind, ShapeFunction};

const P: usize = 512;
const RM: RoundingMode = RoundingMode::ToEven;

struct Hp {
    cc: Consts,
}

impl Hp {
    fn new() -> Self {
        Self {
            cc: Consts::new().expect("constants cache"),
        }
    }
    fn num(&self, v: f64) -> BigFloat {
        BigFloat::from_f64(v, P)
    }
    fn as_f64(&mut self, v: &BigFloat) -> f64 {
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
    fn root(&mut self, kind: SectionKind, beta0: f64) -> BigFloat {
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
    fn printed(&mut self, kind: SectionKind, beta: &BigFloat, l: f64, x: f64, deriv: u8) -> f64 {
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

/// Error measure: relative to the value, or to the amplitude `lam^d` of the d-th derivative
/// where the value passes through zero (pointwise relative error at a zero is undefined for
/// any floating-point evaluation: `x` itself carries a rounding error).
fn scaled_error(ours: f64, exact: f64, lam: f64, deriv: u8) -> f64 {
    (ours - exact).abs() / exact.abs().max(lam.powi(deriv as i32))
}

#[test]
fn cancellation_free_forms_are_accurate_to_1e_12_up_to_mode_30() {
    let mut hp = Hp::new();
    let l = 1.35;
    let mut worst: f64 = 0.0;
    let mut worst_printed_high: f64 = 0.0;
    for kind in [SectionKind::GuidedFree, SectionKind::FreeFree] {
        let first_elastic = if kind == SectionKind::GuidedFree {
            2
        } else {
            3
        };
        for i in first_elastic..=MAX_MODES {
            let f = ShapeFunction::new(kind, i, l);
            let beta = hp.root(kind, f.beta());
            // the f64 root is the correctly rounded one (within an ulp)
            let beta_f64 = hp.as_f64(&beta);
            assert!(
                (f.beta() - beta_f64).abs() <= 2.0 * f64::EPSILON * beta_f64,
                "{kind:?} root {i}: {} vs {beta_f64}",
                f.beta()
            );
            for frac in [0.0, 0.1, 0.37, 0.5, 0.77, 0.93, 1.0] {
                let x = frac * l;
                for d in 0..=3u8 {
                    let exact = hp.printed(kind, &beta, l, x, d);
                    let err = scaled_error(f.eval(x, d), exact, f.wavenumber(), d);
                    assert!(
                        err <= 1e-12,
                        "{kind:?} mode {i} x = {x} d = {d}: error {err:e}"
                    );
                    worst = worst.max(err);
                    if i >= 20 {
                        worst_printed_high = worst_printed_high.max(scaled_error(
                            f.eval_printed(x, d),
                            exact,
                            f.wavenumber(),
                            d,
                        ));
                    }
                }
            }
        }
    }
    eprintln!(
        "worst scaled error, cancellation-free: {worst:e}; printed form, modes 20..30: {worst_printed_high:e}"
    );
    // the printed form is not usable there: it loses far more than half the digits
    assert!(
        worst_printed_high > 1e-6,
        "printed form unexpectedly accurate: {worst_printed_high:e}"
    );
}
