//! Eigenfrequencies against analytic results: the clamped-free cantilever, Greenhill's
//! self-weight buckling, and Ritz monotonicity on the test rig.

mod common;

use std::f64::consts::PI;
use std::path::PathBuf;
use telescopic_runtime::{
    AssembledModel, ContactLaw, Drive, ForceFlow, ModelParams, Profile, Scene, SectionParams,
    closed_contact_eigenvalues, modal_analysis,
};

const EI: f64 = 2.1e11 * 0.83e-8;
const RHO_A: f64 = 7850.0 * 0.001;
const L: f64 = 1.35;

fn mast(modes: usize, vehicle: f64, gravity: f64) -> ModelParams {
    ModelParams {
        damping: Default::default(),
        basis: Default::default(),
        sections: vec![SectionParams {
            length: L,
            mass_per_length: RHO_A,
            bending_stiffness: EI,
            modes,
        }],
        vehicle_mass: vehicle,
        load_mass: 0.0,
        gravity,
        force_flow: if gravity > 0.0 {
            ForceFlow::Cable
        } else {
            ForceFlow::None
        },
        contact_points: 2,
        contact: ContactLaw {
            stiffness: 1.0,
            damping: 0.0,
            clearance: 0.0,
        },
        positions: vec![],
        drive: Drive::Force(Profile::Constant(0.0)),
    }
}

#[test]
fn mast_on_a_heavy_vehicle_is_a_clamped_free_cantilever() {
    let beta_l = [1.87510407, 4.69409113, 7.85475744];
    let exact: Vec<f64> = beta_l
        .iter()
        .map(|b| b * b * (EI / (RHO_A * L.powi(4))).sqrt() / (2.0 * PI))
        .collect();
    let mut previous: Option<Vec<f64>> = None;
    for modes in 4..=30 {
        let model = AssembledModel::new(&mast(modes, 1e9, 0.0)).unwrap();
        let m = modal_analysis(&model, 0.0).unwrap();
        assert_eq!(m.rigid_modes, 1);
        let f = &m.frequencies_hz[..3];
        for i in 0..3 {
            // a Ritz approximation lies above (the vehicle's 1e9 kg leaves a 1e-8 relative
            // softening of the clamp, far below the tolerances here)
            assert!(
                f[i] >= exact[i] * (1.0 - 1e-7),
                "N = {modes}, f{}: {} below {}",
                i + 1,
                f[i],
                exact[i]
            );
        }
        if modes == 12 || modes == 30 {
            eprintln!(
                "N = {modes}: relative errors {:?}",
                (0..3)
                    .map(|i| (f[i] - exact[i]) / exact[i])
                    .collect::<Vec<_>>()
            );
        }
        if modes >= 12 {
            for i in 0..3 {
                let rel = (f[i] - exact[i]) / exact[i];
                assert!(
                    rel < 1e-3,
                    "N = {modes}, f{}: {} vs {} ({rel:e})",
                    i + 1,
                    f[i],
                    exact[i]
                );
            }
        }
        if let Some(prev) = &previous {
            common::assert_not_rising(prev, f, modes);
        }
        previous = Some(f.to_vec());
    }
}

#[test]
fn greenhill_self_weight_buckling() {
    // the lowest eigenvalue after removing the translation crosses zero at
    // rhoA g l^3 / EI = 7.837 (Greenhill 1881); find that g by bisection
    let lowest = |g: f64| {
        // near the critical load the lowest eigenvalue is small by nature: the unchecked
        // spectrum follows it through zero
        let model = AssembledModel::new(&mast(12, 100.0, g)).unwrap();
        closed_contact_eigenvalues(&model, 0.0).unwrap()[0]
    };
    let g_of = |gamma: f64| gamma * EI / (RHO_A * L.powi(3));
    let (mut lo, mut hi) = (g_of(5.0), g_of(10.0));
    assert!(
        lowest(lo) > 0.0 && lowest(hi) < 0.0,
        "no sign change between gamma 5 and 10"
    );
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if lowest(mid) > 0.0 {
            lo = mid
        } else {
            hi = mid
        }
    }
    let gamma = RHO_A * lo * L.powi(3) / EI;
    eprintln!("critical rhoA g l^3 / EI with 12 modes: {gamma:.5}");
    assert!(
        (gamma - 7.837).abs() / 7.837 < 5e-3,
        "critical rhoA g l^3/EI = {gamma}"
    );
    // beyond it the analysis reports the mode as unstable instead of a frequency
    let model = AssembledModel::new(&mast(12, 100.0, g_of(9.0))).unwrap();
    assert_eq!(
        modal_analysis(&model, 0.0)
            .unwrap()
            .unstable_growth_rates
            .len(),
        1
    );
}

#[test]
fn test_rig_frequencies_decrease_as_modes_are_added() {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../scenes/test-rig.toml");
    let mut previous: Option<Vec<f64>> = None;
    for modes in 3..=10 {
        let scene = Scene::load(&path, &[format!("sections.modes={modes}")]).unwrap();
        let model = AssembledModel::new(&scene.params).unwrap();
        let m = modal_analysis(&model, 0.0).unwrap();
        let f = m.frequencies_hz[..3].to_vec();
        if let Some(prev) = &previous {
            common::assert_not_rising(prev, &f, modes);
        }
        previous = Some(f);
    }
}

#[test]
fn prescribed_motion_holds_the_vehicle() {
    // with the vehicle held, the translation is no mode at all and the mast is a cantilever
    let mut p = mast(12, 100.0, 0.0);
    p.drive = Drive::Motion(Profile::Constant(0.0));
    let held = modal_analysis(&AssembledModel::new(&p).unwrap(), 0.0).unwrap();
    let heavy = modal_analysis(&AssembledModel::new(&mast(12, 1e12, 0.0)).unwrap(), 0.0).unwrap();
    assert_eq!(held.rigid_modes, 0);
    for i in 0..5 {
        let rel =
            (held.frequencies_hz[i] - heavy.frequencies_hz[i]).abs() / heavy.frequencies_hz[i];
        assert!(
            rel < 1e-9,
            "f{}: {} vs {}",
            i + 1,
            held.frequencies_hz[i],
            heavy.frequencies_hz[i]
        );
    }
}
