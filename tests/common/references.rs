//! Two tight reference runs of a scene and its predictability horizon, as `telescopic
//! work-precision` measures them.

use telescopic::runtime::Method;
use telescopic::simulation::{MethodChoice, SimulationOptions, Trajectory, simulate_scene};
use telescopic::work_precision::predictability_horizon;
use telescopic::{Scene, Silent};

/// A shipped scene (`scenes/<name>.toml`) with `--set` overrides.
pub fn scene(name: &str, overrides: &[&str]) -> Scene {
    let o: Vec<String> = overrides.iter().map(|s| s.to_string()).collect();
    Scene::load(format!("scenes/{name}.toml").as_ref(), &o).unwrap()
}

/// `method` at `rtol` (and `atol = 1e-3 rtol`).
pub fn tight(method: Method, rtol: f64) -> SimulationOptions {
    SimulationOptions {
        method: MethodChoice::Method(method),
        rtol: Some(rtol),
        atol: Some(1e-3 * rtol),
        ..SimulationOptions::default()
    }
}

/// The samples of `tip_rel` (m).
pub fn tip(t: &Trajectory) -> Vec<f64> {
    t.column("tip_rel").unwrap()
}

/// dop853 at rtol 1e-12 and dopri5 at 1e-10, and where their `tip_rel` part by 1e-9 m.
pub struct References {
    /// The horizon (s, [`predictability_horizon`]).
    pub horizon: f64,
    /// The first reference (dop853).
    pub run: Trajectory,
}

impl References {
    /// The two runs of `scene`.
    pub fn of(scene: &Scene) -> Self {
        let a = simulate_scene(scene, &tight(Method::Dop853, 1e-12), &Silent).unwrap();
        let b = simulate_scene(scene, &tight(Method::Dopri5, 1e-10), &Silent).unwrap();
        let horizon = predictability_horizon(&a.trajectory, &b.trajectory);
        References {
            horizon,
            run: a.trajectory,
        }
    }

    /// Largest `|tip_rel|` difference (m) of `run` from the first reference up to the horizon.
    pub fn worst_in_horizon(&self, run: &Trajectory) -> f64 {
        let t = self.run.column("t").unwrap();
        t.iter()
            .zip(tip(run).iter().zip(tip(&self.run)))
            .filter(|(t, _)| **t <= self.horizon)
            .map(|(_, (x, y))| (x - y).abs())
            .fold(0.0, f64::max)
    }
}
