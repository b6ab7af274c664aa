//! `imex` treats a model's stiff modes implicitly (those turning more than 0.6 rad per
//! output sample: the static correction shapes' and a large basis's high modes), so the step
//! count stays near the paper's 4 modes per section and every output of the state (the
//! contact forces too) agrees with a tight explicit reference.

mod common;

use common::{run_counted, span};
use telescopic_runtime::{AssembledModel, Basis, Method, Model, Scene, Settings, rest_state};

/// case-study-no-clearance over its first 4 s (the extension and the drive's first push),
/// with `basis` and `modes` per section.
fn case_study(basis: Basis, modes: usize) -> AssembledModel {
    let mut scene = Scene::load("../scenes/case-study-no-clearance.toml".as_ref(), &[]).unwrap();
    scene.params.basis = basis;
    for s in &mut scene.params.sections {
        s.modes = modes;
    }
    AssembledModel::new(&scene.params).unwrap()
}

/// Every output at every sample of a run.
fn outputs(model: &dyn Model, samples: &[(f64, Vec<f64>)]) -> Vec<Vec<f64>> {
    let ydot = vec![0.0; 2 * model.dof()];
    samples
        .iter()
        .map(|(t, y)| {
            let mut out = vec![0.0; model.output_names().len()];
            model.outputs(*t, y, &ydot, &mut out);
            out
        })
        .collect()
}

/// The largest difference between two runs' outputs whose names start with `prefix`, over
/// every sample.
fn largest_difference(
    model: &dyn Model,
    ours: &[(f64, Vec<f64>)],
    theirs: &[(f64, Vec<f64>)],
    prefix: &str,
) -> f64 {
    let names = model.output_names();
    let (ours, theirs) = (outputs(model, ours), outputs(model, theirs));
    (0..names.len())
        .filter(|&i| names[i].starts_with(prefix))
        .flat_map(|i| {
            ours.iter()
                .zip(&theirs)
                .map(move |(a, b)| (a[i] - b[i]).abs())
        })
        .fold(0.0, f64::max)
}

#[test]
fn imex_steps_over_the_static_shapes_stiff_modes_and_keeps_every_output() {
    check_stiff_modes(Basis::ModesAndStatic, 2);
}

/// The paper's basis with 9 modes per section: its modes 5 to 9 reach 1.7 kHz, where
/// the explicit part took three times the steps of 4 modes and left the forces 180 N off.
#[test]
fn imex_steps_over_a_large_bases_high_modes_and_keeps_every_output() {
    check_stiff_modes(Basis::Modes, 9);
}

/// `imex` on `basis` with `modes` per section against dop853 at rtol 1e-10, and its step
/// count against the paper's 4 modes.
fn check_stiff_modes(basis: Basis, modes: usize) {
    let model = case_study(basis, modes);
    let span = span(4.0, 1e-3);
    let y0 = rest_state(&model, 0.0);
    let settings = Settings::default();
    let (imex, stats) = run_counted(&model, &y0, &span, Method::Imex, &settings).unwrap();
    let tight = Settings {
        rtol: 1e-10,
        atol: 1e-13,
        ..Settings::default()
    };
    let (reference, _) = run_counted(&model, &y0, &span, Method::Dop853, &tight).unwrap();
    let worst = |prefix: &str| largest_difference(&model, &imex, &reference, prefix);
    let (tip, top, forces) = (worst("tip_rel"), worst("top1_rel"), worst("f_"));
    eprintln!(
        "{basis:?} {modes}: imex {} steps: tip_rel {tip:.2e} m, top1_rel {top:.2e} m, contact forces {forces:.2e} N \
         off dop853 at rtol 1e-10",
        stats.steps
    );
    // the contact forces peak near 400 N: within 1 %, where an explicit beam part left
    // 170 N (its step control held tip_rel, not the stiff modes' share of the forces)
    assert!(tip < 1e-6 && top < 1e-5, "{tip} {top}");
    assert!(forces < 4.0, "{forces}");
    // the step is the paper's basis's, not the stiff modes': counted, not timed
    let paper = case_study(Basis::Modes, 4);
    let (_, paper_stats) = run_counted(
        &paper,
        &rest_state(&paper, 0.0),
        &span,
        Method::Imex,
        &settings,
    )
    .unwrap();
    assert!(
        stats.steps <= paper_stats.steps + paper_stats.steps / 5,
        "{} steps with the static shapes, {} with the paper's 4 modes",
        stats.steps,
        paper_stats.steps
    );
}

/// With a longest step of 8 ms, `imex` crosses the 1 ms output samples and gives them by
/// its steps' cubic Hermite interpolants: at most a quarter of the steps (measured an
/// eighth), every output still close
/// to a tight explicit reference (the static shapes with 6 modes per section, whose stiff
/// modes then reach down to 12 Hz).
#[test]
fn imex_steps_across_samples_up_to_a_longest_step() {
    let model = case_study(Basis::ModesAndStatic, 6);
    let span = span(4.0, 1e-3);
    let y0 = rest_state(&model, 0.0);
    let on_samples = Settings {
        rtol: 1e-5,
        atol: 1e-8,
        ..Settings::default()
    };
    let across = Settings {
        longest_step: Some(8e-3),
        ..on_samples
    };
    let tight = Settings {
        rtol: 1e-10,
        atol: 1e-13,
        ..Settings::default()
    };
    let (long, long_stats) = run_counted(&model, &y0, &span, Method::Imex, &across).unwrap();
    let (_, sample_stats) = run_counted(&model, &y0, &span, Method::Imex, &on_samples).unwrap();
    let (reference, _) = run_counted(&model, &y0, &span, Method::Dop853, &tight).unwrap();
    assert_eq!(long.len(), reference.len(), "every sample is given");
    let worst = |prefix: &str| largest_difference(&model, &long, &reference, prefix);
    let (tip, forces) = (worst("tip_rel"), worst("f_"));
    eprintln!(
        "longest step 8 ms: {} steps against {} on the samples; tip_rel {tip:.2e} m, contact \
         forces {forces:.2e} N off dop853 at rtol 1e-10",
        long_stats.steps, sample_stats.steps
    );
    // counted work, not time: steps end on no sample but where the control puts them
    assert!(4 * long_stats.steps <= sample_stats.steps + sample_stats.steps / 10);
    // the Hermite samples keep tip_rel within 3e-5 m of its 0.2 m peak and the forces
    // within 3 % of their 400 N peak
    assert!(tip < 3e-5, "{tip}");
    assert!(forces < 12.0, "{forces}");
}

/// A longest step that is not a positive number of seconds is refused, naming the rule.
#[test]
fn a_longest_step_that_is_not_positive_is_refused() {
    let model = case_study(Basis::Modes, 4);
    let y0 = rest_state(&model, 0.0);
    for bad in [0.0, -1e-3, f64::NAN, f64::INFINITY] {
        let settings = Settings {
            longest_step: Some(bad),
            ..Settings::default()
        };
        let message = run_counted(&model, &y0, &span(0.1, 1e-3), Method::Imex, &settings)
            .unwrap_err()
            .to_string();
        assert!(
            message.contains("the longest step must be a positive number of seconds"),
            "{message}"
        );
    }
}
