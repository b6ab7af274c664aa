//! Parameter sweeps: the result file does not depend on `--jobs`, on sharding or on being
//! killed and resumed; failed runs are rows, not the end of the sweep; the metrics equal what
//! `simulate` writes; bad sweep files are refused before any run.

mod common;

use common::{scratch, succeeds, telescopic, without_wall};

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};
use telescopic::Silent;
use telescopic::sweep::{Shard, Sweep, SweepOptions, merge_shards, read_table, run_sweep};

fn scene(name: &str) -> String {
    format!("{}/scenes/{name}.toml", common::ROOT)
}

/// Writes a sweep file over `scene` with `body` after the `scene =` line.
fn sweep_file(dir: &Path, name: &str, scene_name: &str, body: &str) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, format!("scene = {:?}\n{body}", scene(scene_name))).unwrap();
    path
}

fn options(out: &Path, jobs: usize, shard: Shard) -> SweepOptions {
    SweepOptions {
        out: out.to_owned(),
        jobs,
        shard,
        resume: false,
        memory_budget: telescopic::run::memory::DEFAULT_MEMORY_BUDGET,
        cancel: Default::default(),
    }
}

/// A column's cells of a result file.
fn column(path: &Path, name: &str) -> Vec<String> {
    read_table(path).unwrap().column(name).unwrap()
}

const GRID: &str = r#"set = ["time.end=1.0"]
[grid]
"contact.clearance" = [0.0, 0.004, 0.01]
"masses.load" = [10.0, 30.0]
"drive.force" = [50.0, 100.0]
"#;

#[test]
fn jobs_do_not_change_the_file() {
    let dir = scratch("sweep-jobs");
    let sweep = Sweep::load(&sweep_file(&dir, "s.toml", "adams-clearance", GRID)).unwrap();
    assert_eq!(sweep.runs.len(), 12);
    let one = dir.join("one.csv");
    let two = dir.join("two.csv");
    run_sweep(&sweep, &options(&one, 1, Shard::whole()), &Silent).unwrap();
    let done = run_sweep(&sweep, &options(&two, 2, Shard::whole()), &Silent).unwrap();
    assert_eq!((done.total, done.written, done.failed), (12, 12, 0));
    assert_eq!(without_wall(&one), without_wall(&two));
    assert_eq!(
        read_table(&one).unwrap().header,
        read_table(&two).unwrap().header
    );
    // the grid's order: the last key (sorted) varies fastest
    let (columns, rows) = without_wall(&one);
    assert!(columns.starts_with("index,contact.clearance,drive.force,masses.load,tip_rel_max,"));
    assert!(rows[0].starts_with("0,0.0,50.0,10.0,"), "{}", rows[0]);
    assert!(rows[1].starts_with("1,0.0,50.0,30.0,"), "{}", rows[1]);
    assert!(rows[2].starts_with("2,0.0,100.0,10.0,"), "{}", rows[2]);
    assert!(rows[11].starts_with("11,0.01,100.0,30.0,"), "{}", rows[11]);
    // the physics shows through: with no clearance the contacts never switch, with one they do
    let switches = column(&one, "contact_switches");
    assert_eq!(switches[0], "0");
    assert!(switches[11].parse::<u64>().unwrap() > 10, "{switches:?}");
    assert!(!dir.join("one.csv.partial").exists());
    std::fs::remove_dir_all(&dir).unwrap();
}

/// max |x|, RMS and the standard deviation from `from` of a CSV column written by `simulate`.
fn simulate_figures(csv: &Path, name: &str, from: f64) -> (f64, f64, f64) {
    let text = std::fs::read_to_string(csv).unwrap();
    let mut lines = text.lines().filter(|l| !l.starts_with('#'));
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let i = header.iter().position(|c| *c == name).unwrap();
    let rows: Vec<(f64, f64)> = lines
        .map(|l| {
            let cells: Vec<f64> = l.split(',').map(|c| c.parse().unwrap()).collect();
            (cells[0], cells[i])
        })
        .collect();
    let max = rows.iter().fold(0.0f64, |m, r| m.max(r.1.abs()));
    let rms = (rows.iter().map(|r| r.1 * r.1).sum::<f64>() / rows.len() as f64).sqrt();
    let late: Vec<f64> = rows.iter().filter(|r| r.0 >= from).map(|r| r.1).collect();
    let mean = late.iter().sum::<f64>() / late.len() as f64;
    let std = (late.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / late.len() as f64).sqrt();
    (max, rms, std)
}

