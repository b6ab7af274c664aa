//! Velocity feedback through the servo's setpoint, on a single section held on its vehicle
//! (one flexible mode, undamped, no clearance): the closed loop's damping ratio, read from
//! the decay of the tip's vibration, is the one designed, and on plants it was not designed
//! for the single-mode theory's; without gains the loop is the open loop; the vehicle comes
//! back to its target; bad files are refused naming the field.

mod common;

use nalgebra::DMatrix;
use telescopic::control::law::sampled::SampledController;
use telescopic::control::{
    closed_loop::velocity::{simulate_velocity, simulate_velocity_told},
    design::velocity::VelocityDesign,
    design::velocity::design_velocity_feedback,
    file::velocity::VelocityFeedback,
    law::velocity::{LawGains, VelocityController},
};
use telescopic::plan::candidates::unshaped;
use telescopic::plan::moving_scene;
use telescopic::run::{SimulationOptions, simulate_scene};
use telescopic::{Scene, Silent};
use telescopic_runtime::{AssembledModel, ContactMode, Lpv, Model, SCurve, modal_analysis_with};

/// A 0.5 m move of the held section (first mode near 2.7 Hz), simulated until `arrival + 6` s.
fn moving() -> (Scene, f64) {
    moving_with(&[])
}

/// The move of [`moving`] on the held section with `overrides` (`key=value`).
fn moving_with(overrides: &[&str]) -> (Scene, f64) {
    let mut all = vec!["sections.modes=2".to_string()];
    all.extend(overrides.iter().map(|o| o.to_string()));
    let scene = common::single_section("servo", "motion = 0.0", 1.0, 0.001, &all);
    let curve = SCurve {
        start: 0.0,
        from: 0.0,
        distance: 0.5,
        v_max: 1.0,
        a_max: 1.0,
        j_max: 20.0,
    };
    let candidate = unshaped(&curve);
    let end = candidate.arrival_s + 6.0;
    (
        moving_scene(&scene, &candidate.profile, end).unwrap(),
        candidate.arrival_s,
    )
}

fn options() -> SimulationOptions {
    SimulationOptions {
        error_estimate: false,
        ..SimulationOptions::default()
    }
}

/// The feedback designed for `scene` adding `zeta`, without measurement noise.
fn noiseless(scene: &Scene, zeta: f64) -> VelocityFeedback {
    let design = VelocityDesign {
        added_damping: zeta,
        ..VelocityDesign::default()
    };
    let mut file = design_velocity_feedback(scene, &design).unwrap();
    file.noise = vec![0.0; 2];
    file
}

/// `(t, tip_rel)` of a run after `from` (s).
fn tip_after(traj: &telescopic::run::Trajectory, from: f64) -> Vec<(f64, f64)> {
    let tip = traj.index("tip_rel").unwrap();
    traj.rows
        .iter()
        .filter(|r| r[0] >= from)
        .map(|r| (r[0], r[tip]))
        .collect()
}

/// The damping ratio from the logarithmic decrement of the first `count` positive peaks.
fn damping_ratio(series: &[(f64, f64)], count: usize) -> f64 {
    let peaks: Vec<f64> = series
        .windows(3)
        .filter(|w| w[1].1 > w[0].1 && w[1].1 >= w[2].1 && w[1].1 > 0.0)
        .map(|w| w[1].1)
        .take(count)
        .collect();
    assert_eq!(peaks.len(), count, "too few peaks: {peaks:?}");
    let delta = (peaks[0] / peaks[count - 1]).ln() / (count - 1) as f64;
    delta / (4.0 * std::f64::consts::PI.powi(2) + delta * delta).sqrt()
}

