//! The figures a run is judged by, shared by the control variants table, the sweep rows and
//! the convergence trials: peak and RMS, the drive's stop, the residual vibration after it.

use crate::run::Trajectory;
use telescopic_runtime::Output;
use telescopic_runtime::Scene;

/// Largest magnitude and root mean square of `values` (both 0 for none).
pub fn peak_and_rms(values: &[f64]) -> (f64, f64) {
    if values.is_empty() {
        return (0.0, 0.0);
    }
    let peak = values.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let rms = (values.iter().map(|v| v * v).sum::<f64>() / values.len() as f64).sqrt();
    (peak, rms)
}

/// When the scene's drive makes its last change (s): its last breakpoint inside the span,
/// else the start. The residual-vibration window starts there.
pub fn drive_stop(scene: &Scene) -> f64 {
    scene
        .params
        .drive_profile()
        .breakpoints()
        .into_iter()
        .filter(|&b| b > scene.time.start && b < scene.time.end)
        .fold(scene.time.start, f64::max)
}

/// The figures of one run over a residual window.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RunMetrics {
    /// Start of the residual-vibration window (s): the drive's last change.
    pub window_start: f64,
    /// Standard deviation of `tip_rel` over the window (m): the oscillation about its mean.
    pub residual_std: f64,
    /// Largest |drive force| (N).
    pub peak_force: f64,
    /// Final vehicle position (m).
    pub final_vehicle: f64,
    /// Peak-to-peak of `tip_rel` over the window (m): the residual amplitude.
    pub residual_p2p: f64,
    /// Time from the window's start until `tip_rel` stays within [`SETTLING_BAND`] of its
    /// final rest (the mean of the window's last quarter), s; `None` if it never does.
    pub settling_time: Option<f64>,
    /// Contact openings and closings in the window, counted between output samples.
    pub window_switches: usize,
}

/// The band about the final rest that settling means (m): +-5 mm.
pub const SETTLING_BAND: f64 = 0.005;

/// The metrics of a run over the window `[window_start, end]`; the drive force is the
/// `drive_force` column when the run has one, else the scene's drive profile.
pub fn metrics(scene: &Scene, trajectory: &Trajectory, window_start: f64) -> RunMetrics {
    let t = trajectory.column("t").expect("t");
    let tip = trajectory.column_of(Output::TipRel).expect("tip_rel");
    let window: Vec<f64> = t
        .iter()
        .zip(&tip)
        .filter(|(t, _)| **t >= window_start)
        .map(|(_, v)| *v)
        .collect();
    let mean = window.iter().sum::<f64>() / window.len().max(1) as f64;
    let var = window.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / window.len().max(1) as f64;
    let peak_force = match trajectory.column_of(Output::DriveForce) {
        Some(f) => f.iter().fold(0.0f64, |m, v| m.max(v.abs())),
        None => t
            .iter()
            .map(|&t| scene.params.drive_profile().value(t).abs())
            .fold(0.0, f64::max),
    };
    let p2p = window.iter().fold(f64::NEG_INFINITY, |m, v| m.max(*v))
        - window.iter().fold(f64::INFINITY, |m, v| m.min(*v));
    let rest = {
        let tail = &window[window.len() - window.len() / 4..];
        tail.iter().sum::<f64>() / tail.len().max(1) as f64
    };
    let times: Vec<f64> = t.iter().copied().filter(|t| *t >= window_start).collect();
    let last_outside = window
        .iter()
        .rposition(|v| (v - rest).abs() > SETTLING_BAND);
    let settling_time = match last_outside {
        None => Some(0.0),
        Some(i) if i + 1 < times.len() => Some(times[i + 1] - window_start),
        Some(_) => None,
    };
    RunMetrics {
        window_start,
        residual_std: var.sqrt(),
        residual_p2p: if window.is_empty() { 0.0 } else { p2p },
        settling_time,
        window_switches: window_switches(scene, trajectory, window_start),
        peak_force,
        final_vehicle: trajectory
            .column_of(Output::Vehicle)
            .and_then(|v| v.last().copied())
            .unwrap_or(0.0),
    }
}

/// Contact state changes in the window, counted between consecutive output samples
/// ([`Trajectory::sampled_switches`]).
fn window_switches(scene: &Scene, trajectory: &Trajectory, window_start: f64) -> usize {
    trajectory.sampled_switches(&scene.params.contact, window_start)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::run::Column;
    use telescopic_runtime::{Output, RunStats};

    #[test]
    fn residual_figures_of_a_decaying_oscillation_and_a_rattling_gap() {
        // adams-clearance: l_S = 10 mm, so a contact closes where |xi| > 5 mm
        let scene = Scene::load("scenes/adams-clearance.toml".as_ref(), &[]).unwrap();
        let dt = 1e-3;
        let rows: Vec<Vec<f64>> = (0..=5000)
            .map(|k| {
                let t = k as f64 * dt;
                let tau = std::f64::consts::TAU;
                let tip = 0.02 * (tau * t).cos() * (-t).exp();
                // a gap swinging to 6 mm once per second: two closings and two openings
                let xi = 0.006 * (tau * t + 0.1).sin();
                vec![t, 0.0, tip, xi]
            })
            .collect();
        let trajectory = Trajectory {
            columns: ["vehicle", "tip_rel", "xi_2_0"]
                .map(|name| Column::Output(Output::parse(name).unwrap()))
                .to_vec(),
            rows,
            stats: RunStats::default(),
        };
        let m = metrics(&scene, &trajectory, 0.0);
        // peak to peak: from +0.02 at t = 0 down to the first trough, where
        // tan(2 pi t) = -1 / (2 pi)
        let tau = std::f64::consts::TAU;
        let trough = 0.5 - (1.0 / tau).atan() / tau;
        let p2p = 0.02 - 0.02 * (tau * trough).cos() * (-trough).exp();
        assert!((m.residual_p2p - p2p).abs() < 1e-6, "{}", m.residual_p2p);
        // the envelope 0.02 e^-t falls under 5 mm at ln 4 s; the last excursion beyond it is
        // within half a period before that
        let settle = m.settling_time.unwrap();
        let envelope = 4f64.ln();
        assert!(
            settle <= envelope + dt && settle > envelope - 0.5,
            "{settle}"
        );
        // 5 periods, 4 switches each
        assert_eq!(m.window_switches, 20);
    }
}
