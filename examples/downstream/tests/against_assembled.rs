//! The model this crate generated at build time against the runtime's quadrature-assembled
//! model of the same configuration: two independent paths (closed-form integrals, Symbolica
//! and emitted code against Gauss-Legendre quadrature and generic code).

use telescopic_runtime::{
    AssembledModel, Method, Model, Scene, Settings, modal_analysis, rest_state, simulate,
};

fn scene() -> Scene {
    Scene::load(telescopic_downstream_example::SCENE.as_ref(), &[]).unwrap()
}

#[test]
fn the_generated_configuration_is_the_scenes() {
    let scene = scene();
    let key = telescopic_runtime::configuration_key(&scene.params);
    assert_eq!(key, "s3_m3x3x3_c2_external_clearance_fixed_force");
    assert_eq!(
        telescopic_downstream_example::CONFIGURATIONS,
        [key.as_str()]
    );
}

#[test]
fn eigenfrequencies_equal_the_assembled_models() {
    let scene = scene();
    let generated = telescopic_downstream_example::prepare(&scene.params)
        .unwrap()
        .unwrap();
    let assembled = AssembledModel::new(&scene.params).unwrap();
    let a = modal_analysis(generated.as_ref(), 0.0).unwrap();
    let b = modal_analysis(&assembled, 0.0).unwrap();
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

/// `tip_rel` at every sample of a tight dop853 run on `model` over the first `end` seconds.
fn tip(model: &dyn Model, end: f64) -> (Vec<f64>, u64) {
    let mut scene = scene();
    scene.time.end = end;
    let names = model.output_names();
    let col = names.iter().position(|n| n == "tip_rel").unwrap();
    let mut out = vec![0.0; names.len()];
    let mut tip = Vec::new();
    let mut observe = |t: f64, y: &[f64], ydot: &[f64]| {
        model.outputs(t, y, ydot, &mut out);
        tip.push(out[col]);
    };
    let settings = Settings {
        rtol: 1e-11,
        atol: 1e-14,
        ..Settings::default()
    };
    let y0 = rest_state(model, 0.0);
    let stats = simulate(
        model,
        &y0,
        &scene.time,
        Method::Dop853,
        &settings,
        &mut observe,
        None,
    )
    .unwrap();
    (tip, stats.switches)
}

#[test]
fn a_short_simulation_equals_the_assembled_models() {
    let scene = scene();
    let generated = telescopic_downstream_example::prepare(&scene.params)
        .unwrap()
        .unwrap();
    let assembled = AssembledModel::new(&scene.params).unwrap();
    let (a, switches_a) = tip(generated.as_ref(), 0.3);
    let (b, switches_b) = tip(&assembled, 0.3);
    assert_eq!(a.len(), 301);
    let worst = a
        .iter()
        .zip(&b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max);
    let peak = b.iter().fold(0.0f64, |m, v| m.max(v.abs()));
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
