//! The figures a run is judged by, shared by the control variants table, the sweep rows and
//! the convergence trials: peak and RMS, the drive's stop, the residual vibration after it.

use crate::simulation::Trajectory;
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
}

/// The metrics of a run over the window `[window_start, end]`; the drive force is the
/// `drive_force` column when the run has one, else the scene's drive profile.
pub fn metrics(scene: &Scene, trajectory: &Trajectory, window_start: f64) -> RunMetrics {
    let t = trajectory.column("t").expect("t");
    let tip = trajectory.column("tip_rel").expect("tip_rel");
    let window: Vec<f64> = t
        .iter()
        .zip(&tip)
        .filter(|(t, _)| **t >= window_start)
        .map(|(_, v)| *v)
        .collect();
    let mean = window.iter().sum::<f64>() / window.len().max(1) as f64;
    let var = window.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / window.len().max(1) as f64;
    let peak_force = match trajectory.column("drive_force") {
        Some(f) => f.iter().fold(0.0f64, |m, v| m.max(v.abs())),
        None => t
            .iter()
            .map(|&t| scene.params.drive_profile().value(t).abs())
            .fold(0.0, f64::max),
    };
    RunMetrics {
        window_start,
        residual_std: var.sqrt(),
        peak_force,
        final_vehicle: trajectory
            .column("vehicle")
            .and_then(|v| v.last().copied())
            .unwrap_or(0.0),
    }
}
