//! Gain scheduling: the design points around the moving telescopic position and the rigid
//! reference motion a controller tracks, shared by the continuous law, the sampled laws and
//! (as the same arithmetic) the emitted C.

use crate::control::file::schema::Controller;
use telescopic_runtime::Profile;

/// The rigid reference `u_ref(t)`, `u_ref'(t)`: piecewise quadratic between nodes, exact for
/// a piecewise-constant force.
pub(crate) struct Reference {
    times: Vec<f64>,
    /// `(u, v, a)` at each node; `a` holds until the next.
    states: Vec<(f64, f64, f64)>,
}

impl Reference {
    /// Integrates `u'' = f(t) / m` from rest at `start` to `end`, on nodes at the profile's
    /// breakpoints and at most `step` apart, with the acceleration at each interval's
    /// midpoint.
    pub(crate) fn new(force: &Profile, mass: f64, start: f64, end: f64, step: f64) -> Self {
        let mut nodes: Vec<f64> = force
            .breakpoints()
            .into_iter()
            .filter(|&b| b > start && b < end)
            .collect();
        // nodes every `step` (an infinite step: the breakpoints, the start and the end only,
        // exact for a piecewise-constant force)
        if step.is_finite() {
            let count = ((end - start) / step).ceil() as usize;
            nodes.extend((0..=count).map(|i| (start + i as f64 * step).min(end)));
        }
        nodes.extend([start, end]);
        nodes.sort_by(f64::total_cmp);
        nodes.dedup();
        let mut states = Vec::with_capacity(nodes.len());
        let (mut u, mut v) = (0.0, 0.0);
        for w in nodes.windows(2) {
            let (t0, t1) = (w[0], w[1]);
            let a = force.value(0.5 * (t0 + t1)) / mass;
            states.push((u, v, a));
            let h = t1 - t0;
            u += v * h + 0.5 * a * h * h;
            v += a * h;
        }
        states.push((u, v, 0.0));
        Reference {
            times: nodes,
            states,
        }
    }

    /// The nodes: `(t, u, v, a)` each, `a` holding until the next node.
    pub(crate) fn nodes(&self) -> impl Iterator<Item = (f64, f64, f64, f64)> + '_ {
        self.times
            .iter()
            .zip(&self.states)
            .map(|(&t, &(u, v, a))| (t, u, v, a))
    }

    /// `(u_ref, u_ref')` at `t` (s); constant extrapolation of the motion outside.
    pub(crate) fn at(&self, t: f64) -> (f64, f64) {
        let i = self.times.partition_point(|&x| x <= t).saturating_sub(1);
        let (u, v, a) = self.states[i];
        let h = (t - self.times[i]).max(0.0);
        (u + v * h + 0.5 * a * h * h, v + a * h)
    }
}

/// The two schedule points around time `t` and the weight of the second, `(i, j, w)`, for a
/// schedule over `a_k` (`section = Some(k)`, `schedule_positions` its points' values of
/// `a_k` from [`Controller::schedule_positions`]; `positions` are the scene's `a_2..a_n`),
/// or the one point of a schedule at fixed positions (`None`). Allocation-free.
pub fn schedule_weights(
    schedule_positions: &[f64],
    section: Option<usize>,
    positions: &[Profile],
    t: f64,
) -> (usize, usize, f64) {
    match section {
        Some(k) => bracket(schedule_positions, positions[k - 2].value(t)),
        None => (0, 0, 0.0),
    }
}

/// The two entries of the ascending `positions` around `a` and the weight of the second:
/// `(i, j, w)`, clamped at the ends (the emitted C's `weights` does the same).
pub(crate) fn bracket(positions: &[f64], a: f64) -> (usize, usize, f64) {
    let last = positions.len() - 1;
    if last == 0 || a <= positions[0] {
        return (0, 0, 0.0);
    }
    if a >= positions[last] {
        return (last, last, 0.0);
    }
    let j = positions.partition_point(|&x| x <= a).clamp(1, last);
    let (x0, x1) = (positions[j - 1], positions[j]);
    (j - 1, j, (a - x0) / (x1 - x0))
}

/// The rigid reference of a sampled controller: nodes at the feedforward's breakpoints only
/// for a piecewise-constant force (exact, and a short table for emitted code), every 1 ms
/// otherwise.
pub(crate) fn reference(file: &Controller, start: f64, end: f64) -> Reference {
    let step = if file.feedforward_steps().is_some() {
        f64::INFINITY
    } else {
        1e-3
    };
    Reference::new(&file.feedforward, file.total_mass_kg, start, end, step)
}
