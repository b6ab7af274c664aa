//! Input shapers of the ZV/ZVD/EI family for one mode, designed undamped: impulse
//! amplitudes (summing to 1) at multiples of the mode's period, and their residual
//! vibration against the frequency (the closed-form sensitivity curve).

use crate::control::design::shaper::{ShaperKind, impulses};
use serde::Serialize;
use std::f64::consts::PI;

/// The residual an EI shaper allows at its design frequency (5 %).
pub const EI_TOLERANCE: f64 = 0.05;

/// A shaper of the ZV/ZVD/EI family.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Shaper {
    /// Zero vibration: two impulses half a period apart.
    Zv,
    /// Zero vibration and derivative: three impulses over one period.
    Zvd,
    /// Extra-insensitive: three impulses over one period, 5 % residual at the design
    /// frequency, zero on either side of it.
    Ei,
    /// Two-hump extra-insensitive: four impulses over one and a half periods.
    TwoHumpEi,
}

crate::named::named_enum!(Shaper, "a shaper", {
    Zv => "zv",
    Zvd => "zvd",
    Ei => "ei",
    TwoHumpEi => "2ei",
});

impl Shaper {
    /// All shapers, shortest first.
    pub const ALL: [Shaper; 4] = [Shaper::Zv, Shaper::Zvd, Shaper::Ei, Shaper::TwoHumpEi];

    /// `[amplitude, multiple of the period]` per impulse (Singhose's undamped forms).
    pub fn impulses(self) -> Vec<[f64; 2]> {
        let v = EI_TOLERANCE;
        match self {
            // the controller's shapers at zero damping, for a period of 1 s
            Shaper::Zv | Shaper::Zvd => {
                let kind = if self == Shaper::Zv {
                    ShaperKind::Zv
                } else {
                    ShaperKind::Zvd
                };
                impulses(kind, 2.0 * PI, 0.0)
                    .into_iter()
                    .map(|(amplitude, delay)| [amplitude, delay])
                    .collect()
            }
            Shaper::Ei => vec![
                [(1.0 + v) / 4.0, 0.0],
                [(1.0 - v) / 2.0, 0.5],
                [(1.0 + v) / 4.0, 1.0],
            ],
            Shaper::TwoHumpEi => {
                let x = (v * v * ((1.0 - v * v).sqrt() + 1.0)).cbrt();
                let a1 = (3.0 * x * x + 2.0 * x + 3.0 * v * v) / (16.0 * x);
                let a2 = 0.5 - a1;
                vec![[a1, 0.0], [a2, 0.5], [a2, 1.0], [a1, 1.5]]
            }
        }
    }

    /// The shaper's length in periods.
    pub fn periods(self) -> f64 {
        self.impulses().last().map_or(0.0, |i| i[1])
    }

    /// Residual vibration of an undamped mode at `ratio` times the design frequency, relative
    /// to the unshaped input's: `|sum_i A_i exp(2 pi i m_i ratio)|`.
    pub fn residual(self, ratio: f64) -> f64 {
        let (mut re, mut im) = (0.0, 0.0);
        for [a, m] in self.impulses() {
            re += a * (2.0 * PI * m * ratio).cos();
            im += a * (2.0 * PI * m * ratio).sin();
        }
        re.hypot(im)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn amplitudes_sum_to_one_and_the_curves_have_their_published_values() {
        for s in Shaper::ALL {
            let sum: f64 = s.impulses().iter().map(|i| i[0]).sum();
            assert!((sum - 1.0).abs() < 1e-15, "{s}");
        }
        assert!(Shaper::Zv.residual(1.0) < 1e-15);
        assert!(Shaper::Zvd.residual(1.0) < 1e-15);
        assert!((Shaper::Ei.residual(1.0) - EI_TOLERANCE).abs() < 1e-15);
        // ZVD's residual at +-10 % frequency error: 2.4 % (flat second-order zero)
        assert!((Shaper::Zvd.residual(1.1) - 0.0245).abs() < 5e-4);
        // the two-hump EI stays under 5 % over a wider band than EI
        let within = |s: Shaper| {
            (50..=150)
                .map(|i| f64::from(i) / 100.0)
                .filter(|&r| s.residual(r) <= EI_TOLERANCE + 1e-9)
                .count()
        };
        assert!(within(Shaper::TwoHumpEi) > within(Shaper::Ei));
        assert!(within(Shaper::Ei) > within(Shaper::Zvd));
        assert!(within(Shaper::Zvd) > within(Shaper::Zv));
    }
}
