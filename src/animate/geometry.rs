//! What a view draws a telescope from: each section's drawing points (material coordinate
//! from its foot) with the shape functions there, evaluated once, and its contact points.
//! A frame's deflection is the product of these rows with the frame's coordinates.

use serde::Serialize;
use telescopic_runtime::{Model, ModelParams};

/// Drawing points per section: enough that a bent section's polyline looks smooth.
pub const DEFAULT_POINTS: usize = 41;

/// One contact point, where a view draws its guide.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ContactSite {
    /// The inner section `k` (1-based, `>= 2`); its guide is on section `k - 1`.
    pub overlap: usize,
    /// Point `j` of the overlap (`0` at the foot of `k`).
    pub point: usize,
    /// Position `s_j` along the overlap (0 at the foot of `k`, 1 at the top of `k - 1`).
    pub fraction: f64,
}

/// A telescope as a view draws it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Telescope {
    /// Length of each section (m), bottom up.
    pub lengths_m: Vec<f64>,
    /// Material coordinate of each drawing point (m from the section's foot), per section.
    pub points_m: Vec<Vec<f64>>,
    /// The row `r` with `w_k(x) = r . z` at each drawing point: `[section][point][coordinate]`
    /// (m per unit of each coordinate; index 0 is the vehicle's translation).
    pub shapes: Vec<Vec<Vec<f32>>>,
    /// The contact points, overlap by overlap.
    pub contacts: Vec<ContactSite>,
    /// Half the clearance `l_S/2` (m): the guide's band edges; a contact is closed when
    /// its gap is beyond them.
    pub half_band_m: f64,
}

impl Telescope {
    /// The telescope of `model` with `points` evenly spaced drawing points per section (2 or
    /// more).
    pub fn of(model: &dyn Model, points: usize) -> Self {
        let params = model.params();
        let lengths_m: Vec<f64> = params.sections.iter().map(|s| s.length).collect();
        let points_m: Vec<Vec<f64>> = lengths_m
            .iter()
            .map(|&l| {
                (0..points)
                    .map(|p| l * p as f64 / (points - 1) as f64)
                    .collect()
            })
            .collect();
        let shapes = points_m
            .iter()
            .enumerate()
            .map(|(k, xs)| {
                xs.iter()
                    .map(|&x| {
                        let row = model.shape_row(k + 1, x, 0);
                        row.iter().map(|&v| v as f32).collect()
                    })
                    .collect()
            })
            .collect();
        let contacts = model
            .layout()
            .contacts()
            .map(|c| ContactSite {
                overlap: c.overlap,
                point: c.point,
                fraction: c.fraction,
            })
            .collect();
        Telescope {
            lengths_m,
            points_m,
            shapes,
            contacts,
            half_band_m: params.contact.half_band(),
        }
    }

    /// Deflection (m) of drawing point `point` of section `section` (0-based) relative to the
    /// vehicle, for coordinates `z`: the row without the translation.
    pub fn relative_deflection(&self, section: usize, point: usize, z: &[f32]) -> f64 {
        self.shapes[section][point]
            .iter()
            .zip(z)
            .skip(1)
            .map(|(&r, &q)| f64::from(r) * f64::from(q))
            .sum()
    }

    /// The largest relative deflection (m) of any drawing point over `frames` (coordinates
    /// per frame).
    pub fn largest_deflection<'a>(&self, frames: impl Iterator<Item = &'a [f32]>) -> f64 {
        let mut largest = 0.0_f64;
        for z in frames {
            for (k, section) in self.shapes.iter().enumerate() {
                for p in 0..section.len() {
                    largest = largest.max(self.relative_deflection(k, p, z).abs());
                }
            }
        }
        largest
    }
}

/// Height (m) of each section's foot above the foot of section 1 at time `t` (s): the foot
/// of section `k` sits at `a_k(t)` along section `k - 1`.
pub fn feet(params: &ModelParams, t: f64) -> Vec<f64> {
    let mut feet = vec![0.0];
    for (i, p) in params.positions.iter().enumerate() {
        feet.push(feet[i] + p.value(t));
    }
    feet
}

/// The telescope's height (m) at time `t` (s): the highest section top.
pub fn height(params: &ModelParams, t: f64) -> f64 {
    feet(params, t)
        .iter()
        .zip(&params.sections)
        .map(|(foot, s)| foot + s.length)
        .fold(0.0, f64::max)
}

/// A deflection scale that draws the largest deflection `largest` (m) at about `share` of
/// the height `height` (m): a round number (1, 2 or 5 times a power of ten), at least 1.
pub fn readable_scale(largest: f64, height: f64, share: f64) -> f64 {
    if !(largest > 0.0 && largest.is_finite()) {
        return 1.0;
    }
    let raw = share * height / largest;
    if raw <= 1.0 {
        return 1.0;
    }
    let decade = 10f64.powf(raw.log10().floor());
    let mantissa = [5.0, 2.0, 1.0]
        .into_iter()
        .find(|&m| m * decade <= raw)
        .unwrap_or(1.0);
    mantissa * decade
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn readable_scales_are_round_and_draw_at_most_the_share() {
        assert_eq!(readable_scale(0.01, 2.5, 0.2), 50.0);
        assert_eq!(readable_scale(0.003, 2.5, 0.2), 100.0);
        assert_eq!(readable_scale(0.0, 2.5, 0.2), 1.0);
        assert_eq!(readable_scale(10.0, 2.5, 0.2), 1.0);
        for largest in [1e-6, 3.3e-4, 0.07, 0.49] {
            let s = readable_scale(largest, 2.5, 0.2);
            assert!(
                s * largest <= 0.5 + 1e-12 && s * largest > 0.1 * 0.5,
                "{largest} {s}"
            );
        }
    }
}
