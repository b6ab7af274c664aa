//! End-to-end tests of `converge` (the smallest model a scene needs) and `shape-errors`
//! (printed vs cancellation-free shape functions).

mod common;

use common::{fails_with, telescopic};

/// Rows of a CSV with a header, as strings.
fn rows(text: &str) -> Vec<Vec<String>> {
    text.lines()
        .skip(1)
        .map(|l| l.split(',').map(str::to_string).collect())
        .collect()
}

#[test]
fn converge_finds_a_model_whose_next_refinement_changes_less_than_tol() {
    let dir = std::env::temp_dir().join(format!("telescopic-converge-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let csv = dir.join("converge.csv");
    let tol = 1e-2;
    let out = telescopic(&[
        "converge",
        "scenes/adams-clearance.toml",
        "--set",
        "time.end=2",
        "--tol",
        &tol.to_string(),
        "--max-modes",
        "9",
        "--max-contacts",
        "3",
        "--csv",
        csv.to_str().unwrap(),
    ]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let chosen: usize = stdout
        .split("modes per section")
        .next()
        .and_then(|s| s.split_whitespace().last())
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("no model in: {stdout}"));
    assert!(stdout.contains("faster than the largest model"), "{stdout}");
    let table = rows(&std::fs::read_to_string(&csv).unwrap());
    let by_modes: Vec<&Vec<String>> = table.iter().filter(|r| r[1] == "3").take(9).collect();
    assert_eq!(by_modes.len(), 9);
    let num = |r: &Vec<String>, i: usize| r[i].parse::<f64>().unwrap();
    // Ritz: adding shape functions never raises a frequency (from 2 modes on, where there
    // are three)
    for w in by_modes[1..].windows(2) {
        for i in 4..7 {
            assert!(
                num(w[1], i) <= num(w[0], i) * (1.0 + 1e-9),
                "{:?} -> {:?}",
                w[0],
                w[1]
            );
        }
    }
    // the chosen model changes by less than tol to the next one, the one before by more
    let change = |a: &Vec<String>, b: &Vec<String>| {
        (4..9)
            .map(|i| (num(a, i) - num(b, i)).abs() / num(b, i).abs())
            .fold(0.0, f64::max)
    };
    let at = |n: usize| by_modes[n - 1];
    assert!(change(at(chosen), at(chosen + 1)) < tol);
    assert!(change(at(chosen - 1), at(chosen)) >= tol);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn converge_rejects_a_bad_tolerance() {
    fails_with(
        &["converge", "scenes/adams-linear.toml", "--tol", "2"],
        &["--tol: must be a relative change in (0, 1)"],
    );
}

#[test]
fn printed_free_free_shape_functions_fail_where_the_cancellation_free_ones_do_not() {
    let out = telescopic(&["shape-errors", "--points", "11"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let table = rows(&String::from_utf8_lossy(&out.stdout));
    assert_eq!(table.len(), 29 + 28, "modes 2..30 and 3..30");
    for r in &table {
        let mode: usize = r[1].parse().unwrap();
        let (free, printed) = (r[2].parse::<f64>().unwrap(), r[3].parse::<f64>().unwrap());
        assert!(free <= 1e-12, "{r:?}");
        if r[0] == "free-free" && mode >= 20 {
            // sigma rounds to 1 and the e^beta terms cancel to nothing
            assert!(printed > 1e-2, "{r:?}");
        }
        if r[0] == "guided-free" {
            // cos(beta)/cosh(beta) cosh(lam x) never exceeds 1: nothing cancels
            assert!(printed <= 1e-12, "{r:?}");
        }
    }
}