#[test]
fn the_closed_loop_damps_the_first_mode_by_the_designed_ratio() {
    let (scene, arrival) = moving();
    let open = simulate_scene(&scene, &options(), &Silent).unwrap();
    // the structure has no damping of its own: the open loop's decrement is zero
    let undamped = damping_ratio(&tip_after(&open.trajectory, arrival), 4);
    assert!(undamped.abs() < 2e-3, "open loop {undamped}");
    for zeta in [0.05, 0.1] {
        let file = noiseless(&scene, zeta);
        let run = simulate_velocity(&scene, &file, &options(), &Silent).unwrap();
        let measured = damping_ratio(&tip_after(&run.simulation.trajectory, arrival), 4);
        eprintln!("designed {zeta}, measured {measured}");
        assert!(
            (measured - zeta).abs() < 0.1 * zeta,
            "designed {zeta}, measured {measured}"
        );
    }
}

/// On plants it was not designed for (another load, a softer or stiffer section) the law
/// still damps the first mode, by the ratio the single-mode theory gives. The plant's mode
/// `y'' + w_p^2 y = -Gamma_p a` (`Gamma_p` its participation in `tip_rel`) on the vehicle
/// `X'' = a`, the gauge read through the design's tip per curvature (`m = r_d / r_p y`), and
/// the law's observer and gains at the design's `w_d` and `Gamma_d`: the damping ratio is
/// that of the least-damped oscillatory root of that 7-state loop. Read from the decay of the
/// nonlinear run, on the plant designed for too.
#[test]
fn on_plants_it_was_not_designed_for_the_damping_follows_the_single_mode_theory() {
    let zeta = 0.1;
    let (design_scene, _) = moving();
    let file = noiseless(&design_scene, zeta);
    let plants: [&[&str]; 4] = [
        &[],
        &["masses.load=10"],
        &["masses.load=10", "sections.youngs_modulus=1.68e11"],
        &["masses.load=2.5", "sections.youngs_modulus=2.52e11"],
    ];
    let design = &file.tables[0].points[0];
    let gains = LawGains::place(
        &file,
        design.first_mode_hz,
        design.tip_per_curvature_m2,
        design.curvature_per_acceleration,
    );
    for overrides in plants {
        let (plant, arrival) = moving_with(overrides);
        let own = &noiseless(&plant, zeta).tables[0].points[0];
        let mode = PlantMode {
            omega: std::f64::consts::TAU * own.first_mode_hz,
            gamma: tip_participation(&plant),
            gauge: design.tip_per_curvature_m2 / own.tip_per_curvature_m2,
        };
        let predicted = single_mode_damping(&mode, &gains);
        let run = simulate_velocity(&plant, &file, &options(), &Silent).unwrap();
        let measured = damping_ratio(&tip_after(&run.simulation.trajectory, arrival), 4);
        let shift = own.first_mode_hz / design.first_mode_hz;
        eprintln!(
            "{overrides:?}: mode x{shift:.3}, predicted {predicted:.4}, measured {measured:.4}"
        );
        assert!(
            (measured - predicted).abs() < 0.05 * predicted,
            "{overrides:?}: predicted {predicted}, measured {measured}"
        );
        let vehicle = run.simulation.trajectory.index("vehicle").unwrap();
        let last = run.simulation.trajectory.rows.last().unwrap()[vehicle];
        assert!((last - 0.5).abs() < 1e-3, "{overrides:?}: vehicle {last}");
    }
}

