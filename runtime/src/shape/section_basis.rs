//! The functions of one section in computing coordinates ([`crate::model`]): the unit
//! translation (global index 0), the section's modes, and for [`Basis::ModesAndStatic`] its
//! static correction shapes ([`crate::shape::spline`]).
//!
//! The correction shapes are smooth between their knots, so as a section gets more modes
//! they lie ever closer to the modes' span: raw B-splines beside 10 modes gave adams-linear a
//! mass matrix of condition 1e13, and eigenvalues and steps lost their digits. Each section
//! therefore carries, instead of the B-splines, their parts orthogonal to its modes,
//! orthonormal among themselves in `int_0^1 f g dxi` (`xi = x / l`): the Householder QR of
//! the functions' values at the quadrature points (weighted by the square roots of the
//! weights over `l`) gives `R`, its rows signed for a positive diagonal (the Gram matrix's
//! Cholesky factor), and the last columns of `R^-1` say how each coordinate function
//! combines the modes and B-splines. The generator derives the same functions exactly. The
//! span, and so the Ritz solution, is the same; the modes' own coordinates are untouched.

use crate::model::params::correction_knots;
use crate::model::params::{Basis, ModelParams, SectionParams};
use crate::model::quadrature::SectionQuadrature;
use crate::shape::spline::{CubicBSpline, correction_shapes};
use crate::shape::{MAX_MODES, SectionKind, SectionShapes, ShapeFunction};
use nalgebra::DMatrix;

/// Most coordinates of one section: [`MAX_MODES`] modes and up to 18 static correction shapes.
pub const MAX_SECTION_COORDINATES: usize = MAX_MODES + 18;

/// A function the section's coordinate functions are made of.
#[derive(Debug, Clone, Copy)]
pub(crate) enum LocalBasis {
    /// The unit translation (value 1, derivatives 0).
    Translation,
    /// `phi(x) - shift`.
    Shape(ShapeFunction, f64),
    /// A cubic B-spline.
    Spline(CubicBSpline),
}

impl LocalBasis {
    #[inline]
    fn eval(&self, x: f64, deriv: u8) -> f64 {
        match self {
            LocalBasis::Translation => f64::from(u8::from(deriv == 0)),
            LocalBasis::Shape(f, shift) if deriv == 0 => f.eval(x, 0) - shift,
            LocalBasis::Shape(f, _) => f.eval(x, deriv),
            LocalBasis::Spline(b) => b.eval(x, deriv),
        }
    }
}

/// One section's coordinate functions and their global indices.
#[derive(Debug, Clone)]
pub(crate) struct SectionBasis {
    /// Global index of each coordinate function: the translation (0) first.
    indices: Vec<usize>,
    /// The functions: the translation, the modes, then the B-splines.
    primitives: Vec<LocalBasis>,
    /// Number of leading functions that are coordinate functions as they are.
    direct: usize,
    /// Column `e`: correction `e` as a combination of `primitives[1..]`.
    corrections: Option<DMatrix<f64>>,
}

impl SectionBasis {
    /// Section `k`'s functions, with its modes at global indices `offset + i - 1` (section 1's
    /// first mode is the translation) and its corrections after them; `quad` the section's
    /// quadrature rule (for the orthogonalization).
    ///
    /// # Errors
    /// A message when a correction shape lies within rounding of the modes' span.
    pub(crate) fn new(
        params: &ModelParams,
        k: usize,
        offset: usize,
        quad: &SectionQuadrature,
    ) -> Result<Self, String> {
        let sec = &params.sections[k - 1];
        let shapes = SectionShapes::new(SectionKind::of_section(k), sec.modes, sec.length);
        let mut indices = vec![0];
        let mut primitives = vec![LocalBasis::Translation];
        for f in shapes.functions() {
            match (k, f.index()) {
                (1, 1) => {} // section 1's rigid mode is the translation, index 0
                (1, i) => {
                    indices.push(offset + i - 1);
                    primitives.push(LocalBasis::Shape(*f, f.eval(0.0, 0)));
                }
                (_, i) => {
                    indices.push(offset + i - 1);
                    primitives.push(LocalBasis::Shape(*f, 0.0));
                }
            }
        }
        let direct = primitives.len();
        let mut basis = SectionBasis {
            indices,
            primitives,
            direct,
            corrections: None,
        };
        if params.basis == Basis::ModesAndStatic {
            let splines = correction_shapes(sec.length, &correction_knots(params, k));
            for (e, b) in splines.into_iter().enumerate() {
                basis.indices.push(offset + sec.modes + e);
                basis.primitives.push(LocalBasis::Spline(b));
            }
            basis.corrections = Some(basis.orthogonalized(quad, k, sec.length)?);
        }
        Ok(basis)
    }

