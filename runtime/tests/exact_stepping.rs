//! Method `exact` (matrix exponential per contact branch) against independent paths: the
//! exponential of matrices built from M, K and the contact vectors by hand, dop853 at a tight
//! tolerance across contact switches, energy conservation across switches, and itself on a
//! different step grid. On the quadrature-assembled model.

mod common;

use common::{exact_lti, rig, run_counted as run, span, tip_rel, undamped_rattle};
use telescopic_runtime::{
    AssembledModel, Drive, ForceFlow, Method, Model, ModelParams, Profile, Settings, SimError,
    mechanical_energy,
};

/// dop853 at the tolerance the exact method is checked against.
fn tight() -> Settings {
    Settings {
        rtol: 1e-12,
        atol: 1e-15,
        ..Settings::default()
    }
}

/// adams-clearance on the assembled model: gravity off, l_S = 0.01 m, F = 100 N from rest.
fn adams_clearance() -> ModelParams {
    let mut p = rig([5, 5]);
    p.gravity = 0.0;
    p.force_flow = ForceFlow::None;
    p.contact.clearance = 0.01;
    p
}

#[test]
fn exact_method_matches_an_independent_matrix_exponential() {
    let mut p = rig([5, 5]);
    p.gravity = 0.0;
    p.force_flow = ForceFlow::None;
    let model = AssembledModel::new(&p).unwrap();
    let (dt, steps) = (1e-3, 2000);
    let reference = exact_lti(&model, 100.0, dt, steps);
    let y0 = vec![0.0; 2 * model.dof()];
    let (samples, _) = run(
        &model,
        &y0,
        &span(dt * steps as f64, dt),
        Method::Exact,
        &Settings::default(),
    )
    .unwrap();
    assert_eq!(samples.len(), steps + 1);
    let worst = samples
        .iter()
        .zip(&reference)
        .map(|((_, y), e)| (tip_rel(&model, y) - tip_rel(&model, e)).abs())
        .fold(0.0, f64::max);
    eprintln!("exact vs hand-built exponential: worst |tip_rel| difference over 2 s {worst:.2e} m");
    // both are exact up to rounding (tip_rel ~0.1 m): the rounding of scaling and squaring
    // depends on the last digits of the spectral radius that scales the velocities, measured
    // 7.8e-11 m with it from an unbalanced Schur decomposition, 8.9e-10 m from a balanced one
    // (the two radii agree to 2e-11); dop853 at rtol 1e-12 agrees to 5.5e-10 m
    assert!(worst < 2e-9, "tip_rel differs by {worst:e} m");
}

#[test]
fn exact_method_agrees_with_dop853_across_contact_switches() {
    let model = AssembledModel::new(&adams_clearance()).unwrap();
    let y0 = vec![0.0; 2 * model.dof()];
    // inside the predictability horizon of the scene (~0.4 s)
    let window = span(0.3, 1e-3);
    let (exact, exact_stats) =
        run(&model, &y0, &window, Method::Exact, &Settings::default()).unwrap();
    let (reference, reference_stats) = run(&model, &y0, &window, Method::Dop853, &tight()).unwrap();
    let (exact_switches, reference_switches) = (exact_stats.switches, reference_stats.switches);
    let worst = exact
        .iter()
        .zip(&reference)
        .map(|((_, a), (_, b))| (tip_rel(&model, a) - tip_rel(&model, b)).abs())
        .fold(0.0, f64::max);
    eprintln!(
        "exact vs dop853 (rtol 1e-12) on [0, 0.3] s: worst |tip_rel| difference {worst:.2e} m, \
         switches {exact_switches} vs {reference_switches}"
    );
    assert!(exact_switches > 10, "only {exact_switches} switches");
    assert_eq!(exact_switches, reference_switches);
    assert!(worst < 1e-9, "tip_rel differs by {worst:e} m");
}

