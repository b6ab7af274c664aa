//! The whole error against the beams: the finite-element reference converges at its order;
//! the Ritz models approach it at their measured rates; a run's truncation estimate bounds
//! its true difference from the beams within a stated factor on every shipped scene with
//! fixed positions; `--accuracy` meets its bound against the beams (fixed positions and, on
//! a scene it was not tuned for, sliding contacts) or the most refined Ritz model (moving
//! positions); `--modes-as-given` keeps the scene's model.

use telescopic::analysis::beam_reference::{BeamResponse, beam_response, element_response};
use telescopic::run::error_budget::{ErrorBudget, Statistic, WindowEnd};
use telescopic::run::stress::Station;
use telescopic::run::{
    MethodReason, ModelSize, NoPrediction, Simulation, SimulationOptions, SizePrediction,
    Trajectory, estimate_error, simulate_scene,
};
use telescopic::{Scene, Silent};
use telescopic_runtime::{AssembledModel, Basis, ElementModel, modal_analysis};

/// The estimate may stand this far either way of the true error (measured on the shipped
/// fixed-position scenes: 0.62 to 2.7, docs/numerics.md).
const ESTIMATE_FACTOR: f64 = 3.0;
/// Below this the true error is the finite-element reference's own (m): 32 and 64 elements
/// per section agree to 2e-7 m on adams-linear; 16 to a few 1e-8 m in the clearance scenes'
/// windows.
const REFERENCE_FLOOR: f64 = 3e-7;

fn scene(name: &str) -> Scene {
    Scene::load(format!("scenes/{name}.toml").as_ref(), &[]).unwrap()
}

fn sized(scene: &Scene, basis: Basis, modes: usize) -> Scene {
    ModelSize { basis, modes }.apply(scene)
}

fn column(t: &Trajectory, name: &str) -> Vec<f64> {
    t.column(name).unwrap_or_else(|| panic!("no column {name}"))
}

/// Largest `|a - b|` of a column up to time `until` (s).
fn difference_until(a: &Trajectory, b: &Trajectory, name: &str, until: f64) -> f64 {
    let (x, y) = (column(a, name), column(b, name));
    let t = column(a, "t");
    x.iter()
        .zip(&y)
        .zip(&t)
        .take_while(|(_, t)| **t <= until + 1e-12)
        .map(|((x, y), _)| (x - y).abs())
        .fold(0.0, f64::max)
}

/// RMS and peak of `tip_rel` after `from` (s).
fn tip_statistics(t: &Trajectory, from: f64) -> (f64, f64) {
    let times = column(t, "t");
    let tip: Vec<f64> = column(t, "tip_rel")
        .into_iter()
        .zip(times)
        .filter(|(_, t)| *t > from)
        .map(|(v, _)| v)
        .collect();
    let rms = (tip.iter().map(|v| v * v).sum::<f64>() / tip.len() as f64).sqrt();
    (rms, tip.iter().fold(0.0_f64, |m, v| m.max(v.abs())))
}

fn budget(sim: &Simulation) -> &ErrorBudget {
    sim.error.as_ref().expect("the run estimates its error")
}

fn statistic(b: &ErrorBudget, which: Statistic) -> f64 {
    let t = b.truncation.as_ref().unwrap();
    t.statistics
        .iter()
        .find(|s| s.statistic == which)
        .unwrap()
        .relative
}

