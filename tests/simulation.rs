//! End-to-end simulation of the shipped scenes on their generated models: every method
//! against every other, the case-study's wedged upper section and free flight, the
//! three-section telescope.
mod common;
use common::{generated, scene};

use nalgebra::{Complex, DMatrix};
use telescopic_runtime::integrate::stability::{
    STEP_CAP_SAFETY, closed_contact_stable_step, closed_contact_step_cap, stability_report,
};
use telescopic_runtime::{
    ContactState, Method, Model, RunStats, Scene, Settings, SimError, model::rest_state, simulate,
};

/// Output columns of a run: `(names, rows [t, outputs...])`.
fn outputs(
    scene: &Scene,
    model: &dyn Model,
    method: Method,
    settings: &Settings,
) -> (Vec<String>, Vec<Vec<f64>>) {
    let (names, rows, _) = outputs_and_stats(scene, model, method, settings);
    (names, rows)
}

/// [`outputs`] and the run's counts.
fn outputs_and_stats(
    scene: &Scene,
    model: &dyn Model,
    method: Method,
    settings: &Settings,
) -> (Vec<String>, Vec<Vec<f64>>, RunStats) {
    let names = model.output_names();
    let mut rows = Vec::new();
    let mut out = vec![0.0; names.len()];
    let y0 = rest_state(model, scene.time.start);
    let stats = simulate(
        model,
        &y0,
        &scene.time,
        method,
        settings,
        &mut |t, y, ydot| {
            model.outputs(t, y, ydot, &mut out);
            let mut row = vec![t];
            row.extend_from_slice(&out);
            rows.push(row);
        },
        None,
    )
    .unwrap_or_else(|e| panic!("{} with {method}: {e}", scene.name));
    (names, rows, stats)
}

fn column(names: &[String], name: &str) -> usize {
    1 + names.iter().position(|n| n == name).unwrap()
}

/// Every method at a tight setting.
fn tight_methods() -> Vec<(Method, Settings)> {
    let adaptive = |rtol: f64| Settings {
        rtol,
        atol: rtol * 1e-3,
        ..Settings::default()
    };
    let fixed = |dt: f64| Settings {
        dt: Some(dt),
        ..Settings::default()
    };
    vec![
        (Method::Dopri5, adaptive(1e-11)),
        (
            Method::GeneralizedAlpha {
                rho_inf: 0.8,
                adaptive: true,
            },
            adaptive(1e-10),
        ),
        (Method::Dop853, adaptive(1e-10)),
        (Method::Esdirk, adaptive(1e-10)),
        // its step count grows fast with the tolerance (docs/numerics.md): 1e-7 is tight
        // enough for these checks' 1e-6 m
        (Method::Imex, adaptive(1e-7)),
        (
            Method::Bdf {
                max_order: 5,
                adaptive: true,
            },
            adaptive(1e-10),
        ),
        (Method::Rk4, fixed(2e-5)),
        (Method::Verlet, fixed(2e-6)),
    ]
}

/// Largest `|tip_rel|` difference between each method and the first, up to `until` (s).
fn agreement(name: &str, until: f64) -> Vec<(String, f64)> {
    let scene = scene(name, &[]);
    let model = generated(&scene);
    let runs: Vec<(Method, Vec<Vec<f64>>, usize)> = tight_methods()
        .into_iter()
        .map(|(method, settings)| {
            let (names, rows) = outputs(&scene, model.as_ref(), method, &settings);
            (method, rows, column(&names, "tip_rel"))
        })
        .collect();
    let (_, reference, tip) = &runs[0];
    runs[1..]
        .iter()
        .map(|(method, rows, _)| {
            assert_eq!(rows.len(), reference.len());
            let worst = rows
                .iter()
                .zip(reference)
                .filter(|(r, _)| r[0] <= until)
                .map(|(r, q)| (r[*tip] - q[*tip]).abs())
                .fold(0.0, f64::max);
            eprintln!("{name}: {method} vs dopri5, worst |tip_rel| difference up to {until} s: {worst:.2e} m");
            (method.name(), worst)
        })
        .collect()
}

#[test]
fn methods_agree_on_the_linear_scenes_over_the_whole_span() {
    for name in ["adams-linear", "case-study-no-clearance"] {
        for (method, worst) in agreement(name, f64::INFINITY) {
            assert!(
                worst < 1e-6,
                "{name}: {method} differs from dopri5 by {worst:e} m"
            );
        }
    }
}

#[test]
fn methods_agree_on_adams_clearance_inside_its_predictability_horizon() {
    for (method, worst) in agreement("adams-clearance", 0.3) {
        assert!(
            worst < 1e-6,
            "adams-clearance: {method} differs from dopri5 by {worst:e} m on [0, 0.3] s"
        );
    }
}