#[test]
fn exact_method_conserves_energy_across_contact_switches() {
    // no damping, no gravity, no drive: energy is a constant of the piecewise-linear motion,
    // so only the located switch times can make it drift
    let (p, state) = undamped_rattle();
    let model = AssembledModel::new(&p).unwrap();
    let y0 = state(model.dof());
    let e0 = mechanical_energy(&model, 0.0, &y0);
    let (samples, stats) = run(
        &model,
        &y0,
        &span(5.0, 0.01),
        Method::Exact,
        &Settings::default(),
    )
    .unwrap();
    let switches = stats.switches;
    let worst = samples
        .iter()
        .map(|(t, y)| ((mechanical_energy(&model, *t, y) - e0) / e0).abs())
        .fold(0.0, f64::max);
    eprintln!(
        "exact, undamped with clearance: {switches} switches, worst relative energy change {worst:.2e}"
    );
    assert!(
        switches > 100,
        "only {switches} switches: the test needs impacts"
    );
    // measured 3.6e-12 over 248k switches (dopri5 at rtol 1e-12: 4.9e-8 on a similar run)
    assert!(worst < 1e-10, "energy drifted by {worst:e} relative");
}

#[test]
fn exact_method_does_not_depend_on_its_step_grid() {
    // samples of 1 ms and 0.25 ms put the regular steps and the partial steps (Taylor series)
    // in different places; the motion must not notice
    let mut p = adams_clearance();
    p.drive = Drive::Force(Profile::Shaped(
        telescopic_runtime::profile::ShapedProfile::PiecewiseConstant {
            times: vec![0.0, 0.10037],
            values: vec![100.0, -60.0],
        },
    ));
    let model = AssembledModel::new(&p).unwrap();
    let y0 = vec![0.0; 2 * model.dof()];
    let (coarse, _) = run(
        &model,
        &y0,
        &span(0.3, 1e-3),
        Method::Exact,
        &Settings::default(),
    )
    .unwrap();
    let (fine, _) = run(
        &model,
        &y0,
        &span(0.3, 2.5e-4),
        Method::Exact,
        &Settings::default(),
    )
    .unwrap();
    let worst = coarse
        .iter()
        .zip(fine.iter().step_by(4))
        .map(|((ta, a), (tb, b))| {
            assert!((ta - tb).abs() < 1e-12);
            (tip_rel(&model, a) - tip_rel(&model, b)).abs()
        })
        .fold(0.0, f64::max);
    eprintln!("exact on 1 ms vs 0.25 ms grids: worst |tip_rel| difference {worst:.2e} m");
    assert!(worst < 1e-10, "tip_rel differs by {worst:e} m");
}

#[test]
fn exact_method_refuses_a_scene_that_is_not_time_invariant() {
    let mut p = adams_clearance();
    p.positions = vec![Profile::Shaped(
        telescopic_runtime::profile::ShapedProfile::Smoothstep {
            start: 0.0,
            end: 1.0,
            from: 0.5,
            to: 1.15,
        },
    )];
    let model = AssembledModel::new(&p).unwrap();
    let y0 = vec![0.0; 2 * model.dof()];
    let err = run(
        &model,
        &y0,
        &span(0.1, 1e-3),
        Method::Exact,
        &Settings::default(),
    )
    .unwrap_err();
    let message = err.to_string();
    assert!(
        matches!(err, SimError::Settings(_)) && message.contains("a_2 moves"),
        "{message}"
    );
}

/// `params` with a_2 moving from 0.8 m to 1.15 m on `[0, rest]` s, at rest after.
fn moving_until(mut params: ModelParams, rest: f64) -> ModelParams {
    params.positions = vec![Profile::Shaped(
        telescopic_runtime::profile::ShapedProfile::Smoothstep {
            start: 0.0,
            end: rest,
            from: 0.8,
            to: 1.15,
        },
    )];
    params
}

/// Worst `|tip_rel|` difference (m) of two runs on the same sample times (asserted equal).
fn worst_tip_difference(model: &dyn Model, a: &[(f64, Vec<f64>)], b: &[(f64, Vec<f64>)]) -> f64 {
    assert_eq!(a.len(), b.len(), "sample counts");
    a.iter()
        .zip(b)
        .map(|((ta, ya), (tb, yb))| {
            assert_eq!(ta, tb, "sample times");
            (tip_rel(model, ya) - tip_rel(model, yb)).abs()
        })
        .fold(0.0, f64::max)
}