/// A law scheduled on the load, on plants of another stiffness than designed for, carrying
/// a table's load or one between two tables, or told a load it does not carry: it damps the
/// first mode by the single-mode theory's ratio for the design interpolated at the load it
/// is told (the interpolation written out here, apart from the law's).
#[test]
fn a_law_scheduled_on_the_load_damps_as_designed_for_the_load_it_is_told() {
    let zeta = 0.1;
    let (design_scene, _) = moving();
    let file = noiseless_at(&design_scene, zeta, &[2.5, 10.0]);
    assert_eq!(file.loads(), [2.5, 10.0]);
    // the plant's overrides, the load the law is told
    let cases: [(&[&str], f64); 3] = [
        (&["masses.load=10", "sections.youngs_modulus=1.68e11"], 10.0),
        (&["masses.load=5", "sections.youngs_modulus=2.52e11"], 5.0),
        (&["masses.load=10"], 5.0),
    ];
    for (overrides, told) in cases {
        let (plant, arrival) = moving_with(overrides);
        let [f, r, c] = interpolated(&file, told);
        let gains = LawGains::place(&file, f, r, c);
        let own = &noiseless(&plant, zeta).tables[0].points[0];
        let mode = PlantMode {
            omega: std::f64::consts::TAU * own.first_mode_hz,
            gamma: tip_participation(&plant),
            gauge: r / own.tip_per_curvature_m2,
        };
        let predicted = single_mode_damping(&mode, &gains);
        let run = simulate_velocity_told(&plant, &file, told, &options(), &Silent).unwrap();
        let measured = damping_ratio(&tip_after(&run.simulation.trajectory, arrival), 4);
        eprintln!(
            "{overrides:?}, told {told} kg: predicted {predicted:.4}, measured {measured:.4}"
        );
        assert!(
            (measured - predicted).abs() < 0.05 * predicted,
            "{overrides:?}, told {told} kg: predicted {predicted}, measured {measured}"
        );
    }
    let (plant, _) = moving_with(&["masses.load=10"]);
    let e = simulate_velocity_told(&plant, &file, f64::NAN, &options(), &Silent)
        .unwrap_err()
        .to_string();
    assert!(e.contains("measured load"), "{e}");
}

/// The feedback designed for `scene` adding `zeta` at each of `loads` (kg), without
/// measurement noise.
fn noiseless_at(scene: &Scene, zeta: f64, loads: &[f64]) -> VelocityFeedback {
    let design = VelocityDesign {
        added_damping: zeta,
        loads_kg: loads.to_vec(),
        ..VelocityDesign::default()
    };
    let mut file = design_velocity_feedback(scene, &design).unwrap();
    file.noise = vec![0.0; 2];
    file
}

/// `[f_1, r, c]` of the first design point of `file`'s two tables, linear in the load
/// between them at `load` (kg).
fn interpolated(file: &VelocityFeedback, load: f64) -> [f64; 3] {
    let (low, high) = (&file.tables[0], &file.tables[1]);
    let w = ((load - low.load_kg) / (high.load_kg - low.load_kg)).clamp(0.0, 1.0);
    let (p, q) = (&low.points[0], &high.points[0]);
    let lerp = |x: f64, y: f64| x + w * (y - x);
    [
        lerp(p.first_mode_hz, q.first_mode_hz),
        lerp(p.tip_per_curvature_m2, q.tip_per_curvature_m2),
        lerp(p.curvature_per_acceleration, q.curvature_per_acceleration),
    ]
}

/// A plant's first mode as the law sees it: angular frequency (rad/s), participation in
/// `tip_rel` (m per m/s^2 times `w^2`), and the gauge's reading in the design's tip per its
/// own (the law's tip estimate per true tip).
struct PlantMode {
    omega: f64,
    gamma: f64,
    gauge: f64,
}

/// The damping ratio of the least-damped oscillatory root of the loop: the state
/// `[X, V, y, y', y^, w^, b^]` (the vehicle's error and velocity, the plant's mode, the
/// observer's estimate), `a = -(k1 X + k2 V + k3 y^ + k4 w^)`.
fn single_mode_damping(plant: &PlantMode, law: &LawGains) -> f64 {
    let [k1, k2, k3, k4] = law.k;
    let [l1, l2, l3] = law.l;
    let feedback = [-k1, -k2, 0.0, 0.0, -k3, -k4, 0.0];
    // the innovation m - y^ - b^, m = gauge y
    let innovation = [0.0, 0.0, plant.gauge, 0.0, -1.0, 0.0, -1.0];
    let mut a = DMatrix::<f64>::zeros(7, 7);
    a[(0, 1)] = 1.0;
    a[(2, 3)] = 1.0;
    a[(3, 2)] = -plant.omega * plant.omega;
    a[(4, 5)] = 1.0;
    a[(5, 4)] = -law.omega * law.omega;
    for j in 0..7 {
        a[(1, j)] += feedback[j];
        a[(3, j)] -= plant.gamma * feedback[j];
        a[(5, j)] -= law.gamma * feedback[j];
        a[(4, j)] += l1 * innovation[j];
        a[(5, j)] += l2 * innovation[j];
        a[(6, j)] += l3 * innovation[j];
    }
    a.complex_eigenvalues()
        .iter()
        .filter(|r| r.im > 1e-9)
        .map(|r| -r.re / r.norm())
        .fold(f64::INFINITY, f64::min)
}

