//! Gauss-Legendre quadrature on a section `[0, l]` (nodes and weights from `gauss-quad`,
//! which uses Bogaert's method: accurate to round-off for any order).
//!
//! **How many points.** Every Galerkin integrand of docs/model.md section 4 is a product of two
//! shape functions (or derivatives) and at most a linear factor: an entire function whose
//! terms on the reference interval `t in [-1, 1]` (`x = l (t + 1)/2`) are `e^(+-w t)`,
//! `cos(w t)`, `sin(w t)` with `w <= (beta_i + beta_j)/2 <= beta_max`, times a polynomial of
//! degree <= 3. For such a term an `n`-point rule errs by about `(e w / (4 n))^(2 n)`
//! relative. With `n = ceil(beta_max) + 16`, that is below `1e-50` for mode 30
//! (`beta = 90.3`, `n = 107`) and below `1e-25` for the lowest modes: far below round-off, so
//! the quadrature is exact to round-off for every supported mode.
//! `tests/quadrature.rs` checks this by comparing with twice the points.

use gauss_quad::legendre::GaussLegendre;
use std::num::NonZeroUsize;

/// Nodes (m) and weights (m) of a Gauss-Legendre rule on `[0, l]`.
#[derive(Debug, Clone, PartialEq)]
pub struct SectionQuadrature {
    /// Quadrature nodes `x` in `(0, l)` (m).
    pub nodes: Vec<f64>,
    /// Weights (m); they sum to `l`.
    pub weights: Vec<f64>,
}

impl SectionQuadrature {
    /// Number of points that integrates products of modes up to root `beta_max` exactly to
    /// round-off (see the module documentation).
    pub fn points_for(beta_max: f64) -> usize {
        beta_max.ceil() as usize + 16
    }

    /// A rule with `points` nodes on `[0, length]`.
    ///
    /// # Panics
    /// If `points == 0`.
    pub fn with_points(length: f64, points: usize) -> Self {
        let rule = GaussLegendre::new(NonZeroUsize::new(points).expect("at least one point"));
        let (nodes, weights) = rule
            .iter()
            .map(|(t, w)| (0.5 * length * (t + 1.0), 0.5 * length * w))
            .unzip();
        Self { nodes, weights }
    }

    /// The rule of [`SectionQuadrature::points_for`] for `beta_max` on `[0, length]`.
    pub fn for_modes(length: f64, beta_max: f64) -> Self {
        Self::with_points(length, Self::points_for(beta_max))
    }

    /// The rule of [`SectionQuadrature::for_modes`] on each piece of `[0, length]` cut at
    /// `breaks` (m, inside, ascending): exact to round-off for products of modes with
    /// functions that are polynomials of degree <= 3 between the breaks (the static
    /// correction shapes of [`crate::shape::spline`]). Without breaks, the plain rule.
    pub fn split_at(length: f64, beta_max: f64, breaks: &[f64]) -> Self {
        let mut edges = vec![0.0];
        edges.extend_from_slice(breaks);
        edges.push(length);
        let points = Self::points_for(beta_max);
        let mut rule = Self {
            nodes: Vec::new(),
            weights: Vec::new(),
        };
        for pair in edges.windows(2) {
            let piece = Self::with_points(pair[1] - pair[0], points);
            rule.nodes.extend(piece.nodes.iter().map(|x| pair[0] + x));
            rule.weights.extend(piece.weights);
        }
        rule
    }

    /// `int_0^l f(x) dx`.
    pub fn integrate(&self, mut f: impl FnMut(f64) -> f64) -> f64 {
        self.nodes
            .iter()
            .zip(&self.weights)
            .map(|(&x, &w)| w * f(x))
            .sum()
    }
}