/// Fraction of the rows with `lo <= t < hi` that satisfy `pred`.
fn fraction(rows: &[Vec<f64>], lo: f64, hi: f64, pred: impl Fn(&[f64]) -> bool) -> f64 {
    let window: Vec<&Vec<f64>> = rows.iter().filter(|r| r[0] >= lo && r[0] < hi).collect();
    window.iter().filter(|r| pred(r)).count() as f64 / window.len() as f64
}

#[test]
fn case_study_wedges_while_driven_and_flies_free_after() {
    let scene = scene("case-study", &[]);
    let model = generated(&scene);
    let half_band = 0.5 * scene.params.contact.clearance;
    let methods = [
        (Method::Dopri5, Settings::default()),
        (
            Method::Rk4,
            Settings {
                dt: Some(5e-5),
                ..Settings::default()
            },
        ),
    ];
    for (method, settings) in methods {
        let (names, rows) = outputs(&scene, model.as_ref(), method, &settings);
        let (xi0, xi1) = (column(&names, "xi_2_0"), column(&names, "xi_2_1"));
        let (f0, f1) = (column(&names, "f_2_0"), column(&names, "f_2_1"));
        // F = +100 N on [0, 4), -100 N on [8, 12); half a second to fall into the guide
        for (lo, hi, sign) in [(0.5, 4.0, 1.0), (8.5, 12.0, -1.0)] {
            // tilted across the clearance, the way the acceleration pushes it
            let oriented = fraction(&rows, lo, hi, |r| {
                r[xi0] * sign > 0.0 && r[xi1] * sign < 0.0
            });
            // both contacts pressed at once, and then always in opposite directions
            let both = fraction(&rows, lo, hi, |r| r[f0] != 0.0 && r[f1] != 0.0);
            let wedge = fraction(&rows, lo, hi, |r| r[f0] * r[f1] < 0.0);
            eprintln!(
                "case-study {method} [{lo}, {hi}) s: tilted with the drive {oriented:.2}, both contacts loaded {both:.2}, as a wedge {wedge:.2}"
            );
            assert!(
                oriented > 0.9,
                "{method}: tilted with the drive only {oriented:.2} of [{lo}, {hi})"
            );
            assert!(
                both > 0.5,
                "{method}: both contacts loaded only {both:.2} of [{lo}, {hi})"
            );
            // (not all: the Kelvin-Voigt law turns adhesive for a moment before separation,
            // docs/model.md section 6, so a force may briefly have the other sign)
            assert!(
                wedge >= 0.99 * both,
                "{method}: both contacts loaded in the same direction too often ({both:.3} vs {wedge:.3})"
            );
        }
        // after the drive stops: stretches with both gaps inside the band
        let mut longest = 0.0f64;
        let mut start = None;
        for r in rows.iter().filter(|r| r[0] > 12.0) {
            let free = r[xi0].abs() <= half_band && r[xi1].abs() <= half_band;
            match (free, start) {
                (true, None) => start = Some(r[0]),
                (false, Some(s)) => {
                    longest = longest.max(r[0] - s);
                    start = None;
                }
                _ => {}
            }
        }
        eprintln!("case-study {method}: longest free flight after 12 s {longest:.3} s");
        assert!(
            longest >= 0.05,
            "{method}: no free motion after 12 s (longest {longest} s)"
        );
    }
}

#[test]
fn three_sections_run_to_the_end_and_stay_bounded() {
    let scene = scene("three-section", &[]);
    let model = generated(&scene);
    let (names, rows) = outputs(&scene, model.as_ref(), Method::Dopri5, &Settings::default());
    assert_eq!(rows.last().unwrap()[0], scene.time.end);
    let tip = column(&names, "tip_rel");
    let worst_tip = rows.iter().map(|r| r[tip].abs()).fold(0.0, f64::max);
    let band = 0.5 * scene.params.contact.clearance;
    let worst_gap = names
        .iter()
        .enumerate()
        .filter(|(_, n)| n.starts_with("xi_"))
        .flat_map(|(i, _)| rows.iter().map(move |r| r[i + 1].abs()))
        .fold(0.0, f64::max);
    eprintln!("three-section: max |tip_rel| {worst_tip:.3} m, max |xi| {worst_gap:.5} m");
    assert!(worst_tip < 1.0, "tip_rel reached {worst_tip} m");
    // penetrations are micrometres: the gaps stay at the guides
    assert!(
        worst_gap < band + 1e-3,
        "a gap reached {worst_gap} m (band {band} m)"
    );
}