/// `Gamma c` of `scene`'s first mode with the vehicle held (closed-contact linear model):
/// the base acceleration's participation `Gamma = phi' M e_vehicle` times the mode's
/// `tip_rel` `c` (mass-normalized shape), 1 for a tip mass on a massless spring.
fn tip_participation(scene: &Scene) -> f64 {
    let model = AssembledModel::exact(&scene.params).unwrap();
    let lpv = Lpv::new(&model, ContactMode::Closed).unwrap();
    let positions: Vec<f64> = scene
        .params
        .positions
        .iter()
        .map(|p| p.value(0.0))
        .collect();
    let rates = vec![0.0; positions.len()];
    let full = lpv.at(&positions, &rates).unwrap();
    let (stiffness, _) = lpv.second_order_at(&positions, &rates).unwrap();
    let modal = modal_analysis_with(&model, &stiffness).unwrap();
    let shape = &modal.shapes[0];
    let mass = model.mass_matrix();
    let tip = lpv
        .outputs()
        .iter()
        .position(|o| o.name == "tip_rel")
        .unwrap();
    let gamma: f64 = (0..model.dof()).map(|j| shape[j] * mass[(j, 0)]).sum();
    let c: f64 = (0..model.dof()).map(|j| full.c[(tip, j)] * shape[j]).sum();
    gamma * c
}

#[test]
fn the_vehicle_comes_back_to_its_target() {
    let (scene, _) = moving();
    let mut file = noiseless(&scene, 0.1);
    file.noise = vec![1e-4, 1e-5];
    let run = simulate_velocity(&scene, &file, &options(), &Silent).unwrap();
    let traj = &run.simulation.trajectory;
    let vehicle = traj.index("vehicle").unwrap();
    let last = traj.rows.last().unwrap();
    assert!(
        (last[vehicle] - 0.5).abs() < 1e-3,
        "vehicle {}",
        last[vehicle]
    );
    // and the correction stayed within its bounds
    let largest = run.forces.iter().map(|c| c.1.abs()).fold(0.0, f64::max);
    assert!(largest > 0.0 && largest <= file.velocity_limit_m_per_s);
    let steps = run.forces.windows(2).map(|w| (w[1].1 - w[0].1).abs());
    let period = 1.0 / file.rate_hz;
    assert!(steps.fold(0.0, f64::max) <= file.acceleration_limit_m_per_s2 * period * (1.0 + 1e-12));
}

#[test]
fn without_gains_the_loop_is_the_open_loop() {
    let (scene, _) = moving();
    let mut file = noiseless(&scene, 0.1);
    // the smallest correction's acceleration a file accepts: the law commands nothing
    file.acceleration_limit_m_per_s2 = f64::MIN_POSITIVE;
    let run = simulate_velocity(&scene, &file, &options(), &Silent).unwrap();
    let open = simulate_scene(&scene, &options(), &Silent).unwrap();
    let (a, b) = (
        tip_after(&run.simulation.trajectory, 0.0),
        tip_after(&open.trajectory, 0.0),
    );
    // the same sample times; the open loop adds a last row at the span's end, off the
    // controller's grid
    assert!(a.len().min(b.len()) > 1000);
    let worst = a
        .iter()
        .zip(&b)
        .map(|(x, y)| {
            assert!((x.0 - y.0).abs() < 1e-9);
            (x.1 - y.1).abs()
        })
        .fold(0.0, f64::max);
    assert!(worst < 1e-6, "largest difference {worst} m");
}

