//! Linear models: their eigenvalues against the modal analysis, their response against a
//! simulation, the state order that is part of the format, and the round trips of the
//! formats that need no outside tool (the clients' tests are in `tests/clients.rs`).
mod common;
use common::scene;

use telescopic::analysis::modes::{ModesOptions, compute_modes};
use telescopic::linear::{Format, Grid, LinearExport, LinearizeOptions, linearize};
use telescopic::run::{SimulationOptions, simulate_scene};
use telescopic::runtime::nalgebra::{DMatrix, DVector};
use telescopic::runtime::{ContactMode, eigenvalues};
use telescopic::{Scene, Silent};

/// Natural frequencies (Hz) of an undamped `A`: the positive imaginary parts over 2 pi.
fn frequencies(a: &DMatrix<f64>) -> Vec<f64> {
    let mut f: Vec<f64> = eigenvalues(a.clone(), "test")
        .unwrap()
        .iter()
        .filter(|l| l.im > 1e-6 * l.norm().max(1.0))
        .map(|l| l.norm() / (2.0 * std::f64::consts::PI))
        .collect();
    f.sort_by(f64::total_cmp);
    f
}

#[test]
fn eigenvalues_of_a_equal_the_modal_analysis_at_several_positions() {
    // without contact damping the modes are A's eigenvalues +-i omega exactly
    let scene = scene("case-study", &["contact.damping=0"]);
    for t in [0.0, 3.0, 6.0, 12.0] {
        let export = linearize(
            &scene,
            &LinearizeOptions {
                at_time: Some(t),
                ..LinearizeOptions::default()
            },
        )
        .unwrap();
        let ours = frequencies(&export.points[0].a);
        let modes = compute_modes(
            &scene,
            &ModesOptions {
                at: Some(t),
                ..ModesOptions::default()
            },
        )
        .unwrap();
        assert_eq!(ours.len(), modes.frequencies_hz.len(), "t = {t}");
        for (a, m) in ours.iter().zip(&modes.frequencies_hz) {
            assert!(
                (a - m).abs() <= 1e-6 * m,
                "t = {t}: {a} Hz from A, {m} Hz from modes"
            );
        }
    }
}

/// `tip_rel` of the exported model driven by a constant force, by the exact zero-order hold:
/// `exp([[A h, B h], [0, 0]])`.
fn zoh_response(export: &LinearExport, force: f64, h: f64, steps: usize) -> Vec<f64> {
    let p = &export.points[0];
    let n = p.a.nrows();
    let mut aug = DMatrix::zeros(n + 1, n + 1);
    aug.view_mut((0, 0), (n, n)).copy_from(&(&p.a * h));
    aug.view_mut((0, n), (n, 1)).copy_from(&(&p.b * h));
    let flow = aug.exp();
    let phi = flow.view((0, 0), (n, n)).into_owned();
    let gamma = flow.view((0, n), (n, 1)).into_owned() * force;
    let tip = export
        .outputs
        .iter()
        .position(|s| s.name == "tip_rel")
        .unwrap();
    let c = p.c.row(tip).transpose();
    let mut x = DVector::zeros(n);
    let mut out = vec![0.0];
    for _ in 0..steps {
        x = &phi * &x + &gamma;
        out.push(c.dot(&x));
    }
    out
}

#[test]
fn the_exported_model_driven_by_the_adams_force_equals_the_simulation() {
    let scene = scene("adams-linear", &[]);
    // through the JSON file, as another tool would read it
    let export = linearize(&scene, &LinearizeOptions::default()).unwrap();
    let mut json = Vec::new();
    export.write(Format::Json, &mut json).unwrap();
    let read = LinearExport::from_json(std::str::from_utf8(&json).unwrap()).unwrap();
    let ours = zoh_response(&read, 100.0, scene.time.sample, 5000);
    let run = simulate_scene(&scene, &SimulationOptions::default(), &Silent).unwrap();
    let sim = run.trajectory.column("tip_rel").unwrap();
    assert_eq!(sim.len(), ours.len());
    let worst = ours
        .iter()
        .zip(&sim)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    let peak = sim.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    eprintln!(
        "ZOH of the exported model vs simulate on adams-linear: {worst:.2e} m (peak {peak:.3} m)"
    );
    assert!(peak > 0.05, "the force moves the load");
    assert!(worst < 1e-6, "tip_rel differs by {worst:e} m");
}