#[test]
fn metrics_equal_what_simulate_writes() {
    // case-study shortened: the drive changes last at t = 4 s, the run ends at 6 s
    let dir = scratch("sweep-metrics");
    let body = r#"set = ["time.end=6.0", "drive.force.times=[0, 2, 4]", "drive.force.values=[100, -100, 0]"]
[[runs]]
"contact.clearance" = 0.005
"telescope.positions.0.to" = 0.9
"#;
    let sweep = Sweep::load(&sweep_file(&dir, "s.toml", "case-study", body)).unwrap();
    let out = dir.join("r.csv");
    run_sweep(&sweep, &options(&out, 1, Shard::whole()), &Silent).unwrap();
    let csv = dir.join("sim.csv");
    // a sweep runs the scene's modes as written (the scene's accuracy is simulate's)
    succeeds(&[
        "simulate",
        "scenes/case-study.toml",
        "--modes-as-given",
        "--set",
        "time.end=6.0",
        "--set",
        "drive.force.times=[0, 2, 4]",
        "--set",
        "drive.force.values=[100, -100, 0]",
        "--set",
        "contact.clearance=0.005",
        "--set",
        "telescope.positions.0.to=0.9",
        "--out",
        csv.to_str().unwrap(),
    ]);
    let (max, rms, std) = simulate_figures(&csv, "tip_rel", 4.0);
    let cell = |name: &str| column(&out, name)[0].parse::<f64>().unwrap();
    // the CSV's numbers are printed round-trip exact: the figures agree to rounding
    assert!(
        (cell("tip_rel_max") - max).abs() <= 1e-14 * max,
        "{} vs {max}",
        cell("tip_rel_max")
    );
    assert!(
        (cell("tip_rel_rms") - rms).abs() <= 1e-12 * rms,
        "{} vs {rms}",
        cell("tip_rel_rms")
    );
    assert!(
        (cell("residual_std") - std).abs() <= 1e-12 * std,
        "{} vs {std}",
        cell("residual_std")
    );
    let force = ["f_2_0", "f_2_1"]
        .iter()
        .map(|c| simulate_figures(&csv, c, 0.0).0)
        .fold(0.0, f64::max);
    assert!((cell("contact_force_max") - force).abs() <= 1e-14 * force);
    // f1 at the final extension, from `telescopic modes` at the end time
    let modes = succeeds(&[
        "modes",
        "scenes/case-study.toml",
        "--set",
        "telescope.positions.0.to=0.9",
        "--set",
        "contact.clearance=0.005",
        "--at",
        "6.0",
        "--json",
    ]);
    let json: serde_json::Value = serde_json::from_slice(&modes.stdout).unwrap();
    let f1 = json["frequencies_hz"][0].as_f64().unwrap();
    assert_eq!(cell("f1_hz"), f1);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn diverging_runs_are_recorded_and_the_sweep_goes_on() {
    let dir = scratch("sweep-diverging");
    let body = r#"set = ["time.end=0.5"]
[grid]
"drive.force" = [100.0, 1e300, 200.0]
"#;
    let path = sweep_file(&dir, "s.toml", "adams-clearance", body);
    let out = dir.join("r.csv");
    let run = succeeds(&[
        "sweep",
        path.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    let err = String::from_utf8_lossy(&run.stderr);
    assert!(err.contains("1 failed"), "{err}");
    let status = column(&out, "status");
    assert_eq!(status, ["ok", "diverged", "ok"]);
    let error = column(&out, "error");
    assert!(
        error[1].contains("drive profile ranges over [1e300, 1e300]"),
        "{}",
        error[1]
    );
    // the failed run's metrics are empty, not NaN or zero
    assert_eq!(column(&out, "tip_rel_max")[1], "");
    assert!(!std::fs::read_to_string(&out).unwrap().contains("NaN"));
    // the other runs are whole: doubling the force doubles the response of this linear-drive
    // run closely (contacts make it not exactly linear)
    let tip: Vec<f64> = column(&out, "tip_rel_max")
        .iter()
        .filter_map(|v| v.parse().ok())
        .collect();
    assert!((tip[1] / tip[0] - 2.0).abs() < 0.5, "{tip:?}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn shards_merge_into_the_unsharded_file() {
    let dir = scratch("sweep-shards");
    let sweep = Sweep::load(&sweep_file(&dir, "s.toml", "adams-clearance", GRID)).unwrap();
    let whole = dir.join("whole.csv");
    run_sweep(&sweep, &options(&whole, 2, Shard::whole()), &Silent).unwrap();
    let mut parts = Vec::new();
    for i in 0..5 {
        let part = dir.join(format!("part{i}.csv"));
        let done = run_sweep(
            &sweep,
            &options(&part, 1, Shard { index: i, count: 5 }),
            &Silent,
        )
        .unwrap();
        assert_eq!(done.total, (0..12).filter(|k| k % 5 == i).count());
        parts.push(part);
    }
    // through the CLI, shards in any order
    let merged = dir.join("merged.csv");
    let mut args = vec!["sweep-merge"];
    args.extend(parts.iter().rev().map(|p| p.to_str().unwrap()));
    args.extend(["--out", merged.to_str().unwrap()]);
    succeeds(&args);
    assert_eq!(without_wall(&merged), without_wall(&whole));
    let table = read_table(&merged).unwrap();
    assert_eq!(table.header_field("sweep"), Some(sweep.hash.as_str()));
    assert_eq!(table.header_field("merged from"), Some("5 shards"));

    // refusals: a shard missing, a shard twice, a shard of another sweep, not a result file
    let refuse = |paths: &[&Path], needles: &[&str]| {
        let err = merge_shards(paths).unwrap_err().to_string();
        for n in needles {
            assert!(err.contains(n), "{err} lacks {n}");
        }
    };
    let p: Vec<&Path> = parts.iter().map(PathBuf::as_path).collect();
    refuse(&p[..4], &["2 run(s) missing (4, 9)", "exactly once"]);
    refuse(
        &[p[0], p[1], p[1], p[2], p[3], p[4]],
        &["shard 1 is given twice"],
    );
    let other = Sweep::load(&sweep_file(
        &dir,
        "other.toml",
        "adams-clearance",
        &GRID.replace("30.0", "31.0"),
    ))
    .unwrap();
    let foreign = dir.join("foreign.csv");
    run_sweep(
        &other,
        &options(&foreign, 2, Shard { index: 4, count: 5 }),
        &Silent,
    )
    .unwrap();
    refuse(
        &[p[0], p[1], p[2], p[3], &foreign],
        &["foreign.csv is from another sweep", "same sweep file"],
    );
    let mixed = dir.join("mixed.csv");
    run_sweep(
        &sweep,
        &options(&mixed, 2, Shard { index: 4, count: 6 }),
        &Silent,
    )
    .unwrap();
    refuse(
        &[p[0], p[1], p[2], p[3], &mixed],
        &["is shard 4 of 6", "is of 5", "one split"],
    );
    std::fs::write(dir.join("plain.csv"), "t,x\n0,1\n").unwrap();
    refuse(
        &[&dir.join("plain.csv")],
        &["not the result of `telescopic sweep`"],
    );
    // the CLI leaves no file when it refuses
    let bad = dir.join("bad.csv");
    let out = telescopic(&[
        "sweep-merge",
        p[0].to_str().unwrap(),
        "--out",
        bad.to_str().unwrap(),
    ]);
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("missing"));
    assert!(!bad.exists());
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A sweep of 60 runs of 5 s each (about a second on one core), for kill and interrupt tests.
const LONG: &str = r#"set = ["time.end=5.0"]
[grid]
"contact.clearance" = [0.002, 0.004, 0.006, 0.008, 0.01, 0.012]
"masses.load" = [5.0, 10.0, 15.0, 20.0, 25.0, 30.0, 35.0, 40.0, 45.0, 50.0]
"#;

/// Starts `sweep FILE --jobs JOBS --out OUT` in the background, standard output discarded.
fn spawn_sweep(path: &Path, out: &Path, jobs: &str, stderr: Stdio) -> std::process::Child {
    Command::new(env!("CARGO_BIN_EXE_telescopic"))
        .args([
            "sweep",
            path.to_str().unwrap(),
            "--jobs",
            jobs,
            "--out",
            out.to_str().unwrap(),
        ])
        .stdout(Stdio::null())
        .stderr(stderr)
        .spawn()
        .unwrap()
}

/// Starts `sweep FILE --out OUT --jobs 1`, waits until its work file holds `rows` rows, and
/// sends it `sig`.
fn stop_midway(path: &Path, out: &Path, rows: usize, sig: i32) -> std::process::Output {
    let mut child = spawn_sweep(path, out, "1", Stdio::piped());
    let partial = out.with_file_name(format!(
        "{}.partial",
        out.file_name().unwrap().to_str().unwrap()
    ));
    let start = Instant::now();
    while std::fs::read_to_string(&partial).map_or(0, |t| t.lines().count().saturating_sub(2))
        < rows
    {
        assert!(
            start.elapsed() < Duration::from_secs(60),
            "the sweep wrote too few rows"
        );
        assert!(
            child.try_wait().unwrap().is_none(),
            "the sweep ended before it was stopped"
        );
        std::thread::sleep(Duration::from_millis(5));
    }
    // SAFETY: kill with a valid pid and signal number has no memory-safety preconditions.
    assert_eq!(unsafe { libc::kill(child.id() as i32, sig) }, 0);
    child.wait_with_output().unwrap()
}

#[test]
fn resume_after_a_kill_gives_the_uninterrupted_file() {
    let dir = scratch("sweep-resume");
    let path = sweep_file(&dir, "s.toml", "adams-clearance", LONG);
    let reference = dir.join("reference.csv");
    run_sweep(
        &Sweep::load(&path).unwrap(),
        &options(&reference, 2, Shard::whole()),
        &Silent,
    )
    .unwrap();

    let out = dir.join("r.csv");
    let killed = stop_midway(&path, &out, 5, libc::SIGKILL);
    assert!(!killed.status.success());
    assert!(!out.exists(), "a killed sweep left its result file");
    let partial = dir.join("r.csv.partial");
    let kept = std::fs::read_to_string(&partial).unwrap().lines().count() - 2;
    assert!(kept < 60, "the sweep finished before the kill");
    // a kill in the middle of a write leaves a torn last row; resume cuts it off
    let mut file = std::fs::OpenOptions::new()
        .append(true)
        .open(&partial)
        .unwrap();
    std::io::Write::write_all(&mut file, b"59,0.012,50.0,0.2").unwrap();
    drop(file);
    let resumed = telescopic(&[
        "sweep",
        path.to_str().unwrap(),
        "--resume",
        "--out",
        out.to_str().unwrap(),
    ]);
    let err = String::from_utf8_lossy(&resumed.stderr);
    assert!(resumed.status.success(), "{err}");
    assert!(err.contains(&format!("{} made now", 60 - kept)), "{err}");
    assert!(err.contains(&format!("{kept} kept from before")), "{err}");
    assert_eq!(without_wall(&out), without_wall(&reference));
    assert!(!partial.exists());
    // a resume of a finished file does nothing and keeps it
    let again = telescopic(&[
        "sweep",
        path.to_str().unwrap(),
        "--resume",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(String::from_utf8_lossy(&again.stderr).contains("0 made now"));
    assert_eq!(without_wall(&out), without_wall(&reference));
    // a work file of another sweep is not resumed
    std::fs::write(
        &partial,
        "# telescopic sweep 0.1.0; sweep 0123456789abcdef; runs 60; shard 0/1\nindex\n",
    )
    .unwrap();
    let foreign = telescopic(&[
        "sweep",
        path.to_str().unwrap(),
        "--resume",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(!foreign.status.success());
    assert!(String::from_utf8_lossy(&foreign.stderr).contains("belongs to another sweep or shard"));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn ctrl_c_stops_between_runs_and_keeps_every_finished_row() {
    let dir = scratch("sweep-ctrl-c");
    let path = sweep_file(&dir, "s.toml", "adams-clearance", LONG);
    let out = dir.join("r.csv");
    let stopped = stop_midway(&path, &out, 3, libc::SIGINT);
    let err = String::from_utf8_lossy(&stopped.stderr);
    // docs/cli.md: 130 after Ctrl-C, as a shell reports a process ended by SIGINT
    assert_eq!(stopped.status.code(), Some(130), "{err}");
    assert!(err.contains("interrupted"), "{err}");
    assert!(err.contains("run again with --resume"), "{err}");
    assert!(!out.exists());
    let partial = std::fs::read_to_string(dir.join("r.csv.partial")).unwrap();
    assert!(partial.ends_with('\n'), "a torn row after Ctrl-C");
    let rows = partial.lines().count() - 2;
    assert!((3..60).contains(&rows), "{rows} rows");
    let resumed = telescopic(&[
        "sweep",
        path.to_str().unwrap(),
        "--resume",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(resumed.status.success());
    assert_eq!(read_table(&out).unwrap().rows.len(), 60);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn sweep_files_are_validated_before_any_run() {
    let dir = scratch("sweep-validate");
    let out = dir.join("r.csv");
    let refused = |body: &str, needles: &[&str]| {
        let path = sweep_file(&dir, "bad.toml", "adams-clearance", body);
        let run = telescopic(&[
            "sweep",
            path.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ]);
        let err = String::from_utf8_lossy(&run.stderr);
        assert!(!run.status.success(), "{body} accepted");
        assert!(!err.contains("panicked"), "{err}");
        for n in needles {
            assert!(err.contains(n), "{body}: {err} lacks {n}");
        }
        assert!(!err.contains("runs 1/"), "a run started: {err}");
        assert!(!out.exists() && !dir.join("r.csv.partial").exists());
    };
    refused(
        "[grid]\n\"contact.clearence\" = [0.0, 0.01]\n",
        &[
            "1 of 1 keys have a value the base scene does not take",
            "contact.clearence=0.0:",
            "clearence",
        ],
    );
    refused(
        "[grid]\n\"contact.clearance\" = []\n",
        &["[grid] `contact.clearance`: the list is empty"],
    );
    refused(
        "[grid]\n\"contact.clearance\" = 0.01\n",
        &["must be a list of values"],
    );
    refused(
        "[grid]\n\"contact.clearance\" = [0.0, -0.01, 0.01]\n",
        &[
            "contact.clearance=-0.01:",
            "must be a finite number >= 0 (got -0.01)",
        ],
    );
    refused(
        "grid_typo = 1\n[grid]\n\"masses.load\" = [1.0]\n",
        &["grid_typo"],
    );
    refused("", &["no runs: give [grid], [[runs]] or [latin]"]);
    refused(
        "[[runs]]\nmethod = \"rk9\"\n",
        &["method=\"rk9\": `method`:", "rk9"],
    );
    refused(
        "[[runs]]\nrtol = \"tight\"\n",
        &["`rtol`: must be a number"],
    );
    refused(
        "[latin]\nsamples = 4\nseed = 1\nranges = { \"masses.load\" = [30.0, 10.0] }\n",
        &["[latin.ranges] `masses.load`: must be [low, high] with low < high"],
    );
    refused("[latin]\nsamples = 4\nranges = {}\n", &["seed"]);
    // each value is fine alone, one combination is not: the run is named
    refused(
        "[grid]\n\"contact.stiffness\" = [1e8, 1e15]\n\"sections.inertia\" = [0.83e-8, 0.83e-10]\n",
        &[
            "1 of 4 runs are invalid",
            "run 3 (contact.stiffness=1e15, sections.inertia=8.3e-11)",
            "1e12",
        ],
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_missing_base_scene_and_bad_options_are_refused() {
    let dir = scratch("sweep-validate-options");
    let out = dir.join("r.csv");
    // the base scene must exist, relative to the sweep file
    std::fs::write(
        dir.join("missing.toml"),
        "scene = \"nowhere.toml\"\n[grid]\n\"masses.load\" = [1.0]\n",
    )
    .unwrap();
    let run = telescopic(&[
        "sweep",
        dir.join("missing.toml").to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    let err = String::from_utf8_lossy(&run.stderr);
    assert!(
        err.contains("`scene` = \"nowhere.toml\": cannot read") && err.contains("nowhere.toml"),
        "{err}"
    );
    // bad options
    let path = sweep_file(
        &dir,
        "ok.toml",
        "adams-clearance",
        "[grid]\n\"masses.load\" = [1.0]\n",
    );
    for (args, needle) in [
        (vec!["--shard", "2/2"], "need 0 <= I < N"),
        (vec!["--shard", "1-2"], "expected I/N"),
        (vec!["--jobs", "0"], "--jobs: must be 1 to 256"),
    ] {
        let mut all = vec![
            "sweep",
            path.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ];
        all.extend(args);
        let run = telescopic(&all);
        assert!(!run.status.success());
        assert!(
            String::from_utf8_lossy(&run.stderr).contains(needle),
            "{}",
            String::from_utf8_lossy(&run.stderr)
        );
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `sweep --shard auto` of `path` into `dir/r.csv` with only the job-array variables `vars`
/// set and the `extra` arguments: whether it succeeded, its stderr, the result table.
fn sweep_with_variables(
    dir: &Path,
    path: &Path,
    vars: &[(&str, &str)],
    extra: &[&str],
) -> (bool, String, Option<telescopic::sweep::SweepTable>) {
    let out = dir.join("r.csv");
    let _ = std::fs::remove_file(&out);
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_telescopic"));
    cmd.args([
        "sweep",
        path.to_str().unwrap(),
        "--shard",
        "auto",
        "--out",
        out.to_str().unwrap(),
    ]);
    cmd.args(extra);
    for v in [
        "SLURM_ARRAY_TASK_ID",
        "SLURM_ARRAY_TASK_MIN",
        "SLURM_ARRAY_TASK_STEP",
        "SLURM_ARRAY_TASK_COUNT",
        "JOB_COMPLETION_INDEX",
    ] {
        cmd.env_remove(v);
    }
    cmd.envs(vars.iter().copied());
    let o = cmd.output().unwrap();
    (
        o.status.success(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
        read_table(&out).ok(),
    )
}

#[test]
fn shard_auto_reads_the_job_array_variables() {
    let dir = scratch("sweep-auto");
    let path = sweep_file(
        &dir,
        "s.toml",
        "adams-clearance",
        "set = [\"time.end=0.1\"]\n[grid]\n\"masses.load\" = [1.0, 2.0, 3.0, 4.0, 5.0]\n",
    );
    let run =
        |vars: &[(&str, &str)], extra: &[&str]| sweep_with_variables(&dir, &path, vars, extra);
    // a Slurm array --array=3-4: task 4 is shard 1 of 2
    let (ok, err, table) = run(
        &[
            ("SLURM_ARRAY_TASK_ID", "4"),
            ("SLURM_ARRAY_TASK_MIN", "3"),
            ("SLURM_ARRAY_TASK_COUNT", "2"),
        ],
        &[],
    );
    assert!(ok, "{err}");
    let table = table.unwrap();
    assert_eq!(table.header_field("shard"), Some("1/2"));
    assert_eq!(table.rows.iter().map(|r| r.0).collect::<Vec<_>>(), [1, 3]);
    // --array=1-9:4 (tasks 1, 5, 9): task 5 is shard 1 of 3; a list with gaps is refused
    let (ok, err, table) = run(
        &[
            ("SLURM_ARRAY_TASK_ID", "5"),
            ("SLURM_ARRAY_TASK_MIN", "1"),
            ("SLURM_ARRAY_TASK_STEP", "4"),
            ("SLURM_ARRAY_TASK_COUNT", "3"),
        ],
        &[],
    );
    assert!(ok, "{err}");
    assert_eq!(
        table.unwrap().rows.iter().map(|r| r.0).collect::<Vec<_>>(),
        [1, 4]
    );
    let (ok, err, _) = run(
        &[
            ("SLURM_ARRAY_TASK_ID", "7"),
            ("SLURM_ARRAY_TASK_MIN", "0"),
            ("SLURM_ARRAY_TASK_COUNT", "3"),
        ],
        &[],
    );
    assert!(
        !ok && err
            .contains("array task 7 (min 0, step 1, count 3) is not one of an evenly spaced range"),
        "{err}"
    );
    // a Kubernetes indexed job: the count from the command line
    let (ok, err, table) = run(&[("JOB_COMPLETION_INDEX", "2")], &["--shard-count", "3"]);
    assert!(ok, "{err}");
    assert_eq!(
        table.unwrap().rows.iter().map(|r| r.0).collect::<Vec<_>>(),
        [2]
    );
    let (ok, err, _) = run(&[("JOB_COMPLETION_INDEX", "2")], &[]);
    assert!(
        !ok && err.contains("give the shard count") && err.contains("(see --shard-count)"),
        "{err}"
    );
    let (ok, err, _) = run(&[], &[]);
    assert!(!ok && err.contains("neither SLURM_ARRAY_TASK_ID"), "{err}");
    let (ok, err, _) = run(
        &[
            ("SLURM_ARRAY_TASK_ID", "x"),
            ("SLURM_ARRAY_TASK_COUNT", "2"),
        ],
        &[],
    );
    assert!(
        !ok && err.contains("SLURM_ARRAY_TASK_ID=\"x\" is not a whole number"),
        "{err}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn latin_hypercube_samples_are_stratified_and_reproducible() {
    let dir = scratch("sweep-latin");
    let body = |seed: u64| {
        format!(
            "set = [\"time.end=0.1\"]\n[latin]\nsamples = 50\nseed = {seed}\n\
             ranges = {{ \"contact.clearance\" = [0.0, 0.01], \"masses.load\" = [10.0, 30.0] }}\n"
        )
    };
    let a = Sweep::load(&sweep_file(&dir, "a.toml", "adams-clearance", &body(7))).unwrap();
    let b = Sweep::load(&sweep_file(&dir, "b.toml", "adams-clearance", &body(7))).unwrap();
    let c = Sweep::load(&sweep_file(&dir, "c.toml", "adams-clearance", &body(8))).unwrap();
    assert_eq!(a.runs, b.runs);
    assert_eq!(
        a.hash, b.hash,
        "the hash is of the contents, not the file's name"
    );
    assert_ne!(a.runs, c.runs);
    assert_eq!(a.keys, ["contact.clearance", "masses.load"]);
    for (k, (lo, hi)) in [(0.0, 0.01), (10.0, 30.0)].into_iter().enumerate() {
        let mut strata: Vec<usize> = a
            .runs
            .iter()
            .map(|r| {
                let v = r.values[k].as_ref().unwrap().as_float().unwrap();
                assert!((lo..hi).contains(&v));
                ((v - lo) / (hi - lo) * 50.0) as usize
            })
            .collect();
        strata.sort_unstable();
        assert_eq!(
            strata,
            (0..50).collect::<Vec<_>>(),
            "one sample per stratum"
        );
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn plot_sweep_draws_lines_and_heat_maps() {
    let dir = scratch("sweep-plot");
    let sweep = Sweep::load(&sweep_file(&dir, "s.toml", "adams-clearance", GRID)).unwrap();
    let out = dir.join("r.csv");
    run_sweep(&sweep, &options(&out, 2, Shard::whole()), &Silent).unwrap();
    let svg = dir.join("lines.svg");
    succeeds(&[
        "plot-sweep",
        out.to_str().unwrap(),
        "--x",
        "contact.clearance",
        "--y",
        "residual_std",
        "--color",
        "masses.load",
        "--out",
        svg.to_str().unwrap(),
    ]);
    let text = std::fs::read_to_string(&svg).unwrap();
    assert!(text.contains("masses.load = 10.0") && text.contains("masses.load = 30.0"));
    let png = dir.join("heat.png");
    succeeds(&[
        "plot-sweep",
        out.to_str().unwrap(),
        "--x",
        "contact.clearance",
        "--y",
        "tip_rel_max",
        "--color",
        "masses.load",
        "--heatmap",
        "--out",
        png.to_str().unwrap(),
    ]);
    assert_eq!(&std::fs::read(&png).unwrap()[1..4], b"PNG");
    let bad = telescopic(&[
        "plot-sweep",
        out.to_str().unwrap(),
        "--x",
        "clearance",
        "--y",
        "tip_rel_max",
        "--out",
        svg.to_str().unwrap(),
    ]);
    let err = String::from_utf8_lossy(&bad.stderr);
    assert!(
        !bad.status.success() && err.contains("--x: `clearance` is not a column"),
        "{err}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn the_example_sweep_files_are_valid() {
    let root = Path::new(common::ROOT);
    let clearance = Sweep::load(&root.join("examples/sweeps/clearance.toml")).unwrap();
    assert_eq!(clearance.runs.len(), 9);
    let case_study = Sweep::load(&root.join("examples/sweeps/case-study.toml")).unwrap();
    assert_eq!(case_study.runs.len(), 84);
    assert_eq!(
        case_study.keys,
        ["contact.clearance", "telescope.positions.0.to"]
    );
}

// ---- reliability: every row of a shard, a merge and a resume is checked ----

/// A small sweep made whole and as two shards, in `dir`: (whole, shard 0, shard 1).
fn small_sweep_and_shards(dir: &Path) -> (PathBuf, PathBuf, PathBuf) {
    let body = "set = [\"time.end=0.3\"]\n[grid]\n\"contact.clearance\" = [0.0, 0.004, 0.01]\n\"masses.load\" = [10.0, 30.0]\n";
    let sweep = Sweep::load(&sweep_file(dir, "s.toml", "adams-clearance", body)).unwrap();
    let whole = dir.join("whole.csv");
    run_sweep(&sweep, &options(&whole, 2, Shard::whole()), &Silent).unwrap();
    let parts: Vec<PathBuf> = (0..2)
        .map(|i| {
            let part = dir.join(format!("part{i}.csv"));
            let shard = Shard { index: i, count: 2 };
            run_sweep(&sweep, &options(&part, 1, shard), &Silent).unwrap();
            part
        })
        .collect();
    (whole, parts[0].clone(), parts[1].clone())
}

/// `sweep-merge` of `parts` into `dir/merged.csv` fails naming every needle, leaving no file.
fn merge_refused(dir: &Path, parts: &[&Path], needles: &[&str]) {
    let merged = dir.join("merged.csv");
    let mut args = vec!["sweep-merge"];
    args.extend(parts.iter().map(|p| p.to_str().unwrap()));
    args.extend(["--out", merged.to_str().unwrap()]);
    common::fails_with(&args, needles);
    assert!(!merged.exists(), "{args:?} left a merged file");
}

#[test]
fn merges_check_every_row_against_the_header() {
    let dir = scratch("sweep-rows");
    let (_, part0, part1) = small_sweep_and_shards(&dir);
    let text = std::fs::read_to_string(&part0).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    let bad = dir.join("bad.csv");
    let with_row = |row: &str| {
        // the rows above the closing line, one of them replaced: the checksum is rebuilt, so
        // only the row check can refuse it
        let mut table = read_table(&part0).unwrap();
        table.rows[0].1 = row.to_string();
        let mut bytes = Vec::new();
        table.write(&mut bytes).unwrap();
        std::fs::write(&bad, bytes).unwrap();
    };
    let row0 = lines[2];
    let cells: Vec<&str> = row0.split(',').collect();
    // truncated mid-row: 10 fields, `steps` = 16
    with_row(&cells[..10].join(",").replace(cells[9], "16"));
    merge_refused(
        &dir,
        &[&bad, &part1],
        &["bad.csv", "line 3", "fields, the columns are"],
    );
    // an extra column
    with_row(&format!("{row0},1"));
    merge_refused(
        &dir,
        &[&bad, &part1],
        &["line 3", "fields, the columns are"],
    );
    // NaN and inf metrics
    for value in ["NaN", "inf"] {
        let mut c = cells.clone();
        c[3] = value;
        with_row(&c.join(","));
        merge_refused(&dir, &[&bad, &part1], &["line 3", "tip_rel_max", "finite"]);
    }
    // a row like 1,0.0,17.897,xxx
    with_row("1,0.0,17.897,xxx");
    merge_refused(&dir, &[&bad, &part1], &["line 3", "fields"]);
    // an unknown status
    let mut c = cells.clone();
    let status = c.len() - 3;
    c[status] = "great";
    with_row(&c.join(","));
    merge_refused(&dir, &[&bad, &part1], &["line 3", "status \"great\""]);
    // a file cut anywhere (its closing line gone) or edited after writing
    std::fs::write(&bad, &text[..text.len() - 30]).unwrap();
    merge_refused(&dir, &[&bad, &part1], &["bad.csv", "truncated"]);
    std::fs::write(&bad, text.replacen(cells[3], "0.5", 1)).unwrap();
    merge_refused(&dir, &[&bad, &part1], &["bad.csv", "SHA-256"]);
    // a huge run count in the header is bounded before anything is allocated for it
    for runs in ["9000000000000", "300000000"] {
        std::fs::write(&bad, text.replacen("runs 6;", &format!("runs {runs};"), 1)).unwrap();
        merge_refused(
            &dir,
            &[&bad, &part1],
            &["line 1", "run count must be 1 to 10000000"],
        );
    }
    // a bad line is quoted in at most a few hundred characters: a 2 MB one is not read whole,
    // one under the 64 KiB line limit is cut
    let merged = dir.join("merged.csv");
    let refused_briefly = |needle: &str| {
        let args = [
            "sweep-merge",
            bad.to_str().unwrap(),
            part1.to_str().unwrap(),
            "--out",
            merged.to_str().unwrap(),
        ];
        let out = telescopic(&args);
        common::failed_cleanly(&args, &out, &[needle]);
        assert!(
            out.stderr.len() < 1000,
            "{} bytes of error",
            out.stderr.len()
        );
    };
    with_row(&"x".repeat(2_000_000));
    refused_briefly("longer than 65536 bytes");
    with_row(&format!("{},{}", "y".repeat(60_000), row0));
    refused_briefly("bytes in all");
    // shards of different splits are named as such, not as a shard given twice
    let third = dir.join("third.csv");
    let sweep = Sweep::load(&dir.join("s.toml")).unwrap();
    run_sweep(
        &sweep,
        &options(&third, 1, Shard { index: 1, count: 3 }),
        &Silent,
    )
    .unwrap();
    let err = merge_shards(&[&part0, &third]).unwrap_err().to_string();
    assert!(
        err.contains("is shard 1 of 3") && err.contains("one split"),
        "{err}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(200))]
    /// A shard cut or corrupted at any byte either merges into exactly the unsharded file or
    /// is refused with a message; never a different result.
    #[test]
    fn a_corrupted_shard_merges_right_or_is_refused(
        cut in proptest::prelude::any::<proptest::sample::Index>(),
        at in proptest::prelude::any::<proptest::sample::Index>(),
        byte in proptest::prelude::any::<u8>(),
        truncate in proptest::prelude::any::<bool>(),
    ) {
        static FILES: std::sync::OnceLock<(PathBuf, Vec<u8>, PathBuf, PathBuf)> =
            std::sync::OnceLock::new();
        let (whole, part0, part1, dir) = {
            let (dir, bytes, whole, part1) = FILES.get_or_init(|| {
                let dir = scratch("sweep-proptest");
                let (whole, part0, part1) = small_sweep_and_shards(&dir);
                (dir.clone(), std::fs::read(&part0).unwrap(), whole, part1)
            });
            (whole.clone(), bytes.clone(), part1.clone(), dir.clone())
        };
        let mut bytes = part0;
        if truncate {
            bytes.truncate(cut.index(bytes.len()));
        } else {
            let i = at.index(bytes.len());
            bytes[i] = byte;
        }
        let corrupted = dir.join(format!("corrupted-{}.csv", std::thread::current().name().unwrap_or("t").replace("::", "-")));
        std::fs::write(&corrupted, &bytes).unwrap();
        match merge_shards(&[&corrupted, &part1]) {
            Ok(table) => {
                let expected = read_table(&whole).unwrap();
                let cells = |t: &telescopic::sweep::SweepTable| -> Vec<String> {
                    t.rows.iter().map(|(_, l)| l.rsplit_once(',').unwrap().0.to_string()).collect()
                };
                proptest::prop_assert_eq!(cells(&table), cells(&expected));
            }
            Err(e) => proptest::prop_assert!(!e.to_string().is_empty()),
        }
    }
}

#[test]
fn resumes_check_the_work_file_and_never_discard_it() {
    let dir = scratch("sweep-resume-check");
    let body = "set = [\"time.end=0.2\"]\n[grid]\n\"masses.load\" = [5.0, 10.0, 15.0, 20.0]\n";
    let path = sweep_file(&dir, "s.toml", "adams-clearance", body);
    let out = dir.join("r.csv");
    let partial = dir.join("r.csv.partial");
    let sweep = Sweep::load(&path).unwrap();
    run_sweep(&sweep, &options(&out, 1, Shard::whole()), &Silent).unwrap();
    let reference = std::fs::read_to_string(&out).unwrap();
    let lines: Vec<&str> = reference.lines().collect();
    let head = format!("{}\n{}\n", lines[0], lines[1]);
    let sweep_args = |resume: bool| {
        let mut args = vec![
            "sweep",
            path.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ];
        if resume {
            args.push("--resume");
        }
        args
    };
    std::fs::remove_file(&out).unwrap();
    // a garbage row, a row twice, an index beyond the sweep's runs: refused, file kept
    for (rows, needle) in [
        (format!("{}\ngarbage,,\n", lines[2]), "line 4"),
        (format!("{0}\n{0}\n", lines[2]), "run 0 is there twice"),
        (
            format!("{}\n", lines[2].replacen("0,", "50,", 1)),
            "index 50 is not a run",
        ),
    ] {
        std::fs::write(&partial, format!("{head}{rows}")).unwrap();
        common::fails_with(&sweep_args(true), &["r.csv.partial", needle]);
        assert_eq!(
            std::fs::read_to_string(&partial).unwrap(),
            format!("{head}{rows}")
        );
    }
    // finished rows without --resume: said, not discarded
    std::fs::write(&partial, format!("{head}{}\n", lines[2])).unwrap();
    common::fails_with(&sweep_args(false), &["holds 1 finished run(s)", "--resume"]);
    assert!(
        std::fs::read_to_string(&partial)
            .unwrap()
            .contains(lines[2])
    );
    // and resumed, they give the uninterrupted file
    succeeds(&sweep_args(true));
    assert_eq!(without_wall(&out), {
        std::fs::write(dir.join("ref.csv"), &reference).unwrap();
        without_wall(&dir.join("ref.csv"))
    });
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_second_sweep_on_the_same_output_refuses() {
    let dir = scratch("sweep-lock");
    let path = sweep_file(&dir, "s.toml", "adams-clearance", LONG);
    let out = dir.join("r.csv");
    let mut first = spawn_sweep(&path, &out, "1", Stdio::null());
    let partial = dir.join("r.csv.partial");
    let start = Instant::now();
    while std::fs::read_to_string(&partial).map_or(0, |t| t.lines().count()) < 3 {
        assert!(start.elapsed() < Duration::from_secs(60));
        std::thread::sleep(Duration::from_millis(5));
    }
    common::fails_with(
        &[
            "sweep",
            path.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ],
        &["another sweep is writing", "locked"],
    );
    common::fails_with(
        &[
            "sweep",
            path.to_str().unwrap(),
            "--resume",
            "--out",
            out.to_str().unwrap(),
        ],
        &["another sweep is writing"],
    );
    // SAFETY: kill with a valid pid and signal number has no memory-safety preconditions.
    unsafe { libc::kill(first.id() as i32, libc::SIGKILL) };
    first.wait().unwrap();
    // the first one's rows are whole and resumable
    succeeds(&[
        "sweep",
        path.to_str().unwrap(),
        "--resume",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(read_table(&out).unwrap().rows.len(), 60);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn jobs_are_bounded_and_signals_are_honoured_promptly() {
    let dir = scratch("sweep-signals");
    let path = sweep_file(&dir, "s.toml", "adams-clearance", LONG);
    let out = dir.join("r.csv");
    for jobs in ["10000", "257", "18446744073709551615"] {
        common::fails_with(
            &[
                "sweep",
                path.to_str().unwrap(),
                "--jobs",
                jobs,
                "--out",
                out.to_str().unwrap(),
            ],
            &["--jobs", "1 to 256"],
        );
    }
    // the most jobs allowed: the first signal is answered within a second (no new run
    // starts), the second ends the sweep within a second
    for sig in [libc::SIGTERM, libc::SIGINT] {
        let _ = std::fs::remove_file(dir.join("r.csv.partial"));
        let mut child = spawn_sweep(&path, &out, "256", Stdio::piped());
        // stderr line by line, as it comes
        let (lines, received) = std::sync::mpsc::channel::<String>();
        let stderr = child.stderr.take().unwrap();
        let reader = std::thread::spawn(move || {
            use std::io::BufRead;
            let mut all = String::new();
            for line in std::io::BufReader::new(stderr)
                .lines()
                .map_while(Result::ok)
            {
                all.push_str(&line);
                all.push('\n');
                let _ = lines.send(line);
            }
            all
        });
        // every line seen so far, for the failure message
        let seen = std::cell::RefCell::new(String::new());
        let wait_for = |needle: &str, limit: Duration, child: &mut std::process::Child| {
            let start = Instant::now();
            loop {
                let left = limit.checked_sub(start.elapsed()).unwrap_or_default();
                match received.recv_timeout(left) {
                    Ok(line) => {
                        seen.borrow_mut().push_str(&format!("{line}\n"));
                        if line.contains(needle) {
                            return;
                        }
                    }
                    Err(e) => panic!(
                        "no `{needle}` within {limit:?} ({e}; the sweep's state: {:?}); its \
                         stderr so far:\n{}",
                        child.try_wait(),
                        seen.borrow()
                    ),
                }
            }
        };
        wait_for("runs 0/60", Duration::from_secs(30), &mut child);
        // SAFETY: kill with a valid pid and signal number has no memory-safety preconditions.
        unsafe { libc::kill(child.id() as i32, sig) };
        wait_for("interrupt: stopping", Duration::from_secs(1), &mut child);
        let second = Instant::now();
        // SAFETY: as above.
        unsafe { libc::kill(child.id() as i32, sig) };
        let status = loop {
            if let Some(status) = child.try_wait().unwrap() {
                break status;
            }
            assert!(
                second.elapsed() < Duration::from_secs(1),
                "no exit within 1 s of the second signal"
            );
            std::thread::sleep(Duration::from_millis(5));
        };
        let err = reader.join().unwrap();
        // 130 whether the runs in progress ended first (the first signal's stop) or not
        assert_eq!(status.code(), Some(130), "{err}");
        // the interrupt says where the finished rows are, or that there are none
        assert!(
            err.contains("kept in") || err.contains("no partial output file"),
            "{err}"
        );
        if dir.join("r.csv.partial").exists() {
            assert!(err.contains("r.csv.partial"), "{err}");
        }
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn large_sweeps_validate_in_bounded_time_and_memory() {
    let dir = scratch("sweep-large");
    // 10^6 Latin samples: validated at the corners and an evenly spaced 10^4
    let body = "[latin]\nsamples = 1000000\nseed = 3\nranges = { \"contact.clearance\" = [0.001, 0.01], \"masses.load\" = [5.0, 20.0] }\n";
    let start = Instant::now();
    let sweep = Sweep::load(&sweep_file(&dir, "l.toml", "adams-clearance", body)).unwrap();
    assert_eq!(sweep.runs.len(), 1_000_000);
    assert!(
        start.elapsed() < Duration::from_secs(30),
        "{:?}",
        start.elapsed()
    );
    // a sample whose corner is invalid is named before any run
    let body = "[latin]\nsamples = 1000000\nseed = 3\nranges = { \"contact.clearance\" = [0.001, 10.0], \"masses.load\" = [5.0, 20.0] }\n";
    let err = Sweep::load(&sweep_file(&dir, "l2.toml", "adams-clearance", body))
        .unwrap_err()
        .to_string();
    assert!(err.contains("contact.clearance=10.0"), "{err}");
    // beyond the memory budget: refused before the runs are made, naming what to change
    let body = "[latin]\nsamples = 10000000\nseed = 3\nranges = { \"contact.clearance\" = [0.001, 0.01], \"masses.load\" = [5.0, 20.0], \"masses.vehicle\" = [5.0, 20.0], \"drive.force\" = [5.0, 20.0] }\n";
    let path = sweep_file(&dir, "l3.toml", "adams-clearance", body);
    let out = Command::new(env!("CARGO_BIN_EXE_telescopic"))
        .args([
            "sweep",
            path.to_str().unwrap(),
            "--out",
            dir.join("r.csv").to_str().unwrap(),
        ])
        .env("TELESCOPIC_MEMORY_BUDGET", "1G")
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(
        err.contains("[latin] samples") && err.contains("TELESCOPIC_MEMORY_BUDGET"),
        "{err}"
    );
    // runs whose trajectories exceed the budget are recorded as unaffordable, naming time.sample
    let body = "set = [\"time.sample=6.1e-7\"]\n[grid]\n\"masses.load\" = [5.0, 10.0]\n";
    let path = sweep_file(&dir, "m.toml", "adams-clearance", body);
    let out = Command::new(env!("CARGO_BIN_EXE_telescopic"))
        .args([
            "sweep",
            path.to_str().unwrap(),
            "--jobs",
            "2",
            "--out",
            dir.join("m.csv").to_str().unwrap(),
        ])
        .env("TELESCOPIC_MEMORY_BUDGET", "512M")
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let table = read_table(&dir.join("m.csv")).unwrap();
    assert_eq!(
        table.column("status").unwrap(),
        ["unaffordable", "unaffordable"]
    );
    assert!(table.column("error").unwrap()[0].contains("time.sample"));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn settings_combine_across_keys() {
    let dir = scratch("sweep-combine");
    let out = dir.join("r.csv");
    // a fixed-step method with its step, in [[runs]] and through `set`
    for body in [
        "set = [\"time.end=0.2\"]\n[[runs]]\nmethod = \"rk4\"\ndt = 5e-5\n[[runs]]\nmethod = \"dopri5\"\n",
        "set = [\"time.end=0.2\", \"dt=5e-5\"]\n[grid]\nmethod = [\"rk4\", \"verlet\"]\n",
    ] {
        let path = sweep_file(&dir, "s.toml", "adams-clearance", body);
        succeeds(&[
            "sweep",
            path.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ]);
        assert_eq!(
            read_table(&out).unwrap().column("status").unwrap(),
            ["ok", "ok"]
        );
    }
    // rk4 without a step anywhere is refused naming the run
    let path = sweep_file(
        &dir,
        "s.toml",
        "adams-clearance",
        "[[runs]]\nmethod = \"rk4\"\n",
    );
    common::fails_with(
        &[
            "sweep",
            path.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ],
        &["run 0", "dt"],
    );
    // a key both in [grid] and [[runs]]
    let path = sweep_file(
        &dir,
        "s.toml",
        "adams-clearance",
        "[grid]\n\"masses.load\" = [5.0]\n[[runs]]\n\"masses.load\" = 10.0\n",
    );
    common::fails_with(
        &[
            "sweep",
            path.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ],
        &["`masses.load` is also a [grid] key"],
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn coloring_by_many_values_is_linear_and_bounded() {
    // 200,000 rows with distinct colour values: grouped in one pass; a line chart refuses
    // more than 64 lines, a heat map takes them
    let columns = format!("index,k,c,{}", telescopic::sweep::METRIC_COLUMNS.join(","));
    let n = 200_000;
    let rows = (0..n)
        .map(|i| (i, format!("{i},{i},{i},0.1,0.1,1,2,,,3,0,4,0,0,ok,,0.001")))
        .collect();
    let table = telescopic::sweep::SweepTable {
        header: format!("# telescopic sweep 0.1.0; sweep 0; runs {n}; shard 0/1; file x"),
        columns,
        rows,
    };
    let start = Instant::now();
    let err = telescopic::sweep::chart(&table, "k", "tip_rel_max", Some("c"), false)
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("200000 distinct values") && err.contains("at most 64"),
        "{err}"
    );
    assert!(
        start.elapsed() < Duration::from_secs(10),
        "{:?}",
        start.elapsed()
    );
}
