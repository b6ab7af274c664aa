//! The finite-element beams against closed-form beams (the clamped-free cantilever, Greenhill's
//! self-weight buckling load through the frequency's fall with gravity) and the static
//! correction basis: a Rayleigh-Ritz upper bound of the elements' frequencies at every size,
//! exactly static under a point force, and its moving contacts' table within its tolerance of
//! the exact evaluation; the elements with contacts sliding across them against the most
//! refined Ritz model.

mod common;

use common::{run_counted, span};
use std::f64::consts::PI;
use telescopic_runtime::model::params::SPLINE_TABLE_TOLERANCE;
use telescopic_runtime::nalgebra::DMatrix;
use telescopic_runtime::{
    AssembledModel, Basis, ContactLaw, Drive, ElementModel, ForceFlow, Method, Model, ModelParams,
    Profile, Scene, SectionParams, Settings, ShapedProfile, modal_analysis, rest_state,
};

const EI: f64 = 2.1e11 * 0.83e-8;
const RHO_A: f64 = 7850.0 * 0.001;
const L: f64 = 1.35;

/// One section on a vehicle of `vehicle` kg.
fn mast(vehicle: f64) -> ModelParams {
    ModelParams {
        damping: Default::default(),
        basis: Default::default(),
        sections: vec![SectionParams {
            length: L,
            mass_per_length: RHO_A,
            bending_stiffness: EI,
            modes: 4,
        }],
        vehicle_mass: vehicle,
        load_mass: 0.0,
        gravity: 0.0,
        force_flow: ForceFlow::None,
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
fn the_elements_on_a_heavy_vehicle_are_the_clamped_free_cantilever() {
    let beta_l = [1.87510407, 4.69409113, 7.85475744];
    let f = ElementModel::new(&mast(1e9), 32)
        .unwrap()
        .frequencies_hz(3)
        .unwrap();
    for (i, b) in beta_l.iter().enumerate() {
        let exact = b * b * (EI / (RHO_A * L.powi(4))).sqrt() / (2.0 * PI);
        let error = f[i] / exact - 1.0;
        eprintln!(
            "f{}: {:.9} Hz against {exact:.9} Hz ({error:.1e})",
            i + 1,
            f[i]
        );
        // Hermite elements converge from above as h^4: 32 elements leave 1e-8 to 2e-6
        assert!((0.0..5e-6).contains(&error), "f{}: {error}", i + 1);
    }
}

#[test]
fn the_elements_carry_the_self_weight_prestress() {
    // Greenhill: a clamped column buckles under its own weight at rhoA g l^3 / EI = 7.8373;
    // the first frequency squared falls linearly with g towards zero there
    let g_critical = 7.8373 * EI / (RHO_A * L.powi(3));
    let f1 = |fraction: f64| {
        let mut p = mast(1e9);
        p.gravity = fraction * g_critical;
        p.force_flow = ForceFlow::Cable;
        ElementModel::new(&p, 32)
            .unwrap()
            .frequencies_hz(1)
            .unwrap()[0]
    };
    let (a, b) = (f1(0.0).powi(2), f1(0.5).powi(2));
    // f^2 at half the critical load, extrapolated linearly: zero at 1.0 within the curvature
    // of f^2(g) (a few per cent)
    let zero_at = a / (a - b) * 0.5;
    eprintln!("f1^2: {a:.5} at g = 0, {b:.5} at half Greenhill's load: zero at {zero_at:.4}");
    assert!((0.95..1.1).contains(&zero_at), "{zero_at}");
}

/// The two-section rig of adams-linear with `modes` and the static correction shapes.
fn corrected(modes: usize) -> ModelParams {
    let mut p = common::rig([modes, modes]);
    p.basis = Basis::ModesAndStatic;
    p
}

#[test]
fn the_static_correction_basis_bounds_the_beams_from_above_and_converges() {
    let beams = ElementModel::new(&common::rig([5, 5]), 32)
        .unwrap()
        .frequencies_hz(5)
        .unwrap();
    let mut previous = f64::INFINITY;
    for modes in [2, 3, 4, 6, 8] {
        let f = modal_analysis(&AssembledModel::new(&corrected(modes)).unwrap(), 0.0)
            .unwrap()
            .frequencies_hz;
        for i in 0..5 {
            assert!(
                f[i] >= beams[i] * (1.0 - 1e-8),
                "{modes} modes, f{}: {} < {}",
                i + 1,
                f[i],
                beams[i]
            );
        }
        let error = f[0] / beams[0] - 1.0;
        eprintln!("{modes} modes + static: f1 error {error:.2e}");
        assert!(
            error <= previous * 1.0001 && error < 5e-5,
            "{modes}: {error}"
        );
        previous = error;
    }
}

#[test]
fn the_static_correction_basis_holds_a_static_tip_deflection_exactly() {
    // a cantilever (the heavy vehicle held) under a tip force: w(l) = F l^3 / (3 EI); with the
    // splines the basis holds the cubic exactly, so K z = F at the tip gives it to rounding,
    // where the paper's 2 modes miss it
    let tip = |basis: Basis| {
        let mut p = mast(1e9);
        p.basis = basis;
        p.sections[0].modes = 2;
        let m = AssembledModel::new(&p).unwrap();
        let n = m.dof();
        let row = m.shape_row(1, L, 0);
        // K on the relative coordinates (the translation is held)
        let k = m
            .stiffness_matrix()
            .view((1, 1), (n - 1, n - 1))
            .into_owned();
        let f = DMatrix::from_fn(n - 1, 1, |i, _| row[i + 1]);
        let z = k.lu().solve(&f).unwrap();
        (1..n).map(|j| row[j] * z[j - 1]).sum::<f64>()
    };
    let exact = L.powi(3) / (3.0 * EI);
    let (with, without) = (tip(Basis::ModesAndStatic), tip(Basis::Modes));
    eprintln!(
        "tip deflection per N: {with:.6e} with the splines, {without:.6e} without, {exact:.6e} exact"
    );
    assert!((with / exact - 1.0).abs() < 1e-10, "{with}");
    assert!((without / exact - 1.0).abs() > 1e-3, "{without}");
}

#[test]
fn moving_contacts_of_the_static_correction_basis_are_tabulated_within_tolerance() {
    let mut p = corrected(3);
    p.contact_points = 2;
    p.positions = vec![Profile::Shaped(ShapedProfile::Smoothstep {
        start: 0.0,
        end: 12.0,
        from: 0.35,
        to: 1.15,
    })];
    let tabulated = AssembledModel::new(&p).unwrap();
    let exact = AssembledModel::exact(&p).unwrap();
    let (n, nc) = (exact.dof(), exact.layout().contact_count());
    for t in [0.0, 0.77, 3.1, 6.0, 9.43, 12.0, 14.0] {
        let (mut g1, mut gd1) = (DMatrix::zeros(n, nc), DMatrix::zeros(n, nc));
        let (mut g2, mut gd2) = (DMatrix::zeros(n, nc), DMatrix::zeros(n, nc));
        tabulated.contact_vectors(t, &mut g1, &mut gd1);
        exact.contact_vectors(t, &mut g2, &mut gd2);
        let scale = g2.abs().max();
        let error = (&g1 - &g2).abs().max() / scale;
        assert!(error <= 2.0 * SPLINE_TABLE_TOLERANCE, "t = {t}: {error:e}");
    }
}

/// `tip_rel` at every sample of a run.
fn tip_rel(model: &dyn Model, samples: &[(f64, Vec<f64>)]) -> Vec<f64> {
    let ydot = vec![0.0; 2 * model.dof()];
    let mut out = vec![0.0; model.output_names().len()];
    samples
        .iter()
        .map(|(t, y)| {
            model.outputs(*t, y, &ydot, &mut out);
            out[1]
        })
        .collect()
}

/// Largest difference of two equally long series.
fn largest_difference(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

/// The elements' contact vectors where the positions move: their rate is the time derivative
/// of the vector (central differences), and the point slides across element boundaries.
#[test]
fn the_elements_sliding_contact_vectors_have_their_time_derivative_as_rate() {
    let scene = Scene::load("../scenes/case-study-no-clearance.toml".as_ref(), &[]).unwrap();
    let beams = ElementModel::new(&scene.params, 16).unwrap();
    let (n, nc) = (beams.dof(), beams.layout().contact_count());
    let (mut g, mut gdot) = (DMatrix::zeros(n, nc), DMatrix::zeros(n, nc));
    let (mut g_plus, mut g_minus) = (DMatrix::zeros(n, nc), DMatrix::zeros(n, nc));
    let mut scratch = DMatrix::zeros(n, nc);
    let h = 1e-6;
    for t in [0.5, 2.0, 5.0, 9.0] {
        beams.contact_vectors(t, &mut g, &mut gdot);
        beams.contact_vectors(t + h, &mut g_plus, &mut scratch);
        beams.contact_vectors(t - h, &mut g_minus, &mut scratch);
        let difference = (&g_plus - &g_minus) / (2.0 * h);
        let error = (&difference - &gdot).abs().max();
        assert!(gdot.abs().max() > 1e-3, "the contacts move at {t} s");
        assert!(error < 1e-6 * gdot.abs().max(), "{t} s: {error}");
    }
}

/// On case-study-no-clearance's first 4 s (the upper section extending, the contacts sliding
/// up to 0.3 m across 8 to 32 elements per section) the elements converge, and they meet the
/// most refined Ritz model (10 modes with the static shapes per section): two independent
/// discretizations of the same beams.
#[test]
fn the_elements_with_sliding_contacts_converge_to_the_most_refined_ritz_model() {
    let scene = Scene::load("../scenes/case-study-no-clearance.toml".as_ref(), &[]).unwrap();
    let samples = span(4.0, 1e-3);
    let tight = Settings {
        rtol: 1e-8,
        atol: 1e-11,
        ..Settings::default()
    };
    let mut refined = scene.params.clone();
    refined.basis = Basis::ModesAndStatic;
    for s in &mut refined.sections {
        s.modes = 10;
    }
    let ritz = AssembledModel::new(&refined).unwrap();
    let (run, _) = run_counted(
        &ritz,
        &rest_state(&ritz, 0.0),
        &samples,
        Method::Dop853,
        &tight,
    )
    .unwrap();
    let ritz_tip = tip_rel(&ritz, &run);
    let tips: Vec<Vec<f64>> = [8, 16, 32]
        .into_iter()
        .map(|elements| {
            let beams = ElementModel::new(&scene.params, elements).unwrap();
            let y0 = rest_state(&beams, 0.0);
            let (run, _) = run_counted(&beams, &y0, &samples, Method::Imex, &tight).unwrap();
            tip_rel(&beams, &run)
        })
        .collect();
    let coarse = largest_difference(&tips[0], &tips[1]);
    let fine = largest_difference(&tips[1], &tips[2]);
    let against_ritz = largest_difference(&tips[2], &ritz_tip);
    let peak = ritz_tip.iter().fold(0.0_f64, |a, v| a.max(v.abs()));
    eprintln!(
        "tip_rel (peak {peak:.3} m): 8 to 16 elements {coarse:.2e} m, 16 to 32 {fine:.2e} m; \
         32 elements against the Ritz model {against_ritz:.2e} m"
    );
    // Hermite elements: the change falls by at least 4 per halving (measured 7.5)
    assert!(fine < coarse / 4.0, "{coarse} {fine}");
    // the two discretizations agree to 1e-5 m, 2e-4 of the peak (measured 2.6e-6 m of
    // 0.048 m: the Ritz model's own truncation, where the elements' last halving moved
    // 4.5e-7 m)
    assert!(against_ritz < 1e-5, "{against_ritz}");
}