#[test]
fn bad_files_and_scenes_are_refused_naming_the_rule() {
    let (scene, _) = moving();
    let file = noiseless(&scene, 0.1);
    let back = VelocityFeedback::from_json(&file.to_json()).unwrap();
    assert_eq!(back, file);
    let mut bad = file.clone();
    bad.rate_hz = 0.0;
    let e = bad.check_fits(&scene).unwrap_err().to_string();
    assert!(e.contains("rate_hz"), "{e}");
    let mut bad = file.clone();
    bad.vehicle_poles_per_mode[1] = -0.5;
    let e = bad.check_fits(&scene).unwrap_err().to_string();
    assert!(e.contains("vehicle_poles_per_mode[1]"), "{e}");
    let mut bad = file.clone();
    bad.tables[0].points[0].curvature_per_acceleration *= -1.0;
    let e = bad.check_fits(&scene).unwrap_err().to_string();
    assert!(
        e.contains("tables[0].points[0].curvature_per_acceleration") && e.contains("opposite sign"),
        "{e}"
    );
    let mut bad = noiseless_at(&scene, 0.1, &[2.5, 10.0]);
    bad.tables[1].load_kg = 2.0;
    let e = bad.check_fits(&scene).unwrap_err().to_string();
    assert!(e.contains("`tables`") && e.contains("ascend"), "{e}");
    let mut bad = noiseless_at(&scene, 0.1, &[2.5, 10.0]);
    let extra = bad.tables[1].points[0].clone();
    bad.tables[1].points.push(extra);
    let e = bad.check_fits(&scene).unwrap_err().to_string();
    assert!(e.contains("tables[1].points"), "{e}");
    // a law of one table is told a load it does not use, and says so
    let told = telescopic::control::ControllerFile::from_json(&file.to_json())
        .unwrap()
        .with_weighed_load(3.0)
        .unwrap();
    assert!(
        told.describe().contains("does not use"),
        "{}",
        told.describe()
    );
    let mut bad = file.clone();
    bad.schedule_parameter = Some("a_9".into());
    let e = bad.check_fits(&scene).unwrap_err().to_string();
    assert!(e.contains("schedule_parameter"), "{e}");
    let mut bad = file.clone();
    bad.tables.clear();
    let e = bad.check_fits(&scene).unwrap_err().to_string();
    assert!(e.contains("`tables`"), "{e}");
    let text = file.to_json().replace("\"version\": 3", "\"version\": 7");
    let e = VelocityFeedback::from_json(&text).unwrap_err().to_string();
    assert!(e.contains("version 7"), "{e}");
    let forced = common::single_section("forced", "force = 1.0", 1.0, 0.001, &[]);
    let e = file.check_fits(&forced).unwrap_err().to_string();
    assert!(e.contains("prescribed motion"), "{e}");
    let e = design_velocity_feedback(&forced, &VelocityDesign::default())
        .unwrap_err()
        .to_string();
    assert!(e.contains("drive.motion"), "{e}");
}

#[test]
fn implausible_values_and_duplicated_keys_are_refused_naming_the_field() {
    let (scene, _) = moving();
    let file = noiseless(&scene, 0.1);
    let refused = |edit: &dyn Fn(&mut VelocityFeedback)| {
        let mut bad = file.clone();
        edit(&mut bad);
        bad.check_fits(&scene).unwrap_err().to_string()
    };
    let e = refused(&|f| f.noise[1] = 1e308);
    assert!(e.contains("noise[1]") && e.contains("1/m"), "{e}");
    let e = refused(&|f| f.tables[0].points[0].first_mode_hz = -2.0);
    assert!(e.contains("tables[0].points[0].first_mode_hz"), "{e}");
    let e = refused(&|f| f.tables[0].points[0].tip_per_curvature_m2 = 1e300);
    assert!(
        e.contains("tables[0].points[0].tip_per_curvature_m2"),
        "{e}"
    );
    let e = refused(&|f| f.tables[0].points[0].curvature_per_acceleration = f64::INFINITY);
    assert!(
        e.contains("tables[0].points[0].curvature_per_acceleration"),
        "{e}"
    );
    let text = file
        .to_json()
        .replacen("\"rate_hz\"", "\"rate_hz\": 10.0,\n  \"rate_hz\"", 1);
    let e = VelocityFeedback::from_json(&text).unwrap_err().to_string();
    assert!(e.contains("`rate_hz` is given twice"), "{e}");
}