/// The run's error, if it fails.
fn run_error(scene: &Scene, model: &dyn Model, method: Method, dt: f64) -> Option<SimError> {
    let y0 = rest_state(model, scene.time.start);
    let settings = Settings {
        dt: Some(dt),
        ..Settings::default()
    };
    simulate(
        model,
        &y0,
        &scene.time,
        method,
        &settings,
        &mut |_, _, _| {},
        None,
    )
    .err()
}

#[test]
fn explicit_methods_are_stable_below_their_limit_and_stopped_above_it() {
    for name in ["adams-linear", "adams-clearance"] {
        let scene = scene(name, &[]);
        let model = generated(&scene);
        let r = stability_report(model.as_ref(), scene.time.start).unwrap();
        for (method, limit) in [(Method::Rk4, r.rk4_step), (Method::Verlet, r.verlet_step)] {
            let settings = Settings {
                dt: Some(0.9 * limit),
                ..Settings::default()
            };
            let (names, rows) = outputs(&scene, model.as_ref(), method, &settings);
            let tip = column(&names, "tip_rel");
            let peak = rows.iter().map(|r| r[tip].abs()).fold(0.0, f64::max);
            eprintln!("{name}: {method} at 0.9 x {limit:.4e} s: peak |tip_rel| {peak:.3} m");
            assert!(peak < 1.0, "{name}: {method} at 0.9 of its limit: {peak} m");
            // with clearance the limit is the closed-contact one, a bound: all contacts are
            // rarely pressed at once, and rk4 survives 1.26 x it on adams-clearance
            if name != "adams-linear" {
                continue;
            }
            let err = run_error(&scene, model.as_ref(), method, 1.1 * limit)
                .unwrap_or_else(|| panic!("{name}: {method} at 1.1 of its limit did not fail"));
            let msg = err.to_string();
            assert!(matches!(err, SimError::Diverged { .. }), "{msg}");
            assert!(msg.contains("above the stability limit"), "{msg}");
        }
    }
}

#[test]
fn implicit_methods_stay_bounded_and_accurate_at_100_times_the_explicit_limit() {
    let scene = scene("adams-linear", &[]);
    let model = generated(&scene);
    let r = stability_report(model.as_ref(), scene.time.start).unwrap();
    let dt = 100.0 * r.rk4_step;
    let reference = outputs(
        &scene,
        model.as_ref(),
        Method::Dopri5,
        &Settings {
            rtol: 1e-10,
            atol: 1e-13,
            ..Settings::default()
        },
    );
    let tip = column(&reference.0, "tip_rel");
    let peak = reference.1.iter().map(|r| r[tip].abs()).fold(0.0, f64::max);
    for name in ["galpha-fixed", "bdf2-fixed"] {
        let method = Method::from_name(name).unwrap();
        let settings = Settings {
            dt: Some(dt),
            ..Settings::default()
        };
        let (_, rows) = outputs(&scene, model.as_ref(), method, &settings);
        let worst = rows
            .iter()
            .zip(&reference.1)
            .map(|(a, b)| (a[tip] - b[tip]).abs())
            .fold(0.0, f64::max);
        eprintln!(
            "{name} at dt = {dt:.3e} s (100 x the rk4 limit): worst tip_rel error {:.2} % of the peak {peak:.3} m",
            100.0 * worst / peak
        );
        assert!(worst < 0.02 * peak, "{name}: {worst} m of {peak} m");
    }
}

/// Dormand-Prince 5(4)'s stability polynomial (the 5th-order propagated solution of its 7
/// stages): `sum_{k<=5} z^k / k! + z^6 / 600`.
fn dopri5_stability(z: Complex<f64>) -> Complex<f64> {
    let mut term = Complex::new(1.0, 0.0);
    let mut sum = term;
    for k in 1..=5 {
        term *= z / k as f64;
        sum += term;
    }
    sum + z.powi(6) / 600.0
}

#[test]
fn the_dopri5_stable_step_is_its_stability_polynomial_on_the_closed_contact_eigenvalues() {
    // two paths: the runtime bisects on the spectral radius of real dopri5 steps of the
    // model; here the textbook polynomial is evaluated on the Jacobian's eigenvalues
    let scene = scene("adams-clearance", &[]);
    let model = generated(&scene);
    let step = closed_contact_stable_step(model.as_ref(), Method::Dopri5, &scene.time).unwrap();
    let n = 2 * model.dof();
    let closed = vec![ContactState::Upper; model.layout().contact_count()];
    let mut jac = DMatrix::zeros(n, n);
    model.jacobian(scene.time.start, &vec![0.0; n], Some(&closed), &mut jac);
    let eigenvalues = jac.complex_eigenvalues();
    let stable = |h: f64| {
        eigenvalues
            .iter()
            .all(|&l| dopri5_stability(l * h).norm() <= 1.0 + 1e-7)
    };
    let (mut lo, mut hi) = (0.0, 1e-3);
    assert!(!stable(hi));
    while hi - lo > 1e-9 * hi {
        let mid = 0.5 * (lo + hi);
        if stable(mid) { lo = mid } else { hi = mid }
    }
    eprintln!("dopri5 stable step {lo:.6e} s from the polynomial, {step:.6e} s from its steps");
    approx::assert_relative_eq!(step, lo, max_relative = 2e-3);
    // the cap is dop853's alone, below its own stable step
    assert!(closed_contact_step_cap(model.as_ref(), Method::Dopri5, &scene.time).is_none());
    let dop853 = closed_contact_stable_step(model.as_ref(), Method::Dop853, &scene.time).unwrap();
    let cap = closed_contact_step_cap(model.as_ref(), Method::Dop853, &scene.time).unwrap();
    approx::assert_relative_eq!(cap, STEP_CAP_SAFETY * dop853);
}

