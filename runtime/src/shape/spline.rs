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
        let t = &self.knots;
        if x < t[0] || x > t[4] {
            return 0.0;
        }
        // degree 0: the interval [t_j, t_j+1) holding x; closed at the section's top
        let mut n0 = [0.0; 4];
        for j in 0..4 {
            let inside = (t[j] <= x && x < t[j + 1])
                || (x == self.end && t[j + 1] == self.end && t[j] < t[j + 1]);
            n0[j] = f64::from(u8::from(inside));
        }
        let step = |lower: &[f64], p: usize, j: usize| {
            ratio(x - t[j], t[j + p] - t[j]) * lower[j]
                + ratio(t[j + p + 1] - x, t[j + p + 1] - t[j + 1]) * lower[j + 1]
        };
        let n1: [f64; 3] = std::array::from_fn(|j| step(&n0, 1, j));
        let n2: [f64; 2] = std::array::from_fn(|j| step(&n1, 2, j));
        // derivative of a degree-p spline from the two of degree p - 1 below it
        let slope = |lower: &[f64], p: usize, j: usize| {
            p as f64
                * (ratio(lower[j], t[j + p] - t[j]) - ratio(lower[j + 1], t[j + p + 1] - t[j + 1]))
        };
        match deriv {
            0 => step(&n2, 3, 0),
            1 => slope(&n2, 3, 0),
            _ => {
                let d2: [f64; 2] = std::array::from_fn(|j| slope(&n1, 2, j));
                slope(&d2, 3, 0)
            }
        }
    }
}

/// The static correction shapes of a section of length `length` (m) with interior knots
/// `knots` (m, strictly inside `(0, length)`, ascending, distinct).
pub fn correction_shapes(length: f64, knots: &[f64]) -> Vec<CubicBSpline> {
    let mut all = vec![0.0; 4];
    all.extend_from_slice(knots);
    all.extend_from_slice(&[length; 4]);
    // B_j has knots all[j..j+5]; the first two carry the foot's value and slope
    (2..all.len() - 4)
        .map(|j| CubicBSpline {
            knots: all[j..j + 5].try_into().expect("five knots"),
            end: length,
        })
        .collect()
}

/// The correction shapes of a section with interior knots `knots` (fractions of its length,
/// as [`correction_shapes`] with length 1) at `xi`: their values into
/// `value[..knots.len() + 2]` and their `d/dxi` into `slope`; allocation-free (the generated
/// models of the basis `modes+static` call it).
pub fn correction_values(knots: &[f64], xi: f64, value: &mut [f64], slope: &mut [f64]) {
    let m = knots.len();
    let knot = |i: usize| match i {
        0..4 => 0.0,
        _ if i < 4 + m => knots[i - 4],
        _ => 1.0,
    };
    for (e, j) in (2..m + 4).enumerate() {
        let b = CubicBSpline {
            knots: std::array::from_fn(|r| knot(j + r)),
            end: 1.0,
        };
        value[e] = b.eval(xi, 0);
        slope[e] = b.eval(xi, 1);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_full_basis_is_a_partition_of_unity_and_derivatives_match_differences() {
        let l = 1.35;
        let knots = [0.1, 0.2, 1.15, 1.25];
        let mut all = vec![0.0; 4];
        all.extend_from_slice(&knots);
        all.extend_from_slice(&[l; 4]);
        let full: Vec<CubicBSpline> = (0..all.len() - 4)
            .map(|j| CubicBSpline {
                knots: all[j..j + 5].try_into().unwrap(),
                end: l,
            })
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
