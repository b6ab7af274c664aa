//! Failure causes are diagnosed, not guessed: a run that hits the step limit because the
//! model is too stiff for an explicit method says so with the numbers; one that hits it for
//! another reason says stiffness is not the cause. Eigen decompositions of non-finite or
//! unresolvable matrices are errors, never hangs.

mod common;

use common::{rig, run, span};
use telescopic_runtime::{
    AssembledModel, EigenError, Method, Settings, SimError, eigenvalues, modal_analysis, rest_state,
};

#[test]
fn the_step_limit_of_an_explicit_method_at_its_stability_limit_says_too_stiff() {
    let model = AssembledModel::new(&rig([4, 4])).unwrap();
    let y0 = rest_state(&model, 0.0);
    // dopri5 is held near 1e-4 s by the 4.5 kHz contact mode: 1000 steps reach 0.1 s
    let settings = Settings {
        max_steps: 1000,
        ..Settings::default()
    };
    let err = run(&model, &y0, &span(1.0, 1e-3), Method::Dopri5, &settings).unwrap_err();
    let SimError::TooManySteps { cause, .. } = &err else {
        panic!("{err}")
    };
    assert!(cause.starts_with("too stiff for this method"), "{err}");
    assert!(
        cause.contains("omega_max") && cause.contains("esdirk"),
        "{err}"
    );
}

#[test]
fn the_step_limit_of_a_tight_tolerance_says_stiffness_is_not_the_cause() {
    let model = AssembledModel::new(&rig([4, 4])).unwrap();
    let y0 = rest_state(&model, 0.0);
    // rtol 1e-13: steps far below the stability limit
    let settings = Settings {
        max_steps: 1000,
        rtol: 1e-13,
        atol: 1e-16,
        ..Settings::default()
    };
    let err = run(&model, &y0, &span(1.0, 1e-3), Method::Dopri5, &settings).unwrap_err();
    let SimError::TooManySteps { cause, .. } = &err else {
        panic!("{err}")
    };
    assert!(
        cause.contains("stayed far below the stability limit")
            && cause.contains("stiffness is not the cause"),
        "{err}"
    );
}

#[test]
fn eigenvalues_refuse_non_finite_matrices_and_balance_badly_scaled_ones() {
    let bad = nalgebra::DMatrix::from_row_slice(2, 2, &[1.0, f64::NAN, 0.0, 1.0]);
    assert!(matches!(
        eigenvalues(bad, "test"),
        Err(EigenError::NonFinite { operation: "test" })
    ));
    // an oscillator of 1e9 rad/s in displacement-velocity form: entries 1 and 1e18
    let w: f64 = 1e9;
    let stiff = nalgebra::DMatrix::from_row_slice(2, 2, &[0.0, 1.0, -w * w, -1e-3 * w]);
    let ev = eigenvalues(stiff, "oscillator").unwrap();
    for l in &ev {
        assert!(
            (l.norm() - w).abs() < 1e-9 * w,
            "|lambda| = {} for omega = {w}",
            l.norm()
        );
    }
}

#[test]
fn the_modal_analysis_refuses_a_spectrum_that_lost_its_digits() {
    let mut p = rig([5, 5]);
    p.contact.stiffness = 1e15;
    let err = modal_analysis(&AssembledModel::new(&p).unwrap(), 0.0).unwrap_err();
    assert!(matches!(err, EigenError::IllConditioned { .. }), "{err}");
    // the rig itself is resolved, with its one rigid mode
    let ok = modal_analysis(&AssembledModel::new(&rig([5, 5])).unwrap(), 0.0).unwrap();
    assert_eq!(ok.rigid_modes, 1);
}
