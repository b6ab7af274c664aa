//! The sensor outputs `kappa_1_0` and `acc_load` against independent paths on adams-linear:
//! the curvature by finite differences of the assembled model's deflection along section 1
//! (its own run, another method), the load's acceleration by differentiating
//! `vehicle + tip_rel` twice in time.

use telescopic::Silent;
use telescopic::run::{SimulationOptions, simulate_scene};
use telescopic::runtime::{AssembledModel, Method, Model, Scene, Settings, rest_state, simulate};

fn scene(overrides: &[&str]) -> Scene {
    let o: Vec<String> = overrides.iter().map(|s| s.to_string()).collect();
    Scene::load("scenes/adams-linear.toml".as_ref(), &o).unwrap()
}

fn max_abs(v: &[f64]) -> f64 {
    v.iter().fold(0.0, |m, x| m.max(x.abs()))
}

#[test]
fn the_foot_curvature_is_the_deflections_second_derivative() {
    let scene = scene(&["time.end=0.5"]);
    let sim = simulate_scene(&scene, &SimulationOptions::default(), &Silent).unwrap();
    let kappa = sim.trajectory.column("kappa_1_0").unwrap();
    // the assembled model, integrated by dopri5, its coordinates at every sample
    let model = AssembledModel::new(&scene.params).unwrap();
    let n = model.dof();
    let mut states: Vec<Vec<f64>> = Vec::new();
    let settings = Settings {
        rtol: 1e-11,
        atol: 1e-14,
        ..Settings::default()
    };
    simulate(
        &model,
        &rest_state(&model, 0.0),
        &scene.time,
        Method::Dopri5,
        &settings,
        &mut |_, y, _| states.push(y[..n].to_vec()),
        None,
    )
    .unwrap();
    assert_eq!(states.len(), kappa.len());
    // w''(0) one-sided, second order: (2 w0 - 5 w1 + 4 w2 - w3) / h^2
    let h = 1e-3 * scene.params.sections[0].length;
    let fd: Vec<f64> = states
        .iter()
        .map(|z| {
            let w = |i: f64| model.displacement(1, i * h, z);
            (2.0 * w(0.0) - 5.0 * w(1.0) + 4.0 * w(2.0) - w(3.0)) / (h * h)
        })
        .collect();
    let scale = max_abs(&kappa);
    assert!(scale > 1e-4, "the foot bends: {scale}");
    let worst = kappa
        .iter()
        .zip(&fd)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    eprintln!("kappa_1_0: worst difference {worst:e} 1/m of {scale:e}");
    assert!(
        worst <= 3e-5 * scale,
        "kappa_1_0 off by {worst:e} of {scale:e}"
    );
}

#[test]
fn the_load_acceleration_is_the_second_time_derivative_of_its_position() {
    let dt = 2e-5;
    let scene = scene(&["time.end=0.4", &format!("time.sample={dt}")]);
    let sim = simulate_scene(&scene, &SimulationOptions::default(), &Silent).unwrap();
    let t = &sim.trajectory;
    let position: Vec<f64> = t
        .column("vehicle")
        .unwrap()
        .iter()
        .zip(t.column("tip_rel").unwrap())
        .map(|(v, r)| v + r)
        .collect();
    let acc = t.column("acc_load").unwrap();
    // central differences, from 0.05 s on (after the step's fastest transients)
    let from = (0.05 / dt) as usize;
    let (mut worst, mut scale) = (0.0f64, 0.0f64);
    for i in from..position.len() - 1 {
        let fd = (position[i + 1] - 2.0 * position[i] + position[i - 1]) / (dt * dt);
        worst = worst.max((fd - acc[i]).abs());
        scale = scale.max(acc[i].abs());
    }
    assert!(scale > 0.1, "the load accelerates: {scale}");
    eprintln!("acc_load: worst difference {worst:e} m/s^2 of {scale:e}");
    assert!(
        worst <= 1e-5 * scale,
        "acc_load off by {worst:e} of {scale:e}"
    );
}
