//! The exports opened by the tools controls engineers use, for real: GNU Octave with its
//! control package runs the `.m` script, python-control and NumPy run the Python script and
//! read the `.npz`, and SciPy's `solve_continuous_are` and python-control's `lqr` solve the
//! Riccati problems of our designs. Each gives the same poles, frequency responses and gains.
//!
//! These tests need the clients and are ignored by a plain `cargo test`; `./scripts/test`
//! installs them (Debian's `octave` and `octave-control`; a virtual environment with
//! `control`, `numpy` and `scipy`, named by `TELESCOPIC_PYTHON`) and runs them. A missing
//! client fails the test, naming it.

mod common;

use common::scratch;

use std::path::Path;
use std::process::Command;
use telescopic::Scene;
use telescopic::control::{DesignOptions, design};
use telescopic::linear::{Format, LinearExport, LinearizeOptions, linearize};
use telescopic::runtime::nalgebra::{Complex, DMatrix};
use telescopic::runtime::{LinearInput, eigenvalues};

/// The frequencies (rad/s) the responses are compared at.
const FREQUENCIES: [f64; 5] = [0.5, 3.0, 30.0, 300.0, 3000.0];

fn case_study(grid: Option<&str>) -> LinearExport {
    let scene = Scene::load("scenes/case-study.toml".as_ref(), &[]).unwrap();
    let mut export = linearize(
        &scene,
        &LinearizeOptions {
            grid: grid.map(|g| g.parse().unwrap()),
            ..LinearizeOptions::default()
        },
    )
    .unwrap();
    export.scene_file = "scenes/case-study.toml".into();
    export
}

fn write(export: &LinearExport, format: Format, path: &Path) {
    let mut bytes = Vec::new();
    export.write(format, &mut bytes).unwrap();
    std::fs::write(path, bytes).unwrap();
}

/// Runs a client; a client that is not there fails the test by name.
fn run(client: &str, what: &str, args: &[&str], dir: &Path) -> String {
    let out = Command::new(client)
        .args(args)
        .current_dir(dir)
        .output()
        .unwrap_or_else(|e| {
            panic!("{what} ({client}) cannot be run: {e}; ./scripts/test installs it")
        });
    let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(
        out.status.success(),
        "{what} failed: {}\n{stdout}\n{}",
        out.status,
        String::from_utf8_lossy(&out.stderr)
    );
    stdout
}

fn python() -> String {
    std::env::var("TELESCOPIC_PYTHON").unwrap_or_else(|_| "python3".into())
}

/// `H(i w) = C (i w I - A)^-1 B + D` of one input, one row per output.
fn frequency_response(
    a: &DMatrix<f64>,
    b: &DMatrix<f64>,
    c: &DMatrix<f64>,
    w: f64,
) -> Vec<Complex<f64>> {
    let n = a.nrows();
    // i w I - A
    let shifted = DMatrix::from_fn(n, n, |i, j| {
        Complex::new(-a[(i, j)], if i == j { w } else { 0.0 })
    });
    let bc = b.map(|v| Complex::new(v, 0.0));
    let x = shifted.lu().solve(&bc).expect("i w is not an eigenvalue");
    (0..c.nrows())
        .map(|r| {
            (0..n)
                .map(|j| Complex::new(c[(r, j)], 0.0) * x[(j, 0)])
                .sum()
        })
        .collect()
}

/// Parses lines of whitespace-separated numbers.
fn numbers(text: &str) -> Vec<Vec<f64>> {
    text.lines()
        .filter(|l| !l.trim().is_empty())
        .map(|l| {
            l.split_whitespace()
                .map(|v| v.parse::<f64>().unwrap())
                .collect()
        })
        .collect()
}

/// Every pole of `theirs` has one of `ours` within `tol` of the largest magnitude.
fn same_poles(ours: &[Complex<f64>], theirs: &[Complex<f64>], what: &str) {
    assert_eq!(ours.len(), theirs.len(), "{what}: pole counts");
    let scale = ours.iter().fold(0.0f64, |m, p| m.max(p.norm()));
    for p in theirs {
        let nearest = ours
            .iter()
            .map(|q| (q - p).norm())
            .fold(f64::INFINITY, f64::min);
        assert!(
            nearest <= 1e-9 * scale,
            "{what}: pole {p} is {nearest:e} from ours"
        );
    }
}

