//! The FMUs of `telescopic fmu` in a real importer, FMPy (from PyPI, in the test environment
//! `./scripts/test` makes): its validation finds no problem in the descriptions; the
//! co-simulation FMU of adams-clearance with the scene's own drive force as input equals
//! `telescopic simulate` on the predictability window; the model-exchange FMU under CVode
//! equals it on adams-linear and locates every contact switch of adams-clearance; a
//! parameter set through FMPy changes the result as `--set` does.
//!
//! Ignored by a plain `cargo test`; a missing client fails the test, naming it.

mod common;

use common::{scratch, succeeds};
use std::path::Path;
use std::process::Command;

fn python() -> String {
    std::env::var("TELESCOPIC_PYTHON").unwrap_or_else(|_| "python3".into())
}

/// Runs a Python script in `dir` and returns its last stdout line as JSON.
fn fmpy(dir: &Path, script: &str) -> serde_json::Value {
    std::fs::write(dir.join("check.py"), script).unwrap();
    let out = Command::new(python())
        .arg("check.py")
        .current_dir(dir)
        .output()
        .unwrap_or_else(|e| {
            panic!("FMPy (TELESCOPIC_PYTHON) cannot be run: {e}; ./scripts/test installs it")
        });
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "FMPy failed: {}\n{stdout}\n{}",
        out.status,
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_str(stdout.lines().last().unwrap()).unwrap()
}

/// `telescopic fmu` of `scene` (with `sets`) into `dir/name.fmu`.
fn export(dir: &Path, scene: &str, kind: &str, name: &str) -> String {
    let path = dir.join(format!("{name}.fmu"));
    succeeds(&[
        "fmu",
        scene,
        "--kind",
        kind,
        "--out",
        path.to_str().unwrap(),
    ]);
    path.to_str().unwrap().to_string()
}

/// `tip_rel` of `telescopic simulate` with `sets`, sampled at `sample` s.
fn simulate(dir: &Path, scene: &str, sets: &[&str]) -> Vec<f64> {
    let csv = dir.join("reference.csv");
    let mut args = vec!["simulate", scene, "--out", csv.to_str().unwrap()];
    for s in sets {
        args.extend(["--set", s]);
    }
    succeeds(&args);
    let text = std::fs::read_to_string(&csv).unwrap();
    // past the error budget's `#` lines
    let mut lines = text.lines().filter(|l| !l.starts_with('#'));
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = header.iter().position(|h| *h == "tip_rel").unwrap();
    lines
        .map(|l| l.split(',').nth(col).unwrap().parse().unwrap())
        .collect()
}

fn numbers(v: &serde_json::Value) -> Vec<f64> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect()
}

