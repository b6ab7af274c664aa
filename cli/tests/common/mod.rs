//! Helpers shared by the end-to-end tests of the binary.
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// The workspace root: the binary runs there, so scene paths read `scenes/...`.
pub const ROOT: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/..");

/// Tests name scenes and docs by paths from the workspace root (`scenes/adams-linear.toml`),
/// as a user at the root does; cargo runs a package's tests in the package's directory
/// (`cli/`), so every test binary moves to the root before `main`: a constructor in
/// `.init_array`, the same hand-written mechanism as the binary's closed-stdout check.
extern "C" fn move_to_workspace_root() {
    std::env::set_current_dir(ROOT).expect("the workspace root exists");
}

#[used]
#[unsafe(link_section = ".init_array")]
static MOVE_TO_WORKSPACE_ROOT: extern "C" fn() = move_to_workspace_root;

/// The binary's runs keep no error budgets for reuse between tests (each test reads its own
/// run's estimate, whatever ran before); the tests of reuse name a directory of their own.
extern "C" fn keep_no_budget_records() {
    // SAFETY: this runs in `.init_array`, before `main`, while no other thread exists
    unsafe { std::env::set_var("TELESCOPIC_CACHE_DIR", "off") };
}

#[used]
#[unsafe(link_section = ".init_array")]
static KEEP_NO_BUDGET_RECORDS: extern "C" fn() = keep_no_budget_records;

/// Runs the binary from the workspace root.
pub fn telescopic(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_telescopic"))
        .args(args)
        .current_dir(ROOT)
        .output()
        .expect("the binary runs")
}

/// Runs the binary and checks it succeeded (the failure shows its stderr).
pub fn succeeds(args: &[&str]) -> Output {
    let out = telescopic(args);
    assert!(
        out.status.success(),
        "{args:?} failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

/// The command failed cleanly: non-zero exit, an error line naming `needles`, no panic.
pub fn fails_with(args: &[&str], needles: &[&str]) {
    failed_cleanly(args, &telescopic(args), needles);
}

/// `out` (of a run with `args`) is a clean failure: non-zero exit, nothing on stdout, no
/// panic, stderr naming every needle.
pub fn failed_cleanly(args: &[&str], out: &Output, needles: &[&str]) {
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "{args:?} should fail");
    assert!(!err.contains("panicked"), "{args:?} panicked: {err}");
    assert!(
        out.stdout.is_empty(),
        "{args:?} printed to stdout on failure"
    );
    for n in needles {
        assert!(err.contains(n), "{args:?}: stderr lacks `{n}`:\n{err}");
    }
}

/// A fresh scratch directory `telescopic-NAME-PID` in the temporary directory; a name
/// taken twice in one test binary panics (two tests running at once would delete each
/// other's files).
pub fn scratch(name: &str) -> PathBuf {
    static TAKEN: std::sync::Mutex<Vec<String>> = std::sync::Mutex::new(Vec::new());
    let mut taken = TAKEN.lock().unwrap_or_else(|e| e.into_inner());
    assert!(
        !taken.iter().any(|t| t == name),
        "scratch directory `{name}` is taken by another test of this binary"
    );
    taken.push(name.to_string());
    drop(taken);
    let dir = std::env::temp_dir().join(format!("telescopic-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A sweep result file's column line and rows with the `wall_s` cell (the last) cut off:
/// what must not depend on how the sweep was run.
pub fn without_wall(path: &Path) -> (String, Vec<String>) {
    let table = telescopic::sweep::read_table(path).unwrap();
    let rows = table
        .rows
        .iter()
        .map(|(_, l)| l.rsplit_once(',').unwrap().0.to_string())
        .collect();
    (table.columns, rows)
}

/// A run's CSV as `simulate` writes it: the header (`t` first) and the rows, `#` lines left
/// out.
pub struct Csv {
    /// Column names, `t` first: a name's position is its index in a row.
    pub names: Vec<String>,
    /// The samples.
    pub rows: Vec<Vec<f64>>,
}

impl Csv {
    /// Reads the CSV at `path`.
    pub fn read(path: &Path) -> Csv {
        let text = std::fs::read_to_string(path).unwrap();
        let mut lines = text.lines().filter(|l| !l.starts_with('#'));
        let names = lines.next().unwrap().split(',').map(String::from).collect();
        let rows = lines
            .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
            .collect();
        Csv { names, rows }
    }

    /// The index of column `name` in a row.
    pub fn column(&self, name: &str) -> usize {
        self.names.iter().position(|n| n == name).unwrap()
    }

    /// The value of `name` in the row at time `t` (s).
    pub fn at(&self, name: &str, t: f64) -> f64 {
        let col = self.column(name);
        let row = self
            .rows
            .iter()
            .min_by(|a, b| (a[0] - t).abs().total_cmp(&(b[0] - t).abs()))
            .unwrap();
        assert!((row[0] - t).abs() < 1e-9, "no sample at {t}");
        row[col]
    }
}
