//! Exact stepping with a held input ([`ExactTicks`]): a force held over each tick and set
//! anew between ticks, taken by superposition on exponentials built once, against two
//! independent paths: one exact run over the whole span where the force does not change, and
//! dopri5 at a tight tolerance, restarted at every tick, where it does; and the run that goes on
//! with its method where a hand-over is refused.
mod common;
use common::{generated, scene};

use telescopic::fmu::held::HeldDrive;
use telescopic_runtime::integrate::Integrator;
use telescopic_runtime::integrate::exact::ExactTicks;
use telescopic_runtime::{Method, Settings, rest_state, simulate};

/// The largest difference of two states, over the largest entry of the first.
fn relative_difference(a: &[f64], b: &[f64]) -> f64 {
    let scale = a.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let diff = a
        .iter()
        .zip(b)
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
    diff / scale
}

#[test]
fn ticks_with_the_force_set_anew_each_tick_follow_one_exact_run_of_the_span() {
    // adams-clearance: a constant 100 N on a free vehicle, contacts closing and opening;
    // up to 0.3 s, before an impact at about 0.4 s that turns differences of 1e-11 (two
    // dopri5 runs at rtol 1e-11 and 1e-12) into 1e-3
    let scene = scene("adams-clearance", &["time.end=0.3"]);
    let base = generated(&scene);
    let y0 = rest_state(base.as_ref(), scene.time.start);
    let mut reference = Vec::new();
    let whole = simulate(
        base.as_ref(),
        &y0,
        &scene.time,
        Method::Exact,
        &Settings::default(),
        &mut |t, y, _| reference.push((t, y.to_vec())),
        None,
    )
    .unwrap();
    assert!(whole.switches > 0, "the contacts switch in the span");
    let held = HeldDrive::new(base, 100.0).unwrap();
    let settings = Settings::default();
    let mut ticks =
        ExactTicks::new(&held, scene.time.start, &y0, scene.time.sample, &settings).unwrap();
    let mut worst = 0.0f64;
    for (t, y) in &reference[1..] {
        // the same force, set anew: each branch takes it again by superposition
        held.set_input(100.0);
        ticks.input_changed();
        ticks.advance_to(*t).unwrap();
        worst = worst.max(relative_difference(y, ticks.state()));
    }
    assert!(worst < 1e-9, "largest relative difference {worst:e}");
    let stats = ticks.stats();
    assert!(stats.switches > 0);
    // exponentials built once per branch, not per tick
    assert!(
        stats.exponentials < 100,
        "{} exponentials",
        stats.exponentials
    );
}

#[test]
fn ticks_with_a_changing_held_force_agree_with_dopri5_restarted_at_every_tick() {
    let scene = scene("adams-clearance", &["time.end=0.3"]);
    let base = generated(&scene);
    let y0 = rest_state(base.as_ref(), scene.time.start);
    let tick = scene.time.sample;
    let force = |k: usize| 100.0 + 60.0 * (0.37 * k as f64).sin();
    let exact_plant = HeldDrive::new(generated(&scene), force(0)).unwrap();
    let dopri_plant = HeldDrive::new(base, force(0)).unwrap();
    let mut exact = ExactTicks::new(
        &exact_plant,
        scene.time.start,
        &y0,
        tick,
        &Settings::default(),
    )
    .unwrap();
    let tight = Settings {
        rtol: 1e-11,
        atol: 1e-14,
        ..Settings::default()
    };
    let span = scene.time;
    let mut dopri = Integrator::new(&dopri_plant, &y0, &span, Method::Dopri5, &tight).unwrap();
    let ticks = ((span.end - span.start) / tick).round() as usize;
    let mut worst = 0.0f64;
    for k in 0..ticks {
        exact_plant.set_input(force(k));
        dopri_plant.set_input(force(k));
        exact.input_changed();
        dopri.input_changed();
        let t = span.start + (k + 1) as f64 * tick;
        exact.advance_to(t).unwrap();
        dopri.advance_to(t, &mut |_, _, _| {}).unwrap();
        worst = worst.max(relative_difference(dopri.state(), exact.state()));
    }
    assert!(
        exact.stats().switches > 0,
        "the contacts switch in the span"
    );
    assert!(worst < 1e-7, "largest relative difference {worst:e}");
}

#[test]
fn exact_ticks_refuse_moving_positions_naming_the_cause() {
    let scene = scene("case-study", &[]);
    let plant = HeldDrive::new(generated(&scene), 0.0).unwrap();
    let y0 = rest_state(&plant, scene.time.start);
    let err = ExactTicks::new(&plant, 0.0, &y0, 1e-3, &Settings::default())
        .err()
        .expect("the positions move until 12 s")
        .to_string();
    assert!(
        err.contains("a_2 moves") && err.contains("held input"),
        "{err}"
    );
    // from the positions' rest on it applies
    assert!(ExactTicks::new(&plant, 12.0, &y0, 1e-3, &Settings::default()).is_ok());
}

#[test]
fn exact_ticks_refuse_a_tick_or_a_time_that_is_not_finite() {
    let scene = scene("adams-clearance", &[]);
    let plant = HeldDrive::new(generated(&scene), 100.0).unwrap();
    let y0 = rest_state(&plant, 0.0);
    for tick in [0.0, -1e-3, f64::NAN, f64::INFINITY] {
        let err = ExactTicks::new(&plant, 0.0, &y0, tick, &Settings::default())
            .err()
            .unwrap_or_else(|| panic!("tick {tick} accepted"))
            .to_string();
        assert!(err.contains("positive finite tick"), "{err}");
    }
    let mut ticks = ExactTicks::new(&plant, 0.0, &y0, 1e-3, &Settings::default()).unwrap();
    let err = ticks.advance_to(f64::NAN).unwrap_err().to_string();
    assert!(err.contains("finite time"), "{err}");
    ticks.advance_to(2e-3).unwrap();
    assert_eq!(ticks.time(), 2e-3);
    assert!(ticks.state().iter().all(|v| v.is_finite()));
}

