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
    let common = jumps.first().map_or(0.0, |&(t0, _)| {
        let (omega, zeta) = mode(t0);
        mean_delay(&impulses(kind, omega, zeta))
    });
    for &(t, d) in jumps {
        let (omega, zeta) = mode(t);
        let imp = impulses(kind, omega, zeta);
        let shift = common - mean_delay(&imp);
        for (amplitude, delay) in imp {
            shaped.push((t + delay + shift, amplitude * d));
        }
    }
    levels(shaped)
}

/// How a shaped profile is placed in time.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ShaperTiming {
    /// Every train after its jump, with a common mean delay ([`shape`]): the shaped profile
    /// ends up to one damped period after the original's last change.
    Delayed,
    /// Inside the original's span ([`shape_within`]): the first train starts at the first
    /// jump, the last ends at the last jump; the rest-to-rest travel is kept.
    #[default]
    Within,
}

crate::named::named_enum!(ShaperTiming, "a shaper timing", {
    Delayed => "delayed",
    Within => "within",
});

/// The shaped force inside the original profile's span, for a rest-to-rest profile (the
/// force ends at zero, `sum dF = 0`, and so does the velocity, `sum dF t = 0`): the jump
/// times are mapped by `tau = tau_1 + c (t - t_1)` so that the first train starts at the
/// first jump and the last train ends at the last jump, every train centred on its `tau`
/// (its mean delay) and scaled by `1 / c^2`. The compression by `c` and that scale keep
/// the rest-to-rest property and the rigid travel `sum dF t^2 / (2 m)` exactly (up to the
/// trains' own spread, as for [`shape`]).
///
/// # Errors
/// Why the trains cannot sit within the span: the profile is not rest to rest, or too short
/// for its trains (then [`shape`] applies).
pub fn shape_within(
    jumps: &[(f64, f64)],
    kind: ShaperKind,
    mode: impl Fn(f64) -> (f64, f64),
) -> Result<Profile, &'static str> {
    let train = |t: f64| {
        let (omega, zeta) = mode(t);
        let imp = impulses(kind, omega, zeta);
        let mean = mean_delay(&imp);
        (imp, mean)
    };
    let (Some(&(t_first, _)), Some(&(t_last, _))) = (jumps.first(), jumps.last()) else {
        return Ok(Profile::Constant(0.0));
    };
    let scale = jumps.iter().map(|(_, d)| d.abs()).fold(0.0, f64::max);
    let force_end: f64 = jumps.iter().map(|(_, d)| d).sum();
    let velocity_end: f64 = jumps.iter().map(|(t, d)| d * (t - t_first)).sum();
    let span = t_last - t_first;
    if jumps.len() < 2 || force_end.abs() > 1e-9 * scale || velocity_end.abs() > 1e-9 * scale * span
    {
        return Err(
            "the profile is not rest to rest (its force or its velocity does not end \
                    at zero)",
        );
    }
    let tau_first = t_first + train(t_first).1;
    // the last train ends at the last jump: its centre sits its spread after the mean
    // (a fixed point: the train's length depends on the mode at its centre, which moves
    // slowly with it; converged to rounding in a few rounds)
    let mut tau_last = t_last;
    for _ in 0..50 {
        let (imp, mean) = train(tau_last);
        let next = t_last - (imp.last().map_or(0.0, |&(_, d)| d) - mean);
        let done = (next - tau_last).abs() <= 1e-13 * span;
        tau_last = next;
        if done {
            break;
        }
    }
    if tau_last <= tau_first + 0.1 * span {
        return Err("the profile is too short for its trains");
    }
    let c = (tau_last - tau_first) / span;
    let mut shaped: Vec<(f64, f64)> = Vec::new();
    for &(t, d) in jumps {
        let tau = tau_first + c * (t - t_first);
        let (imp, mean) = train(tau);
        for (amplitude, delay) in imp {
            shaped.push((tau + delay - mean, amplitude * d / (c * c)));
        }
    }
    // the ends exactly at the original's, not at the rounding of the map
    if let Some(first) = shaped.iter_mut().min_by(|a, b| a.0.total_cmp(&b.0)) {
        first.0 = first.0.max(t_first);
    }
    if let Some(last) = shaped.iter_mut().max_by(|a, b| a.0.total_cmp(&b.0)) {
        last.0 = last.0.min(t_last);
    }
    Ok(levels(shaped))
}