    /// The paper's modes of a section alone, as they are (no translation, no shift).
    pub(crate) fn paper_modes(section: &SectionParams, kind: SectionKind) -> Self {
        let shapes = SectionShapes::new(kind, section.modes, section.length);
        let primitives: Vec<_> = shapes
            .functions()
            .iter()
            .map(|&f| LocalBasis::Shape(f, 0.0))
            .collect();
        SectionBasis {
            indices: (0..primitives.len()).collect(),
            direct: primitives.len(),
            primitives,
            corrections: None,
        }
    }

    /// The corrections' combinations of `primitives[1..]` (see the module documentation).
    fn orthogonalized(
        &self,
        quad: &SectionQuadrature,
        k: usize,
        length: f64,
    ) -> Result<DMatrix<f64>, String> {
        let own = self.primitives.len() - 1;
        // the inner product of xi = x / l (weights over the length): the corrections are then
        // functions of xi alone, as the generator derives them
        let values = DMatrix::from_fn(quad.nodes.len(), own, |q, j| {
            (quad.weights[q] / length).sqrt() * self.primitives[j + 1].eval(quad.nodes[q], 0)
        });
        // R with a positive diagonal (the Cholesky factor of the Gram matrix), so that each
        // correction is the one the generator's Gram-Schmidt gives, sign included
        let mut r = values.qr().r();
        for (i, mut row) in r.row_iter_mut().enumerate() {
            if row[i] < 0.0 {
                row.neg_mut();
            }
        }
        let largest = r.diagonal().amax();
        let first = self.direct - 1;
        if let Some(e) = (first..own).find(|&e| r[(e, e)].abs() <= 1e-12 * largest) {
            return Err(format!(
                "section {k}: static correction shape {} lies within rounding of the span of \
                 the modes and the other shapes; give the section fewer modes",
                e + 1 - first
            ));
        }
        let inverse = r
            .solve_upper_triangular(&DMatrix::identity(own, own))
            .expect("checked nonsingular");
        Ok(inverse.columns(first, own - first).into_owned())
    }

    /// Number of coordinate functions (the translation included).
    pub(crate) fn len(&self) -> usize {
        self.indices.len()
    }

    /// Global index of each coordinate function.
    pub(crate) fn indices(&self) -> &[usize] {
        &self.indices
    }

    /// The coordinate functions' values (`deriv = 0`), slopes (1) or curvatures (2) at `x`
    /// (m) into `out[..len]`; allocation-free.
    #[inline]
    pub(crate) fn values(&self, x: f64, deriv: u8, out: &mut [f64]) {
        match &self.corrections {
            None => {
                for (o, b) in out.iter_mut().zip(&self.primitives) {
                    *o = b.eval(x, deriv);
                }
            }
            Some(c) => {
                let mut raw = [0.0; MAX_SECTION_COORDINATES + 1];
                for (r, b) in raw.iter_mut().zip(&self.primitives) {
                    *r = b.eval(x, deriv);
                }
                out[..self.direct].copy_from_slice(&raw[..self.direct]);
                for (e, column) in c.column_iter().enumerate() {
                    out[self.direct + e] = column
                        .iter()
                        .zip(&raw[1..self.primitives.len()])
                        .map(|(a, b)| a * b)
                        .sum();
                }
            }
        }
    }

    /// `sum_j z[index_j] psi_j(x)` (`deriv`-th derivative).
    pub(crate) fn combine(&self, x: f64, deriv: u8, z: &[f64]) -> f64 {
        let mut v = [0.0; MAX_SECTION_COORDINATES + 1];
        self.values(x, deriv, &mut v);
        self.indices.iter().zip(&v).map(|(&j, a)| z[j] * a).sum()
    }

    /// `int rhoA psi_a psi_b` and `int (EI psi_a'' psi_b'' - P psi_a' psi_b')` over the
    /// section by `quad`, `prestress = (p0, p1)` giving `P(x) = p0 + p1 x` (N).
    pub(crate) fn integrals(
        &self,
        section: &SectionParams,
        quad: &SectionQuadrature,
        prestress: (f64, f64),
    ) -> (DMatrix<f64>, DMatrix<f64>) {
        let m = self.len();
        let mut mass = DMatrix::zeros(m, m);
        let mut stiff = DMatrix::zeros(m, m);
        let (mut v, mut d1, mut d2) = (vec![0.0; m], vec![0.0; m], vec![0.0; m]);
        for (&x, &w) in quad.nodes.iter().zip(&quad.weights) {
            self.values(x, 0, &mut v);
            self.values(x, 1, &mut d1);
            self.values(x, 2, &mut d2);
            let rho_a = w * section.mass_per_length;
            let ei = w * section.bending_stiffness;
            let p = w * (prestress.0 + prestress.1 * x);
            for a in 0..m {
                for b in 0..m {
                    mass[(a, b)] += rho_a * v[a] * v[b];
                    stiff[(a, b)] += ei * d2[a] * d2[b] - p * d1[a] * d1[b];
                }
            }
        }
        (mass, stiff)
    }
}
