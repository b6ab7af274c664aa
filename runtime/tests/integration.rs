//! Time integration against physics: energy conservation and dissipation, momentum, the exact
//! solution of the linear time-invariant system, and every failure mode with its message.
//! All on the quadrature-assembled model (the generated ones are exercised end to end in the
//! workspace's tests/).

mod common;

use common::{exact_lti, rig, run, run_counted, span, tip_rel};
use nalgebra::{DMatrix, DVector};
use telescopic_runtime::integrate::METHOD_NAMES;
use telescopic_runtime::{
    AssembledModel, ContactState, Drive, ForceFlow, Layout, Method, Model, ModelParams, Profile,
    Settings, SimError, mechanical_energy, simulate,
};

fn tight() -> Settings {
    Settings {
        rtol: 1e-11,
        atol: 1e-14,
        ..Settings::default()
    }
}

/// A conservative rig: no gravity, no damping, no drive, fixed positions.
fn conservative(clearance: f64) -> ModelParams {
    let mut p = rig([3, 3]);
    p.gravity = 0.0;
    p.force_flow = ForceFlow::None;
    p.contact.damping = 0.0;
    p.contact.clearance = clearance;
    p.drive = Drive::Force(Profile::Constant(0.0));
    p
}

/// A non-zero initial state: the upper section displaced and moving, the vehicle moving.
fn excited(model: &dyn Model, scale: f64) -> Vec<f64> {
    let n = model.dof();
    let mut y = vec![0.0; 2 * n];
    for i in 1..n {
        y[i] = scale * 1e-3 * (1.0 + 0.3 * i as f64).recip();
        y[n + i] = scale * 0.02 * if i % 2 == 0 { 1.0 } else { -1.0 };
    }
    y[n] = 0.5;
    y
}

/// The error of a run that must fail.
fn failure<T>(result: Result<T, SimError>) -> SimError {
    match result {
        Ok(_) => panic!("the run succeeded; a failure was expected"),
        Err(e) => e,
    }
}

#[test]
fn energy_is_conserved_without_damping() {
    for clearance in [0.0, 0.004] {
        let model = AssembledModel::new(&conservative(clearance)).unwrap();
        let y0 = excited(&model, if clearance > 0.0 { 4.0 } else { 1.0 });
        let e0 = mechanical_energy(&model, 0.0, &y0);
        // dopri5 loses energy at a rate proportional to its tolerance (measured: 1e-5 over
        // 5 s at rtol 1e-10, 1e-7 at 1e-12), so conservation to 1e-6 needs a tight one
        let settings = Settings {
            rtol: 1e-12,
            atol: 1e-15,
            ..Settings::default()
        };
        let samples = run(&model, &y0, &span(5.0, 0.01), Method::Dopri5, &settings).unwrap();
        let worst = samples
            .iter()
            .map(|(t, y)| ((mechanical_energy(&model, *t, y) - e0) / e0).abs())
            .fold(0.0, f64::max);
        assert!(
            worst < 1e-6,
            "l_S = {clearance}: energy drifted by {worst:e} relative over 5 s"
        );
        eprintln!("l_S = {clearance}: worst relative energy change over 5 s {worst:.2e}");
    }
}

#[test]
fn energy_never_increases_with_damping() {
    for clearance in [0.0, 0.004] {
        let mut p = conservative(clearance);
        p.contact.damping = 1000.0;
        let model = AssembledModel::new(&p).unwrap();
        let y0 = excited(&model, 4.0);
        let samples = run(&model, &y0, &span(2.0, 0.001), Method::Dopri5, &tight()).unwrap();
        let energies: Vec<f64> = samples
            .iter()
            .map(|(t, y)| mechanical_energy(&model, *t, y))
            .collect();
        for (i, w) in energies.windows(2).enumerate() {
            assert!(
                w[1] <= w[0] * (1.0 + 1e-9),
                "l_S = {clearance}: energy rose from {} to {} J at t = {} s",
                w[0],
                w[1],
                samples[i + 1].0
            );
        }
        let lost = 1.0 - energies.last().unwrap() / energies[0];
        assert!(
            lost > 1e-3,
            "l_S = {clearance}: damping removed only {lost:e} of the energy"
        );
    }
}

