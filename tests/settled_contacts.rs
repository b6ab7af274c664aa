//! Method `dop853-imex` (dop853 across impacts, imex over closed contacts whose modes have
//! rung down) against tight reference runs: on three plants with impacts (case-study, the
//! clearance rig of the Adams comparison, and a case-study with a heavier load, half the
//! contact damping and 6 mm of clearance, which no setting of the method was chosen on) it
//! keeps dop853's accuracy inside the predictability horizon and the references' statistics
//! beyond it with less work; without clearance it is imex over the whole span; where the
//! contacts never settle it is dop853, bit for bit.

mod common;

use common::references::References;
use common::scene;
use telescopic::Silent;
use telescopic::analysis::work_precision::statistics_error;
use telescopic::run::{MethodChoice, SimulationOptions, Trajectory, simulate_scene};
use telescopic::runtime::Method;

fn run(scene: &telescopic::Scene, method: Method) -> Trajectory {
    let options = SimulationOptions {
        method: MethodChoice::Method(method),
        ..SimulationOptions::default()
    };
    simulate_scene(scene, &options, &Silent).unwrap().trajectory
}

#[test]
fn over_settled_contacts_it_keeps_dop853s_accuracy_with_less_work() {
    let plants = [
        ("case-study", vec![]),
        ("adams-clearance", vec![]),
        (
            "case-study",
            vec![
                "masses.load=30.0",
                "contact.damping=500.0",
                "contact.clearance=0.006",
            ],
        ),
    ];
    for (name, overrides) in plants {
        let scene = scene(name, &overrides);
        let references = References::of(&scene);
        let settled = run(&scene, Method::Dop853Imex);
        let explicit = run(&scene, Method::Dop853);
        let (s, e) = (&settled.stats, &explicit.stats);
        let worst = references.worst_in_horizon(&settled);
        let statistics = statistics_error(&settled, &references.run);
        let switches = references.run.stats.switches as f64;
        eprintln!(
            "{name} {overrides:?}: within {worst:.2e} m in [0, {}] s (dop853 {:.2e} m); \
             {} of {} steps over settled contacts; {} against {} right-hand sides; \
             {} switches against the reference's {switches}; statistics {statistics:.3}",
            references.horizon,
            references.worst_in_horizon(&explicit),
            s.long_steps,
            s.steps,
            s.rhs_evals,
            e.rhs_evals,
            s.switches
        );
        assert!(worst <= 1e-6, "{name}: {worst:e} m inside the horizon");
        assert!(
            s.long_steps * 10 >= s.steps,
            "{name}: imex took only {} of {} steps",
            s.long_steps,
            s.steps
        );
        assert!(
            (s.rhs_evals as f64) < 0.75 * e.rhs_evals as f64,
            "{name}: {} right-hand sides against dop853's {}",
            s.rhs_evals,
            e.rhs_evals
        );
        // beyond the horizon: the references' own statistics floor is about 10 % (docs)
        assert!(
            (s.switches as f64 - switches).abs() <= 0.25 * switches,
            "{name}: {} switches against {switches}",
            s.switches
        );
        assert!(
            statistics <= 0.3,
            "{name}: statistics differ by {statistics}"
        );
    }
}

#[test]
fn without_clearance_it_steps_over_the_contacts_as_imex_does() {
    let scene = scene("case-study-no-clearance", &[]);
    let references = References::of(&scene);
    // no impacts: the references agree over the whole span
    assert_eq!(references.horizon, scene.time.end);
    let settled = run(&scene, Method::Dop853Imex);
    let imex = run(&scene, Method::Imex);
    let worst = references.worst_in_horizon(&settled);
    eprintln!(
        "case-study-no-clearance: within {worst:.2e} m over 16 s (imex {:.2e} m), {} of {} steps by imex",
        references.worst_in_horizon(&imex),
        settled.stats.long_steps,
        settled.stats.steps
    );
    assert!(worst <= 1e-6, "{worst:e} m");
    assert!(settled.stats.long_steps * 10 >= settled.stats.steps * 9);
}

#[test]
fn where_the_contacts_never_settle_it_is_dop853() {
    // three-section rattles (a switch every 1.3 ms): no closed phase quiets down
    let scene = scene("three-section", &["time.end=4.0"]);
    let settled = run(&scene, Method::Dop853Imex);
    let explicit = run(&scene, Method::Dop853);
    assert_eq!(settled.stats.long_steps, 0);
    assert_eq!(settled.rows, explicit.rows);
}
