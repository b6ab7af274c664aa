//! Ctrl-C (SIGINT) and SIGTERM never leave a partial output file: not at the final path, and
//! not as the temporary file beside it.

mod common;

use common::scratch;

use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

/// A long run: case-study with 1.6 million samples (a CSV of about 200 MB).
fn long_run(csv: &Path) -> Child {
    Command::new(env!("CARGO_BIN_EXE_telescopic"))
        .args([
            "simulate",
            "scenes/case-study.toml",
            "--set",
            "time.sample=1e-5",
            "--out",
        ])
        .arg(csv)
        .current_dir(common::ROOT)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the binary runs")
}

fn signal(child: &Child, sig: i32) {
    // SAFETY: kill with a valid pid and signal number has no memory-safety preconditions.
    assert_eq!(unsafe { libc::kill(child.id() as i32, sig) }, 0);
}

/// Files in `dir` (names).
fn files(dir: &Path) -> Vec<String> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect()
}

#[test]
fn an_interrupted_csv_write_leaves_no_file() {
    let dir = scratch("interrupt-write");
    let csv = dir.join("run.csv");
    let mut child = long_run(&csv);
    let tmp = dir.join(format!(".run.csv.tmp-{}", child.id()));
    // wait until the CSV is being written, then interrupt
    let start = Instant::now();
    while !tmp.exists() {
        assert!(
            child.try_wait().unwrap().is_none(),
            "the run ended before its CSV was written"
        );
        assert!(
            start.elapsed() < Duration::from_secs(120),
            "no CSV write started"
        );
        std::thread::sleep(Duration::from_millis(1));
    }
    std::thread::sleep(Duration::from_millis(20));
    signal(&child, libc::SIGINT);
    let out = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(130), "{err}");
    assert!(err.contains("interrupted"), "{err}");
    assert!(files(&dir).is_empty(), "left behind: {:?}", files(&dir));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_terminated_run_leaves_no_file_and_keeps_an_old_one() {
    let dir = scratch("interrupt-run");
    let csv = dir.join("run.csv");
    std::fs::write(&csv, "the previous run\n").unwrap();
    let child = long_run(&csv);
    std::thread::sleep(Duration::from_millis(300));
    signal(&child, libc::SIGTERM);
    let out = child.wait_with_output().unwrap();
    assert_eq!(out.status.code(), Some(130));
    assert_eq!(files(&dir), vec!["run.csv".to_string()]);
    assert_eq!(std::fs::read_to_string(&csv).unwrap(), "the previous run\n");
    std::fs::remove_dir_all(&dir).unwrap();
}