/// `tip_rel` samples and the run's counts.
fn tip_and_stats(
    scene: &Scene,
    model: &dyn Model,
    method: Method,
    settings: &Settings,
) -> (Vec<f64>, RunStats) {
    let (names, rows, stats) = outputs_and_stats(scene, model, method, settings);
    let tip = column(&names, "tip_rel");
    (rows.iter().map(|r| r[tip]).collect(), stats)
}

#[test]
fn the_step_cap_takes_dop853_off_the_stability_boundary() {
    // the whole scene for the step counts; errors pointwise inside the predictability
    // horizon (0.4 s), against a tight run on [0, 0.3] s
    let scene = scene("adams-clearance", &[]);
    let model = generated(&scene);
    let tight = Settings {
        rtol: 1e-11,
        atol: 1e-14,
        ..Settings::default()
    };
    let horizon = self::scene("adams-clearance", &["time.end=0.3"]);
    let (reference, _) = tip_and_stats(&horizon, model.as_ref(), Method::Dopri5, &tight);
    let method = Method::Dop853;
    let run = |step_cap: bool| {
        let settings = Settings {
            rtol: 1e-6,
            atol: 1e-9,
            step_cap,
            ..Settings::default()
        };
        let (tips, stats) = tip_and_stats(&scene, model.as_ref(), method, &settings);
        let worst = tips
            .iter()
            .zip(&reference)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        (worst, stats)
    };
    let (capped_error, capped) = run(true);
    let (free_error, free) = run(false);
    eprintln!(
        "{method}: capped at {:.3e} s: {} steps, {} rejected, {} rhs, error {capped_error:.2e} m; \
         uncapped: {} steps, {} rejected, {} rhs, error {free_error:.2e} m",
        capped.step_cap.unwrap(),
        capped.steps,
        capped.rejected,
        capped.rhs_evals,
        free.steps,
        free.rejected,
        free.rhs_evals
    );
    assert!(free.step_cap.is_none());
    // the boundary hover: the uncapped control grows into instability and rejects
    assert!(
        2 * capped.rejected < free.rejected,
        "{method}: {} rejected with the cap, {} without",
        capped.rejected,
        free.rejected
    );
    for (what, e) in [("capped", capped_error), ("uncapped", free_error)] {
        assert!(e < 1e-6, "{method} {what}: tip_rel error {e:e} m");
    }
}

/// One rule of "closed" and one sampled switch counter: none at zero clearance (the linear
/// law has no free band, whatever the sign of the gaps), and with clearance no more than the
/// integrator's own count of switches (it sees those between samples too) and not none.
#[test]
fn the_sampled_switch_count_is_zero_without_clearance_and_bounded_by_the_runs() {
    use telescopic::run::{SimulationOptions, simulate_scene};
    let options = SimulationOptions {
        error_estimate: false,
        ..SimulationOptions::default()
    };
    let linear = scene("case-study-no-clearance", &[]);
    let run = simulate_scene(&linear, &options, &telescopic::Silent).unwrap();
    let gaps = run.trajectory.gap_columns();
    let sign_changes = run
        .trajectory
        .rows
        .windows(2)
        .filter(|w| gaps.iter().any(|&g| (w[0][g] > 0.0) != (w[1][g] > 0.0)))
        .count();
    assert!(
        sign_changes > 0,
        "the gaps change sign: the old counter counted those"
    );
    assert_eq!(
        run.trajectory.sampled_switches(&linear.params.contact, 0.0),
        0
    );
    let rattling = scene("adams-clearance", &[]);
    let run = simulate_scene(&rattling, &options, &telescopic::Silent).unwrap();
    let sampled = run
        .trajectory
        .sampled_switches(&rattling.params.contact, 0.0) as u64;
    assert!(
        sampled > 0 && sampled <= run.trajectory.stats.switches,
        "{sampled} sampled, {} in the run",
        run.trajectory.stats.switches
    );
}