/// Mean delay (s) of a train of impulses whose amplitudes sum to one.
fn mean_delay(imp: &[(f64, f64)]) -> f64 {
    imp.iter().map(|(a, d)| a * d).sum()
}

/// The piecewise-constant profile of the jumps `(time, change)`, zero before the first.
fn levels(mut shaped: Vec<(f64, f64)>) -> Profile {
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

    /// The case study's drive: +100, 0, -100, 0 N from 0, 4, 8, 12 s.
    fn case_study_force() -> Profile {
        Profile::Shaped(ShapedProfile::PiecewiseConstant {
            times: vec![0.0, 4.0, 8.0, 12.0],
            values: vec![100.0, 0.0, -100.0, 0.0],
        })
    }

    /// Breakpoints and levels of a piecewise-constant profile.
    fn levels_of(profile: &Profile) -> (&[f64], &[f64]) {
        match profile {
            Profile::Shaped(ShapedProfile::PiecewiseConstant { times, values }) => (times, values),
            _ => panic!("piecewise constant"),
        }
    }

    #[test]
    fn a_shaped_step_profile_keeps_its_levels_and_total() {
        let profile = case_study_force();
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

    /// Rigid final velocity and position (per unit mass) of a piecewise-constant force that
    /// ends at zero, from its jumps: the exact double integral.
    fn rigid_end(profile: &Profile, end: f64) -> (f64, f64) {
        let (times, values) = levels_of(profile);
        let (mut level, mut v, mut x) = (0.0, 0.0, 0.0);
        for (i, &t) in times.iter().enumerate() {
            let dt = times.get(i + 1).copied().unwrap_or(end) - t;
            level = values[i];
            x += v * dt + 0.5 * level * dt * dt;
            v += level * dt;
        }
        assert_eq!(level, values[values.len() - 1]);
        (v, x)
    }

    #[test]
    fn trains_within_the_span_keep_the_rest_to_rest_travel_and_cancel_the_mode() {
        let profile = case_study_force();
        let j = jumps(&profile, 0.0).unwrap();
        let omega = 2.0 * PI * 0.8;
        for kind in [ShaperKind::Zv, ShaperKind::Zvd] {
            let within = shape_within(&j, kind, |_| (omega, 0.0)).unwrap();
            let delayed = shape(&j, kind, |_| (omega, 0.0));
            // the original's span: nothing before 0 s, the force back at zero by 12 s, where
            // the delayed trains still brake
            assert_eq!(within.value(-1e-9), 0.0);
            assert!(
                within.value(12.0).abs() < 1e-9,
                "{kind}: {}",
                within.value(12.0)
            );
            assert!(delayed.value(12.0).abs() > 10.0);
            // rest to rest, and the rigid travel of the original (per unit mass)
            let (v0, x0) = rigid_end(&profile, 20.0);
            let (v, x) = rigid_end(&within, 20.0);
            assert!(v0.abs() < 1e-9 && v.abs() < 1e-9, "{kind}: {v0}, {v}");
            assert!((x - x0).abs() < 1e-9 * x0.abs(), "{kind}: {x} against {x0}");
            // an undamped oscillator at the mode is left at rest after 12 s: the sum of its
            // step responses' phasors vanishes, where the original leaves an amplitude
            let phasor = |p: &Profile| {
                let (times, values) = levels_of(p);
                let steps = (0..times.len()).map(|i| {
                    let before = if i == 0 { 0.0 } else { values[i - 1] };
                    (values[i] - before, times[i])
                });
                residual(&steps.collect::<Vec<_>>(), omega)
            };
            assert!(
                phasor(&within) < 1e-9 * 100.0,
                "{kind}: {}",
                phasor(&within)
            );
            assert!(phasor(&profile) > 10.0);
        }
        // a profile that is not rest to rest has no trains within its span, and says why
        let coasting = vec![(0.0, 100.0), (4.0, -100.0)];
        let why = shape_within(&coasting, ShaperKind::Zvd, |_| (omega, 0.0)).unwrap_err();
        assert!(why.contains("rest to rest"), "{why}");
    }
}
