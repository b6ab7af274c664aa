//! Input shapers on the model, against their closed form: a single section held on the
//! vehicle, gravity and clearance off, one flexible mode and no damping, is the linear
//! undamped oscillator the shapers are designed for. Its residual vibration after a shaped
//! S-curve, relative to the unshaped S-curve's, is the shaper's sensitivity curve
//! `|sum_i A_i exp(2 pi i m_i r)|` at the ratio `r` of the true to the design frequency;
//! at `r = 1` it is zero for ZV and ZVD and the 5 % tolerance for EI.

use telescopic::analysis::modes::{ModesOptions, compute_modes};
use telescopic::plan::candidates::{matched, shaped, unshaped};
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

#[test]
fn the_matched_move_leaves_an_undamped_mode_at_rest_and_a_detuned_one_does_not() {
    let scene = Scene::from_toml_str(MAST, "mast".as_ref(), &[]).unwrap();
    let curve = SCurve {
        start: 0.0,
        from: 0.0,
        distance: 2.0,
        v_max: 1.0,
        a_max: 2.0,
        j_max: 40.0,
    };
    let held = moving_scene(&scene, &unshaped(&curve).profile, 1.0).unwrap();
    let period = 1.0
        / compute_modes(&held, &ModesOptions::default())
            .unwrap()
            .frequencies_hz[0];
    let plain = unshaped(&curve);
    let end = plain.arrival_s + 3.0;
    let reference = residual(&scene, &plain.profile, plain.arrival_s, end);
    let design = Profile::Constant(period);
    let found = matched("m", &curve, &design, (1.0, 1.0)).unwrap();
    // each box v/a spans the fewest whole periods the acceleration limit allows
    let k = (curve.v_max / (period * curve.a_max)).ceil();
    assert_eq!(found.periods, [k, k]);
    for a in found.accelerations {
        assert!((curve.v_max / a - k * period).abs() < 1e-12 * period, "{a}");
    }
    let tuned = found.candidate;
    let at_rest = residual(&scene, &tuned.profile, tuned.arrival_s, end) / reference;
    // each pulse is a jerk ramp convolved with a box of whole periods, whose spectrum is
    // zero at the mode: the linear mode ends at rest (to the integration's error)
    assert!(
        at_rest < 1e-6,
        "the matched move leaves {at_rest} of the S-curve's"
    );
    for (stretch, what) in [((1.15, 1.15), "both"), ((1.0, 0.85), "the braking")] {
        let detuned = matched("m", &curve, &design, stretch).unwrap().candidate;
        let left = residual(&scene, &detuned.profile, detuned.arrival_s, end) / reference;
        assert!(
            left > 10.0 * at_rest.max(1e-3),
            "{what} detuned leaves {left} against {at_rest} of the S-curve's"
        );
    }
    // within the limits: the same cruise velocity, and never faster than the rigid move
    assert!(tuned.arrival_s >= plain.arrival_s - 1e-12);
    let h = 1e-4;
    for k in 0..2000 {
        let t = tuned.arrival_s * f64::from(k) / 2000.0;
        let (_, v, a) = tuned.profile.state(t);
        assert!(
            v.abs() <= curve.v_max + 1e-12 && a.abs() <= curve.a_max + 1e-12,
            "t {t}"
        );
        let jerk = (tuned.profile.state(t + h).2 - a) / h;
        assert!(
            jerk.abs() <= curve.j_max * (1.0 + 1e-6),
            "t {t}: jerk {jerk}"
        );
    }
}

#[test]
fn a_jerk_segments_motion_runs_as_written_and_one_that_does_not_end_at_rest_is_refused() {
    let with = |segments: &str| {
        let motion =
            format!("motion = {{ kind = \"jerk-segments\", start = 0.1, segments = {segments} }}");
        Scene::from_toml_str(&MAST.replace("motion = 0.0", &motion), "mast".as_ref(), &[])
    };
    // +j for 0.2 s, -j for 0.4 s, +j for 0.2 s: rest to rest, over by 0.9 s
    let scene = with("[[0.2, 0.5], [0.4, -0.5], [0.2, 0.5]]").unwrap();
    let options = SimulationOptions {
        error_estimate: false,
        ..SimulationOptions::default()
    };
    let run = simulate_scene(&scene, &options, &Silent).unwrap();
    let vehicle = run.trajectory.index("vehicle").unwrap();
    let last = run.trajectory.rows.last().unwrap();
    // the travel of a jerk j over T/4, -j over T/2, +j over T/4 (T = 0.8 s) is j T^3 / 32
    let travel = 0.5 * 0.8_f64.powi(3) / 32.0;
    assert!(
        (last[vehicle] - travel).abs() < 1e-12,
        "{} m",
        last[vehicle]
    );
    for (segments, rule) in [
        ("[[0.2, 0.5], [0.4, -0.5]]", "must end at rest"),
        ("[[-0.2, 0.5]]", "durations must be >= 0"),
        ("[]", "at least one"),
    ] {
        let error = with(segments).unwrap_err().to_string();
        assert!(
            error.contains("drive.motion.segments") && error.contains(rule),
            "{segments}: {error}"
        );
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
        // the candidates run side by side: whichever reaches its stop point first names it
        ("evaluating", "evaluating "),
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