#[test]
fn the_elements_converge_at_fourth_order_and_the_ritz_models_approach_them_from_above() {
    let scene = scene("adams-linear");
    let f = |n: usize| {
        ElementModel::new(&scene.params, n)
            .unwrap()
            .frequencies_hz(5)
            .unwrap()
    };
    let (f16, f32, f64_) = (f(16), f(32), f(64));
    for i in 1..5 {
        // Hermite elements: frequencies converge as h^4, so halving h divides the change by 16
        let ratio = (f16[i] - f32[i]).abs() / (f32[i] - f64_[i]).abs();
        eprintln!(
            "f{}: {:.8} {:.8} {:.8} Hz, ratio {ratio:.1}",
            i + 1,
            f16[i],
            f32[i],
            f64_[i]
        );
        assert!((10.0..25.0).contains(&ratio), "f{}: {ratio}", i + 1);
    }
    let ritz = |basis, n| {
        let s = sized(&scene, basis, n);
        modal_analysis(&AssembledModel::new(&s.params).unwrap(), 0.0)
            .unwrap()
            .frequencies_hz
    };
    // Rayleigh-Ritz: every Ritz frequency lies above the beams', and falls with the modes
    let errors: Vec<f64> = [5, 8, 12]
        .iter()
        .map(|&n| {
            let r = ritz(Basis::Modes, n);
            for i in 0..5 {
                assert!(r[i] > f32[i] * (1.0 - 1e-9), "{n} modes, f{}", i + 1);
            }
            r[0] / f32[0] - 1.0
        })
        .collect();
    eprintln!("f1 errors of the paper's 5, 8, 12 modes: {errors:?}");
    // the paper's f1 converges at about N^-5 from 5 to 8 and N^-4 from 8 to 12 modes
    let rate = |a: f64, b: f64, na: f64, nb: f64| (a / b).ln() / (nb / na).ln();
    assert!(
        (4.0..6.5).contains(&rate(errors[0], errors[1], 5.0, 8.0)),
        "{errors:?}"
    );
    assert!(
        (3.0..5.5).contains(&rate(errors[1], errors[2], 8.0, 12.0)),
        "{errors:?}"
    );
    // the static correction shapes: 3 modes beat the paper's 12 fifty times over in f1
    let corrected = ritz(Basis::ModesAndStatic, 3);
    let e = corrected[0] / f32[0] - 1.0;
    eprintln!("f1 error with 3 modes and the static correction shapes: {e:.2e}");
    assert!(
        e > -1e-9 && e < errors[2] / 50.0,
        "{e} against {}",
        errors[2]
    );
}

#[test]
fn the_linear_scenes_truncation_estimate_bounds_its_error_against_the_beams() {
    let scene = scene("adams-linear");
    let stations = Station::parse_list("1:0,1:0.675").unwrap();
    let beams = element_response(&scene, 32, &stations, &Silent).unwrap();
    let finer = element_response(&scene, 64, &[], &Silent).unwrap();
    let own = difference_until(&beams.trajectory, &finer.trajectory, "tip_rel", 5.0);
    eprintln!("32 against 64 elements: {own:.2e} m");
    assert!(own < 5e-7, "{own}");
    let options = SimulationOptions {
        stations: stations.clone(),
        ..SimulationOptions::default()
    };
    for (basis, modes) in [
        (Basis::Modes, 5),
        (Basis::Modes, 8),
        (Basis::ModesAndStatic, 2),
        (Basis::ModesAndStatic, 3),
    ] {
        let sim = simulate_scene(&sized(&scene, basis, modes), &options, &Silent).unwrap();
        let b = budget(&sim);
        assert_eq!(b.window.reason, WindowEnd::SpanEnd);
        let estimate = b.truncation.as_ref().unwrap().tip_m;
        let truth = difference_until(&sim.trajectory, &beams.trajectory, "tip_rel", 5.0);
        eprintln!(
            "{basis:?} {modes}: tip_rel estimate {estimate:.2e} m, against the beams {truth:.2e} m"
        );
        assert!(truth > REFERENCE_FLOOR);
        assert!(
            estimate <= ESTIMATE_FACTOR * truth && truth <= ESTIMATE_FACTOR * estimate,
            "{basis:?} {modes}: {estimate} against {truth}"
        );
        for (s, m) in stations.iter().zip(&b.truncation.as_ref().unwrap().moments) {
            let name = s.moment_name();
            let peak = column(&beams.trajectory, &name)
                .iter()
                .fold(0.0_f64, |a, v| a.max(v.abs()));
            let truth = difference_until(&sim.trajectory, &beams.trajectory, &name, 5.0) / peak;
            eprintln!(
                "  {name}: estimate {:.2} %, against the beams {:.2} %",
                100.0 * m.relative,
                100.0 * truth
            );
            assert!(m.relative <= ESTIMATE_FACTOR * truth && truth <= ESTIMATE_FACTOR * m.relative);
        }
        check_other_outputs(&format!("{basis:?} {modes}"), &sim, &beams);
    }
    // the paper's 5 modes of the default run: the 8.7 mm over 5 s
    let default = simulate_scene(&scene, &SimulationOptions::default(), &Silent).unwrap();
    let truth = difference_until(&default.trajectory, &beams.trajectory, "tip_rel", 5.0);
    assert!((8e-3..9.5e-3).contains(&truth), "{truth}");
    assert!(
        default.summary().contains("truncation"),
        "{}",
        default.summary()
    );
}

