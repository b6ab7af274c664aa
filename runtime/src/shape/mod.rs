//! The paper's shape functions (docs/model.md section 4) and the roots of their characteristic
//! equations, evaluated in cancellation-free forms.
//!
//! Normalisation is the paper's printed one:
//!
//! * section 1, "transversally movable - free":
//!   `phi_i(x) = cos(lam_i x) + cos(beta_i)/cosh(beta_i) cosh(lam_i x)`, `beta_i = lam_i l`,
//!   roots of `tan(beta) + tanh(beta) = 0`; `beta_1 = 0` gives the constant 2;
//! * sections `k >= 2`, "free-free": `phi_1 = 1`, `phi_2 = x`, and for `i >= 3`
//!   `phi_i(x) = cosh(kap x) + cos(kap x) - sigma (sinh(kap x) + sin(kap x))`,
//!   `sigma = (cosh(kap l) - cos(kap l)) / (sinh(kap l) - sin(kap l))`, roots of
//!   `cos(beta) cosh(beta) = 1`.
//!
//! The printed forms add hyperbolic terms of size `e^beta` that cancel to O(1); from about
//! the 10th mode on they lose most of their digits in floating point. Here every hyperbolic
//! term is rewritten with exponentials of non-positive argument only (derivation in the
//! comments of [`ShapeFunction::eval`]), which is algebraically equal and loses nothing.

#[cfg(feature = "reference")]
pub mod reference;
pub(crate) mod section_basis;
pub mod spline;

use std::f64::consts::PI;

pub use telescopic_config::MAX_MODES;

/// Which boundary-value problem a section's shape functions come from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum SectionKind {
    /// Section 1: slope zero and shear zero at the foot (it translates with the vehicle),
    /// free at the top.
    GuidedFree,
    /// Sections `k >= 2`: free at both ends.
    FreeFree,
}

impl SectionKind {
    /// The kind of section `k` (1-based).
    pub fn of_section(k: usize) -> Self {
        if k == 1 {
            Self::GuidedFree
        } else {
            Self::FreeFree
        }
    }
}

/// Dimensionless root `beta_i = lam_i l` of mode `i` (1-based) of the given section kind.
///
/// `GuidedFree`: `beta_1 = 0`, then the roots of `tan(beta) + tanh(beta) = 0`
/// (2.36502, 5.49780, ...). `FreeFree`: modes 1 and 2 are the rigid modes (`beta = 0`), then the
/// roots of `cos(beta) cosh(beta) = 1` (4.73004, 7.85320, ...).
///
/// # Panics
/// If `i == 0` (modes are numbered from 1).
pub fn mode_root(kind: SectionKind, i: usize) -> f64 {
    assert!(i >= 1, "mode indices start at 1");
    match kind {
        SectionKind::GuidedFree if i == 1 => 0.0,
        SectionKind::GuidedFree => {
            // tan(b) + tanh(b) = 0 multiplied by cos(b): g(b) = sin b + cos b tanh b. On
            // [(i-1.5) pi, (i-1) pi] g runs from sin = +-1 to -+tanh: exactly one root.
            let m = (i - 1) as f64;
            let g = |b: f64| {
                let (s, c) = b.sin_cos();
                let th = b.tanh();
                (s + c * th, c - s * th + c * (1.0 - th * th))
            };
            safeguarded_newton(g, (m - 0.5) * PI, m * PI, (m - 0.25) * PI)
        }
        SectionKind::FreeFree if i <= 2 => 0.0,
        SectionKind::FreeFree => {
            // cos(b) cosh(b) = 1 divided by cosh(b): g(b) = cos b - sech b, one root in
            // [m pi, (m+1) pi] near (m + 1/2) pi with m = i - 2.
            let m = (i - 2) as f64;
            let g = |b: f64| {
                let sech = 1.0 / b.cosh();
                (b.cos() - sech, -b.sin() + sech * b.tanh())
            };
            safeguarded_newton(g, m * PI, (m + 1.0) * PI, (m + 0.5) * PI)
        }
    }
}

