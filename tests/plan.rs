//! Input shapers on the model, against their closed form: a single section held on the
//! vehicle, gravity and clearance off, one flexible mode and no damping, is the linear
//! undamped oscillator the shapers are designed for. Its residual vibration after a shaped
//! S-curve, relative to the unshaped S-curve's, is the shaper's sensitivity curve
//! `|sum_i A_i exp(2 pi i m_i r)|` at the ratio `r` of the true to the design frequency;
//! at `r = 1` it is zero for ZV and ZVD and the 5 % tolerance for EI.

use telescopic::analysis::modes::{ModesOptions, compute_modes};
use telescopic::plan::candidates::{shaped, unshaped};
use telescopic::plan::moving_scene;
use telescopic::plan::shapers::Shaper;
use telescopic::run::{SimulationOptions, simulate_scene};
use telescopic::{Scene, Silent};
use telescopic_runtime::{Profile, SCurve};

const MAST: &str = r#"
name = "mast"
description = "one section held on the vehicle, one flexible mode, undamped"

[sections]
count = 1
length = 1.35
area = 0.001
inertia = 0.83e-8
density = 7850.0
youngs_modulus = 2.1e11
modes = 2

[masses]
vehicle = 100.0
load = 17.897

[gravity]
g = 0.0
force_flow = "none"

[drive]
motion = 0.0

[time]
start = 0.0
end = 1.0
sample = 0.001
"#;

/// The largest `|tip_rel|` (m) after `arrival` (s) of a run of `scene` moving along
/// `profile`: the amplitude of the residual vibration (the oscillation is about 0 once the
/// setpoint rests).
fn residual(scene: &Scene, profile: &Profile, arrival: f64, end: f64) -> f64 {
    let moving = moving_scene(scene, profile, end).unwrap();
    let options = SimulationOptions {
        error_estimate: false,
        ..SimulationOptions::default()
    };
    let run = simulate_scene(&moving, &options, &Silent).unwrap();
    let tip = run.trajectory.index("tip_rel").unwrap();
    run.trajectory
        .rows
        .iter()
        .filter(|r| r[0] >= arrival)
        .map(|r| r[tip].abs())
        .fold(0.0, f64::max)
}

#[test]
fn shaped_moves_leave_the_closed_form_residual_on_an_undamped_mode() {
    let scene = Scene::from_toml_str(MAST, "mast".as_ref(), &[]).unwrap();
    let curve = SCurve {
        start: 0.0,
        from: 0.0,
        distance: 0.6,
        v_max: 1.0,
        a_max: 2.0,
        j_max: 40.0,
    };
    let held = moving_scene(&scene, &unshaped(&curve).profile, 1.0).unwrap();
    let report = compute_modes(&held, &ModesOptions::default()).unwrap();
    assert_eq!(report.frequencies_hz.len(), 1, "one flexible mode");
    let f = report.frequencies_hz[0];
    let period = 1.0 / f;
    let plain = unshaped(&curve);
    let end = plain.arrival_s + 3.0 * 1.5 * 1.4 * period;
    let reference = residual(&scene, &plain.profile, plain.arrival_s, end);
    assert!(reference > 1e-4, "the unshaped move leaves {reference} m");
    for shaper in [Shaper::Zv, Shaper::Zvd, Shaper::Ei, Shaper::TwoHumpEi] {
        for ratio in [0.7, 0.85, 1.0, 1.15, 1.3] {
            // designed for f / ratio: the true frequency is `ratio` times the design's
            let design = Profile::Constant(ratio * period);
            let c = shaped(String::new(), &curve, shaper, (&design, 1.0, 1.0));
            let measured = residual(&scene, &c.profile, c.arrival_s, end) / reference;
            let expected = shaper.residual(ratio);
            assert!(
                (measured - expected).abs() < 2e-3,
                "{shaper} at {ratio}: residual {measured:.5} of the unshaped, closed form {expected:.5}"
            );
        }
    }
}

/// A caller that asks a plan to stop once a note containing `after` was given (at once for
/// an empty `after`), and keeps every note.
struct StopAfter {
    after: &'static str,
    notes: std::sync::Mutex<Vec<String>>,
}

impl telescopic::Reporter for StopAfter {
    fn note(&self, line: &str) {
        self.notes.lock().unwrap().push(line.to_string());
    }
    fn stop_requested(&self) -> bool {
        self.after.is_empty()
            || self
                .notes
                .lock()
                .unwrap()
                .iter()
                .any(|n| n.contains(self.after))
    }
}

#[test]
fn a_plan_stops_at_its_next_run_or_eigen_analysis_when_its_caller_asks() {
    use telescopic::plan::{MoveLimits, PlanOptions, plan_move};
    let scene = Scene::load("scenes/adams-linear.toml".as_ref(), &[]).unwrap();
    let options = PlanOptions::new(MoveLimits {
        distance: 2.0,
        v_max: 1.0,
        a_max: 1.0,
        j_max: 5.0,
    });
    for (after, stopped_in) in [
        ("", "first mode's schedule"),
        ("evaluating", "evaluating s-curve"),
    ] {
        let caller = StopAfter {
            after,
            notes: Default::default(),
        };
        let error = plan_move(&scene, &options, &caller).unwrap_err();
        assert!(
            matches!(&error, telescopic::Error::Stopped { what } if what.contains(stopped_in)),
            "{error}"
        );
        let notes = caller.notes.lock().unwrap();
        let evaluated = notes.iter().filter(|n| n.contains("evaluating")).count();
        assert!(evaluated <= 1, "went on after the stop: {notes:?}");
    }
}
