//! The work budget: its step prediction against the steps real runs take on the shipped
//! scenes, and the refusal, before any work, of runs whose predicted work is absurd.
mod common;
use common::scene;

use telescopic::run::budget::estimate_steps;
use telescopic::run::models::{ModelChoice, ModelRegistry};
use telescopic::run::{MethodChoice, SimulationOptions, plan, simulate_scene};
use telescopic::{Error, Scene, Silent};
use telescopic_runtime::Method;

#[test]
fn the_predicted_steps_are_within_a_factor_3_of_real_runs() {
    // the prediction assumes every contact closed; real runs spend time in free flight and
    // in rejected steps, so it is an estimate, but one good enough to call a run absurd
    let cases = [
        ("adams-clearance", Method::Dopri5),
        ("adams-clearance", Method::Dop853),
        ("adams-clearance", Method::Exact),
        ("adams-linear", Method::Dopri5),
        ("case-study", Method::Dopri5),
        ("case-study", Method::Dop853),
        ("case-study-no-clearance", Method::Dopri5),
        ("three-section", Method::Dop853),
    ];
    for (name, method) in cases {
        let scene = scene(name, &[]);
        let options = SimulationOptions {
            method: MethodChoice::Method(method),
            ..SimulationOptions::default()
        };
        let planned = plan(&scene, &options).unwrap();
        let model = ModelRegistry::default()
            .build(&scene.params, ModelChoice::Auto)
            .unwrap()
            .model;
        let predicted = estimate_steps(&scene, model.as_ref(), method, &planned.settings)
            .unwrap()
            .expect("explicit methods and exact stepping have a prediction")
            .steps;
        // exact stepping's long steps over rung-down contact modes are not predicted (the
        // estimate is of the short steps, the worst case): compared without them, and with
        // them the estimate must stay an upper bound
        let short_only = SimulationOptions {
            long_steps: false,
            ..options.clone()
        };
        let run = simulate_scene(&scene, &short_only, &Silent).unwrap();
        let steps = run.trajectory.stats.steps as f64;
        eprintln!("{name} {method}: predicted {predicted:.0}, took {steps}");
        assert!(
            predicted / steps < 3.0 && steps / predicted < 3.0,
            "{name} {method}: predicted {predicted:.0} steps, the run took {steps}"
        );
        if method == Method::Exact {
            let run = simulate_scene(&scene, &options, &Silent).unwrap();
            let long = run.trajectory.stats.steps as f64;
            eprintln!("{name} {method} with long steps: took {long}");
            assert!(long < steps / 3.0 && long < predicted, "{long} steps");
        }
    }
}

#[test]
fn absurd_runs_are_refused_before_they_start_with_the_estimate_and_the_cause() {
    let cases: [(&str, &[&str], &[&str]); 3] = [
        (
            "case-study",
            &["sections.area=1e-12"],
            &[
                "would need about",
                "steps over 16 s",
                "more than the step limit",
                "an implicit method is not bound by it (the method esdirk or bdf)",
            ],
        ),
        (
            "case-study-no-clearance",
            &["contact.damping=1e10"],
            &["contact damping", "contact.damping"],
        ),
        (
            "adams-clearance",
            &["contact.stiffness=1e15"],
            &["stiffest mode with closed contacts", "contact.stiffness"],
        ),
    ];
    // (the stiff contact damping without clearance is what auto's imex steps over: there the
    // explicit method is the one refused; docs/numerics.md says what imex's forces are worth)
    for (name, overrides, needles) in cases {
        let scene = scene(name, overrides);
        let start = std::time::Instant::now();
        let options = SimulationOptions {
            method: MethodChoice::Method(Method::Dopri5),
            ..SimulationOptions::default()
        };
        let options = if name == "case-study-no-clearance" {
            options
        } else {
            SimulationOptions::default()
        };
        let err = simulate_scene(&scene, &options, &Silent).unwrap_err();
        assert!(
            start.elapsed().as_secs_f64() < 5.0,
            "{name}: the refusal took too long"
        );
        assert!(matches!(err, Error::Unaffordable { .. }), "{name}: {err}");
        let message = err.to_string();
        for n in needles {
            assert!(
                message.contains(n),
                "{name} {overrides:?}: `{n}` missing from: {message}"
            );
        }
    }
    // a damping beyond anything double precision resolves is refused earlier, by the scene
    let err = Scene::load(
        "scenes/case-study-no-clearance.toml".as_ref(),
        &["contact.damping=1e300".to_string()],
    )
    .unwrap_err()
    .to_string();
    assert!(
        err.contains("`contact.damping`") && err.contains("damping ratio"),
        "{err}"
    );
    // a fixed step: the count is span / dt
    let scene = scene("adams-linear", &[]);
    let options = SimulationOptions {
        method: MethodChoice::Method(Method::Rk4),
        dt: Some(1e-8),
        ..SimulationOptions::default()
    };
    let err = simulate_scene(&scene, &options, &Silent)
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("needs about 5.00e8 steps") && err.contains("raise the step dt"),
        "{err}"
    );
}

#[test]
fn an_unaffordable_run_blames_the_structural_damping_when_it_is_the_cause() {
    // stiffness-proportional damping within the plausibility bound still puts a damping rate
    // of beta omega^2 far above the fastest frequency: an explicit method's step collapses
    let scene = scene("case-study", &["sections.rayleigh_beta=1e3"]);
    let options = SimulationOptions {
        method: MethodChoice::Method(Method::Dopri5),
        ..SimulationOptions::default()
    };
    let err = simulate_scene(&scene, &options, &Silent).unwrap_err();
    assert!(matches!(err, Error::Unaffordable { .. }), "{err}");
    let message = err.to_string();
    assert!(
        message.contains("the damping: the fastest damping rate")
            && message
                .contains("The cause lies in sections.rayleigh_alpha and sections.rayleigh_beta"),
        "{message}"
    );
}