/// Newton's method kept inside a sign-changing bracket (bisection when a step leaves it).
/// Hand-written: a 20-line root finder on a known bracket does not justify a dependency.
fn safeguarded_newton(g: impl Fn(f64) -> (f64, f64), mut lo: f64, mut hi: f64, start: f64) -> f64 {
    let g_lo = g(lo).0;
    let mut x = start;
    for _ in 0..200 {
        let (gx, dgx) = g(x);
        if gx == 0.0 {
            return x;
        }
        if (gx < 0.0) == (g_lo < 0.0) {
            lo = x
        } else {
            hi = x
        }
        let newton = x - gx / dgx;
        if newton == x {
            return x; // the step is below half an ulp: converged
        }
        let next = if newton >= lo && newton <= hi && dgx != 0.0 {
            newton
        } else {
            0.5 * (lo + hi)
        };
        if (next - x).abs() <= 2.0 * f64::EPSILON * x.abs() {
            return next;
        }
        x = next;
    }
    x
}

/// One shape function `phi_{k,i}` of a section of length `l`, with its constants computed
/// once. Evaluation is allocation-free.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShapeFunction {
    kind: SectionKind,
    index: usize,
    length: f64,
    beta: f64,
    /// Wavenumber `beta / l` (1/m).
    lambda: f64,
    /// `cos(beta)`, GuidedFree only.
    cos_beta: f64,
    /// FreeFree: `N / D` with `N = cos b - sin b - e^-b`, `D = 1 - e^-2b - 2 sin b e^-b`,
    /// so that `sigma = 1 - 2 e^-b N / D`.
    ratio: f64,
    /// FreeFree: `sigma` itself (close to 1, computed without cancellation).
    sigma: f64,
}

impl ShapeFunction {
    /// Shape function of mode `i` (1-based) of a section of kind `kind` and length `length` (m).
    ///
    /// # Panics
    /// If `i == 0` or `length` is not positive and finite.
    pub fn new(kind: SectionKind, i: usize, length: f64) -> Self {
        assert!(
            length > 0.0 && length.is_finite(),
            "section length must be positive"
        );
        let beta = mode_root(kind, i);
        let (s, c) = beta.sin_cos();
        let e = (-beta).exp();
        let (ratio, sigma) = if kind == SectionKind::FreeFree && i >= 3 {
            let n = c - s - e;
            let d = 1.0 - e * e - 2.0 * s * e;
            (n / d, 1.0 - 2.0 * e * n / d)
        } else {
            (0.0, 0.0)
        };
        Self {
            kind,
            index: i,
            length,
            beta,
            lambda: beta / length,
            cos_beta: c,
            ratio,
            sigma,
        }
    }

    /// Mode index `i` (1-based).
    pub fn index(&self) -> usize {
        self.index
    }

    /// Dimensionless root `beta = lam l`.
    pub fn beta(&self) -> f64 {
        self.beta
    }

    /// Wavenumber `lam = beta / l` (1/m).
    pub fn wavenumber(&self) -> f64 {
        self.lambda
    }

    /// Section length `l` (m).
    pub fn length(&self) -> f64 {
        self.length
    }

    /// `sigma` of a free-free elastic mode (0 for other modes).
    pub fn sigma(&self) -> f64 {
        self.sigma
    }

    /// The `deriv`-th derivative (0..=3) of the shape function at `x` (m), in m^-deriv.
    ///
    /// # Panics
    /// If `deriv > 3`.
    #[inline]
    pub fn eval(&self, x: f64, deriv: u8) -> f64 {
        assert!(
            deriv <= 3,
            "shape functions are evaluated up to the third derivative"
        );
        match self.kind {
            SectionKind::GuidedFree if self.index == 1 => {
                if deriv == 0 {
                    2.0
                } else {
                    0.0
                }
            }
            SectionKind::GuidedFree => self.eval_guided_free(x, deriv),
            SectionKind::FreeFree if self.index == 1 => {
                if deriv == 0 {
                    1.0
                } else {
                    0.0
                }
            }
            SectionKind::FreeFree if self.index == 2 => match deriv {
                0 => x,
                1 => 1.0,
                _ => 0.0,
            },
            SectionKind::FreeFree => self.eval_free_free(x, deriv),
        }
    }