/// Every other output the run prints against the beams inside the window: `top1_rel`, the
/// gaps and the contact forces are within [`ESTIMATE_FACTOR`] of their stated truncation
/// error either way (where the truth stands above the elements' own error of that output).
fn check_other_outputs(name: &str, sim: &Simulation, beams: &BeamResponse) {
    let b = budget(sim);
    let t = b.truncation.as_ref().unwrap();
    for (column, estimate) in &t.outputs {
        let floor = match column.as_str() {
            c if c.starts_with("f_") => 1e-2,
            c if c.starts_with("top") || c.starts_with("xi_") => REFERENCE_FLOOR,
            _ => continue,
        };
        let truth = difference_until(&sim.trajectory, &beams.trajectory, column, b.window.end);
        eprintln!("  {name} {column}: estimate {estimate:.2e}, against the beams {truth:.2e}");
        assert!(
            truth <= (ESTIMATE_FACTOR * estimate).max(floor),
            "{name} {column}: {estimate} against {truth}"
        );
        assert!(
            truth <= floor || *estimate <= ESTIMATE_FACTOR * truth,
            "{name} {column}: {estimate} against {truth}"
        );
    }
}

/// The beams' statistics against a run's, with the run's estimate: the true relative
/// difference of the RMS and peak of `tip_rel` beyond the window is within the estimate
/// times the factor, or within 2 % (the spread of two careful runs of a chaotic scene).
fn check_statistics(name: &str, sim: &Simulation, beams: &BeamResponse) {
    let b = budget(sim);
    assert_eq!(b.window.reason, WindowEnd::FirstSwitch, "{name}");
    let (rms, peak) = tip_statistics(&sim.trajectory, b.window.end);
    let (rms_b, peak_b) = tip_statistics(&beams.trajectory, b.window.end);
    for (what, got, want, which) in [
        ("rms", rms, rms_b, Statistic::TipRms),
        ("peak", peak, peak_b, Statistic::TipPeak),
    ] {
        let truth = (got - want).abs() / want;
        let estimate = statistic(b, which);
        eprintln!(
            "{name}: {what} tip_rel {got:.4e} m against the beams' {want:.4e} m: {:.2} %, estimate {:.2} %",
            100.0 * truth,
            100.0 * estimate
        );
        assert!(
            truth <= (ESTIMATE_FACTOR * estimate).max(0.02),
            "{name} {what}: {truth} against {estimate}"
        );
    }
}

#[test]
fn the_clearance_scenes_truncation_estimates_hold_against_the_beams() {
    for (name, elements) in [("adams-clearance", 16), ("three-section", 8)] {
        let scene = scene(name);
        let beams = element_response(&scene, elements, &[], &Silent).unwrap();
        let sim = simulate_scene(&scene, &SimulationOptions::default(), &Silent).unwrap();
        let b = budget(&sim);
        let estimate = b.truncation.as_ref().unwrap().tip_m;
        let truth = difference_until(&sim.trajectory, &beams.trajectory, "tip_rel", b.window.end);
        eprintln!(
            "{name}: window to {} s, tip_rel estimate {estimate:.2e} m, against the beams {truth:.2e} m",
            b.window.end
        );
        assert!(
            truth <= (ESTIMATE_FACTOR * estimate).max(REFERENCE_FLOOR),
            "{name}: {estimate} against {truth}"
        );
        check_statistics(name, &sim, &beams);
    }
}

/// Runs `scene` at `accuracy` and checks it against `beams`: `tip_rel` inside the window
/// within the accuracy, and with clearance the RMS and peak beyond it within 5 %; returns the
/// run.
fn check_accuracy(name: &str, accuracy: f64, beams: &BeamResponse) -> Simulation {
    check_scene_accuracy(name, &scene(name), accuracy, beams)
}