fn same_response(ours: &[Complex<f64>], theirs: &[Complex<f64>], what: &str) {
    assert_eq!(ours.len(), theirs.len());
    let scale = ours.iter().fold(0.0f64, |m, h| m.max(h.norm()));
    for (i, (a, b)) in ours.iter().zip(theirs).enumerate() {
        assert!(
            (a - b).norm() <= 1e-8 * a.norm().max(1e-6 * scale),
            "{what}: output {i}: {a} against {b}"
        );
    }
}

#[test]
#[ignore = "needs GNU Octave with its control package: run ./scripts/test"]
fn octave_runs_the_matlab_export_with_the_same_poles_and_frequency_response() {
    let dir = scratch("clients-octave");
    let export = case_study(None);
    write(&export, Format::Matlab, &dir.join("model.m"));
    let w: Vec<String> = FREQUENCIES.iter().map(|f| f.to_string()).collect();
    std::fs::write(
        dir.join("check.m"),
        format!(
            "model;\np = pole(sys);\nP = [real(p) imag(p)];\nsave('-ascii', '-double', 'poles.txt', 'P');\n\
             w = [{}];\nH = freqresp(sys, w);\nH = reshape(H, size(H, 1), numel(w));\n\
             HH = [real(H); imag(H)];\nsave('-ascii', '-double', 'response.txt', 'HH');\n\
             names = sys.stname;\nfid = fopen('names.txt', 'w'); fprintf(fid, '%s\\n', names{{:}}); fclose(fid);\n",
            w.join(" ")
        ),
    )
    .unwrap();
    run(
        "octave",
        "GNU Octave",
        &["--no-gui", "--quiet", "check.m"],
        &dir,
    );
    let point = &export.points[0];
    let ours = eigenvalues(point.a.clone(), "test").unwrap();
    let theirs: Vec<Complex<f64>> =
        numbers(&std::fs::read_to_string(dir.join("poles.txt")).unwrap())
            .iter()
            .map(|r| Complex::new(r[0], r[1]))
            .collect();
    same_poles(&ours, &theirs, "Octave's pole()");
    let response = numbers(&std::fs::read_to_string(dir.join("response.txt")).unwrap());
    let outputs = export.outputs.len();
    for (k, &w) in FREQUENCIES.iter().enumerate() {
        let theirs: Vec<Complex<f64>> = (0..outputs)
            .map(|i| Complex::new(response[i][k], response[outputs + i][k]))
            .collect();
        same_response(
            &frequency_response(&point.a, &point.b, &point.c, w),
            &theirs,
            &format!("Octave's freqresp at {w} rad/s"),
        );
    }
    let names = std::fs::read_to_string(dir.join("names.txt")).unwrap();
    let ours: Vec<&str> = export.states.iter().map(|s| s.name.as_str()).collect();
    assert_eq!(
        names.lines().collect::<Vec<_>>(),
        ours,
        "state names survive in Octave"
    );

    // a grid: one model per point (Octave's control package has no model arrays)
    let grid = case_study(Some("a2=0.35:1.15:3"));
    write(&grid, Format::Matlab, &dir.join("grid.m"));
    std::fs::write(
        dir.join("check_grid.m"),
        "grid;\nfid = fopen('grid.txt', 'w');\nfor k = 1:numel(sys)\n  p = pole(sys{k});\n  \
         fprintf(fid, '%.17g\\n', max(abs(p)));\nend\nfclose(fid);\n",
    )
    .unwrap();
    run(
        "octave",
        "GNU Octave",
        &["--no-gui", "--quiet", "check_grid.m"],
        &dir,
    );
    let theirs = numbers(&std::fs::read_to_string(dir.join("grid.txt")).unwrap());
    assert_eq!(theirs.len(), 3);
    for (p, t) in grid.points.iter().zip(&theirs) {
        let ours = eigenvalues(p.a.clone(), "test")
            .unwrap()
            .iter()
            .fold(0.0f64, |m, l| m.max(l.norm()));
        assert!(
            (ours - t[0]).abs() <= 1e-9 * ours,
            "grid point a2 = {:?}: {ours} against {}",
            p.positions,
            t[0]
        );
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
#[ignore = "needs python-control, NumPy and SciPy: run ./scripts/test"]
fn python_control_runs_the_python_export_and_numpy_reads_the_npz() {
    let dir = scratch("clients-python");
    let export = case_study(None);
    write(&export, Format::Python, &dir.join("model.py"));
    write(
        &case_study(Some("a2=0.35:1.15:3")),
        Format::Npz,
        &dir.join("grid.npz"),
    );
    std::fs::write(
        dir.join("check.py"),
        format!(
            "import json, numpy as np, control\nfrom model import sys, A\n\
             w = np.array({FREQUENCIES:?})\np = sys.poles()\n\
             H = np.array([sys(1j * x) for x in w])\n\
             z = np.load('grid.npz')\n\
             print(json.dumps({{'poles': [[x.real, x.imag] for x in p], \
             'H_re': H.real.tolist(), 'H_im': H.imag.tolist(), 'states': list(sys.state_labels), \
             'inputs': list(sys.input_labels), 'outputs': list(sys.output_labels), \
             'npz_A': z['A'].tolist(), 'npz_grid': z['grid'].tolist(), \
             'npz_states': [str(s) for s in z['states']], 'npz_parameter': str(z['grid_parameter'])}}))\n"
        ),
    )
    .unwrap();
    let out = run(
        &python(),
        "python-control (TELESCOPIC_PYTHON)",
        &["check.py"],
        &dir,
    );
    let v: serde_json::Value = serde_json::from_str(out.lines().last().unwrap()).unwrap();
    let point = &export.points[0];
    let ours = eigenvalues(point.a.clone(), "test").unwrap();
    let theirs: Vec<Complex<f64>> = v["poles"]
        .as_array()
        .unwrap()
        .iter()
        .map(|x| Complex::new(x[0].as_f64().unwrap(), x[1].as_f64().unwrap()))
        .collect();
    same_poles(&ours, &theirs, "python-control's poles()");
    for (k, &w) in FREQUENCIES.iter().enumerate() {
        let theirs: Vec<Complex<f64>> = (0..export.outputs.len())
            .map(|i| {
                Complex::new(
                    v["H_re"][k][i][0].as_f64().unwrap(),
                    v["H_im"][k][i][0].as_f64().unwrap(),
                )
            })
            .collect();
        same_response(
            &frequency_response(&point.a, &point.b, &point.c, w),
            &theirs,
            &format!("python-control at {w} rad/s"),
        );
    }
    let names = |key: &str| -> Vec<String> {
        v[key]
            .as_array()
            .unwrap()
            .iter()
            .map(|s| s.as_str().unwrap().to_string())
            .collect()
    };
    assert_eq!(
        names("states"),
        export
            .states
            .iter()
            .map(|s| s.name.clone())
            .collect::<Vec<_>>()
    );
    assert_eq!(names("inputs"), ["F"]);
    assert_eq!(
        names("outputs"),
        export
            .outputs
            .iter()
            .map(|s| s.name.clone())
            .collect::<Vec<_>>()
    );
    // the .npz, read by NumPy: every digit of the grid's matrices
    let grid = case_study(Some("a2=0.35:1.15:3"));
    for (k, p) in grid.points.iter().enumerate() {
        for i in 0..p.a.nrows() {
            for j in 0..p.a.ncols() {
                assert_eq!(v["npz_A"][k][i][j].as_f64().unwrap(), p.a[(i, j)]);
            }
        }
    }
    assert_eq!(v["npz_grid"][2].as_f64().unwrap(), 1.15);
    assert_eq!(v["npz_parameter"], "a_2");
    assert_eq!(names("npz_states")[4], "r_2");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
#[ignore = "needs SciPy and python-control: run ./scripts/test"]
fn the_riccati_solver_agrees_with_scipy_and_python_control() {
    // the design problems of case-study's schedule, and textbook-sized others
    let scene = Scene::load("scenes/case-study.toml".as_ref(), &[]).unwrap();
    let controller = design(&scene, &DesignOptions::default()).unwrap();
    let mut problems: Vec<serde_json::Value> = controller
        .schedule
        .iter()
        .map(|p| serde_json::json!({"A": p.a, "B": p.b, "Q": p.q, "R": p.r}))
        .collect();
    problems.push(serde_json::json!({
        "A": [[0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [-2.0, -3.0, 1.0]],
        "B": [[0.0, 0.5], [0.0, 0.0], [1.0, 2.0]],
        "Q": [[2.0, 0.5, 0.0], [0.5, 1.0, 0.0], [0.0, 0.0, 3.0]],
        "R": [[1.0, 0.2], [0.2, 2.0]],
    }));
    let dir = scratch("clients-riccati");
    std::fs::write(
        dir.join("problems.json"),
        serde_json::to_string(&problems).unwrap(),
    )
    .unwrap();
    std::fs::write(
        dir.join("check.py"),
        "import json, numpy as np, scipy.linalg as sl, control\n\
         out = []\n\
         for p in json.load(open('problems.json')):\n\
         \x20   A, B, Q, R = (np.array(p[k]) for k in 'ABQR')\n\
         \x20   X = sl.solve_continuous_are(A, B, Q, R)\n\
         \x20   K, S, E = control.lqr(A, B, Q, R)\n\
         \x20   out.append({'X': X.tolist(), 'K_scipy': np.linalg.solve(R, B.T @ X).tolist(), 'K_control': np.asarray(K).tolist()})\n\
         print(json.dumps(out))\n",
    )
    .unwrap();
    let out = run(
        &python(),
        "SciPy and python-control (TELESCOPIC_PYTHON)",
        &["check.py"],
        &dir,
    );
    let theirs: serde_json::Value = serde_json::from_str(out.lines().last().unwrap()).unwrap();
    let m = |v: &serde_json::Value| -> DMatrix<f64> {
        let rows: Vec<Vec<f64>> = serde_json::from_value(v.clone()).unwrap();
        DMatrix::from_row_iterator(rows.len(), rows[0].len(), rows.into_iter().flatten())
    };
    for (i, p) in problems.iter().enumerate() {
        let ours = telescopic::control::design::riccati::care(
            &m(&p["A"]),
            &m(&p["B"]),
            &m(&p["Q"]),
            &m(&p["R"]),
        )
        .unwrap();
        let x = m(&theirs[i]["X"]);
        let rel = (&ours.x - &x).norm() / x.norm();
        eprintln!(
            "problem {i}: X differs from SciPy's by {rel:.2e} relative; our residual {:.2e}",
            ours.residual
        );
        assert!(rel < 1e-8, "problem {i}: X differs from SciPy's by {rel:e}");
        for key in ["K_scipy", "K_control"] {
            let k = m(&theirs[i][key]);
            let rel = (&ours.k - &k).norm() / k.norm();
            assert!(rel < 1e-8, "problem {i}: K differs from {key} by {rel:e}");
        }
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
#[ignore = "needs pdflatex: run ./scripts/test"]
fn pdflatex_compiles_the_latex_export() {
    let dir = scratch("clients-latex");
    let mut export = case_study(None);
    // a name with every character LaTeX gives a meaning
    export.scene = r"odd \ {&} $5 #1 50% a_b ~x <y>".into();
    write(&export, Format::Latex, &dir.join("model.tex"));
    run(
        "pdflatex",
        "pdflatex",
        &["-interaction=nonstopmode", "-halt-on-error", "model.tex"],
        &dir,
    );
    assert!(dir.join("model.pdf").exists());
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The largest difference of a Bode curve from python-control's frequency response (real
/// and imaginary parts at the same frequencies), relative to each point's own size with a
/// floor far below the curve's peak.
fn worst_relative_difference(
    curve: &telescopic::linear::bode::ResponseCurve,
    re: &serde_json::Value,
    im: &serde_json::Value,
) -> f64 {
    let scale = curve.magnitude.iter().fold(0.0_f64, |m, x| m.max(*x));
    let mut worst = 0.0_f64;
    for (k, (mag, phase)) in curve.magnitude.iter().zip(&curve.phase_deg).enumerate() {
        let theirs = Complex::new(re[k].as_f64().unwrap(), im[k].as_f64().unwrap());
        let ours = Complex::from_polar(*mag, phase.to_radians());
        worst = worst.max((ours - theirs).norm() / theirs.norm().max(1e-9 * scale));
    }
    worst
}

#[test]
#[ignore = "needs python-control, NumPy and SciPy: run ./scripts/test"]
fn bode_equals_python_control_and_the_discrete_model_equals_scipys_cont2discrete() {
    use telescopic::linear::bode::{BodeOptions, frequency_response};
    let dir = scratch("clients-bode");
    // damped structure, both inputs, an output with feedthrough (acc_load)
    let scene = Scene::load(
        "scenes/case-study.toml".as_ref(),
        &["sections.damping_ratio=0.02".to_string()],
    )
    .unwrap();
    let linear = LinearizeOptions {
        positions: vec![(2, 0.8)],
        disturbance: true,
        ..LinearizeOptions::default()
    };
    let options = BodeOptions {
        linear: LinearizeOptions {
            disturbance: false,
            ..linear.clone()
        },
        outputs: vec!["tip_rel".into(), "kappa_1_0".into(), "acc_load".into()],
        inputs: vec![LinearInput::DriveForce, LinearInput::LoadForce],
        ..BodeOptions::default()
    };
    let ours = frequency_response(&scene, &options).unwrap();
    let dt = 1e-3;
    let export = linearize(
        &scene,
        &LinearizeOptions {
            discrete: Some(dt),
            ..linear
        },
    )
    .unwrap();
    assert_eq!(export.inputs[1].name, "F_load");
    write(&export, Format::Python, &dir.join("model.py"));
    let f: Vec<String> = ours.f_hz.iter().map(|f| format!("{f:e}")).collect();
    std::fs::write(
        dir.join("check.py"),
        format!(
            "import json, warnings, numpy as np, control, scipy.signal\n\
             warnings.simplefilter('ignore')\n\
             from model import sys, sysd, A, B, C, D, Ad, Bd, dt, outputs, inputs\n\
             w = 2 * np.pi * np.array([{}])\n\
             r = control.frequency_response(sys, omega=w, squeeze=False)\n\
             H = r.complex\n\
             ad, bd, _, _, _ = scipy.signal.cont2discrete((A, B, C, D), dt, method='zoh')\n\
             print(json.dumps({{'re': H.real.tolist(), 'im': H.imag.tolist(), \
             'outputs': outputs, 'inputs': inputs, 'Ad': ad.tolist(), 'Bd': bd.tolist(), \
             'sysd_dt': float(sysd.dt)}}))\n",
            f.join(", ")
        ),
    )
    .unwrap();
    let out = run(
        &python(),
        "python-control and SciPy (TELESCOPIC_PYTHON)",
        &["check.py"],
        &dir,
    );
    let v: serde_json::Value = serde_json::from_str(out.lines().last().unwrap()).unwrap();
    let index = |key: &str, name: &str| {
        v[key]
            .as_array()
            .unwrap()
            .iter()
            .position(|s| s == name)
            .unwrap()
    };
    for curve in &ours.curves {
        let (o, i) = (
            index("outputs", &curve.output),
            index("inputs", &curve.input),
        );
        let worst = worst_relative_difference(curve, &v["re"][o][i], &v["im"][o][i]);
        eprintln!(
            "{} from {}: worst relative difference {worst:.2e}",
            curve.output, curve.input
        );
        assert!(
            worst < 1e-6,
            "{} from {}: {worst}",
            curve.output,
            curve.input
        );
    }
    let (ad, bd) = &export.discrete.as_ref().unwrap().points[0];
    for (name, ours) in [("Ad", ad), ("Bd", bd)] {
        let rows: Vec<Vec<f64>> = serde_json::from_value(v[name].clone()).unwrap();
        let theirs =
            DMatrix::from_row_iterator(rows.len(), rows[0].len(), rows.into_iter().flatten());
        let diff = (ours - &theirs).abs().max() / theirs.abs().max();
        eprintln!("{name}: largest difference from cont2discrete {diff:.2e} of its largest entry");
        assert!(diff < 1e-9, "{name}: {diff}");
    }
    assert_eq!(v["sysd_dt"].as_f64().unwrap(), dt);
    std::fs::remove_dir_all(&dir).unwrap();
}