#[test]
fn momentum_grows_as_force_times_time() {
    let mut p = rig([4, 4]);
    p.gravity = 0.0;
    p.force_flow = ForceFlow::None;
    let force = 100.0;
    p.drive = Drive::Force(Profile::Constant(force));
    let model = AssembledModel::new(&p).unwrap();
    let n = model.dof();
    let y0 = vec![0.0; 2 * n];
    for method in [Method::Dopri5, Method::Rk4] {
        let settings = Settings {
            dt: (method == Method::Rk4).then_some(2e-5),
            ..tight()
        };
        let samples = run(&model, &y0, &span(1.0, 0.05), method, &settings).unwrap();
        for (t, y) in &samples {
            let zd = DVector::from_column_slice(&y[n..]);
            let momentum = (model.mass_matrix() * zd)[0];
            assert!(
                (momentum - force * t).abs() <= 1e-8 * force * t.max(1e-3),
                "{method}: momentum {momentum} at t = {t}, F t = {}",
                force * t
            );
        }
    }
}

#[test]
fn linear_scene_matches_the_exact_solution() {
    // adams-linear on the assembled model: gravity off, F = 100 N from rest
    let mut p = rig([5, 5]);
    p.gravity = 0.0;
    p.force_flow = ForceFlow::None;
    let model = AssembledModel::new(&p).unwrap();
    let (dt, steps) = (1e-3, 2000);
    let exact = exact_lti(&model, 100.0, dt, steps);
    let y0 = vec![0.0; 2 * model.dof()];
    let cases = [
        (Method::Dopri5, tight()),
        (
            Method::GeneralizedAlpha {
                rho_inf: 0.8,
                adaptive: true,
            },
            Settings {
                rtol: 1e-9,
                atol: 1e-12,
                ..Settings::default()
            },
        ),
        (Method::Dop853, tight()),
        (
            Method::Esdirk,
            Settings {
                rtol: 1e-10,
                atol: 1e-13,
                ..Settings::default()
            },
        ),
        (
            Method::Bdf {
                max_order: 5,
                adaptive: true,
            },
            Settings {
                rtol: 1e-10,
                atol: 1e-13,
                ..Settings::default()
            },
        ),
        (
            Method::Imex,
            Settings {
                rtol: 1e-8,
                atol: 1e-11,
                ..Settings::default()
            },
        ),
        (
            Method::Rk4,
            Settings {
                dt: Some(2e-5),
                ..Settings::default()
            },
        ),
        (
            Method::Verlet,
            Settings {
                dt: Some(2e-6),
                ..Settings::default()
            },
        ),
    ];
    for (method, settings) in cases {
        let samples = run(&model, &y0, &span(dt * steps as f64, dt), method, &settings).unwrap();
        assert_eq!(samples.len(), steps + 1);
        let worst = samples
            .iter()
            .zip(&exact)
            .map(|((_, y), e)| (tip_rel(&model, y) - tip_rel(&model, e)).abs())
            .fold(0.0, f64::max);
        eprintln!("{method}: worst |tip_rel - exact| over 2 s = {worst:.2e} m");
        assert!(
            worst < 1e-6,
            "{method}: tip_rel off the exact solution by {worst:e} m"
        );
    }
}