/// [`check_accuracy`] of a scene given whole.
fn check_scene_accuracy(
    name: &str,
    scene: &Scene,
    accuracy: f64,
    beams: &BeamResponse,
) -> Simulation {
    let options = SimulationOptions {
        accuracy: Some(accuracy),
        ..SimulationOptions::default()
    };
    let sim = simulate_scene(scene, &options, &Silent).unwrap();
    let b = budget(&sim);
    let truth = difference_until(&sim.trajectory, &beams.trajectory, "tip_rel", b.window.end);
    eprintln!(
        "{name} at {accuracy:e} m: basis {}, {:?} modes, {}; tip_rel inside [0, {}] s against the beams {truth:.2e} m (estimate {:.2e} m)",
        sim.basis.word(),
        sim.modes,
        sim.plan.method,
        b.window.end,
        b.total_m().unwrap()
    );
    assert!(truth <= accuracy, "{name}: {truth} > {accuracy}");
    check_prediction(name, scene, &sim, truth);
    if b.window.reason == WindowEnd::FirstSwitch {
        // beyond the first impacts the motion is chaotic: the reference's own statistics
        // move when its mass moves by 1e-9 (measured 2.3 % of case-study's RMS), so the
        // bound is the statistics tolerance plus that scatter of the reference; the nudged
        // reference (a whole reference run) is made only when the tolerance alone is passed
        let (rms, peak) = tip_statistics(&sim.trajectory, b.window.end);
        let (rms_b, peak_b) = tip_statistics(&beams.trajectory, b.window.end);
        let within = |got: f64, want: f64| (got - want).abs() <= 0.05 * want;
        if !(within(rms, rms_b) && within(peak, peak_b)) {
            let mut nudged = scene.clone();
            nudged.params.vehicle_mass *= 1.0 + 1e-9;
            let again = beam_response(&nudged, &[], &Silent).unwrap();
            let (rms_c, peak_c) = tip_statistics(&again.trajectory, b.window.end);
            for (what, got, want, other) in
                [("RMS", rms, rms_b, rms_c), ("peak", peak, peak_b, peak_c)]
            {
                let scatter = (want - other).abs();
                eprintln!(
                    "{name}: {what} of tip_rel {got:.4} against {want:.4} (the reference's scatter {scatter:.1e})"
                );
                assert!(
                    (got - want).abs() <= 0.05 * want + scatter,
                    "{name}: {what} {got} against {want} (the reference's scatter {scatter:e})"
                );
            }
        }
    }
    sim
}

/// Without clearance the size is predicted before any run and its companion confirms it in
/// the search's first two runs; the prediction's estimate stands within [`ESTIMATE_FACTOR`]
/// of the true error (above the reference's floor). With clearance nothing is predicted.
fn check_prediction(name: &str, scene: &Scene, sim: &Simulation, truth: f64) {
    let MethodReason::TotalAccuracy {
        prediction,
        confirmed,
        search_runs,
        ..
    } = &sim.plan.reason
    else {
        panic!(
            "{name}: not picked for a whole accuracy: {:?}",
            sim.plan.reason
        );
    };
    if !scene.params.contact.is_linear() {
        assert_eq!(
            prediction,
            &SizePrediction::Skipped(NoPrediction::Clearance),
            "{name}"
        );
        return;
    }
    let SizePrediction::Predicted { estimated_m, .. } = prediction else {
        panic!("{name}: no size predicted: {prediction}");
    };
    eprintln!("{name}: {prediction}, true error {truth:.2e} m");
    assert!(
        *confirmed && *search_runs == 2,
        "{name}: {}",
        sim.plan.reason
    );
    if truth > REFERENCE_FLOOR {
        let ratio = estimated_m / truth;
        assert!(
            (1.0 / ESTIMATE_FACTOR..=ESTIMATE_FACTOR).contains(&ratio),
            "{name}: the prediction's estimate {estimated_m:.2e} m against {truth:.2e} m"
        );
    }
}

#[test]
fn accuracy_is_met_against_the_beams_on_the_fixed_position_scenes() {
    for (name, elements) in [
        ("adams-linear", 32),
        ("adams-clearance", 16),
        ("three-section", 8),
        ("test-rig", 32),
    ] {
        let beams = element_response(&scene(name), elements, &[], &Silent).unwrap();
        for accuracy in [1e-3, 1e-4] {
            check_accuracy(name, accuracy, &beams);
        }
    }
}

