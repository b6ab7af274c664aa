//! The modal surrogate that predicts a model's size: its response against the exact
//! solution of the linear system it stands for.

mod common;

use common::{exact_lti, rig, tip_rel};
use telescopic_runtime::analysis::modal_surrogate::surrogate_tip;
use telescopic_runtime::{AssembledModel, Drive, ForceFlow, Profile};

/// The rig without gravity or contact damping (the surrogate leaves both out), pushed by
/// 100 N from rest.
fn undamped_rig(modes: usize) -> AssembledModel {
    let mut p = rig([modes, modes]);
    p.gravity = 0.0;
    p.force_flow = ForceFlow::None;
    p.contact.damping = 0.0;
    p.drive = Drive::Force(Profile::Constant(100.0));
    AssembledModel::new(&p).unwrap()
}

/// The largest difference of two responses, relative to the first one's peak.
fn relative_difference(a: &[f64], b: &[f64]) -> f64 {
    let peak = a.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    let worst = a
        .iter()
        .zip(b)
        .fold(0.0_f64, |m, (x, y)| m.max((x - y).abs()));
    worst / peak
}

#[test]
fn the_surrogate_follows_the_exact_solution_of_the_linear_system() {
    for modes in [3, 5, 8] {
        let model = undamped_rig(modes);
        let (dt, steps) = (1e-3, 2000);
        let exact: Vec<f64> = exact_lti(&model, 100.0, dt, steps)
            .iter()
            .map(|y| tip_rel(&model, &y[..]))
            .collect();
        let surrogate = surrogate_tip(&model, (0.0, dt * steps as f64), dt).unwrap();
        assert_eq!(surrogate.len(), exact.len());
        // the modes above the sixth answer quasi-statically in the surrogate: their
        // vibration, far above the drive's step, is all it leaves out (2e-9 to 1.4e-7 of the
        // peak measured)
        let off = relative_difference(&exact, &surrogate);
        assert!(
            off < 1e-5,
            "{modes} modes per section: {off:.2e} of the peak"
        );
    }
}

#[test]
fn the_surrogate_is_linear_in_the_drive_and_at_rest_without_it() {
    let respond = |force: f64| {
        let mut p = rig([5, 5]);
        p.drive = Drive::Force(Profile::Constant(force));
        let model = AssembledModel::new(&p).unwrap();
        surrogate_tip(&model, (0.0, 1.0), 1e-3).unwrap()
    };
    let (base, larger) = (respond(100.0), respond(250.0));
    let peak = base.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    assert!(peak > 0.0);
    let scaled: Vec<f64> = base.iter().map(|v| 2.5 * v).collect();
    let off = relative_difference(&scaled, &larger);
    assert!(
        off < 1e-12,
        "2.5 times the force: {off:.2e} of the peak off"
    );
    assert!(respond(0.0).iter().all(|&y| y == 0.0));
}
