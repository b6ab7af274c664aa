//! High-precision reals (512 bits, about 154 significant digits) for the numeric factors of
//! the emitted equations: mode roots and the closed-form Galerkin integrals, whose
//! `e^(2 beta)` terms (up to 1e78 at mode 30) cancel to O(1) and would leave nothing of an
//! `f64`. Results are rounded once, to the nearest `f64`, when emitted.
//!
//! A thin wrapper over `astro-float` (the arbitrary-precision crate Symbolica's own floats
//! build on here): the operators it lacks, at one fixed precision.

use astro_float::{BigFloat, Consts, Radix, RoundingMode};
use std::cell::RefCell;
use std::cmp::Ordering;
use std::ops::{Add, Div, Mul, Neg, Sub};

/// Working precision in bits.
pub const PRECISION: usize = 512;
const RM: RoundingMode = RoundingMode::ToEven;

thread_local! {
    static CONSTS: RefCell<Consts> = RefCell::new(Consts::new().expect("astro-float constants cache"));
}

/// A real number with [`PRECISION`] bits.
#[derive(Debug, Clone)]
pub struct Real(BigFloat);

impl Real {
    /// Exact conversion of an `f64`.
    pub fn from_f64(v: f64) -> Self {
        Real(BigFloat::from_f64(v, PRECISION))
    }

    /// An integer.
    pub fn int(v: i64) -> Self {
        Real(BigFloat::from_i64(v, PRECISION))
    }

    /// Zero.
    pub fn zero() -> Self {
        Self::int(0)
    }

    /// The nearest `f64` (correctly rounded: the decimal expansion carries ~154 digits and
    /// Rust's parser rounds correctly).
    pub fn to_f64(&self) -> f64 {
        if self.0.is_zero() {
            return 0.0;
        }
        let s = CONSTS
            .with(|c| self.0.format(Radix::Dec, RM, &mut c.borrow_mut()))
            .expect("format a finite real");
        s.parse().unwrap_or_else(|_| panic!("cannot read back {s}"))
    }

    fn unary(&self, f: impl FnOnce(&BigFloat, &mut Consts) -> BigFloat) -> Self {
        CONSTS.with(|c| Real(f(&self.0, &mut c.borrow_mut())))
    }

    /// `e^x`.
    pub fn exp(&self) -> Self {
        self.unary(|x, c| x.exp(PRECISION, RM, c))
    }

    /// `sin x`.
    pub fn sin(&self) -> Self {
        self.unary(|x, c| x.sin(PRECISION, RM, c))
    }

    /// `cos x`.
    pub fn cos(&self) -> Self {
        self.unary(|x, c| x.cos(PRECISION, RM, c))
    }

    /// `cosh x`.
    pub fn cosh(&self) -> Self {
        self.unary(|x, c| x.cosh(PRECISION, RM, c))
    }

    /// `sinh x`.
    pub fn sinh(&self) -> Self {
        self.unary(|x, c| x.sinh(PRECISION, RM, c))
    }

    /// `sqrt x`.
    pub fn sqrt(&self) -> Self {
        Real(self.0.sqrt(PRECISION, RM))
    }

    /// `|x|`.
    pub fn abs(&self) -> Self {
        Real(self.0.abs())
    }

    /// True for exactly zero.
    pub fn is_zero(&self) -> bool {
        self.0.is_zero()
    }
}

impl Add for &Real {
    type Output = Real;
    fn add(self, o: &Real) -> Real {
        Real(self.0.add(&o.0, PRECISION, RM))
    }
}

impl Sub for &Real {
    type Output = Real;
    fn sub(self, o: &Real) -> Real {
        Real(self.0.sub(&o.0, PRECISION, RM))
    }
}

impl Mul for &Real {
    type Output = Real;
    fn mul(self, o: &Real) -> Real {
        Real(self.0.mul(&o.0, PRECISION, RM))
    }
}

impl Div for &Real {
    type Output = Real;
    fn div(self, o: &Real) -> Real {
        Real(self.0.div(&o.0, PRECISION, RM))
    }
}

impl Neg for &Real {
    type Output = Real;
    fn neg(self) -> Real {
        Real(-self.0.clone())
    }
}

impl PartialEq for Real {
    fn eq(&self, o: &Self) -> bool {
        self.0.partial_cmp(&o.0) == Some(Ordering::Equal)
    }
}

impl PartialOrd for Real {
    fn partial_cmp(&self, o: &Self) -> Option<Ordering> {
        self.0.partial_cmp(&o.0)
    }
}

/// Which characteristic equation a section's elastic modes solve (docs/model.md section 4).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Kind {
    /// Section 1: `tan b + tanh b = 0`.
    GuidedFree,
    /// Sections `k >= 2`: `cos b cosh b = 1`.
    FreeFree,
}

/// The root `beta_i` of mode `i` (1-based) to [`PRECISION`] bits: bracketed Newton in
/// `f64` for a start, then Newton in high precision (quadratic: 6 steps are plenty).
/// Rigid modes give 0.
pub fn mode_root(kind: Kind, i: usize) -> Real {
    use std::f64::consts::PI;
    let start = match kind {
        Kind::GuidedFree if i == 1 => return Real::zero(),
        Kind::FreeFree if i <= 2 => return Real::zero(),
        // tan b = -tanh b ~ -1: b ~ (i - 1.25) pi; cos b cosh b = 1: b ~ (i - 1.5) pi
        Kind::GuidedFree => (i as f64 - 1.25) * PI,
        Kind::FreeFree => (i as f64 - 1.5) * PI,
    };
    let mut b = Real::from_f64(start);
    for _ in 0..40 {
        let (s, c, sh, ch) = (b.sin(), b.cos(), b.sinh(), b.cosh());
        let (g, dg) = match kind {
            // sin b cosh b + cos b sinh b = 0; derivative 2 cos b cosh b
            Kind::GuidedFree => (&(&s * &ch) + &(&c * &sh), &(&Real::int(2) * &c) * &ch),
            // cos b cosh b - 1 = 0; derivative cos b sinh b - sin b cosh b
            Kind::FreeFree => (&(&c * &ch) - &Real::int(1), &(&c * &sh) - &(&s * &ch)),
        };
        let step = &g / &dg;
        b = &b - &step;
        // converged to the working precision (the f64 start is within 1e-3, so quadratic
        // convergence is reached at once)
        if step.abs() < Real::from_f64(1e-140) {
            break;
        }
    }
    b
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn roots_solve_their_equations_to_working_precision() {
        for i in 2..=30 {
            let b = mode_root(Kind::GuidedFree, i);
            let r = &(&b.sin() * &b.cosh()) + &(&b.cos() * &b.sinh());
            assert!(
                (&r / &b.cosh()).abs() < Real::from_f64(1e-140),
                "guided-free {i}"
            );
        }
        for i in 3..=30 {
            let b = mode_root(Kind::FreeFree, i);
            let r = &(&b.cos() * &b.cosh()) - &Real::int(1);
            assert!(
                (&r / &b.cosh()).abs() < Real::from_f64(1e-140),
                "free-free {i}"
            );
        }
        assert!((mode_root(Kind::GuidedFree, 2).to_f64() - 2.365020372431352).abs() < 1e-15);
        assert!((mode_root(Kind::FreeFree, 3).to_f64() - 4.730040744862704).abs() < 1e-15);
    }
}