#[test]
fn accuracy_is_met_against_the_most_refined_ritz_model_on_the_moving_scenes() {
    for name in ["case-study-no-clearance", "case-study"] {
        let beams = beam_response(&scene(name), &[], &Silent).unwrap();
        let sim = check_accuracy(name, 1e-3, &beams);
        // without clearance every printed output is within its stated truncation error
        // either way (with clearance a contact the reference closes just before the window's
        // end reads its force there: docs/numerics.md)
        if name == "case-study-no-clearance" {
            check_other_outputs(name, &sim, &beams);
        }
    }
}

/// case-study-no-clearance with the vehicle's position prescribed (5 m in 8 s) instead of
/// its force: the surrogate's input is then the vehicle's acceleration.
fn prescribed_motion() -> Scene {
    let path = "scenes/case-study-no-clearance.toml";
    let text = std::fs::read_to_string(path).unwrap();
    let force = text
        .lines()
        .find(|l| l.starts_with("force = "))
        .expect("the scene's drive force");
    let motion = "motion = { kind = \"smoothstep\", start = 0, end = 8, from = 0, to = 5 }";
    Scene::from_toml_str(&text.replace(force, motion), path.as_ref(), &[]).unwrap()
}

#[test]
fn a_size_predicted_on_a_scene_it_was_not_tuned_for_is_confirmed_and_met() {
    // a heavier load on a softer structure than any shipped scene, a prescribed motion, and
    // the paper's scene at a tenth of a millimetre (there the refined Ritz model's own error,
    // some 5e-5 m, is most of the difference: this checks the prediction's confirmation and
    // the pick against it, not the last digit)
    let overrides = ["masses.load=30", "sections.youngs_modulus=1.9e11"].map(String::from);
    let heavier = Scene::load("scenes/case-study-no-clearance.toml".as_ref(), &overrides).unwrap();
    for (name, scene, accuracy) in [
        (
            "case-study-no-clearance",
            scene("case-study-no-clearance"),
            1e-4,
        ),
        ("30 kg on E = 1.9e11", heavier, 1e-3),
        ("prescribed motion", prescribed_motion(), 1e-3),
    ] {
        let beams = beam_response(&scene, &[], &Silent).unwrap();
        let sim = check_scene_accuracy(name, &scene, accuracy, &beams);
        check_other_outputs(name, &sim, &beams);
    }
}

/// The done-when of the accuracy on moving scenes, on the beams themselves: a heavier load
/// on a softer structure than any shipped scene, over case-study-no-clearance's first 4 s
/// while the upper section extends, against the finite elements with the contacts sliding
/// across them (16 per section; 32 moved `tip_rel` by 4.5e-7 m on the shipped scene,
/// `runtime/tests/beams_and_bases.rs`). The whole error in `tip_rel` is within the accuracy,
/// and the printed gaps, contact forces and `top1_rel` within their stated error.
#[test]
fn accuracy_is_met_against_the_elements_with_sliding_contacts() {
    let overrides = [
        "masses.load=30",
        "sections.youngs_modulus=1.9e11",
        "time.end=4",
    ];
    let overrides = overrides.map(String::from);
    let scene = Scene::load("scenes/case-study-no-clearance.toml".as_ref(), &overrides).unwrap();
    let beams = element_response(&scene, 16, &[], &Silent).unwrap();
    for accuracy in [1e-3, 1e-4] {
        let name = format!("30 kg on E = 1.9e11, first 4 s, {accuracy:e} m");
        let sim = check_scene_accuracy(&name, &scene, accuracy, &beams);
        check_other_outputs(&name, &sim, &beams);
        // the integration share (a tenth: 1e-4 and 1e-5 m) lets imex's steps cross the
        // samples; the companion stepped on every sample, so the stated errors hold the
        // interpolation too
        assert_eq!(sim.plan.settings.longest_step, Some(8e-3), "{name}");
        assert!(
            budget(&sim).truncation.as_ref().unwrap().interpolation,
            "{name}"
        );
    }
}