fn worst(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

/// The FMPy header every script shares: the scene's own drive, a step of 100 N from t = 0.
const PRELUDE: &str = "import json, numpy as np, fmpy\nfrom fmpy.validation import validate_fmu\n\
    drive = np.array([(0.0, 100.0), (10.0, 100.0)], dtype=[('time', np.float64), ('F', np.float64)])\n";

#[test]
#[ignore = "needs FMPy: run ./scripts/test"]
fn fmpy_validates_and_co_simulates_adams_clearance_like_simulate() {
    let dir = scratch("fmpy-cs");
    let both = export(&dir, "scenes/adams-clearance.toml", "both", "both");
    let cs = export(&dir, "scenes/adams-clearance.toml", "cs", "cs");
    let me = export(&dir, "scenes/adams-linear.toml", "me", "me");
    // a prescribed motion: input a_vehicle, output drive_force
    let moved = dir.join("moved.toml");
    let text = std::fs::read_to_string("scenes/adams-linear.toml")
        .unwrap()
        .replace(
            "force = 100.0            # N from t = 0",
            r#"motion = { kind = "smoothstep", start = 0, end = 2, from = 0, to = 1 }"#,
        );
    std::fs::write(&moved, text).unwrap();
    let motion = export(&dir, moved.to_str().unwrap(), "both", "motion");
    let v = fmpy(
        &dir,
        &format!(
            "{PRELUDE}problems = {{k: [str(p) for p in validate_fmu(f)] for k, f in \
             [('both', '{both}'), ('cs', '{cs}'), ('me', '{me}'), ('motion', '{motion}')]}}\n\
             r = fmpy.simulate_fmu('{cs}', fmi_type='CoSimulation', stop_time=0.3, step_size=1e-3, \
             output_interval=1e-3, input=drive, output=['tip_rel'])\n\
             s = fmpy.simulate_fmu('{both}', fmi_type='CoSimulation', stop_time=0.3, step_size=1e-3, \
             output_interval=1e-3, input=drive, output=['tip_rel'], \
             start_values={{'contact.clearance': 0.004, 'masses.load': 10.0}})\n\
             print(json.dumps({{'problems': problems, 'tip': r['tip_rel'].tolist(), \
             'set': s['tip_rel'].tolist()}}))\n"
        ),
    );
    for kind in ["both", "cs", "me", "motion"] {
        assert_eq!(
            v["problems"][kind],
            serde_json::json!([]),
            "FMPy's validation of {kind}"
        );
    }
    // the predictability window of adams-clearance is [0, 0.3] s (docs/model.md section 6)
    let ours = simulate(&dir, "scenes/adams-clearance.toml", &["time.end=0.3"]);
    let theirs = numbers(&v["tip"]);
    assert_eq!(theirs.len(), ours.len());
    let e = worst(&theirs, &ours);
    eprintln!("FMPy co-simulation (1 ms, input held) against simulate: {e:.2e} m");
    assert!(e < 1e-6, "{e}");
    // parameters through FMPy = --set
    let set = simulate(
        &dir,
        "scenes/adams-clearance.toml",
        &["time.end=0.3", "contact.clearance=0.004", "masses.load=10"],
    );
    let e = worst(&numbers(&v["set"]), &set);
    eprintln!("FMPy with start values against simulate --set: {e:.2e} m");
    assert!(e < 1e-6, "{e}");
    assert!(
        worst(&numbers(&v["set"]), &ours) > 1e-4,
        "the parameters changed the run"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
#[ignore = "needs FMPy: run ./scripts/test"]
fn fmpy_model_exchange_with_cvode_matches_simulate_and_locates_the_switches() {
    let dir = scratch("fmpy-me");
    let linear = export(&dir, "scenes/adams-linear.toml", "me", "linear");
    let clearance = export(&dir, "scenes/adams-clearance.toml", "me", "clearance");
    let v = fmpy(
        &dir,
        &format!(
            "{PRELUDE}r = fmpy.simulate_fmu('{linear}', fmi_type='ModelExchange', solver='CVode', \
             relative_tolerance=1e-8, stop_time=1.0, output_interval=1e-3, input=drive, output=['tip_rel'])\n\
             c = fmpy.simulate_fmu('{clearance}', fmi_type='ModelExchange', solver='CVode', \
             relative_tolerance=1e-10, stop_time=0.3, output_interval=1e-3, input=drive, \
             output=['tip_rel'], record_events=True)\n\
             t = c['time']\n\
             events = [float(t[i]) for i in range(1, len(t)) if t[i] == t[i - 1]]\n\
             grid = np.isclose(t * 1000, np.round(t * 1000), atol=1e-9) & np.concatenate([[True], t[1:] != t[:-1]])\n\
             print(json.dumps({{'linear': r['tip_rel'].tolist(), 'events': events, \
             'clearance': c['tip_rel'][grid].tolist()}}))\n"
        ),
    );
    let ours = simulate(&dir, "scenes/adams-linear.toml", &["time.end=1"]);
    let e = worst(&numbers(&v["linear"]), &ours);
    eprintln!("FMPy model exchange (CVode) on adams-linear against simulate: {e:.2e} m");
    assert!(e < 1e-5, "{e}");
    // every switch of the clearance law: where a gap crosses a band edge in a finely
    // sampled run of ours
    let csv = dir.join("fine.csv");
    succeeds(&[
        "simulate",
        "scenes/adams-clearance.toml",
        "--set",
        "time.end=0.3",
        "--set",
        "time.sample=1e-5",
        "--out",
        csv.to_str().unwrap(),
    ]);
    let text = std::fs::read_to_string(&csv).unwrap();
    let mut lines = text.lines().filter(|l| !l.starts_with('#'));
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let rows: Vec<Vec<f64>> = lines
        .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
        .collect();
    let half_band = 0.005;
    let mut crossings = Vec::new();
    for (j, name) in header
        .iter()
        .enumerate()
        .filter(|(_, h)| h.starts_with("xi_"))
    {
        let _ = name;
        for edge in [half_band, -half_band] {
            for w in rows.windows(2) {
                if (w[0][j] - edge) * (w[1][j] - edge) < 0.0 {
                    crossings.push(w[1][0]);
                }
            }
        }
    }
    let events = numbers(&v["events"]);
    eprintln!(
        "switches: {} located by CVode, {} in our run",
        events.len(),
        crossings.len()
    );
    assert!(!crossings.is_empty());
    assert_eq!(events.len(), crossings.len());
    for e in &events {
        let nearest = crossings
            .iter()
            .map(|c| (c - e).abs())
            .fold(f64::INFINITY, f64::min);
        assert!(
            nearest <= 2e-5,
            "an event at {e} s is {nearest} s from any switch of ours"
        );
    }
    let ours = simulate(&dir, "scenes/adams-clearance.toml", &["time.end=0.3"]);
    let e = worst(&numbers(&v["clearance"]), &ours);
    eprintln!("FMPy model exchange on adams-clearance against simulate: {e:.2e} m");
    assert!(e < 1e-5, "{e}");
    std::fs::remove_dir_all(&dir).unwrap();
}
