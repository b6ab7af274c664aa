//! Structural damping against its definitions: a single section with a modal damping ratio
//! rings down at that ratio (logarithmic decrement of the simulated free vibration), the
//! damped eigenvalues carry it exactly, Rayleigh damping's ratios follow
//! `alpha / (2 omega) + beta omega / 2`, and the linear model's `A` carries the damping.

mod common;

use telescopic::Silent;
use telescopic::run::{SimulationOptions, simulate_scene};
use telescopic::runtime::{
    AssembledModel, ContactMode, Lpv, Scene, damped_modes, eigenvalues, modal_analysis,
};

/// A single section on its vehicle (no contacts), knocked by a 5 ms force pulse.
fn cantilever(extra: &[&str]) -> Scene {
    let o: Vec<String> = extra.iter().map(|s| s.to_string()).collect();
    let pulse = r#"force = { kind = "piecewise-constant", times = [0, 0.005], values = [400, 0] }"#;
    common::single_section("cantilever", pulse, 4.0, 0.0002, &o)
}

/// The damping ratio of the ring-down of `x` (sampled at `dt`) after `from` s: a least-squares
/// line through the logarithms of its positive peaks gives the decrement per period `delta`,
/// `zeta = delta / sqrt(4 pi^2 + delta^2)`.
fn ring_down_ratio(x: &[f64], dt: f64, from: f64) -> (f64, usize) {
    let start = (from / dt) as usize;
    let peaks: Vec<f64> = (start + 1..x.len() - 1)
        .filter(|&i| x[i] > 0.0 && x[i] > x[i - 1] && x[i] >= x[i + 1])
        .map(|i| x[i].ln())
        .collect();
    let n = peaks.len() as f64;
    let mean_i = (n - 1.0) / 2.0;
    let mean_y = peaks.iter().sum::<f64>() / n;
    let (mut sxy, mut sxx) = (0.0, 0.0);
    for (i, y) in peaks.iter().enumerate() {
        sxy += (i as f64 - mean_i) * (y - mean_y);
        sxx += (i as f64 - mean_i).powi(2);
    }
    let delta = -sxy / sxx;
    (
        delta / (4.0 * std::f64::consts::PI.powi(2) + delta * delta).sqrt(),
        peaks.len(),
    )
}

#[test]
fn a_modal_damping_ratio_is_the_ring_downs_logarithmic_decrement() {
    for (setting, first_mode_ratio) in [
        ("sections.damping_ratio=0.02", 0.02),
        ("sections.damping_ratio=[0.05, 0.01]", 0.05),
    ] {
        let scene = cantilever(&[setting]);
        let sim = simulate_scene(&scene, &SimulationOptions::default(), &Silent).unwrap();
        let tip = sim.trajectory.column("tip_rel").unwrap();
        // the higher modes (40 Hz and up) have died out after 1 s
        let (zeta, peaks) = ring_down_ratio(&tip, scene.time.sample, 1.0);
        eprintln!("{setting}: ring-down ratio {zeta:.6} over {peaks} peaks");
        assert!(peaks >= 6, "{peaks} peaks");
        assert!(
            (zeta - first_mode_ratio).abs() < 0.01 * first_mode_ratio,
            "{setting}: ring-down ratio {zeta} vs {first_mode_ratio}"
        );
        // the damped eigenvalues carry the ratio of every mode exactly
        let model = AssembledModel::new(&scene.params).unwrap();
        let modes = modal_analysis(&model, 0.0).unwrap();
        let damped = damped_modes(&model, &modes).unwrap();
        for (i, m) in damped.iter().enumerate() {
            let want = scene.params.damping.modal_ratio(i);
            assert!(m.from_eigenvalues);
            assert!(
                (m.ratio - want).abs() < 1e-9,
                "mode {i}: {} vs {want}",
                m.ratio
            );
            let expected_hz = m.undamped_hz * (1.0 - want * want).sqrt();
            assert!((m.damped_hz - expected_hz).abs() < 1e-9 * expected_hz);
        }
    }
}

#[test]
fn rayleigh_ratios_follow_alpha_over_two_omega_plus_beta_omega_over_two() {
    let (alpha, beta) = (0.8, 1.5e-4);
    let scene = cantilever(&[
        &format!("sections.rayleigh_alpha={alpha}"),
        &format!("sections.rayleigh_beta={beta}"),
    ]);
    let model = AssembledModel::new(&scene.params).unwrap();
    let modes = modal_analysis(&model, 0.0).unwrap();
    let damped = damped_modes(&model, &modes).unwrap();
    assert_eq!(damped.len(), 4);
    for m in &damped {
        let omega = 2.0 * std::f64::consts::PI * m.undamped_hz;
        let want = alpha / (2.0 * omega) + beta * omega / 2.0;
        eprintln!(
            "{:.3} Hz: zeta {:.6} (Rayleigh {want:.6})",
            m.undamped_hz, m.ratio
        );
        assert!(
            (m.ratio - want).abs() < 1e-8 * want.max(1e-3),
            "{} vs {want}",
            m.ratio
        );
    }
}

#[test]
fn the_linear_model_carries_the_structural_damping() {
    let scene = cantilever(&["sections.damping_ratio=0.03"]);
    let model = AssembledModel::new(&scene.params).unwrap();
    let lpv = Lpv::new(&model, ContactMode::Closed).unwrap();
    let linear = lpv.at(&[], &[]).unwrap();
    let lambdas = eigenvalues(linear.a.clone(), "test").unwrap();
    let elastic: Vec<f64> = lambdas
        .iter()
        .filter(|l| l.im > 1.0)
        .map(|l| -l.re / l.norm())
        .collect();
    assert_eq!(elastic.len(), 4, "{lambdas:?}");
    for zeta in elastic {
        assert!((zeta - 0.03).abs() < 1e-9, "{zeta}");
    }
    // without damping the elastic eigenvalues are imaginary
    let undamped = AssembledModel::new(&cantilever(&[]).params).unwrap();
    let a0 = Lpv::new(&undamped, ContactMode::Closed)
        .unwrap()
        .at(&[], &[])
        .unwrap()
        .a;
    let worst = eigenvalues(a0, "test")
        .unwrap()
        .iter()
        .filter(|l| l.im > 1.0)
        .fold(0.0_f64, |m, l| m.max((l.re / l.norm()).abs()));
    assert!(worst < 1e-9, "{worst}");
}
