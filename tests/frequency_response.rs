//! The frequency response and the disturbance input against statics: a single section held
//! at its foot, pushed at its tip by `F_load`, bends at zero frequency by the cantilever's
//! `F l^3 / (3 EI)`; the CSV's columns; the refusals.

mod common;

use telescopic::linear::LinearizeOptions;
use telescopic::linear::bode::{BodeOptions, frequency_response};
use telescopic::runtime::LinearInput;
use telescopic::{Error, Scene};

/// A single section held at its foot (a prescribed motion at rest), lightly damped.
fn held_cantilever() -> Scene {
    let o = [
        "sections.modes=8".to_string(),
        "sections.damping_ratio=0.02".to_string(),
    ];
    common::single_section("held-cantilever", "motion = 0.0", 1.0, 0.001, &o)
}

#[test]
fn a_tip_force_bends_the_held_cantilever_by_f_l3_over_3ei_at_low_frequency() {
    let scene = held_cantilever();
    let options = BodeOptions {
        inputs: vec![LinearInput::LoadForce],
        outputs: vec!["tip_rel".into(), "kappa_1_0".into()],
        from_hz: Some(1e-4),
        to_hz: Some(100.0),
        ..BodeOptions::default()
    };
    let response = frequency_response(&scene, &options).unwrap();
    let ei = 2.1e11 * 0.83e-8;
    let l: f64 = 1.35;
    let tip = &response.curves[0];
    assert_eq!(tip.column, "tip_rel_from_F_load");
    let static_tip = l.powi(3) / (3.0 * ei);
    let error = tip.magnitude[0] / static_tip - 1.0;
    eprintln!(
        "static tip compliance {:.6e} m/N vs F l^3/(3 EI) {static_tip:.6e}: {error:.2e}",
        tip.magnitude[0]
    );
    assert!(error.abs() < 2e-3, "{error}");
    assert!(
        tip.phase_deg[0].abs() < 1e-3,
        "in phase with the force: {}",
        tip.phase_deg[0]
    );
    // the curvature at the foot: M(0) = F l, so w''(0) = F l / EI (the slowest-converging
    // place of the series, docs/model.md section 7)
    let kappa = &response.curves[1];
    let error = kappa.magnitude[0] / (l / ei) - 1.0;
    eprintln!("static foot curvature per N: {error:.2e}");
    assert!(error.abs() < 0.06, "{error}");
    // the first resonance is marked and sits where the peak is
    let (peak, _) = tip
        .magnitude
        .iter()
        .enumerate()
        .fold((0, 0.0), |b, (i, &m)| if m > b.1 { (i, m) } else { b });
    let f1 = response.natural_hz[0];
    assert!(
        (response.f_hz[peak] / f1 - 1.0).abs() < 0.03,
        "peak at {} Hz, f1 {f1} Hz",
        response.f_hz[peak]
    );
}

#[test]
fn the_csv_has_a_magnitude_and_a_phase_column_per_output_and_bad_requests_are_refused() {
    let scene = Scene::load("scenes/test-rig.toml".as_ref(), &[]).unwrap();
    let options = BodeOptions {
        linear: LinearizeOptions {
            positions: vec![(2, 0.8)],
            ..LinearizeOptions::default()
        },
        outputs: vec!["tip_rel".into(), "vehicle".into()],
        ..BodeOptions::default()
    };
    let response = frequency_response(&scene, &options).unwrap();
    let mut csv = Vec::new();
    response.write_csv(&mut csv).unwrap();
    let text = String::from_utf8(csv).unwrap();
    let mut lines = text.lines();
    assert_eq!(
        lines.next().unwrap(),
        "f_hz,tip_rel_mag,tip_rel_phase_deg,vehicle_mag,vehicle_phase_deg"
    );
    assert_eq!(lines.count(), 400);
    assert!(response.f_hz.windows(2).all(|w| w[1] > w[0]));
    assert!(
        response
            .curves
            .iter()
            .all(|c| c.magnitude.iter().all(|m| m.is_finite()))
    );
    // the rigid vehicle: |vehicle / F| falls as 1 / (m w^2) below the first resonance
    let m = scene.params.total_mass();
    let w0 = 2.0 * std::f64::consts::PI * response.f_hz[0];
    let rigid = 1.0 / (m * w0 * w0);
    assert!((response.curves[1].magnitude[0] / rigid - 1.0).abs() < 0.02);
    for (options, flag) in [
        (
            BodeOptions {
                outputs: vec!["nonsense".into()],
                ..BodeOptions::default()
            },
            "BodeOptions::outputs",
        ),
        (
            BodeOptions {
                // the scene is force-driven: it has no acceleration input
                inputs: vec![LinearInput::VehicleAcceleration],
                ..BodeOptions::default()
            },
            "BodeOptions::inputs",
        ),
        (
            BodeOptions {
                outputs: vec!["tip_rel".into(), "vehicle".into(), "tip_rel".into()],
                ..BodeOptions::default()
            },
            "BodeOptions::outputs: `tip_rel` is named twice",
        ),
        (
            BodeOptions {
                from_hz: Some(-1.0),
                ..BodeOptions::default()
            },
            "BodeOptions::from_hz",
        ),
        (
            BodeOptions {
                from_hz: Some(10.0),
                to_hz: Some(1.0),
                ..BodeOptions::default()
            },
            "BodeOptions::to_hz",
        ),
        (
            BodeOptions {
                points: 1,
                ..BodeOptions::default()
            },
            "BodeOptions::points",
        ),
    ] {
        let e = frequency_response(&scene, &options).unwrap_err();
        assert!(
            matches!(e, Error::Option { .. }) && e.to_string().contains(flag),
            "{e}"
        );
    }
}