/// The additive method converges at its order 4 on the linear scene (every contact closed,
/// so its implicit part carries the 3 kHz contact modes) with steps far above the contact
/// modes' explicit limit: fixed steps of `T / N` for `N` = 50 to 400 against the exact
/// solution: the error falls at every halving, by `2^3.97` from 100 to 200 steps (measured;
/// `2^3.5` from 50 to 100, still pre-asymptotic, and `2^4.7` from 200 to 400, where the error
/// nears the reference's own).
#[test]
fn the_imex_method_converges_at_order_four_stepping_over_the_contact_modes() {
    use telescopic_runtime::integrate::imex::Imex;
    use telescopic_runtime::integrate::{ContactTracker, Stepper, System};
    let mut p = rig([3, 3]);
    p.gravity = 0.0;
    p.force_flow = ForceFlow::None;
    let model = AssembledModel::new(&p).unwrap();
    let end = 0.2;
    let exact = exact_lti(&model, 100.0, end, 1);
    let target = tip_rel(&model, &exact[1]);
    let n = model.dof();
    let error = |steps: usize| {
        let h = end / steps as f64;
        let mut stepper = Imex::new(n, &Settings::default(), h);
        let mut y = vec![0.0; 2 * n];
        let (mut f, mut y1) = (vec![0.0; 2 * n], vec![0.0; 2 * n]);
        let mut sys = System {
            model: &model,
            tracker: ContactTracker::new(&model, 0.0, &y),
            stats: Default::default(),
            time_cap: f64::INFINITY,
        };
        for k in 0..steps {
            let t = k as f64 * h;
            sys.rhs(t, &y, &mut f);
            stepper.step(&mut sys, t, &y, &f, h, &mut y1).unwrap();
            y.copy_from_slice(&y1);
        }
        (tip_rel(&model, &y) - target).abs()
    };
    // the contact modes' frequency: every step below is far beyond explicit stability
    let omega_contact = 2.0 * std::f64::consts::PI * 2500.0;
    let errors: Vec<f64> = [50, 100, 200, 400].iter().map(|&s| error(s)).collect();
    eprintln!(
        "imex fixed steps h omega_contact {:.0}..{:.0}: errors {errors:?}",
        omega_contact * end / 400.0,
        omega_contact * end / 50.0
    );
    assert!(errors.windows(2).all(|p| p[1] < p[0]), "{errors:?}");
    // in the asymptotic range (100 -> 200 steps, h omega_contact 31 -> 16)
    let order = (errors[1] / errors[2]).log2();
    assert!(
        (3.7..=4.3).contains(&order),
        "observed order {order:.2} ({errors:?})"
    );
    assert!(errors[3] < 1e-10, "{errors:?}");
}

#[test]
fn explicit_method_above_its_stability_limit_reports_divergence() {
    let model = AssembledModel::new(&rig([5, 5])).unwrap();
    let y0 = vec![0.0; 2 * model.dof()];
    for (method, dt) in [(Method::Rk4, 1e-3), (Method::Verlet, 1e-3)] {
        let settings = Settings {
            dt: Some(dt),
            ..Settings::default()
        };
        let mut seen = 0;
        let err = simulate(
            &model,
            &y0,
            &span(1.0, 1e-3),
            method,
            &settings,
            &mut |_, y, _| {
                assert!(
                    y.iter().all(|v| v.is_finite()),
                    "non-finite sample handed out"
                );
                seen += 1;
            },
            None,
        )
        .unwrap_err();
        let msg = err.to_string();
        assert!(matches!(err, SimError::Diverged { .. }), "{msg}");
        for needle in [
            "diverged at t = ",
            &format!("method {method}"),
            "stability limit",
            "largest stable step",
        ] {
            assert!(msg.contains(needle), "`{needle}` missing from: {msg}");
        }
        assert!(
            seen < 1000,
            "{method}: the run went on to the end ({seen} samples)"
        );
    }
}

#[test]
fn impossible_tolerance_reports_step_underflow() {
    let mut p = rig([3, 3]);
    p.contact.clearance = 0.004;
    let model = AssembledModel::new(&p).unwrap();
    let y0 = vec![0.0; 2 * model.dof()];
    let settings = Settings {
        rtol: 1e-30,
        atol: 1e-40,
        ..Settings::default()
    };
    let err = failure(run(
        &model,
        &y0,
        &span(0.1, 1e-3),
        Method::Dopri5,
        &settings,
    ));
    let msg = err.to_string();
    assert!(matches!(err, SimError::StepUnderflow { .. }), "{msg}");
    assert!(
        msg.contains("method dopri5") && msg.contains("at t = "),
        "{msg}"
    );
    assert!(msg.contains("tolerance is too tight"), "{msg}");
}

