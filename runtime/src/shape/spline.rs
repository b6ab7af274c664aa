//! Static correction shapes: the cubic B-splines that, added to a section's modes, hold its
//! static deflection under forces at its contact points exactly.
//!
//! A beam's static deflection under point forces is a cubic between the forces, with a jump
//! in its third derivative (the shear) at each of them and nonzero moment and shear where a
//! force acts at a free end. The paper's modes have zero moment and shear at free ends
//! (and section 1's zero shear at its foot), so their series converges slowly exactly there
//! (docs/numerics.md measures it). The cubic splines with knots at the contact stations hold
//! every such deflection: with the modes (which hold `1` and `x` on sections `k >= 2`) they
//! span it. Their B-spline basis is well conditioned however close two stations are (the
//! truncated powers `(x - x_s)^3_+` of the same span are not: their mass matrix reached a
//! condition number of 1e11 on adams-linear).
//!
//! The basis of a section: the clamped cubic B-splines on the knots `0, 0, 0, 0, x_1, ...,
//! x_m, l, l, l, l` (`x_i` the interior knots), without the first two, the only ones with a
//! value or a slope at the foot: the rest vanish there with their slope, as section 1's
//! relative coordinates require, and complement the rigid `1` and `x` on the other sections.
//! That is `m + 2` functions.

/// One cubic B-spline by its five knots (m), nondecreasing.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CubicBSpline {
    knots: [f64; 5],
    /// The section's top (m): the spline is closed on the right there.
    end: f64,
}

/// `a / b`, with the B-spline convention `0 / 0 = 0` for repeated knots.
fn ratio(a: f64, b: f64) -> f64 {
    if b == 0.0 { 0.0 } else { a / b }
}

impl CubicBSpline {
    /// The value (`deriv = 0`), slope (1) or curvature (2) at `x` (m), by the Cox-de Boor
    /// recursion on the five knots.
    pub fn eval(&self, x: f64, deriv: u8) -> f64 {
        let Some((n1, n2)) = self.lower_degrees(x) else {
            return 0.0;
        };
        match deriv {
            0 => self.step(x, &n2, 3, 0),
            1 => self.slope(&n2, 3, 0),
            _ => {
                let d2: [f64; 2] = std::array::from_fn(|j| self.slope(&n1, 2, j));
                self.slope(&d2, 3, 0)
            }
        }
    }

    /// The value and the slope at `x` (m), from one recursion.
    pub fn value_and_slope(&self, x: f64) -> (f64, f64) {
        match self.lower_degrees(x) {
            Some((_, n2)) => (self.step(x, &n2, 3, 0), self.slope(&n2, 3, 0)),
            None => (0.0, 0.0),
        }
    }

    /// The B-splines of degrees 1 and 2 on the knots' sub-ranges at `x`; `None` outside the
    /// support.
    fn lower_degrees(&self, x: f64) -> Option<([f64; 3], [f64; 2])> {
        let t = &self.knots;
        if x < t[0] || x > t[4] {
            return None;
        }
        // degree 0: the interval [t_j, t_j+1) holding x; closed at the section's top
        let n0: [f64; 4] = std::array::from_fn(|j| {
            let inside = (t[j] <= x && x < t[j + 1])
                || (x == self.end && t[j + 1] == self.end && t[j] < t[j + 1]);
            f64::from(u8::from(inside))
        });
        let n1: [f64; 3] = std::array::from_fn(|j| self.step(x, &n0, 1, j));
        let n2: [f64; 2] = std::array::from_fn(|j| self.step(x, &n1, 2, j));
        Some((n1, n2))
    }

    /// Degree `p` spline `j` at `x` from the two of degree `p - 1` below it.
    fn step(&self, x: f64, lower: &[f64], p: usize, j: usize) -> f64 {
        let t = &self.knots;
        ratio(x - t[j], t[j + p] - t[j]) * lower[j]
            + ratio(t[j + p + 1] - x, t[j + p + 1] - t[j + 1]) * lower[j + 1]
    }

