//! Inputs at the edges of the physics: every reproduction of the reliability issue ends within
//! 10 s (an upper bound against hangs, not a speed claim) with a clear error naming the field,
//! the bound or the cause, or with a correct result.

mod common;

use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

/// Runs the binary with a deadline: kills it and fails the test if it runs longer.
fn run_within(args: &[&str], limit: Duration) -> Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_telescopic"))
        .args(args)
        .current_dir(common::ROOT)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the binary runs");
    let start = Instant::now();
    while child.try_wait().unwrap().is_none() {
        if start.elapsed() > limit {
            let _ = child.kill();
            panic!("{args:?} ran longer than {limit:?}");
        }
        std::thread::sleep(Duration::from_millis(5));
    }
    child.wait_with_output().unwrap()
}

/// Fails within 10 s, cleanly, naming every needle.
fn refused(args: &[&str], needles: &[&str]) {
    let out = run_within(args, Duration::from_secs(10));
    assert_eq!(
        out.status.code(),
        Some(1),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    common::failed_cleanly(args, &out, needles);
}

#[test]
fn sizes_are_bounded_before_any_allocation() {
    for count in ["1000000000000", "1000000000", "100000000"] {
        let set = format!("sections.count={count}");
        refused(
            &["simulate", "scenes/adams-clearance.toml", "--set", &set],
            &["sections.count", "must be in 1..=16", "see docs/scenes.md"],
        );
    }
    refused(
        &[
            "modes",
            "scenes/adams-clearance.toml",
            "--shapes",
            "1000000000",
        ],
        &["--shapes", "must be 2 to 10000"],
    );
    refused(
        &["shape-errors", "--points", "1000000000"],
        &["--points", "must be 2 to 1000"],
    );
    refused(
        &[
            "converge",
            "scenes/adams-clearance.toml",
            "--tol",
            "1e-2",
            "--max-contacts",
            "1000000",
        ],
        &["--max-contacts", "must be 3 to 32"],
    );
    refused(
        &[
            "work-precision",
            "scenes/adams-linear.toml",
            "--repeat",
            "1000000000",
        ],
        &["--repeat", "must be 1 to 100"],
    );
    refused(
        &[
            "work-precision",
            "scenes/adams-linear.toml",
            "--rtols",
            "1e-5,0",
        ],
        &["--rtols", "1e-13 to 0.1"],
    );
    refused(
        &[
            "simulate",
            "scenes/case-study.toml",
            "--set",
            "time.sample=1e-12",
        ],
        &[
            "time.sample",
            "more than the limit of 100000000 output values",
            "raise time.sample",
        ],
    );
}

#[test]
fn work_precision_lists_are_bounded_and_without_repeats_before_the_reference_run() {
    let rtols: Vec<String> = (0..40)
        .map(|i| format!("{:e}", 1e-3 / (1.0 + i as f64)))
        .collect();
    refused(
        &[
            "work-precision",
            "scenes/adams-linear.toml",
            "--rtols",
            &rtols.join(","),
        ],
        &["--rtols", "40 entries, at most 32"],
    );
    refused(
        &[
            "work-precision",
            "scenes/adams-linear.toml",
            "--rtols",
            "1e-5,1e-4,1e-5",
        ],
        &["--rtols", "1e-5 is given twice"],
    );
    refused(
        &[
            "work-precision",
            "scenes/adams-linear.toml",
            "--modes",
            "4,6,4",
        ],
        &["--modes", "given twice"],
    );
    refused(
        &[
            "work-precision",
            "scenes/adams-linear.toml",
            "--modes",
            "4",
            "--rtols",
            "0",
        ],
        &["--rtols", "1e-13 to 0.1"],
    );
}

#[test]
fn stiff_sections_end_in_a_correct_result_or_a_clear_error() {
    // these used to hang in the Schur decomposition
    let out = run_within(
        &[
            "stability",
            "scenes/adams-clearance.toml",
            "--set",
            "sections.youngs_modulus=1e24",
        ],
        Duration::from_secs(10),
    );
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(
        err.contains("orders of magnitude") && err.contains("double precision"),
        "{err}"
    );
    refused(
        &[
            "simulate",
            "scenes/adams-clearance.toml",
            "--set",
            "sections.youngs_modulus=1e30",
            "--method",
            "rk4",
            "--dt",
            "1e-4",
        ],
        &[
            "contact.stiffness against sections.youngs_modulus[0]",
            "bending stiffness",
        ],
    );
    refused(
        &[
            "simulate",
            "scenes/adams-clearance.toml",
            "--set",
            "sections.youngs_modulus=1e24",
            "--method",
            "dop853",
        ],
        &[
            "would need about",
            "more than the step limit",
            "stiffest mode",
        ],
    );
    refused(
        &[
            "work-precision",
            "scenes/adams-clearance.toml",
            "--set",
            "sections.youngs_modulus=1e24",
            "--methods",
            "rk4",
        ],
        &["would need about", "more than the step limit"],
    );
}

/// The `h omega_max` of rk4's limit on the model, from `telescopic stability`'s report.
fn rk4_h_omega(report: &str) -> f64 {
    let line = report
        .lines()
        .find(|l| l.starts_with("rk4 "))
        .expect("an rk4 line");
    line.split_whitespace().last().unwrap().parse().unwrap()
}

#[test]
fn stability_of_stiff_sections_is_right_not_garbage() {
    // E = 1e20: the bending modes outrun the contacts; rk4's limit on an undamped mode is
    // h omega = 2 sqrt(2) (it used to report 0.0234)
    let out = run_within(
        &[
            "stability",
            "scenes/adams-clearance.toml",
            "--set",
            "sections.youngs_modulus=1e20",
        ],
        Duration::from_secs(10),
    );
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let h_omega = rk4_h_omega(&text);
    assert!(
        (h_omega - 2.0 * 2f64.sqrt()).abs() < 0.01,
        "rk4 h omega = {h_omega}:\n{text}"
    );
    // E = 1e22 without gravity: stable, not "unstable" by rounding
    let out = run_within(
        &[
            "stability",
            "scenes/adams-clearance.toml",
            "--set",
            "sections.youngs_modulus=1e22",
            "--set",
            "gravity.g=0",
        ],
        Duration::from_secs(10),
    );
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success());
    assert!(text.contains("largest growth rate 0 (stable)"), "{text}");
    assert!(
        (rk4_h_omega(&text) - 2.0 * 2f64.sqrt()).abs() < 0.01,
        "{text}"
    );
}

