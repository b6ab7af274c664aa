//! The model this crate generated at build time, run through the `telescopic` library's
//! analyses (`simulate_scene`, `compute_modes`, `linearize`), against the same analyses on
//! the quadrature-assembled model of the same configuration: two independent paths
//! (closed-form integrals, Symbolica and emitted code against Gauss-Legendre quadrature and
//! generic code).

use telescopic::analysis::modes::{ModesOptions, compute_modes};
use telescopic::linear::{LinearizeOptions, linearize};
use telescopic::run::models::ModelChoice;
use telescopic::run::{MethodChoice, SimulationOptions, simulate_scene};
use telescopic::runtime::Method;
use telescopic::{Scene, Silent};

fn scene() -> Scene {
    Scene::load(telescopic_downstream_example::SCENE.as_ref(), &[]).unwrap()
}

#[test]
fn the_generated_configuration_is_the_scenes() {
    let scene = scene();
    let key = telescopic::runtime::configuration_key(&scene.params);
    assert_eq!(key, "s3_m3x3x3_c2_external_clearance_fixed_force");
    assert_eq!(
        telescopic_downstream_example::CONFIGURATIONS,
        [key.as_str()]
    );
    // not one of the committed models: without this crate's set it has none
    let committed = telescopic::run::models::ModelRegistry::default();
    assert!(
        committed
            .build(&scene.params, ModelChoice::Generated)
            .is_err()
    );
}

#[test]
fn eigenfrequencies_equal_the_assembled_models() {
    let scene = scene();
    let modes = |model| {
        compute_modes(
            &scene,
            &ModesOptions {
                model,
                models: telescopic_downstream_example::models(),
                ..ModesOptions::default()
            },
        )
        .unwrap()
    };
    let (a, b) = (modes(ModelChoice::Generated), modes(ModelChoice::Assembled));
    assert!(
        a.model.contains("telescopic-downstream-example"),
        "{}",
        a.model
    );
    assert_eq!(b.model, "quadrature-assembled model");
    assert_eq!(a.rigid_modes, 1);
    assert_eq!(
        a.frequencies_hz.len(),
        8,
        "9 coordinates, one rigid translation"
    );
    assert_eq!(a.frequencies_hz.len(), b.frequencies_hz.len());
    for (fa, fb) in a.frequencies_hz.iter().zip(&b.frequencies_hz) {
        assert!((fa - fb).abs() <= 1e-9 * fb, "{fa} Hz against {fb} Hz");
    }
    // a graduated steel telescope of ~4 m: its first bending mode near 1 Hz
    assert!(
        a.frequencies_hz[0] > 0.3 && a.frequencies_hz[0] < 3.0,
        "{:?}",
        a.frequencies_hz
    );
}

#[test]
fn a_short_simulation_equals_the_assembled_models() {
    let mut scene = scene();
    scene.time.end = 0.3;
    let run = |model| {
        let options = SimulationOptions {
            method: MethodChoice::Method(Method::Dop853),
            rtol: Some(1e-11),
            atol: Some(1e-14),
            model,
            models: telescopic_downstream_example::models(),
            ..SimulationOptions::default()
        };
        simulate_scene(&scene, &options, &Silent).unwrap()
    };
    let (generated, assembled) = (run(ModelChoice::Generated), run(ModelChoice::Assembled));
    assert!(generated.model.contains("telescopic-downstream-example"));
    let a = generated.trajectory.column("tip_rel").unwrap();
    let b = assembled.trajectory.column("tip_rel").unwrap();
    assert_eq!(a.len(), 301);
    let worst = a
        .iter()
        .zip(&b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max);
    let peak = b.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let (switches_a, switches_b) = (
        generated.trajectory.stats.switches,
        assembled.trajectory.stats.switches,
    );
    eprintln!(
        "tip_rel peak {peak:e} m, largest difference {worst:e} m, switches {switches_a}/{switches_b}"
    );
    assert!(peak > 1e-4, "the pulse moves the load: peak {peak} m");
    assert!(
        worst <= 1e-9,
        "generated and assembled differ by {worst} m in tip_rel"
    );
    assert_eq!(switches_a, switches_b);
}

#[test]
fn the_linear_model_equals_the_assembled_models() {
    let scene = scene();
    let export = |model| {
        linearize(
            &scene,
            &LinearizeOptions {
                model,
                models: telescopic_downstream_example::models(),
                ..LinearizeOptions::default()
            },
        )
        .unwrap()
    };
    let (a, b) = (
        export(ModelChoice::Generated),
        export(ModelChoice::Assembled),
    );
    assert!(
        a.model.contains("telescopic-downstream-example"),
        "{}",
        a.model
    );
    assert_eq!(a.states, b.states);
    assert_eq!(a.outputs, b.outputs);
    let (ma, mb) = (&a.points[0], &b.points[0]);
    for (x, y) in [(&ma.a, &mb.a), (&ma.b, &mb.b), (&ma.c, &mb.c)] {
        let scale = y.amax().max(1e-300);
        let worst = (x - y).amax();
        assert!(worst <= 1e-9 * scale, "differ by {worst} against {scale}");
    }
}