#[test]
fn the_law_holds_its_command_through_non_finite_measurements() {
    let (scene, _) = moving();
    let file = noiseless(&scene, 0.3);
    let setpoint = scene.params.drive_profile().clone();
    let mut law = VelocityController::new(&file, setpoint, 5.0).unwrap();
    let period = 1.0 / file.rate_hz;
    let step = file.acceleration_limit_m_per_s2 * period;
    let (mut last, mut t) = (0.0_f64, 0.0);
    for k in 0..2000 {
        t = k as f64 * period;
        let measured = [0.9 * setpoint_at(&scene, t), 1e-4 * (7.0 * t).sin()];
        let y = match k % 97 {
            3 => [f64::NAN, measured[1]],
            5 => [measured[0], f64::INFINITY],
            7 => [1e308, -1e308],
            _ => measured,
        };
        let v = law.step(t, &y, 0.0);
        assert!(v.is_finite(), "tick {k}: {v}");
        assert!(v.abs() <= file.velocity_limit_m_per_s && (v - last).abs() <= step * (1.0 + 1e-12));
        last = v;
    }
    // after the bad ticks the law runs on: a good tick's command is a finite, bounded one
    let v = law.step(t + period, &[0.0, 0.0], 0.0);
    assert!(v.is_finite());
}

/// The scene's prescribed vehicle position at `t` (s).
fn setpoint_at(scene: &Scene, t: f64) -> f64 {
    scene.params.drive_profile().value(t)
}

#[test]
fn the_quasi_static_curvature_of_a_slow_move_is_the_designed_one() {
    // a move slow against the first mode (2.7 Hz): the section bends as the static solve of
    // the linear model says, c times the setpoint's acceleration, plus the small undamped
    // vibration the jerk switches leave; the least-squares c of the nonlinear run is c
    let scene = common::single_section(
        "slow",
        "motion = 0.0",
        1.0,
        0.001,
        &["sections.modes=3".to_string()],
    );
    let curve = SCurve {
        start: 0.0,
        from: 0.0,
        distance: 0.5,
        v_max: 0.2,
        a_max: 0.1,
        j_max: 0.05,
    };
    let candidate = unshaped(&curve);
    let moving = moving_scene(&scene, &candidate.profile, candidate.arrival_s).unwrap();
    let mut file = noiseless(&moving, 0.1);
    file.acceleration_limit_m_per_s2 = f64::MIN_POSITIVE;
    let c = file.tables[0].points[0].curvature_per_acceleration;
    let run = simulate_velocity(&moving, &file, &options(), &Silent).unwrap();
    let traj = &run.simulation.trajectory;
    let kappa = traj.index("kappa_1_0").unwrap();
    let (mut along, mut norm) = (0.0, 0.0);
    for r in &traj.rows {
        let a = candidate.profile.acceleration(r[0]);
        along += r[kappa] * a;
        norm += a * a;
    }
    let fitted = along / norm;
    assert!(
        (fitted - c).abs() < 0.01 * c.abs(),
        "designed {c:e}, fitted {fitted:e} 1/m per m/s^2"
    );
}

