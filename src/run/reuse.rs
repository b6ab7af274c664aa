//! Reuse of work between runs: a run's error budget, and its accuracy search's pick, kept on
//! disk by the run's identity, so that a repeated run of the same scene with the same options
//! pays for its own integration only.
//!
//! A record is named by the SHA-256 of everything a run's result depends on: telescopic's
//! version and the digest of the sources it was built from (`build.rs`), the scene after
//! overrides (every value, at full precision), the options that change a result, and the
//! generated model sets a run may use. It holds the budget, the pick
//! (when an accuracy search made one) and the SHA-256 of every output sample of the run the
//! budget belongs to. A repeated run integrates its scene (the picked size, for a search) and
//! compares its outputs with that digest: runs are deterministic, so equal outputs mean the
//! same run, and its companion would give the same budget. Outputs that differ by one bit (say,
//! another machine's arithmetic) make the record stale: the run estimates afresh and replaces it.
//!
//! Records are written to a temporary file and renamed, so a reader never sees a partial one;
//! two processes writing the same record write the same bytes. A record that cannot be read
//! or written costs a note and a fresh estimate, never a failed run.
//!
//! ```
//! use telescopic::run::{SimulationOptions, simulate_scene};
//! use telescopic::{Scene, Silent};
//!
//! let dir = std::env::temp_dir().join(format!("telescopic-reuse-doc-{}", std::process::id()));
//! let scene = Scene::load("scenes/adams-linear.toml".as_ref(), &["time.end=0.2".into()])?;
//! let options = SimulationOptions { reuse: Some(dir.clone()), ..SimulationOptions::default() };
//! let first = simulate_scene(&scene, &options, &Silent)?;
//! let again = simulate_scene(&scene, &options, &Silent)?;
//! let (first, again) = (first.error.unwrap(), again.error.unwrap());
//! assert!(first.reused.is_none() && again.reused.is_some());
//! assert_eq!(first.truncation, again.truncation);
//! std::fs::remove_dir_all(dir).unwrap();
//! # Ok::<(), telescopic::Error>(())
//! ```

use super::error_budget::ErrorBudget;
use super::method::MethodReason;
use super::options::SimulationOptions;
use super::predicted_size::SizePrediction;
use super::simulation::Simulation;
use super::sized::ModelSize;
use super::trajectory::Trajectory;
use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};
use std::path::{Path, PathBuf};
use telescopic_runtime::Scene;

/// The environment variable that names the directory of records (a path, or `off`).
pub const CACHE_DIR_VARIABLE: &str = "TELESCOPIC_CACHE_DIR";

/// The directory the faces keep records in by default: [`CACHE_DIR_VARIABLE`] when set
/// (`off` keeps none), else `$XDG_CACHE_HOME/telescopic/budgets`, else
/// `$HOME/.cache/telescopic/budgets`; `None` when none of them is set.
pub fn default_dir() -> Option<PathBuf> {
    let var = |name: &str| std::env::var_os(name).filter(|v| !v.is_empty());
    if let Some(dir) = var(CACHE_DIR_VARIABLE) {
        return (dir != "off").then(|| PathBuf::from(dir));
    }
    let base = var("XDG_CACHE_HOME")
        .map(PathBuf::from)
        .or_else(|| var("HOME").map(|home| Path::new(&home).join(".cache")))?;
    Some(base.join("telescopic").join("budgets"))
}

/// The pick of an accuracy search, as [`MethodReason::TotalAccuracy`] holds it (its
/// integration's own reason is the repeated run's).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Pick {
    /// The accuracy asked for (m).
    pub accuracy_m: f64,
    /// The estimated whole error (m); `None` when not a number.
    pub estimated_m: Option<f64>,
    /// The size picked.
    pub size: ModelSize,
    /// What the search predicted.
    pub prediction: SizePrediction,
    /// Whether the prediction was confirmed.
    pub confirmed: bool,
    /// The sizes tried, with their verdicts.
    pub tried: Vec<String>,
    /// The search's runs.
    pub search_runs: usize,
    /// The search's wall time (s).
    pub search_s: f64,
}

impl Pick {
    /// The pick `reason` holds, when it is an accuracy search's.
    pub fn of(reason: &MethodReason) -> Option<Pick> {
        let MethodReason::TotalAccuracy {
            accuracy_m,
            estimated_m,
            basis,
            modes,
            prediction,
            confirmed,
            tried,
            search_runs,
            search_s,
            ..
        } = reason
        else {
            return None;
        };
        Some(Pick {
            accuracy_m: *accuracy_m,
            estimated_m: estimated_m.is_finite().then_some(*estimated_m),
            size: ModelSize {
                basis: *basis,
                modes: *modes,
            },
            prediction: prediction.clone(),
            confirmed: *confirmed,
            tried: tried.clone(),
            search_runs: *search_runs,
            search_s: *search_s,
        })
    }

