//! Two tight reference runs of a scene and its predictability horizon, as `telescopic
//! work-precision` measures them.

use telescopic::analysis::work_precision::{
    REFERENCE_RUNS, predictability_horizon, tip_error_in_horizon,
};
use telescopic::run::{MethodChoice, SimulationOptions, Trajectory, simulate_scene};
use telescopic::runtime::Method;
use telescopic::{Scene, Silent};

/// `method` at `rtol` (and `atol = 1e-3 rtol`).
pub fn tight(method: Method, rtol: f64) -> SimulationOptions {
    SimulationOptions {
        method: MethodChoice::Method(method),
        rtol: Some(rtol),
        atol: Some(1e-3 * rtol),
        ..SimulationOptions::default()
    }
}

/// The work-precision command's two reference runs ([`REFERENCE_RUNS`]) and where their
/// `tip_rel` part.
pub struct References {
    /// The horizon (s, [`predictability_horizon`]).
    pub horizon: f64,
    /// The first reference.
    pub run: Trajectory,
}

impl References {
    /// The two runs of `scene`.
    pub fn of(scene: &Scene) -> Self {
        let [(m1, r1), (m2, r2)] = REFERENCE_RUNS;
        let a = simulate_scene(scene, &tight(m1, r1), &Silent).unwrap();
        let b = simulate_scene(scene, &tight(m2, r2), &Silent).unwrap();
        let horizon = predictability_horizon(&a.trajectory, &b.trajectory);
        References {
            horizon,
            run: a.trajectory,
        }
    }

    /// Largest `|tip_rel|` difference (m) of `run` from the first reference up to the horizon.
    pub fn worst_in_horizon(&self, run: &Trajectory) -> f64 {
        tip_error_in_horizon(run, &self.run, self.horizon)
    }
}