    /// `cos y + cos(b) cosh(y)/cosh(b)` and derivatives, `y = lam x`. With
    /// `cosh y / cosh b = e^(y-b) (1 + e^-2y) / (1 + e^-2b)` and
    /// `sinh y / cosh b = -e^(y-b) expm1(-2y) / (1 + e^-2b)` no term exceeds 1 in size.
    fn eval_guided_free(&self, x: f64, deriv: u8) -> f64 {
        let y = self.lambda * x;
        let (s, c) = y.sin_cos();
        let scale = (y - self.beta).exp() / (1.0 + (-2.0 * self.beta).exp());
        let cosh_ratio = scale * (1.0 + (-2.0 * y).exp());
        let sinh_ratio = -scale * (-2.0 * y).exp_m1();
        let cb = self.cos_beta;
        let l = self.lambda;
        match deriv {
            0 => c + cb * cosh_ratio,
            1 => l * (-s + cb * sinh_ratio),
            2 => l * l * (-c + cb * cosh_ratio),
            _ => l * l * l * (s + cb * sinh_ratio),
        }
    }

    /// Free-free elastic mode, `y = kap x`. Writing `sigma = 1 - eps`,
    /// `eps = (cos b - sin b - e^-b) / (sinh b - sin b)`:
    /// `cosh y - sigma sinh y = e^-y + eps sinh y` and `sinh y - sigma cosh y = -e^-y + eps cosh y`,
    /// with `eps sinh y = (N/D) (e^(y-b) - e^(-y-b))` (`N`, `D` as in the struct): every
    /// exponential has a non-positive argument.
    fn eval_free_free(&self, x: f64, deriv: u8) -> f64 {
        let y = self.lambda * x;
        let (s, c) = y.sin_cos();
        let up = (y - self.beta).exp();
        let down = (-y - self.beta).exp();
        let em = (-y).exp();
        let hyp_c = em + self.ratio * (up - down); // cosh y - sigma sinh y
        let hyp_s = -em + self.ratio * (up + down); // sinh y - sigma cosh y
        let sg = self.sigma;
        let l = self.lambda;
        match deriv {
            0 => hyp_c + c - sg * s,
            1 => l * (hyp_s - s - sg * c),
            2 => l * l * (hyp_c - c + sg * s),
            _ => l * l * l * (hyp_s + s + sg * c),
        }
    }

    /// The printed form of the paper (eqs. 16, 17), evaluated literally in `f64`. Kept to show
    /// where it fails (it loses digits to cancellation from about mode 10 on); never used by
    /// the models.
    pub fn eval_printed(&self, x: f64, deriv: u8) -> f64 {
        let y = self.lambda * x;
        let l = self.lambda;
        let b = self.beta;
        match (self.kind, self.index) {
            (SectionKind::GuidedFree, 1) | (SectionKind::FreeFree, 1 | 2) => self.eval(x, deriv),
            (SectionKind::GuidedFree, _) => {
                let k = b.cos() / b.cosh();
                let v = match deriv {
                    0 => y.cos() + k * y.cosh(),
                    1 => -y.sin() + k * y.sinh(),
                    2 => -y.cos() + k * y.cosh(),
                    _ => y.sin() + k * y.sinh(),
                };
                v * l.powi(deriv as i32)
            }
            (SectionKind::FreeFree, _) => {
                let sigma = (b.cosh() - b.cos()) / (b.sinh() - b.sin());
                let v = match deriv {
                    0 => y.cosh() + y.cos() - sigma * (y.sinh() + y.sin()),
                    1 => y.sinh() - y.sin() - sigma * (y.cosh() + y.cos()),
                    2 => y.cosh() - y.cos() - sigma * (y.sinh() - y.sin()),
                    _ => y.sinh() + y.sin() - sigma * (y.cosh() - y.cos()),
                };
                v * l.powi(deriv as i32)
            }
        }
    }
}

/// The shape functions `phi_{k,1..=N}` of one section.
#[derive(Debug, Clone, PartialEq)]
pub struct SectionShapes {
    functions: Vec<ShapeFunction>,
}