#[test]
fn exact_stepping_takes_over_when_the_positions_come_to_rest() {
    use telescopic_runtime::integrate::exact::exact_tail_start;
    let tight = |rtol: f64| Settings {
        rtol,
        atol: 1e-3 * rtol,
        ..Settings::default()
    };
    // l_S = 0: no events, no chaos, so the runs can agree pointwise over the whole span
    let linear = moving_until(rig([4, 4]), 0.5);
    let whole = span(1.0, 1e-3);
    assert_eq!(exact_tail_start(&linear, &whole), Some(0.5));
    assert_eq!(
        exact_tail_start(&linear, &span(0.5, 1e-3)),
        None,
        "nothing left to step"
    );
    assert_eq!(
        exact_tail_start(&rig([4, 4]), &whole),
        None,
        "exact from the start"
    );
    // rounded up to the sample grid
    assert_eq!(
        exact_tail_start(&moving_until(rig([4, 4]), 0.4995), &whole),
        Some(0.5)
    );
    // and the clearance law, inside adams-clearance's predictability horizon (~0.4 s)
    let clearance = moving_until(adams_clearance(), 0.1);
    let window = span(0.3, 1e-3);
    assert_eq!(exact_tail_start(&clearance, &window), Some(0.1));
    for (params, span, limit) in [(linear, whole, 1e-9), (clearance, window, 1e-8)] {
        let model = AssembledModel::new(&params).unwrap();
        let y0 = vec![0.0; 2 * model.dof()];
        let t_exact = exact_tail_start(&params, &span).unwrap();
        let hybrid = Settings {
            exact_from: Some(t_exact),
            ..tight(1e-11)
        };
        let (mixed, mixed_stats) = run(&model, &y0, &span, Method::Dop853, &hybrid).unwrap();
        let (reference, reference_stats) =
            run(&model, &y0, &span, Method::Dop853, &tight(1e-12)).unwrap();
        let worst = worst_tip_difference(&model, &mixed, &reference);
        eprintln!(
            "dop853 then exact from {t_exact} s vs dop853 (rtol 1e-12) on [0, {}] s (l_S = {} m): \
             worst |tip_rel| difference {worst:.2e} m, switches {} vs {}, {} exponentials",
            span.end,
            params.contact.clearance,
            mixed_stats.switches,
            reference_stats.switches,
            mixed_stats.exponentials
        );
        assert!(
            mixed_stats.exponentials >= 1,
            "the tail was stepped exactly"
        );
        assert_eq!(mixed_stats.switches, reference_stats.switches);
        assert!(worst < limit, "tip_rel differs by {worst:e} m");
    }
}

#[test]
fn exact_stepping_from_a_time_off_the_sample_grid_is_refused() {
    let params = moving_until(rig([3, 3]), 0.5);
    let model = AssembledModel::new(&params).unwrap();
    let y0 = vec![0.0; 2 * model.dof()];
    let settings = Settings {
        exact_from: Some(0.5005),
        ..Settings::default()
    };
    let err = run(&model, &y0, &span(1.0, 1e-3), Method::Dopri5, &settings).unwrap_err();
    assert!(
        matches!(err, SimError::Settings(ref m) if m.contains("sample time")),
        "{err}"
    );
    // and from a time at which the positions still move, exact stepping refuses as a whole
    let settings = Settings {
        exact_from: Some(0.25),
        ..Settings::default()
    };
    let err = run(&model, &y0, &span(1.0, 1e-3), Method::Dopri5, &settings).unwrap_err();
    assert!(err.to_string().contains("a_2 moves"), "{err}");
}

/// Runs `params` exactly on `[0, end]` with and without the long steps over closed
/// contacts' modes; returns the worst `tip_rel` difference (m) and both runs' statistics.
fn long_against_short(
    params: &ModelParams,
    end: f64,
) -> (
    f64,
    telescopic_runtime::RunStats,
    telescopic_runtime::RunStats,
) {
    let model = AssembledModel::new(params).unwrap();
    let y0 = vec![0.0; 2 * model.dof()];
    let window = span(end, 1e-3);
    let short_only = Settings {
        long_steps: false,
        ..Settings::default()
    };
    let (long, long_stats) =
        run(&model, &y0, &window, Method::Exact, &Settings::default()).unwrap();
    let (short, short_stats) = run(&model, &y0, &window, Method::Exact, &short_only).unwrap();
    let worst = long
        .iter()
        .zip(&short)
        .map(|((_, a), (_, b))| (tip_rel(&model, a) - tip_rel(&model, b)).abs())
        .fold(0.0, f64::max);
    (worst, long_stats, short_stats)
}