#[test]
fn modes_that_double_precision_cannot_resolve_are_refused_not_printed() {
    // 1e20: seven "rigid" modes and frequencies above 1e8 Hz used to come out
    refused(
        &[
            "modes",
            "scenes/adams-clearance.toml",
            "--set",
            "contact.stiffness=1e20",
        ],
        &[
            "contact.stiffness against sections.youngs_modulus",
            "beyond a ratio of 1e12",
        ],
    );
    // 1e15: passes the parameter check, but the 0.7 Hz mode would vanish in rounding
    refused(
        &[
            "modes",
            "scenes/adams-clearance.toml",
            "--set",
            "contact.stiffness=1e15",
        ],
        &["orders of magnitude", "vanish in the rounding"],
    );
    // a stiff but resolvable contact still gives its modes, with exactly one rigid mode
    let out = run_within(
        &[
            "modes",
            "scenes/adams-clearance.toml",
            "--set",
            "contact.stiffness=1e12",
            "--json",
        ],
        Duration::from_secs(10),
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let doc: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(doc["rigid_modes"], 1);
    let f1 = doc["frequencies_hz"][0].as_f64().unwrap();
    assert!(f1 > 0.5 && f1 < 1.0, "f1 = {f1} Hz");
}

#[test]
fn implausible_masses_name_their_fields() {
    for (set, field) in [
        (
            "sections.density=1e-30",
            "sections.area[0] and sections.density[0]",
        ),
        (
            "sections.area=1e-300",
            "sections.area[0] and sections.density[0]",
        ),
        ("masses.load=1e300", "masses.load against sections.area[0]"),
    ] {
        refused(
            &["modes", "scenes/adams-clearance.toml", "--set", set],
            &[field, "differ by more than 1e12"],
        );
    }
}

#[test]
fn failure_causes_are_diagnosed() {
    // an absurd force with gravity off: the drive, not buckling, is named
    for method in ["auto", "dopri5", "esdirk"] {
        refused(
            &[
                "simulate",
                "scenes/adams-clearance.toml",
                "--set",
                "drive.force=1e300",
                "--method",
                method,
            ],
            &[
                "no buckled mode",
                "drive profile ranges over [1e300, 1e300]",
            ],
        );
    }
    // a dopri5 run does not claim exact stepping
    let dir = std::env::temp_dir().join(format!("telescopic-extremes-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let csv = dir.join("run.csv");
    let out = run_within(
        &[
            "simulate",
            "scenes/adams-clearance.toml",
            "--method",
            "dopri5",
            "--set",
            "time.end=0.2",
            "--out",
            csv.to_str().unwrap(),
        ],
        Duration::from_secs(10),
    );
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    assert!(err.contains("method dopri5"), "{err}");
    assert!(
        err.contains("exact stepping would apply (method exact or auto; this run: dopri5)"),
        "{err}"
    );
    assert!(!err.contains("exact stepping (method exact)"), "{err}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn inputs_and_outputs_are_checked_before_the_run() {
    // an unwritable plot and a broken compare scene fail at once, not after the run
    refused(
        &[
            "simulate",
            "scenes/case-study.toml",
            "--plot",
            "/nonexistent-dir/run.svg",
        ],
        &["--plot", "does not exist"],
    );
    refused(
        &[
            "simulate",
            "scenes/case-study.toml",
            "--out",
            "/nonexistent-dir/run.csv",
        ],
        &["--out", "does not exist"],
    );
    refused(
        &[
            "simulate",
            "scenes/case-study.toml",
            "--plot",
            "/tmp/run.svg",
            "--compare",
            "scenes/absent.toml",
        ],
        &["cannot read scene file scenes/absent.toml"],
    );
    refused(
        &[
            "work-precision",
            "scenes/adams-linear.toml",
            "--csv",
            "/nonexistent-dir/t.csv",
        ],
        &["--csv", "does not exist"],
    );
}

#[test]
fn a_closed_standard_output_is_an_error() {
    // Rust's standard library discards writes to a closed stdout; the CSV would be lost
    // with exit code 0
    for command in [
        "simulate scenes/adams-linear.toml --set time.end=0.1",
        "modes scenes/test-rig.toml",
        "stability scenes/adams-linear.toml",
    ] {
        let out = Command::new("sh")
            .arg("-c")
            .arg(format!(
                "exec >&-; exec '{}' {command}",
                env!("CARGO_BIN_EXE_telescopic")
            ))
            .current_dir(common::ROOT)
            .stderr(Stdio::piped())
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{command}: {err}");
        assert!(
            err.contains("standard output is closed"),
            "{command}: {err}"
        );
    }
}

// ---- reliability: output paths, inputs, sizes, memory, units ----

use std::os::unix::fs::FileTypeExt;
use std::path::Path;

/// A scratch sweep over adams-clearance with two short runs, and its result and shard.
fn small_sweep(dir: &Path) -> (String, String) {
    let sweep = dir.join("s.toml");
    std::fs::write(
        &sweep,
        format!(
            "scene = {:?}\nset = [\"time.end=0.2\"]\n[grid]\n\"masses.load\" = [5.0, 10.0]\n",
            format!("{}/scenes/adams-clearance.toml", common::ROOT)
        ),
    )
    .unwrap();
    let result = dir.join("r.csv");
    common::succeeds(&[
        "sweep",
        sweep.to_str().unwrap(),
        "--out",
        result.to_str().unwrap(),
    ]);
    (
        sweep.to_str().unwrap().to_string(),
        result.to_str().unwrap().to_string(),
    )
}

#[test]
fn outputs_to_devices_are_streamed_and_never_replaced() {
    let dir = common::scratch("out-devices");
    let (sweep, result) = small_sweep(&dir);
    let null_is_a_device = || {
        std::fs::metadata("/dev/null")
            .unwrap()
            .file_type()
            .is_char_device()
    };
    assert!(null_is_a_device());
    for args in [
        vec![
            "simulate",
            "scenes/adams-linear.toml",
            "--set",
            "time.end=0.1",
            "--out",
            "/dev/null",
        ],
        vec![
            "linearize",
            "scenes/adams-linear.toml",
            "--out",
            "/dev/null",
        ],
        vec![
            "design",
            "scenes/adams-linear.toml",
            "--no-table",
            "--out",
            "/dev/null",
        ],
        vec!["sweep", &sweep, "--out", "/dev/null"],
        vec!["sweep-merge", &result, "--out", "/dev/null"],
        vec![
            "work-precision",
            "scenes/adams-linear.toml",
            "--methods",
            "rk4",
            "--csv",
            "/dev/null",
        ],
    ] {
        common::succeeds(&args);
        assert!(null_is_a_device(), "{args:?} replaced /dev/null");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn fifos_are_streamed_symlinks_followed_and_directories_refused() {
    let dir = common::scratch("out-streams");
    // a FIFO is written as a stream: the reader gets what a file would hold
    let fifo = dir.join("fifo");
    let c_path = std::ffi::CString::new(fifo.to_str().unwrap()).unwrap();
    // SAFETY: a valid NUL-terminated path and a mode.
    assert_eq!(unsafe { libc::mkfifo(c_path.as_ptr(), 0o600) }, 0);
    let reader = {
        let fifo = fifo.clone();
        std::thread::spawn(move || std::fs::read_to_string(fifo).unwrap())
    };
    let file = dir.join("direct.csv");
    let sim = |out: &Path| {
        common::succeeds(&[
            "simulate",
            "scenes/adams-linear.toml",
            "--set",
            "time.end=0.1",
            "--out",
            out.to_str().unwrap(),
        ])
    };
    sim(&fifo);
    sim(&file);
    assert_eq!(
        reader.join().unwrap(),
        std::fs::read_to_string(&file).unwrap()
    );
    assert!(std::fs::metadata(&fifo).unwrap().file_type().is_fifo());
    // a symlink stays a link and its target is written
    let target = dir.join("target.csv");
    std::fs::write(&target, "old").unwrap();
    let link = dir.join("link.csv");
    std::os::unix::fs::symlink(&target, &link).unwrap();
    sim(&link);
    assert!(
        std::fs::symlink_metadata(&link)
            .unwrap()
            .file_type()
            .is_symlink()
    );
    assert_eq!(
        std::fs::read_to_string(&target).unwrap(),
        std::fs::read_to_string(&file).unwrap()
    );
    // anything else is refused naming the flag
    refused(
        &[
            "simulate",
            "scenes/adams-linear.toml",
            "--out",
            dir.to_str().unwrap(),
        ],
        &["--out", "is a directory"],
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn an_output_that_is_an_input_is_refused() {
    let dir = common::scratch("out-input");
    let (sweep, result) = small_sweep(&dir);
    let scene = dir.join("scene.toml");
    std::fs::copy(format!("{}/scenes/adams-linear.toml", common::ROOT), &scene).unwrap();
    let before = std::fs::read(&scene).unwrap();
    // the same file spelled another way: through `..` and through a link
    let spelled = format!(
        "{}/../{}/scene.toml",
        dir.display(),
        dir.file_name().unwrap().to_str().unwrap()
    );
    let link = dir.join("link.toml");
    std::os::unix::fs::symlink(&scene, &link).unwrap();
    let controller = dir.join("c.json");
    common::succeeds(&[
        "design",
        scene.to_str().unwrap(),
        "--no-table",
        "--out",
        controller.to_str().unwrap(),
    ]);
    let c = controller.to_str().unwrap();
    for args in [
        vec!["simulate", scene.to_str().unwrap(), "--out", &spelled],
        vec![
            "simulate",
            scene.to_str().unwrap(),
            "--out",
            link.to_str().unwrap(),
        ],
        vec!["linearize", scene.to_str().unwrap(), "--out", &spelled],
        vec![
            "design",
            scene.to_str().unwrap(),
            "--no-table",
            "--out",
            &spelled,
        ],
        vec![
            "simulate",
            scene.to_str().unwrap(),
            "--controller",
            c,
            "--out",
            c,
        ],
        vec!["sweep", &sweep, "--out", &sweep],
        vec!["sweep-merge", &result, "--out", &result],
    ] {
        refused(&args, &["--out", "is the input", "would destroy the input"]);
    }
    assert_eq!(std::fs::read(&scene).unwrap(), before);
    // the base scene a sweep reads
    let base_sweep = dir.join("b.toml");
    std::fs::write(
        &base_sweep,
        "scene = \"scene.toml\"\n[grid]\n\"masses.load\" = [5.0]\n",
    )
    .unwrap();
    refused(
        &[
            "sweep",
            base_sweep.to_str().unwrap(),
            "--out",
            scene.to_str().unwrap(),
        ],
        &["--out", "is the input"],
    );
    assert_eq!(std::fs::read(&scene).unwrap(), before);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn inputs_have_a_size_cap_checked_before_reading() {
    let dir = common::scratch("input-caps");
    let (_, _) = small_sweep(&dir);
    for args in [
        vec!["simulate", "/dev/zero"],
        vec![
            "simulate",
            "scenes/adams-linear.toml",
            "--controller",
            "/dev/zero",
        ],
        vec!["sweep", "/dev/zero", "--out", "/dev/null"],
    ] {
        refused(&args, &["/dev/zero", "more than the 16777216 bytes"]);
    }
    // result files are read line by line, a line at most 64 KiB
    for args in [
        vec!["sweep-merge", "/dev/zero", "--out", "/dev/null"],
        vec![
            "plot-sweep",
            "/dev/zero",
            "--x",
            "a",
            "--y",
            "b",
            "--out",
            "/tmp/x.svg",
        ],
    ] {
        refused(&args, &["/dev/zero", "line 1 is longer than 65536 bytes"]);
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn memory_is_predicted_before_allocating() {
    refused(
        &[
            "linearize",
            "scenes/case-study.toml",
            "--set",
            "sections.modes=30",
            "--grid",
            "a2=0.35:1.15:10000",
            "--out",
            "/dev/null",
        ],
        &[
            "--grid",
            "GiB",
            "more than the budget",
            "TELESCOPIC_MEMORY_BUDGET",
        ],
    );
    let out = Command::new(env!("CARGO_BIN_EXE_telescopic"))
        .args([
            "simulate",
            "scenes/adams-clearance.toml",
            "--set",
            "time.sample=6.1e-7",
            "--out",
            "/dev/null",
        ])
        .env("TELESCOPIC_MEMORY_BUDGET", "256M")
        .current_dir(common::ROOT)
        .output()
        .unwrap();
    common::failed_cleanly(
        &["simulate"],
        &out,
        &["time.sample", "more than the budget of 256 MiB"],
    );
}

#[test]
fn numeric_outputs_that_would_not_be_finite_are_refused() {
    refused(
        &[
            "linearize",
            "scenes/case-study.toml",
            "--discrete",
            "1e100",
            "--out",
            "/dev/null",
        ],
        &["--discrete", "not finite", "too long"],
    );
    for (flag, value) in [("--from", "1e-300"), ("--to", "1e300"), ("--from", "1e13")] {
        refused(
            &[
                "bode",
                "scenes/case-study.toml",
                flag,
                value,
                "--out",
                "/dev/null",
            ],
            &[flag, "must be a frequency"],
        );
    }
}

#[test]
fn implausible_structural_damping_is_refused_naming_its_field() {
    for (field, value) in [("rayleigh_beta", "1e150"), ("rayleigh_alpha", "1e150")] {
        let set = format!("sections.{field}={value}");
        for command in ["modes", "stability", "bode", "simulate"] {
            let mut args = vec![command, "scenes/case-study.toml", "--set", &set];
            if matches!(command, "simulate" | "bode") {
                args.extend(["--out", "/dev/null"]);
            }
            refused(&args, &[&format!("sections.{field}"), "damping ratio"]);
        }
    }
}

#[test]
fn the_memory_budget_reaches_every_command_that_runs_scenes() {
    let dir = common::scratch("analysis-budget");
    let controller = dir.join("c.json");
    let controller = controller.to_str().unwrap();
    for args in [
        vec!["converge", "scenes/adams-linear.toml", "--tol", "0.01"],
        vec!["modes", "scenes/three-section.toml", "--shapes", "10000"],
        vec![
            "work-precision",
            "scenes/adams-linear.toml",
            "--repeat",
            "1",
        ],
        vec![
            "work-precision",
            "scenes/adams-linear.toml",
            "--modes",
            "4,6",
            "--repeat",
            "1",
        ],
        vec![
            "design",
            "scenes/case-study.toml",
            "--controller",
            "lqr",
            "--out",
            controller,
        ],
    ] {
        let out = Command::new(env!("CARGO_BIN_EXE_telescopic"))
            .args(&args)
            .env("TELESCOPIC_MEMORY_BUDGET", "64K")
            .current_dir(common::ROOT)
            .output()
            .unwrap();
        common::failed_cleanly(
            &args,
            &out,
            &["more than the budget of 64 KiB", "TELESCOPIC_MEMORY_BUDGET"],
        );
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn values_in_the_wrong_unit_name_the_field_and_say_si() {
    // a modulus in GPa on a scene whose soft contacts break no other rule
    refused(
        &[
            "modes",
            "scenes/three-section.toml",
            "--set",
            "contact.stiffness=1e5",
            "--set",
            "sections.youngs_modulus=210",
        ],
        &[
            "`sections.youngs_modulus[0]`",
            "values are SI",
            "MPa or GPa",
        ],
    );
    refused(
        &[
            "simulate",
            "scenes/case-study.toml",
            "--set",
            "contact.clearance=10",
            "--out",
            "/dev/null",
        ],
        &[
            "contact.clearance",
            "a clearance is a small play",
            "Values are SI",
            "10 mm would be 1e-2 m",
        ],
    );
    refused(
        &[
            "simulate",
            "scenes/case-study.toml",
            "--set",
            "sections.length=1350",
            "--out",
            "/dev/null",
        ],
        &["`sections.length[0]", "Values are SI", "millimetres"],
    );
    refused(
        &[
            "simulate",
            "scenes/case-study.toml",
            "--set",
            "sections.youngs_modulus=2.1e5",
            "--out",
            "/dev/null",
        ],
        // refused before the run (it used to buckle at 0.7 s first)
        &["sections.youngs_modulus[0]", "would sag", "MPa"],
    );
}

#[test]
fn design_settings_name_their_usable_range() {
    for limit in ["1e300", "1e-300"] {
        refused(
            &[
                "design",
                "scenes/adams-linear.toml",
                "--force-limit",
                limit,
                "--out",
                "/dev/null",
            ],
            &["--force-limit", "1e-3 to 1e4 N"],
        );
    }
}

#[test]
fn negative_numbers_reach_the_options_own_check() {
    // a value with a leading minus, in scientific notation too, is the option's value (not
    // clap's "unexpected argument '-1'"), and its check names the rule
    for (flag, value, rule) in [
        ("--accuracy", "-1e-6", "1e-5 to 1e-1 m"),
        ("--rtol", "-1", "tolerances must be positive"),
        ("--atol", "-1E-9", "tolerances must be positive"),
        ("--dt", "-0.1", "> 0"),
    ] {
        refused(
            &[
                "simulate",
                "scenes/adams-linear.toml",
                flag,
                value,
                "--out",
                "/dev/null",
            ],
            &[flag, rule],
        );
    }
    refused(
        &[
            "design",
            "scenes/adams-linear.toml",
            "--force-limit",
            "-300",
            "--out",
            "/dev/null",
        ],
        &["--force-limit", "1e-3 to 1e4 N"],
    );
}

#[test]
fn exit_codes_agree_with_the_docs() {
    // a parser error: 2; any other error: 1 (130 after Ctrl-C: tests/sweep.rs)
    let out = common::telescopic(&["simulate", "--no-such-flag"]);
    assert_eq!(out.status.code(), Some(2));
    let out = common::telescopic(&["simulate", "scenes/absent.toml"]);
    assert_eq!(out.status.code(), Some(1));
    let docs = std::fs::read_to_string(format!("{}/docs/cli.md", common::ROOT)).unwrap();
    for code in ["`0`", "`1`", "`2`", "`130`"] {
        assert!(
            docs.contains(code),
            "docs/cli.md does not state exit code {code}"
        );
    }
}

#[test]
fn a_users_text_never_leaves_its_comment_or_breaks_an_output() {
    let dir = common::scratch("user-text");
    let text =
        std::fs::read_to_string(format!("{}/scenes/adams-linear.toml", common::ROOT)).unwrap();
    let name_line = text
        .lines()
        .find(|l| l.starts_with("name = "))
        .expect("the scene has a name");
    // `name` as TOML writes it, escapes included
    let with_name = |name: &str, file: &str| {
        let path = dir.join(file);
        std::fs::write(
            &path,
            text.replace(name_line, &format!("name = \"{name}\"")),
        )
        .unwrap();
        path
    };
    // a control character in the name (a newline would start a line of code in a comment)
    let bell = with_name(r"bell\u0007 x\nimport os", "ctl.toml");
    refused(
        &["modes", bell.to_str().unwrap()],
        &["`name`", "one line of text without control characters"],
    );
    // a newline in the scene's path, and `*/` and markup in its name
    let odd = with_name("a */ b <&> %", "odd\nimport os.toml");
    let o = odd.to_str().unwrap();
    let py = dir.join("lin.py");
    let svg = dir.join("run.svg");
    let page = dir.join("run.html");
    let tex = dir.join("lin.tex");
    for args in [
        &[
            "linearize",
            o,
            "--format",
            "python",
            "--out",
            py.to_str().unwrap(),
        ][..],
        &[
            "linearize",
            o,
            "--format",
            "latex",
            "--out",
            tex.to_str().unwrap(),
        ],
        &[
            "simulate",
            o,
            "--set",
            "time.end=0.2",
            "--plot",
            svg.to_str().unwrap(),
            "--out",
            "/dev/null",
        ],
        &[
            "animate",
            o,
            "--set",
            "time.end=0.2",
            "--out",
            page.to_str().unwrap(),
        ],
    ] {
        common::succeeds(args);
    }
    // the Python file's header stays comments: every line before the code is one
    let python = std::fs::read_to_string(&py).unwrap();
    let head: Vec<&str> = python
        .lines()
        .take_while(|l| !l.starts_with("import numpy"))
        .collect();
    assert!(
        head.len() >= 3 && head.iter().all(|l| l.starts_with('#')),
        "{head:#?}"
    );
    for path in [&py, &svg, &page, &tex] {
        let bytes = std::fs::read(path).unwrap();
        let bad = bytes
            .iter()
            .position(|&b| b < 0x20 && !matches!(b, b'\t' | b'\n' | b'\r'));
        assert!(
            bad.is_none(),
            "{}: a control character at byte {bad:?}",
            path.display()
        );
    }
    std::fs::remove_dir_all(&dir).unwrap();
}
