//! The strain-rate law from a machine's sensors (`vehicle` + `kappa_1_0`, sampled at 1 kHz
//! with noise, delay and saturation) on case-study with clearance: its reduction, force and
//! travel at the default settings, on plants it was not designed for, its file's checks.

use telescopic::control::{
    Controller, DesignOptions, Estimator, SampledLaw, compare_with_open_loop, design,
};
use telescopic::run::SimulationOptions;
use telescopic::{Scene, Silent};

fn scene(overrides: &[&str]) -> Scene {
    let o: Vec<String> = overrides.iter().map(|s| s.to_string()).collect();
    Scene::load("scenes/case-study.toml".as_ref(), &o).unwrap()
}

fn sensors() -> DesignOptions {
    DesignOptions {
        sensors: vec!["vehicle".into(), "kappa_1_0".into()],
        ..DesignOptions::default()
    }
}

/// Reduction of the residual std, peak force (N) and travel against the open loop of `plant`.
fn run(plant: &Scene, controller: &Controller) -> (f64, f64, f64) {
    let run =
        compare_with_open_loop(plant, controller, &SimulationOptions::default(), &Silent).unwrap();
    let reduction = run.without.residual_std / run.with.residual_std;
    let travel = run.with.final_vehicle / run.without.final_vehicle - 1.0;
    eprintln!(
        "{}: {reduction:.2}x, peak {:.1} N, travel {:+.3} %, p2p {:.1} % of open loop, {} \
         switches",
        plant.name,
        run.with.peak_force,
        100.0 * travel,
        100.0 * run.with.residual_p2p / run.without.residual_p2p,
        run.with.window_switches
    );
    (reduction, run.with.peak_force, travel)
}

#[test]
fn the_strain_rate_law_damps_case_study_with_clearance_from_the_machine_sensors() {
    let nominal = scene(&[]);
    // the default law with these sensors is the strain-rate law
    let controller = design(&nominal, &sensors()).unwrap();
    let sampled = controller.sampled.as_ref().unwrap();
    let law = sampled.strain_rate.as_ref().expect("strain-rate law");
    assert_eq!(sampled.estimator, Estimator::None);
    assert!(sampled.points.is_empty());
    // the first mode from the symmetric modal analysis equals the design's, taken from the
    // eigenvalues of the state matrix (another path); tip per root curvature grows as the
    // telescope extends (a longer cantilever bends more at the tip per curvature at the foot)
    for (p, point) in law.points.iter().zip(&controller.schedule) {
        assert!(
            (p.first_mode_hz - point.first_mode_hz).abs() <= 1e-6 * point.first_mode_hz,
            "{} Hz against {} Hz",
            p.first_mode_hz,
            point.first_mode_hz
        );
        assert!(p.tip_per_curvature_m2 > 0.0 && p.gain > 0.0, "{p:?}");
    }
    assert!(
        law.points
            .windows(2)
            .all(|w| w[1].tip_per_curvature_m2 > w[0].tip_per_curvature_m2),
        "{:?}",
        law.points
    );
    assert_eq!(
        Controller::from_json(&controller.to_json()).unwrap(),
        controller
    );
    // measured 18.5x at 188 N and +0.18 % travel (docs/control.md): the 10x
    let (reduction, peak, travel) = run(&nominal, &controller);
    assert!(reduction >= 10.0, "{reduction}x");
    assert!(peak <= 300.0 + 1e-9, "{peak} N");
    assert!(travel.abs() <= 0.01, "travel {travel}");
}

#[test]
fn the_strain_rate_law_holds_on_plants_it_was_not_designed_for() {
    let controller = design(&scene(&[]), &sensors()).unwrap();
    // measured 4.9x to 5.2x, 18.2x, 21.7x, 18.6x and 4.6x (docs/control.md):
    // at least 5x on the three
    // plants whose open loop settles into a repeatable residual; the travel within 1 % of that
    // plant's open loop except for the heavier load, which the vehicle loop drives to the
    // nominal rigid travel (+9.3 %). The softer sections' open loop rattles in the residual
    // window, so its residual std is a statistic of a chaotic run: 0.035 to 0.059 m between
    // equally valid methods and tolerances (3.1x to 5.3x against the same controlled
    // residual, 0.0111 m to four digits in each): there a 5x goal does not hold
    // robustly (docs/control.md), and the test asks for the bottom of that spread. The
    // heavier load's open loop rattles too: 0.224 to 0.238 m between paths (4.9x to 5.2x
    // against 0.0459 m in each), so it gets the bottom of its spread
    for (change, least) in [
        ("masses.load=30", 4.8),
        ("contact.clearance=0.005", 5.0),
        ("contact.clearance=0.02", 5.0),
        ("contact.stiffness=0.11875e9", 5.0),
        ("sections.youngs_modulus=1.89e11", 3.0),
    ] {
        let (reduction, peak, travel) = run(&scene(&[change]), &controller);
        assert!(reduction >= least, "{change}: {reduction}x");
        assert!(peak <= 300.0 + 1e-9, "{change}: {peak} N");
        let bound = if change.starts_with("masses.load") {
            0.1
        } else {
            0.01
        };
        assert!(travel.abs() <= bound, "{change}: travel {travel}");
    }
}

#[test]
fn strain_rate_designs_and_files_are_checked() {
    let plant = scene(&[]);
    let err = |options: DesignOptions| design(&plant, &options).unwrap_err().to_string();
    let e = err(DesignOptions {
        sensors: vec!["vehicle".into(), "acc_load".into()],
        law: SampledLaw::StrainRate,
        ..DesignOptions::default()
    });
    assert!(
        e.contains("DesignOptions::sensors") && e.contains("kappa_1_0"),
        "{e}"
    );
    let e = "pid".parse::<SampledLaw>().unwrap_err();
    assert!(
        e.contains("`pid` is not a sampled law; use auto, lqr or strain-rate"),
        "{e}"
    );
    let e = err(DesignOptions {
        added_damping: -0.1,
        ..sensors()
    });
    assert!(e.contains("DesignOptions::added_damping"), "{e}");
    let controller = design(&plant, &sensors()).unwrap();
    let edit = |f: &dyn Fn(&mut Controller)| {
        let mut c = controller.clone();
        f(&mut c);
        c.check_fits(&plant).unwrap_err().to_string()
    };
    fn law(c: &mut Controller) -> &mut telescopic::control::file::schema::StrainRateLaw {
        c.sampled.as_mut().unwrap().strain_rate.as_mut().unwrap()
    }
    let e = edit(&|c| law(c).points[2].gain = f64::NAN);
    assert!(e.contains("sampled.strain_rate.points[2].gain"), "{e}");
    let e = edit(&|c| {
        law(c).points.pop();
    });
    assert!(e.contains("sampled.strain_rate.points"), "{e}");
    let e = edit(&|c| c.sampled.as_mut().unwrap().sensors[1] = "acc_load".into());
    assert!(
        e.contains("sampled.sensors") && e.contains("kappa_1_0"),
        "{e}"
    );
    let e = edit(&|c| c.sampled.as_mut().unwrap().estimator = Estimator::Linear);
    assert!(e.contains("sampled.estimator"), "{e}");
}