/// The emitted C law, built with AddressSanitizer and UBSan, fed case-study's designed
/// feedback scheduled on three loads tick by tick (the scheduled position swept below,
/// across and above its table, a load between two tables, NaN and infinite inputs among
/// them), gives the library's corrections bit for bit and rejects exactly the non-finite
/// ticks.
#[test]
#[ignore = "needs a C compiler (cc) with sanitizers; the test command installs gcc"]
fn the_emitted_feedback_law_is_the_library_law_tick_by_tick_under_sanitizers() {
    use telescopic::control::emit::velocity::{FEEDBACK_FILES, write_velocity_c};
    use telescopic_runtime::Profile;
    let scene = common::scene("case-study", &[]);
    let curve = SCurve {
        start: 0.0,
        from: 0.0,
        distance: 23.0,
        v_max: 2.5,
        a_max: 0.7,
        j_max: 2.0,
    };
    let setpoint: Profile = unshaped(&curve).profile;
    let moving = moving_scene(&scene, &setpoint, 20.0).unwrap();
    let design = VelocityDesign {
        loads_kg: vec![10.0, 20.0, 30.0],
        ..VelocityDesign::default()
    };
    let file = design_velocity_feedback(&moving, &design).unwrap();
    assert!(file.tables[0].points.len() > 2, "a scheduled law");
    // between the second and the third table
    let load = 23.7;
    let dir = std::env::temp_dir().join(format!("telescopic-feedback-c-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    write_velocity_c(&file, &dir).unwrap();
    let program = dir.join("velocity_ticks");
    let driver = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/c/velocity_ticks.c");
    common::compile_c(
        &[
            "-O1",
            "-g",
            "-fsanitize=address,undefined",
            "-fno-sanitize-recover=all",
        ],
        &[&driver, &dir.join(FEEDBACK_FILES[1])],
        &dir,
        &program,
    );
    let (lines, expected, hostile) = ticks_of(&file, &setpoint, load);
    // the ticks from a file: a pipe both ways would fill while the other end still writes
    let input = dir.join("ticks.txt");
    std::fs::write(&input, &lines).unwrap();
    let out = std::process::Command::new(&program)
        .stdin(std::fs::File::open(&input).unwrap())
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{text}{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let mut printed = text.lines();
    for (k, want) in expected.iter().enumerate() {
        let got: f64 = printed
            .next()
            .expect("a correction per tick")
            .parse()
            .unwrap();
        assert_eq!(
            got.to_bits(),
            want.to_bits(),
            "tick {k}: C {got:e}, library {want:e}"
        );
    }
    assert_eq!(printed.next(), Some(format!("rejected {hostile}").as_str()));
    let largest = expected.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    assert!(
        largest > 0.0 && largest <= file.velocity_limit_m_per_s,
        "{largest}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// 16 s of ticks for the law of `file` around `setpoint`, told `load` (kg): the move and its
/// end, a curvature and a vehicle off their setpoint, every 211th tick's four inputs in turn
/// non-finite. The lines the C driver reads, the library's corrections, and the ticks the law
/// must reject.
fn ticks_of(
    file: &VelocityFeedback,
    setpoint: &telescopic_runtime::Profile,
    load: f64,
) -> (String, Vec<f64>, usize) {
    use std::fmt::Write as _;
    let ticks = (16.0 * file.rate_hz) as usize;
    let mut lines = String::new();
    let mut library = VelocityController::new(file, setpoint.clone(), load).unwrap();
    let mut expected = Vec::with_capacity(ticks);
    let mut hostile = 0;
    for k in 0..ticks {
        let t = k as f64 / file.rate_hz;
        let (s, _, s_acc) = setpoint.state(t);
        let mut u = s + 0.01 * (1.3 * t).sin();
        let mut kappa = 2e-3 * s_acc + 5e-4 * (6.0 * t).sin();
        let mut a = 0.2 + 1.2 * k as f64 / ticks as f64;
        let mut weighed = load;
        match k % 211 {
            17 => kappa = f64::NAN,
            101 => u = f64::INFINITY,
            160 => a = f64::NAN,
            190 => weighed = f64::NAN,
            _ => {}
        }
        hostile += usize::from(matches!(k % 211, 17 | 101 | 160 | 190));
        // a tick the law rejects holds its command and leaves its state: the library's law,
        // told its load once, is then not stepped
        let held = expected.last().copied().unwrap_or(0.0);
        expected.push(if weighed.is_nan() {
            held
        } else {
            library.step(t, &[u, kappa], a)
        });
        let _ = writeln!(lines, "{u:e} {kappa:e} {a:e} {weighed:e} {s:e} {s_acc:e}");
    }
    (lines, expected, hostile)
}
