//! Input shaping of a piecewise-constant drive force: every jump of the force becomes a
//! sequence of smaller jumps timed so that the first mode, excited by each of them, cancels
//! itself (ZV: two impulses half a damped period apart; ZVD: three, robust to a mode
//! frequency off by some percent). The mode follows the telescopic positions: each jump
//! is shaped with the frequency and damping at the positions of its time.

use std::f64::consts::PI;
use telescopic_runtime::{Profile, ShapedProfile};

/// The shaper's kind.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ShaperKind {
    /// Zero vibration: two impulses.
    Zv,
    /// Zero vibration and derivative: three impulses, insensitive to small frequency errors.
    #[default]
    Zvd,
}

crate::named::named_enum!(ShaperKind, "a shaper", {
    Zv => "zv",
    Zvd => "zvd",
});

/// Amplitudes and delays (s) of the shaper's impulses for a mode of natural frequency
/// `omega` (rad/s) and damping ratio `zeta` (0 <= zeta < 1).
pub fn impulses(kind: ShaperKind, omega: f64, zeta: f64) -> Vec<(f64, f64)> {
    let zeta = zeta.clamp(0.0, 0.99);
    let damped = omega * (1.0 - zeta * zeta).sqrt();
    let half = PI / damped;
    let k = (-zeta * PI / (1.0 - zeta * zeta).sqrt()).exp();
    match kind {
        ShaperKind::Zv => {
            let s = 1.0 + k;
            vec![(1.0 / s, 0.0), (k / s, half)]
        }
        ShaperKind::Zvd => {
            let s = (1.0 + k) * (1.0 + k);
            vec![(1.0 / s, 0.0), (2.0 * k / s, half), (k * k / s, 2.0 * half)]
        }
    }
}

/// The jumps of a piecewise-constant (or constant) force from `start` on: `(time, change)`,
/// the force switched on at `start` (the scene starts at rest) counted as the first.
///
/// # Errors
/// A message for a profile that is not piecewise constant.
pub fn jumps(profile: &Profile, start: f64) -> Result<Vec<(f64, f64)>, String> {
    let mut out = vec![(start, profile.value(start))];
    match profile {
        Profile::Constant(_) | Profile::Shaped(ShapedProfile::Constant { .. }) => {}
        Profile::Shaped(ShapedProfile::PiecewiseConstant { times, values }) => {
            for i in 1..times.len() {
                if times[i] > start {
                    out.push((times[i], values[i] - values[i - 1]));
                }
            }
        }
        _ => {
            return Err("the shaper needs a piecewise-constant drive force (kind = \
                 \"piecewise-constant\" or a number)"
                .into());
        }
    }
    out.retain(|&(_, d)| d != 0.0);
    Ok(out)
}

/// The shaped force: every jump `(t, dF)` becomes the jumps `(t + delay + shift, amplitude
/// dF)` of the shaper for the mode `mode(t)` = `(omega, zeta)` at its time, each train
/// shifted so that its mean delay is the first train's (a common delay: the rigid travel
/// stays the same). A piecewise-constant profile, zero before the first jump.
pub fn shape(jumps: &[(f64, f64)], kind: ShaperKind, mode: impl Fn(f64) -> (f64, f64)) -> Profile {
    let mut shaped: Vec<(f64, f64)> = Vec::new();
    // every train's mean delay is the first one's: a common delay keeps the rigid travel
    // (to first order) whatever the local frequency, and the first train starts at its jump
    let mean = |imp: &[(f64, f64)]| imp.iter().map(|(a, d)| a * d).sum::<f64>();
    let common = jumps.first().map_or(0.0, |&(t0, _)| {
        let (omega, zeta) = mode(t0);
        mean(&impulses(kind, omega, zeta))
    });
    for &(t, d) in jumps {
        let (omega, zeta) = mode(t);
        let imp = impulses(kind, omega, zeta);
        let shift = common - mean(&imp);
        for (amplitude, delay) in imp {
            shaped.push((t + delay + shift, amplitude * d));
        }
    }
    shaped.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut times: Vec<f64> = Vec::new();
    let mut values: Vec<f64> = Vec::new();
    let mut level = 0.0;
    for (t, d) in shaped {
        level += d;
        match times.last() {
            Some(&last) if last == t => *values.last_mut().expect("one per time") = level,
            _ => {
                times.push(t);
                values.push(level);
            }
        }
    }
    if times.is_empty() {
        return Profile::Constant(0.0);
    }
    // zero before the first jump: a leading zero level just before it
    times.insert(0, times[0] - 1.0);
    values.insert(0, 0.0);
    Profile::Shaped(ShapedProfile::PiecewiseConstant { times, values })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Residual vibration of an undamped oscillator after the impulses: the amplitude of
    /// `sum A_i e^(i omega t_i)` relative to one impulse.
    fn residual(imp: &[(f64, f64)], omega: f64) -> f64 {
        let (re, im) = imp.iter().fold((0.0, 0.0), |(re, im), &(a, t)| {
            (re + a * (omega * t).cos(), im + a * (omega * t).sin())
        });
        (re * re + im * im).sqrt()
    }

    #[test]
    fn zv_and_zvd_cancel_their_mode_and_keep_the_impulse() {
        let omega = 2.0 * PI * 1.12;
        for kind in [ShaperKind::Zv, ShaperKind::Zvd] {
            let imp = impulses(kind, omega, 0.0);
            let sum: f64 = imp.iter().map(|(a, _)| a).sum();
            assert!((sum - 1.0).abs() < 1e-15);
            assert!(residual(&imp, omega) < 1e-12, "{kind}");
        }
        // ZVD is robust: 10 % off in frequency leaves less than ZV does
        let off = 1.1 * omega;
        let zv = residual(&impulses(ShaperKind::Zv, omega, 0.0), off);
        let zvd = residual(&impulses(ShaperKind::Zvd, omega, 0.0), off);
        assert!(zvd < zv && zvd < 0.03, "zv {zv}, zvd {zvd}");
    }

    #[test]
    fn a_shaped_step_profile_keeps_its_levels_and_total() {
        let profile = Profile::Shaped(ShapedProfile::PiecewiseConstant {
            times: vec![0.0, 4.0, 8.0, 12.0],
            values: vec![100.0, 0.0, -100.0, 0.0],
        });
        let j = jumps(&profile, 0.0).unwrap();
        assert_eq!(
            j,
            vec![(0.0, 100.0), (4.0, -100.0), (8.0, -100.0), (12.0, 100.0)]
        );
        let shaped = shape(&j, ShaperKind::Zvd, |_| (2.0 * PI, 0.0));
        // the levels between the shaped transitions are the original ones
        assert_eq!(shaped.value(-0.5), 0.0);
        assert!((shaped.value(2.0) - 100.0).abs() < 1e-12);
        assert!((shaped.value(6.0) - 0.0).abs() < 1e-12);
        assert!((shaped.value(10.0) + 100.0).abs() < 1e-12);
        assert!(shaped.value(14.0).abs() < 1e-12);
        // inside the first transition: a quarter of the force
        assert!((shaped.value(0.2) - 25.0).abs() < 1e-12);
    }
}