#[test]
fn modes_as_given_keeps_the_scenes_model_and_says_whether_the_whole_error_is_met() {
    let scene = scene("adams-linear");
    let options = SimulationOptions {
        accuracy: Some(1e-6),
        modes_as_given: true,
        ..SimulationOptions::default()
    };
    let sim = simulate_scene(&scene, &options, &Silent).unwrap();
    assert_eq!(sim.modes, vec![5, 5]);
    assert_eq!(sim.basis, Basis::Modes);
    let b = budget(&sim);
    assert!(b.integration_m.unwrap() <= 1e-6 / 3.0);
    assert!(
        b.truncation.as_ref().unwrap().tip_m > 1e-3,
        "the paper's 5 modes: millimetres"
    );
    // a whole accuracy below what the models can certify is refused by name
    let e = simulate_scene(
        &scene,
        &SimulationOptions {
            accuracy: Some(1e-6),
            ..SimulationOptions::default()
        },
        &Silent,
    )
    .unwrap_err();
    assert!(
        e.to_string().contains("SimulationOptions::accuracy")
            && e.to_string()
                .contains("see SimulationOptions::modes_as_given"),
        "{e}"
    );
}

#[test]
fn the_companion_made_beside_the_run_gives_the_budget_of_one_made_after_it() {
    // simulate_scene makes the run and its companion at once (two threads where two cores
    // are free); estimate_error makes the companion after the run: the same runs, the same
    // budget to the last bit
    for name in ["adams-clearance", "case-study-no-clearance"] {
        let s = scene(name);
        let options = SimulationOptions::default();
        let together = simulate_scene(&s, &options, &Silent).unwrap();
        let alone = SimulationOptions {
            error_estimate: false,
            ..options.clone()
        };
        let run = simulate_scene(&s, &alone, &Silent).unwrap();
        assert!(run.error.is_none());
        let after = estimate_error(&s, &options, &run, &Silent).unwrap();
        assert!(after.truncation.is_some(), "{name}: no companion");
        assert_eq!(
            format!("{:?}", budget(&together)),
            format!("{after:?}"),
            "{name}"
        );
    }
}

/// Where the run's method is picked from the table, its companion is integrated a tenth as
/// coarsely, and the stated error holds the run's own integration error, measured on the
/// run. Modes+static 14 on case-study-no-clearance's first 2 s, integrated to 1e-4 m: imex
/// at rtol 1e-4, its steps across the samples. Its integration and interpolation error
/// (against the same size by dop853 at rtol 1e-10) is of the size of its truncation, so a
/// budget that left it out could state less than it.
#[test]
fn the_companion_integrated_finer_measures_the_runs_integration_error() {
    let s = Scene::load(
        "scenes/case-study-no-clearance.toml".as_ref(),
        &["time.end=2".to_string()],
    )
    .unwrap();
    let s = sized(&s, Basis::ModesAndStatic, 14);
    let options = SimulationOptions {
        accuracy: Some(1e-4),
        modes_as_given: true,
        ..SimulationOptions::default()
    };
    let sim = simulate_scene(&s, &options, &Silent).unwrap();
    let b = budget(&sim);
    let t = b.truncation.as_ref().unwrap();
    assert!(t.integration && t.interpolation, "{b:?}");
    let row_error = sim.plan.integration_error_m.unwrap();
    assert!(
        b.integration_m.unwrap() * 10.0 <= row_error,
        "the companion's own integration {:?} against the run's row {row_error}",
        b.integration_m
    );
    let tight = SimulationOptions {
        method: telescopic::run::MethodChoice::Method(telescopic_runtime::Method::Dop853),
        rtol: Some(1e-10),
        atol: Some(1e-13),
        error_estimate: false,
        modes_as_given: true,
        ..SimulationOptions::default()
    };
    let reference = simulate_scene(&s, &tight, &Silent).unwrap();
    let integration = difference_until(&sim.trajectory, &reference.trajectory, "tip_rel", 2.0);
    let stated = b.total_m().unwrap();
    assert!(
        integration > 0.3 * t.tip_m,
        "the run's integration error {integration:.2e} m must matter beside the stated \
         {stated:.2e} m for this test to tell"
    );
    assert!(
        (integration..=10.0 * integration).contains(&stated),
        "stated {stated:.2e} m, the run's integration and interpolation {integration:.2e} m"
    );
}
