//! Reuse of a run's error budget between runs (`telescopic::run::reuse`): a repeated run of
//! the same scene and options makes one run and states the budget its companion would give;
//! anything that changes the run's outputs makes it estimate afresh.

use std::path::{Path, PathBuf};
use std::sync::Mutex;
use telescopic::Scene;
use telescopic::report::Reporter;
use telescopic::run::reuse::{self, Record};
use telescopic::run::{
    NoPrediction, Simulation, SimulationOptions, SizePrediction, simulate_scene,
};

/// Counts the runs started and keeps the notes.
#[derive(Default)]
struct Counting {
    starts: Mutex<usize>,
    notes: Mutex<Vec<String>>,
}

impl Counting {
    /// Whether a note holds `needle`.
    fn noted(&self, needle: &str) -> bool {
        self.notes
            .lock()
            .unwrap()
            .iter()
            .any(|n| n.contains(needle))
    }
}

impl Reporter for Counting {
    fn start(&self, _what: &str) {
        *self.starts.lock().unwrap() += 1;
    }
    fn note(&self, line: &str) {
        self.notes.lock().unwrap().push(line.to_string());
    }
}

/// A directory of records of its own, emptied.
fn records(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("telescopic-reuse-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

fn scene(name: &str, sets: &[&str]) -> Scene {
    let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
    Scene::load(Path::new(&format!("scenes/{name}.toml")), &sets).unwrap()
}

/// Runs `scene` with the options a face gives (the scene's own accuracy), keeping records in
/// `dir`; the run and its reporter.
fn run(scene: &Scene, dir: &Path) -> (Simulation, Counting) {
    let options = SimulationOptions {
        reuse: Some(dir.to_path_buf()),
        ..SimulationOptions::default()
    }
    .for_scene(scene);
    let counting = Counting::default();
    let simulation = simulate_scene(scene, &options, &counting).unwrap();
    (simulation, counting)
}

#[test]
fn a_repeated_accuracy_run_reuses_its_pick_and_budget_in_one_run() {
    let dir = records("accuracy");
    let scene = scene("case-study-no-clearance", &["time.end=2"]);
    let (first, first_reporter) = run(&scene, &dir);
    let (second, second_reporter) = run(&scene, &dir);
    // the first searched (a size and its companion at least); the second made one run
    assert!(*first_reporter.starts.lock().unwrap() >= 2);
    assert_eq!(*second_reporter.starts.lock().unwrap(), 1);
    assert_eq!(first.trajectory.rows, second.trajectory.rows);
    assert_eq!((first.basis, &first.modes), (second.basis, &second.modes));
    assert_eq!(first.plan.reason, second.plan.reason);
    let (a, b) = (first.error.clone().unwrap(), second.error.clone().unwrap());
    assert_eq!(a.reused, None);
    assert_eq!(
        b.reused.as_deref(),
        Some(reuse::record_path(&dir, &identity(&scene)).as_path())
    );
    assert_eq!(
        a.clone(),
        telescopic::run::error_budget::ErrorBudget {
            reused: None,
            ..b.clone()
        }
    );
    assert!(second.summary().contains("error budget reused from"));
    assert!(second_reporter.noted("accuracy search: reused the pick"));
    std::fs::remove_dir_all(&dir).unwrap();
}

fn identity(scene: &Scene) -> String {
    let options = SimulationOptions::default().for_scene(scene);
    reuse::identity(scene, &options)
}

#[test]
fn a_record_whose_run_differs_is_replaced_by_a_fresh_estimate() {
    let dir = records("stale");
    let scene = scene("adams-clearance", &["time.end=0.5"]);
    let (first, _) = run(&scene, &dir);
    let path = reuse::record_path(&dir, &identity(&scene));
    let kept: Record = serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    assert_eq!(kept.pick, None);
    // a record of another run under this run's name: its outputs' digest differs
    let stale = Record {
        outputs: "0".repeat(64),
        budget: telescopic::run::error_budget::ErrorBudget {
            integration_m: Some(1.0),
            ..kept.budget.clone()
        },
        ..kept.clone()
    };
    std::fs::write(&path, serde_json::to_string(&stale).unwrap()).unwrap();
    let (again, reporter) = run(&scene, &dir);
    assert!(reporter.noted("outputs differ"));
    assert_eq!(again.error, first.error);
    let replaced: Record = serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    assert_eq!(replaced, kept);
    // a record of an accuracy search under a plain run's name does not fit: no panic, afresh
    let searched = Record {
        pick: Some(reuse::Pick {
            accuracy_m: 1e-3,
            estimated_m: Some(1e-4),
            size: "static:2".parse().unwrap(),
            prediction: SizePrediction::Skipped(NoPrediction::Clearance),
            confirmed: false,
            tried: Vec::new(),
            search_runs: 2,
            search_s: 0.1,
        }),
        ..kept.clone()
    };
    std::fs::write(&path, serde_json::to_string(&searched).unwrap()).unwrap();
    let (fitted, reporter) = run(&scene, &dir);
    assert!(reporter.noted("does not fit these options"));
    assert_eq!(fitted.error, first.error);
    // an unreadable record is noted and replaced the same way
    std::fs::write(&path, "{ not json").unwrap();
    let (third, reporter) = run(&scene, &dir);
    assert!(reporter.noted("unreadable record"));
    assert_eq!(third.error, first.error);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn another_scene_or_option_is_another_run() {
    let base = scene("adams-clearance", &[]);
    // loaded twice, the same scene is the same run (no hash-ordered map in its identity)
    assert_eq!(identity(&base), identity(&scene("adams-clearance", &[])));
    assert_ne!(
        identity(&base),
        identity(&scene("adams-clearance", &["contact.clearance=0.004"]))
    );
    let options = SimulationOptions::default();
    let tighter = SimulationOptions {
        rtol: Some(1e-8),
        ..SimulationOptions::default()
    };
    assert_ne!(
        reuse::identity(&base, &options),
        reuse::identity(&base, &tighter)
    );
}

#[test]
fn a_directory_that_cannot_hold_records_costs_a_note_not_the_run() {
    let dir = records("unwritable");
    std::fs::write(&dir, "a file, not a directory").unwrap();
    let scene = scene("adams-linear", &["time.end=0.3"]);
    let (simulation, reporter) = run(&scene, &dir);
    assert!(simulation.error.is_some_and(|e| e.truncation.is_some()));
    assert!(reporter.noted("not kept for reuse"));
    std::fs::remove_file(&dir).unwrap();
}