    /// The derivative of degree `p` spline `j` from the two of degree `p - 1` below it.
    fn slope(&self, lower: &[f64], p: usize, j: usize) -> f64 {
        let t = &self.knots;
        p as f64 * (ratio(lower[j], t[j + p] - t[j]) - ratio(lower[j + 1], t[j + p + 1] - t[j + 1]))
    }

    /// Clamped B-spline `j` on the interior `knots` of a section ending at `end` (m): the
    /// knots `0, 0, 0, 0, knots.., end, end, end, end`, from index `j` on.
    fn clamped(knots: &[f64], end: f64, j: usize) -> Self {
        let knot = |i: usize| match i {
            0..4 => 0.0,
            _ if i < 4 + knots.len() => knots[i - 4],
            _ => end,
        };
        Self {
            knots: std::array::from_fn(|r| knot(j + r)),
            end,
        }
    }
}

/// The static correction shapes of a section of length `length` (m) with interior knots
/// `knots` (m, strictly inside `(0, length)`, ascending, distinct).
pub fn correction_shapes(length: f64, knots: &[f64]) -> Vec<CubicBSpline> {
    // the first two clamped B-splines carry the foot's value and slope
    (2..knots.len() + 4)
        .map(|j| CubicBSpline::clamped(knots, length, j))
        .collect()
}

/// The correction shapes of a section with interior knots `knots` (fractions of its length,
/// as [`correction_shapes`] with length 1) at `xi`: their values into
/// `value[..knots.len() + 2]` and their `d/dxi` into `slope`; allocation-free (the generated
/// models of the basis `modes+static` call it).
pub fn correction_values(knots: &[f64], xi: f64, value: &mut [f64], slope: &mut [f64]) {
    for (e, j) in (2..knots.len() + 4).enumerate() {
        (value[e], slope[e]) = CubicBSpline::clamped(knots, 1.0, j).value_and_slope(xi);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_full_basis_is_a_partition_of_unity_and_derivatives_match_differences() {
        let l = 1.35;
        let knots = [0.1, 0.2, 1.15, 1.25];
        let full: Vec<CubicBSpline> = (0..knots.len() + 4)
            .map(|j| CubicBSpline::clamped(&knots, l, j))
            .collect();
        for i in 0..=200 {
            let x = l * i as f64 / 200.0;
            let sum: f64 = full.iter().map(|b| b.eval(x, 0)).sum();
            assert!((sum - 1.0).abs() < 1e-14, "x = {x}: {sum}");
            for b in &full {
                let h = 1e-6;
                if knots
                    .iter()
                    .chain(&[0.0, l])
                    .any(|k| (x - k).abs() < 2.0 * h)
                {
                    continue;
                }
                let fd1 = (b.eval(x + h, 0) - b.eval(x - h, 0)) / (2.0 * h);
                let fd2 = (b.eval(x + h, 1) - b.eval(x - h, 1)) / (2.0 * h);
                assert!(
                    (fd1 - b.eval(x, 1)).abs() < 1e-6 * (1.0 + fd1.abs()),
                    "slope at {x}"
                );
                assert!(
                    (fd2 - b.eval(x, 2)).abs() < 1e-5 * (1.0 + fd2.abs()),
                    "curvature at {x}"
                );
            }
        }
    }

    #[test]
    fn correction_shapes_vanish_with_their_slope_at_the_foot() {
        let shapes = correction_shapes(2.0, &[0.5]);
        assert_eq!(shapes.len(), 3);
        for s in &shapes {
            assert_eq!(s.eval(0.0, 0), 0.0);
            assert_eq!(s.eval(0.0, 1), 0.0);
        }
        // the last one is the top's: value 1 there
        assert_eq!(shapes[2].eval(2.0, 0), 1.0);
    }
}