    /// The search's reason, with `integration` the run's own.
    pub fn reason(self, integration: MethodReason) -> MethodReason {
        MethodReason::TotalAccuracy {
            accuracy_m: self.accuracy_m,
            estimated_m: self.estimated_m.unwrap_or(f64::NAN),
            basis: self.size.basis,
            modes: self.size.modes,
            prediction: self.prediction,
            confirmed: self.confirmed,
            tried: self.tried,
            search_runs: self.search_runs,
            search_s: self.search_s,
            integration: Box::new(integration),
        }
    }
}

/// What a run keeps for the next run of its identity.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Record {
    /// telescopic's version that wrote it (for a reader; the identity holds it).
    pub version: String,
    /// [`outputs_digest`] of the run the budget belongs to.
    pub outputs: String,
    /// The budget, its `reused` unset.
    pub budget: ErrorBudget,
    /// The accuracy search's pick, when the run made one.
    pub pick: Option<Pick>,
}

impl Record {
    /// The record of a finished `simulation`: `None` when it has no budget to keep.
    pub fn of(simulation: &Simulation) -> Option<Record> {
        Some(Record {
            version: env!("CARGO_PKG_VERSION").to_string(),
            outputs: outputs_digest(&simulation.trajectory),
            budget: simulation.error.clone()?,
            pick: Pick::of(&simulation.plan.reason),
        })
    }
}

/// What a lookup found.
#[derive(Debug)]
pub enum Lookup {
    /// A record of this identity.
    Found(Box<Record>),
    /// None yet.
    Missing,
    /// A record that cannot be read, and why.
    Unreadable(String),
}

/// A run's identity: the record's file name (hex SHA-256, see the module documentation).
pub fn identity(scene: &Scene, options: &SimulationOptions) -> String {
    // every field named, so that an option added later cannot be left out of the identity
    let SimulationOptions {
        method,
        rtol,
        atol,
        dt,
        step_cap,
        long_steps,
        model,
        models,
        accuracy,
        stations,
        modes_as_given,
        moment_tolerance,
        statistics_tolerance,
        coordinates,
        steps_across_samples,
        // no record is read or kept without an estimate; the memory budget refuses a run
        // or not, and the records' directory is where the identity is looked up
        error_estimate: _,
        memory_budget: _,
        reuse: _,
    } = options;
    let text = format!(
        "telescopic {} {}\nscene {scene:?}\nmethod {method:?} rtol {rtol:?} atol {atol:?} \
         dt {dt:?} step-cap {step_cap} long-steps {long_steps} model {model:?} sets {:?} \
         accuracy {accuracy:?} stations {stations:?} modes-as-given {modes_as_given} \
         moment-tolerance {moment_tolerance:?} statistics-tolerance {statistics_tolerance:?} \
         coordinates {coordinates} across-samples {steps_across_samples}",
        env!("CARGO_PKG_VERSION"),
        env!("TELESCOPIC_SOURCE_DIGEST"),
        models.set_names(),
    );
    format!("{:x}", Sha256::digest(text.as_bytes()))
}

/// The SHA-256 (hex) of a run's outputs: its columns' names and every sample's bits.
pub fn outputs_digest(trajectory: &Trajectory) -> String {
    let mut hasher = Sha256::new();
    for name in trajectory.names() {
        hasher.update(name.as_bytes());
        hasher.update([0]);
    }
    for row in &trajectory.rows {
        hasher.update((row.len() as u64).to_le_bytes());
        for value in row {
            hasher.update(value.to_bits().to_le_bytes());
        }
    }
    format!("{:x}", hasher.finalize())
}

/// The record of `identity` in `dir`.
pub fn load(dir: &Path, identity: &str) -> Lookup {
    let path = record_path(dir, identity);
    let text = match std::fs::read_to_string(&path) {
        Ok(text) => text,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Lookup::Missing,
        Err(e) => return Lookup::Unreadable(format!("{}: {e}", path.display())),
    };
    // the identity names the version and the sources: a record under it is theirs
    match serde_json::from_str::<Record>(&text) {
        Ok(record) => Lookup::Found(Box::new(record)),
        Err(e) => Lookup::Unreadable(format!("{}: {e}", path.display())),
    }
}

/// Keeps `record` as `identity` in `dir` (created when missing): written whole to a
/// temporary file, then renamed.
///
/// # Errors
/// The file system's error, with the path.
pub fn store(dir: &Path, identity: &str, record: &Record) -> Result<PathBuf, String> {
    let path = record_path(dir, identity);
    let text = serde_json::to_string(record).map_err(|e| e.to_string())?;
    // unique per process and per write, so that two writers never share a temporary file
    static WRITES: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);
    let write = WRITES.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let temporary = dir.join(format!(".{identity}.{}.{write}.tmp", std::process::id()));
    std::fs::create_dir_all(dir)
        .and_then(|()| std::fs::write(&temporary, text))
        .and_then(|()| std::fs::rename(&temporary, &path))
        .map_err(|e| {
            let _ = std::fs::remove_file(&temporary);
            format!("{}: {e}", path.display())
        })?;
    Ok(path)
}

/// Where the record of `identity` lives in `dir`.
pub fn record_path(dir: &Path, identity: &str) -> PathBuf {
    dir.join(format!("{identity}.json"))
}