#[test]
fn the_state_order_is_the_documented_one() {
    let export = linearize(&scene("three-section", &[]), &LinearizeOptions::default()).unwrap();
    let names: Vec<&str> = export.states.iter().map(|s| s.name.as_str()).collect();
    let coordinates = [
        "u", "q_1_2", "q_1_3", "q_1_4", "r_2", "q_2_2", "q_2_3", "q_2_4", "r_3", "q_3_2", "q_3_3",
        "q_3_4",
    ];
    let rates: Vec<String> = coordinates.iter().map(|c| format!("{c}_dot")).collect();
    let expected: Vec<&str> = coordinates
        .iter()
        .copied()
        .chain(rates.iter().map(String::as_str))
        .collect();
    assert_eq!(names, expected);
    let units: Vec<&str> = export.states[..12]
        .iter()
        .map(|s| s.unit.as_str())
        .collect();
    assert_eq!(
        units,
        [
            "m", "m", "m", "m", "m", "rad", "m", "m", "m", "rad", "m", "m"
        ]
    );
    let outputs: Vec<&str> = export.outputs.iter().map(|s| s.name.as_str()).collect();
    assert_eq!(
        outputs,
        [
            "vehicle",
            "tip_rel",
            "top1_rel",
            "xi_2_0",
            "xi_2_1",
            "xi_3_0",
            "xi_3_1",
            "f_2_0",
            "f_2_1",
            "f_3_0",
            "f_3_1",
            "kappa_1_0",
            "acc_load"
        ]
    );
    assert_eq!(export.inputs[0].name, "F");
    // a prescribed motion is driven by the vehicle's acceleration, and the vehicle follows it
    let text: String = std::fs::read_to_string("scenes/case-study.toml")
        .unwrap()
        .lines()
        .map(|l| {
            if l.trim_start().starts_with("force =") {
                "motion = { kind = \"smoothstep\", start = 0, end = 8, from = 0, to = 10 }"
            } else {
                l
            }
        })
        .collect::<Vec<_>>()
        .join("\n");
    let motion = Scene::from_toml_str(&text, "motion.toml".as_ref(), &[]).unwrap();
    let export = linearize(&motion, &LinearizeOptions::default()).unwrap();
    assert_eq!(
        (
            export.inputs[0].name.as_str(),
            export.inputs[0].unit.as_str()
        ),
        ("a_vehicle", "m/s^2")
    );
    let p = &export.points[0];
    let n = p.a.nrows() / 2;
    // u'' = input exactly: the row of u_dot is the input alone
    assert_eq!(p.b[(n, 0)], 1.0);
    assert!(p.a.row(n).iter().all(|&v| v == 0.0));
}

#[test]
fn json_and_latex_round_trip() {
    let scene = scene("case-study", &[]);
    let grid: Grid = "a2=0.35:1.15:5".parse().unwrap();
    let export = linearize(
        &scene,
        &LinearizeOptions {
            grid: Some(grid),
            ..LinearizeOptions::default()
        },
    )
    .unwrap();
    let mut json = Vec::new();
    export.write(Format::Json, &mut json).unwrap();
    let back = LinearExport::from_json(std::str::from_utf8(&json).unwrap()).unwrap();
    // every digit and name (compared whole, reported briefly)
    assert!(back == export, "the JSON round trip changed the export");
    // LaTeX: six significant digits of every entry of the first point
    let mut tex = Vec::new();
    export.check_format(Format::Latex).unwrap();
    export.write(Format::Latex, &mut tex).unwrap();
    let tex = String::from_utf8(tex).unwrap();
    let a_block = tex.split("\\[ A = \\begin{bmatrix}\n").nth(1).unwrap();
    let a_block = a_block.split("\n\\end{bmatrix}").next().unwrap();
    let a = &export.points[0].a;
    for (i, row) in a_block.split(" \\\\\n").enumerate() {
        for (j, cell) in row.split(" & ").enumerate() {
            let value = match cell.split_once("\\cdot 10^{") {
                Some((m, e)) => {
                    m.parse::<f64>().unwrap() * 10f64.powi(e.trim_end_matches('}').parse().unwrap())
                }
                None => cell.parse::<f64>().unwrap(),
            };
            let want = a[(i, j)];
            assert!(
                (value - want).abs() <= 6e-6 * want.abs(),
                "A[{i}][{j}]: {cell} against {want:e}"
            );
        }
    }
}

#[test]
fn bad_operating_points_and_grids_are_refused_with_the_rule() {
    let scene = scene("case-study", &[]);
    let err = linearize(
        &scene,
        &LinearizeOptions {
            positions: vec![(2, 1.5)],
            ..LinearizeOptions::default()
        },
    )
    .unwrap_err();
    // the error names the option as data, not only in its text
    assert!(
        matches!(
            err,
            telescopic::Error::Option {
                option: telescopic::OptionName::Positions,
                ..
            }
        ),
        "{err:?}"
    );
    let err = err.to_string();
    assert!(
        err.contains("a2 = 1.5 m is outside the valid overlap") && err.contains("[0, 1.35)"),
        "{err}"
    );
    let err = linearize(
        &scene,
        &LinearizeOptions {
            grid: Some("a2=0.0:1.4:5".parse().unwrap()),
            ..LinearizeOptions::default()
        },
    )
    .unwrap_err()
    .to_string();
    assert!(
        err.contains("LinearizeOptions::grid") && err.contains("outside the valid overlap"),
        "{err}"
    );
    let err = linearize(
        &scene,
        &LinearizeOptions {
            positions: vec![(3, 1.0)],
            ..LinearizeOptions::default()
        },
    )
    .unwrap_err()
    .to_string();
    assert!(err.contains("its positions are a2..a2"), "{err}");
    let err = linearize(
        &scene,
        &LinearizeOptions {
            positions: vec![(2, 0.5), (2, 0.7)],
            ..LinearizeOptions::default()
        },
    )
    .unwrap_err()
    .to_string();
    assert!(
        err == "LinearizeOptions::positions: a2 is given twice",
        "{err}"
    );
    for bad in ["a2=1:2", "b2=0:1:3", "a2=0:1:1", "a2=0:x:3"] {
        assert!(bad.parse::<Grid>().is_err(), "{bad} parsed");
    }
    // a model too large for LaTeX says so
    let big = linearize(
        &telescopic::Scene::load(
            "scenes/three-section.toml".as_ref(),
            &["sections.modes=6".into()],
        )
        .unwrap(),
        &LinearizeOptions::default(),
    )
    .unwrap();
    let err = big.check_format(Format::Latex).unwrap_err().to_string();
    assert!(err.contains("at most 24 states, this one has 36"), "{err}");
    // open contacts: no contact forces among the outputs
    let open = linearize(
        &scene,
        &LinearizeOptions {
            contacts: ContactMode::Open,
            ..LinearizeOptions::default()
        },
    )
    .unwrap();
    assert!(!open.outputs.iter().any(|s| s.name.starts_with("f_")));
}