#[test]
fn long_steps_over_a_lasting_contact_agree_with_the_short_steps() {
    // adams-clearance presses the upper section against its guide from about 0.49 s to
    // 1.29 s: the long steps take that phase once the impact's ringing has died out
    let (worst, long, short) = long_against_short(&adams_clearance(), 1.2);
    eprintln!(
        "exact on [0, 1.2] s: {} steps ({} long) against {} short only; switches {} vs {}; \
         worst |tip_rel| difference {worst:.2e} m",
        long.steps, long.long_steps, short.steps, long.switches, short.switches
    );
    assert_eq!(short.long_steps, 0);
    assert!(long.long_steps > 400, "only {} long steps", long.long_steps);
    assert!(
        3 * long.steps < short.steps,
        "{} steps against {}",
        long.steps,
        short.steps
    );
    assert_eq!(long.switches, short.switches);
    // both exact up to rounding; the scene amplifies rounding differences by ~1e3 per 0.5 s
    // of rattling (the short steps on 1 ms and 0.5 ms grids differ by as much)
    assert!(worst < 1e-8, "tip_rel differs by {worst:e} m");
    // and an independent integrator through the same contact: dop853 at rtol 1e-12 stays
    // within 6.4e-8 m of it (measured; the short steps too: its own error, amplified by
    // the rattle before the contact)
    let model = AssembledModel::new(&adams_clearance()).unwrap();
    let y0 = vec![0.0; 2 * model.dof()];
    let window = span(1.2, 1e-3);
    let (reference, _) = run(&model, &y0, &window, Method::Dop853, &tight()).unwrap();
    let (exact, _) = run(&model, &y0, &window, Method::Exact, &Settings::default()).unwrap();
    let against_dop853 = exact
        .iter()
        .zip(&reference)
        .map(|((_, a), (_, b))| (tip_rel(&model, a) - tip_rel(&model, b)).abs())
        .fold(0.0, f64::max);
    eprintln!("long steps vs dop853 (rtol 1e-12) on [0, 1.2] s: {against_dop853:.2e} m");
    assert!(against_dop853 < 2e-7, "{against_dop853:e} m");
}

#[test]
fn long_steps_never_skip_a_switch_across_clearances_and_forces() {
    // every band-edge crossing the short steps find, the long steps find too: 9 scenes
    // with lasting contacts of different depths, over their first half second
    for clearance in [0.002, 0.005, 0.01] {
        for force in [50.0, 150.0, 400.0] {
            let mut p = adams_clearance();
            p.contact.clearance = clearance;
            p.drive = Drive::Force(Profile::Constant(force));
            let (worst, long, short) = long_against_short(&p, 0.5);
            eprintln!(
                "l_S {clearance} m, F {force} N: {} long steps of {}, switches {} vs {}, \
                 worst |tip_rel| difference {worst:.2e} m",
                long.long_steps, long.steps, long.switches, short.switches
            );
            assert_eq!(long.switches, short.switches, "l_S {clearance}, F {force}");
            assert!(worst < 1e-8, "l_S {clearance}, F {force}: {worst:e} m");
        }
    }
}