#[test]
fn step_limit_reports_too_many_steps() {
    let model = AssembledModel::new(&rig([3, 3])).unwrap();
    let y0 = vec![0.0; 2 * model.dof()];
    let settings = Settings {
        max_steps: 50,
        ..Settings::default()
    };
    let err = failure(run(
        &model,
        &y0,
        &span(1.0, 1e-3),
        Method::Dopri5,
        &settings,
    ));
    assert!(
        matches!(err, SimError::TooManySteps { steps: 50, .. }),
        "{err}"
    );
    assert!(err.to_string().contains("method dopri5"), "{err}");
}

#[test]
fn a_work_cap_stops_the_run_once_it_is_passed_and_not_before() {
    let model = AssembledModel::new(&rig([3, 3])).unwrap();
    let y0 = vec![0.0; 2 * model.dof()];
    let capped = |max_operations: f64| {
        let settings = Settings {
            max_operations,
            ..Settings::default()
        };
        run_counted(&model, &y0, &span(0.2, 1e-3), Method::Dopri5, &settings)
    };
    let whole = capped(f64::INFINITY).unwrap().1.operations();
    // a cap equal to the run's own work lets it finish with the same count
    assert_eq!(capped(whole).unwrap().1.operations(), whole);
    // half of it stops the run past the cap, short of the whole run's work
    let err = failure(capped(whole / 2.0));
    match err {
        SimError::OverBudget {
            operations, budget, ..
        } => assert!(
            budget == whole / 2.0 && operations > budget && operations < whole,
            "{operations} against {budget} of {whole}"
        ),
        other => panic!("{other}"),
    }
}

/// A model whose Jacobian is zero: Newton's iteration matrix no longer describes the step.
struct WrongJacobian(AssembledModel);

impl Model for WrongJacobian {
    fn layout(&self) -> &Layout {
        self.0.layout()
    }
    fn params(&self) -> &ModelParams {
        self.0.params()
    }
    fn mass_matrix(&self) -> &DMatrix<f64> {
        self.0.mass_matrix()
    }
    fn stiffness_matrix(&self) -> &DMatrix<f64> {
        self.0.stiffness_matrix()
    }
    fn damping_matrix(&self) -> Option<&DMatrix<f64>> {
        self.0.damping_matrix()
    }
    fn drive_vector(&self) -> &DVector<f64> {
        self.0.drive_vector()
    }
    fn contact_vectors(&self, t: f64, g: &mut DMatrix<f64>, gdot: &mut DMatrix<f64>) {
        self.0.contact_vectors(t, g, gdot)
    }
    fn contact_vectors_at(
        &self,
        positions: &[f64],
        rates: &[f64],
        g: &mut DMatrix<f64>,
        gdot: &mut DMatrix<f64>,
    ) {
        self.0.contact_vectors_at(positions, rates, g, gdot)
    }
    fn contact_gaps(&self, t: f64, y: &[f64], xi: &mut [f64], xi_dot: &mut [f64]) {
        self.0.contact_gaps(t, y, xi, xi_dot)
    }
    fn rhs(&self, t: f64, y: &[f64], s: Option<&[ContactState]>, ydot: &mut [f64]) {
        self.0.rhs(t, y, s, ydot)
    }
    fn jacobian(&self, _: f64, _: &[f64], _: Option<&[ContactState]>, jac: &mut DMatrix<f64>) {
        jac.fill(0.0);
    }
    fn displacement(&self, section: usize, x: f64, z: &[f64]) -> f64 {
        self.0.displacement(section, x, z)
    }
    fn outputs(&self, t: f64, y: &[f64], ydot: &[f64], out: &mut [f64]) {
        self.0.outputs(t, y, ydot, out)
    }
}