#[test]
fn a_sampled_controller_steps_exactly_once_the_positions_rest_and_agrees_with_dop853_imex() {
    use telescopic::Silent;
    use telescopic::control::{DesignOptions, design, simulate_controlled};
    use telescopic::run::{MethodChoice, MethodReason, SimulationOptions};
    use telescopic_runtime::Output;
    // without clearance the runs can be compared sample by sample
    let scene = scene("case-study-no-clearance", &["accuracy=0.1"]);
    let controller = design(
        &scene,
        &DesignOptions {
            sensors: vec!["vehicle".into(), "kappa_1_0".into()],
            ..DesignOptions::default()
        },
    )
    .unwrap();
    let plain = SimulationOptions {
        error_estimate: false,
        modes_as_given: true,
        ..SimulationOptions::default()
    };
    let auto = simulate_controlled(&scene, &controller, &plain, &Silent).unwrap();
    let MethodReason::SampledController { exact_from, .. } = auto.plan.reason else {
        panic!("{:?}", auto.plan.reason)
    };
    assert_eq!(exact_from, Some(12.0));
    let given = SimulationOptions {
        method: MethodChoice::Method(Method::Dop853Imex),
        ..plain
    };
    let throughout = simulate_controlled(&scene, &controller, &given, &Silent).unwrap();
    let tip = |run: &telescopic::run::Simulation| run.trajectory.column_of(Output::TipRel).unwrap();
    let (a, b) = (tip(&auto), tip(&throughout));
    let peak = b.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let worst = a
        .iter()
        .zip(&b)
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
    assert!(
        worst < 1e-4 * peak,
        "tip_rel differs by {worst:e} m (peak {peak:e} m)"
    );
    // the exact ticks cost fewer right-hand sides than dop853-imex's over the rest
    let (sa, sb) = (&auto.trajectory.stats, &throughout.trajectory.stats);
    assert!(
        sa.rhs_evals < sb.rhs_evals,
        "{} against {}",
        sa.rhs_evals,
        sb.rhs_evals
    );
    assert!(sa.exponentials > 0);
}

#[test]
fn a_hand_over_the_model_refuses_goes_on_with_the_plans_method() {
    use telescopic::run::{HeldInputStepper, SimulationOptions, plan};
    use telescopic_runtime::TimeSpan;
    // case-study's positions move until 12 s: a hand-over asked for at 0.1 s is refused
    let scene = scene("case-study", &[]);
    let plant = HeldDrive::new(generated(&scene), 0.0).unwrap();
    let y0 = rest_state(&plant, 0.0);
    let span = TimeSpan {
        start: 0.0,
        end: 0.3,
        sample: 1e-3,
    };
    let mut given = plan(&scene, &SimulationOptions::default()).unwrap();
    given.method = Method::Dopri5;
    given.settings.exact_from = None;
    let mut asked = given.clone();
    asked.settings.exact_from = Some(0.1);
    let mut plain = HeldInputStepper::new(&given, &plant, &span, &y0).unwrap();
    let mut handing = HeldInputStepper::new(&asked, &plant, &span, &y0).unwrap();
    for k in 1..=300 {
        let t = k as f64 * 1e-3;
        plain.advance_to(t).unwrap();
        handing.advance_to(t).unwrap();
    }
    assert!(!handing.is_exact(), "exact stepping took moving positions");
    // the refused hand-over left the run as it was: the same steps to the last bit
    assert_eq!(plain.state(), handing.state());
    assert_eq!(plain.stats().steps, handing.stats().steps);
    assert!(plain.stats().steps > 0);
}

#[test]
fn a_sampled_run_whose_hand_over_is_refused_does_not_claim_exact_ticks() {
    use telescopic::Silent;
    use telescopic::control::closed_loop::sampled::simulate_sampled;
    use telescopic::control::{DesignOptions, design};
    use telescopic::run::{MethodReason, PreparedRun, SimulationOptions};
    // the positions move until 12 s: a hand-over asked for at 0.1 s is refused
    let scene = scene("case-study-no-clearance", &["time.end=0.3"]);
    let sensors = vec!["vehicle".into(), "kappa_1_0".into()];
    let controller = design(
        &scene,
        &DesignOptions {
            sensors,
            ..DesignOptions::default()
        },
    )
    .unwrap();
    let options = SimulationOptions {
        error_estimate: false,
        modes_as_given: true,
        ..SimulationOptions::default()
    };
    let mut run = PreparedRun::new(&scene, &options, &Silent).unwrap();
    run.plan.settings.exact_from = Some(0.1);
    let sampled = simulate_sampled(run, &controller, &Silent).unwrap();
    let reason = &sampled.simulation.plan.reason;
    let MethodReason::SampledController { exact_from, .. } = reason else {
        panic!("{reason:?}")
    };
    assert_eq!(*exact_from, None, "{reason}");
    assert!(!reason.to_string().contains("exact stepping"), "{reason}");
    assert_eq!(sampled.simulation.trajectory.stats.exponentials, 0);
}