/// The rig without gravity or prestress driven by a force held at `values` from `times`
/// (s), run 0.4 s by method exact and by dop853 at rtol 1e-12: exact's counts, its worst
/// `tip_rel` difference to dop853 and dop853's peak `tip_rel` (m).
fn exact_against_dop853(
    times: Vec<f64>,
    values: Vec<f64>,
) -> (telescopic_runtime::RunStats, f64, f64) {
    let mut p = rig([5, 5]);
    p.gravity = 0.0;
    p.force_flow = ForceFlow::None;
    p.drive = Drive::Force(Profile::Shaped(
        telescopic_runtime::profile::ShapedProfile::PiecewiseConstant { times, values },
    ));
    let model = AssembledModel::new(&p).unwrap();
    let y0 = vec![0.0; 2 * model.dof()];
    let window = span(0.4, 1e-3);
    let (exact, stats) = run(&model, &y0, &window, Method::Exact, &Settings::default()).unwrap();
    let (reference, _) = run(&model, &y0, &window, Method::Dop853, &tight()).unwrap();
    let peak = reference
        .iter()
        .map(|(_, y)| tip_rel(&model, y).abs())
        .fold(0.0, f64::max);
    let worst = exact
        .iter()
        .zip(&reference)
        .map(|((_, a), (_, b))| (tip_rel(&model, a) - tip_rel(&model, b)).abs())
        .fold(0.0, f64::max);
    (stats, worst, peak)
}

/// A drive that steps often on closed contacts (a force record held between samples): every
/// segment has the same `A`, so its exponential is built once and each later segment takes
/// `gamma` from `int exp(A s) ds` (one more exponential); the motion agrees with dop853 at a
/// tight tolerance as a run built afresh per segment does.
#[test]
fn drive_steps_on_one_branch_share_its_exponential() {
    let times: Vec<f64> = (0..24)
        .map(|k| 0.0125 * k as f64 + 0.003 * (k % 3) as f64)
        .collect();
    let values: Vec<f64> = (0..24)
        .map(|k| if k % 2 == 0 { 100.0 } else { -70.0 })
        .collect();
    let (stats, worst, peak) = exact_against_dop853(times, values);
    eprintln!(
        "24 drive steps: {} exponentials; worst |tip_rel| difference to dop853 {worst:.2e} m \
         (peak {peak:.2e} m)",
        stats.exponentials
    );
    assert_eq!(stats.exponentials, 2, "one flow and one input integral");
    // measured 1.67e-11 m (2.3e-9 of the peak), the same as with 24 exponentials built afresh
    assert!(worst < 1e-8 * peak, "tip_rel differs by {worst:e} m");
}

/// A recorded force: a new value at every sample, its time stamps a few ulps off the run's
/// sample times (as a logger's text and a record's mean interval give them). Exact
/// stepping takes one regular step per sample (a matrix-vector product) and a step of those
/// ulps at an off-grid stamp (a few Taylor terms), one Jacobian for the whole record (each
/// drive step takes the first branch's `A` once the model's right-hand side agrees with
/// it), and agrees with dop853 at rtol 1e-12.
#[test]
fn a_force_stepping_at_every_sample_takes_one_step_per_sample() {
    let samples = 400;
    let ulps = |k: usize| 1.0 + [-3.0, 0.0, 2.0][k % 3] * f64::EPSILON;
    let times: Vec<f64> = (0..samples).map(|k| k as f64 * 1e-3 * ulps(k)).collect();
    let values: Vec<f64> = (0..samples)
        .map(|k| 100.0 * ((k as f64 * 0.37).sin() + 0.3 * (k as f64 * 2.9).cos()))
        .collect();
    let (stats, worst, peak) = exact_against_dop853(times, values);
    eprintln!(
        "{samples} drive steps: {} steps, {} Taylor terms, {} Jacobians, {} exponentials; \
         worst |tip_rel| difference to dop853 {worst:.2e} m (peak {peak:.2e} m)",
        stats.steps, stats.taylor_terms, stats.jacobian_evals, stats.exponentials
    );
    let off_grid = (1..samples).filter(|&k| ulps(k) != 1.0).count() as u64;
    assert_eq!(
        stats.steps,
        samples as u64 + off_grid,
        "a step per sample and stamp"
    );
    assert!(
        stats.taylor_terms <= 4 * off_grid,
        "{} Taylor terms",
        stats.taylor_terms
    );
    assert_eq!(stats.jacobian_evals, 1, "one Jacobian");
    assert_eq!(stats.exponentials, 2, "one flow and one input integral");
    assert!(worst < 1e-8 * peak, "tip_rel differs by {worst:e} m");
}