#[test]
fn wrong_jacobian_reports_newton_failure() {
    let model = WrongJacobian(AssembledModel::new(&rig([3, 3])).unwrap());
    let y0 = vec![0.0; 2 * model.dof()];
    let settings = Settings {
        dt: Some(1e-3),
        ..Settings::default()
    };
    let method = Method::GeneralizedAlpha {
        rho_inf: 0.8,
        adaptive: false,
    };
    let err = failure(run(&model, &y0, &span(0.1, 1e-3), method, &settings));
    let msg = err.to_string();
    assert!(matches!(err, SimError::NewtonFailure { .. }), "{msg}");
    assert!(
        msg.contains("method galpha-fixed") && msg.contains("at t = 0.000000 s"),
        "{msg}"
    );
}

#[test]
fn telescopic_position_leaving_its_range_is_an_error() {
    // scene validation forbids this; a caller building parameters by hand is stopped too
    let mut p = rig([3, 3]);
    p.positions = vec![Profile::Shaped(
        telescopic_runtime::ShapedProfile::PiecewiseLinear {
            times: vec![0.0, 1.0],
            values: vec![1.0, 1.5],
        },
    )];
    let model = AssembledModel::new(&p).unwrap();
    let y0 = vec![0.0; 2 * model.dof()];
    let err = failure(run(
        &model,
        &y0,
        &span(1.0, 1e-3),
        Method::Dopri5,
        &Settings::default(),
    ));
    let SimError::PositionOutOfRange { t, section, .. } = &err else {
        panic!("{err}")
    };
    assert_eq!(*section, 2);
    // a_2 reaches l_1 = 1.35 m at t = 0.7 s
    assert!((0.69..=0.71).contains(t), "{err}");
    assert!(err.to_string().contains("a_2 = 1.35"), "{err}");
}

#[test]
fn method_names_round_trip_and_bad_names_are_listed() {
    for name in [
        "dopri5",
        "rk4",
        "verlet",
        "dop853",
        "esdirk",
        "bdf",
        "bdf2",
        "bdf-fixed",
        "bdf2-fixed",
        "galpha",
        "galpha-fixed",
        "galpha-rho0.5",
        "galpha-fixed-rho0",
    ] {
        assert_eq!(Method::from_name(name).unwrap().name(), name);
    }
    let err = Method::from_name("euler").unwrap_err();
    for (known, _) in METHOD_NAMES.iter().take(5) {
        assert!(err.contains(known), "{err}");
    }
    assert!(
        Method::from_name("galpha-rho1.5")
            .unwrap_err()
            .contains("[0, 1]")
    );
    for bad in ["bdf0", "bdf6", "bdfx", "bdf6-fixed"] {
        let err = Method::from_name(bad).unwrap_err();
        assert!(err.contains("1 to 5"), "{err}");
    }
    let model = AssembledModel::new(&rig([3, 3])).unwrap();
    let y0 = vec![0.0; 2 * model.dof()];
    let err = failure(run(
        &model,
        &y0,
        &span(0.1, 1e-3),
        Method::Rk4,
        &Settings::default(),
    ));
    assert!(err.to_string().contains("give the step dt"), "{err}");
}

#[test]
fn undamped_step_limits_are_the_textbook_ones() {
    // two independent paths: omega_max from the symmetric eigenproblem, the limit from the
    // spectral radius of the methods' step matrices
    use telescopic_runtime::integrate::stability::{
        RK4_IMAGINARY_AXIS, VERLET_LIMIT, stability_report,
    };
    let model = AssembledModel::new(&conservative(0.0)).unwrap();
    let r = stability_report(&model, 0.0).unwrap();
    eprintln!(
        "omega_max = {:.6e} rad/s, rk4 h omega = {:.6}, verlet h omega = {:.6}",
        r.omega_max,
        r.rk4_step * r.omega_max,
        r.verlet_step * r.omega_max
    );
    assert!(r.growth_rate < 1e-6 * r.omega_max);
    assert!((r.rk4_step * r.omega_max / RK4_IMAGINARY_AXIS - 1.0).abs() < 1e-5);
    assert!((r.verlet_step * r.omega_max / VERLET_LIMIT - 1.0).abs() < 1e-5);
}