impl SectionShapes {
    /// The first `modes` shape functions of a section of the given kind and length (m).
    pub fn new(kind: SectionKind, modes: usize, length: f64) -> Self {
        Self {
            functions: (1..=modes)
                .map(|i| ShapeFunction::new(kind, i, length))
                .collect(),
        }
    }

    /// The shape functions, mode 1 first.
    pub fn functions(&self) -> &[ShapeFunction] {
        &self.functions
    }

    /// Number of modes `N`.
    pub fn len(&self) -> usize {
        self.functions.len()
    }

    /// True when the section has no modes (never for a validated scene).
    pub fn is_empty(&self) -> bool {
        self.functions.is_empty()
    }

    /// Largest root `beta` among the modes (sets the quadrature order).
    pub fn max_beta(&self) -> f64 {
        self.functions.iter().map(|f| f.beta()).fold(0.0, f64::max)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn roots_match_the_papers_listed_digits() {
        let gf = [0.0, 2.36502, 5.49780, 8.63938, 11.78097];
        for (i, want) in gf.iter().enumerate() {
            assert!(
                (mode_root(SectionKind::GuidedFree, i + 1) - want).abs() < 6e-6,
                "guided-free {i}"
            );
        }
        let ff = [4.73004, 7.85320, 10.99561, 14.13717];
        for (i, want) in ff.iter().enumerate() {
            assert!(
                (mode_root(SectionKind::FreeFree, i + 3) - want).abs() < 6e-6,
                "free-free {i}"
            );
        }
    }

    #[test]
    fn roots_solve_their_characteristic_equations_and_approach_the_asymptotes() {
        for i in 2..=MAX_MODES {
            let b = mode_root(SectionKind::GuidedFree, i);
            // tan b + tanh b = 0 <=> sin b cosh b + cos b sinh b = 0; scaled by 1/cosh b.
            // residual of a correctly rounded root: a few ulps of beta times |g'| ~ 1.4
            assert!(
                (b.sin() + b.cos() * b.tanh()).abs() < 8.0 * f64::EPSILON * b,
                "mode {i}"
            );
            assert_relative_eq!(b, (i as f64 - 1.25) * PI, max_relative = 0.02);
        }
        for i in 3..=MAX_MODES {
            let b = mode_root(SectionKind::FreeFree, i);
            assert!(
                (b.cos() - 1.0 / b.cosh()).abs() < 8.0 * f64::EPSILON * b,
                "mode {i}"
            );
            assert_relative_eq!(b, (i as f64 - 1.5) * PI, max_relative = 0.01);
        }
    }

    #[test]
    fn boundary_conditions_hold() {
        let l = 1.35;
        for i in 1..=MAX_MODES {
            let f = ShapeFunction::new(SectionKind::GuidedFree, i, l);
            let s = f.wavenumber().powi(3).max(1.0);
            // slope and shear zero at the foot; moment and shear zero at the top
            assert!(f.eval(0.0, 1).abs() < 1e-12 * s, "mode {i}");
            assert!(f.eval(0.0, 3).abs() < 1e-12 * s, "mode {i}");
            assert!(f.eval(l, 2).abs() < 1e-12 * s, "mode {i}");
            assert!(f.eval(l, 3).abs() < 1e-12 * s, "mode {i}");
            let g = ShapeFunction::new(SectionKind::FreeFree, i, l);
            let s = g.wavenumber().powi(3).max(1.0);
            for x in [0.0, l] {
                assert!(g.eval(x, 2).abs() < 1e-12 * s, "mode {i}");
                assert!(g.eval(x, 3).abs() < 1e-12 * s, "mode {i}");
            }
        }
    }

    #[test]
    fn printed_form_agrees_for_low_modes() {
        let l = 1.35;
        for kind in [SectionKind::GuidedFree, SectionKind::FreeFree] {
            for i in 1..=5 {
                let f = ShapeFunction::new(kind, i, l);
                for x in [0.0, 0.3, 0.9, l] {
                    for d in 0..=3 {
                        let s = f.wavenumber().powi(d as i32).max(1.0);
                        // the printed form loses ~cosh(beta) ulps: 1e-9 is all it can promise by mode 5
                        assert!((f.eval(x, d) - f.eval_printed(x, d)).abs() < 1e-9 * s);
                    }
                }
            }
        }
    }
}
