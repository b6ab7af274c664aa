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
    /// telescopic's version that wrote it.
    pub version: String,
    /// [`outputs_digest`] of the run the budget belongs to.
    pub outputs: String,
    /// The budget, its `reused` unset.
    pub budget: ErrorBudget,
    /// The accuracy search's pick, when the run made one.
    pub pick: Option<Pick>,
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
    let o = options;
    let text = format!(
        "telescopic {} {}\nscene {scene:?}\nmethod {:?} rtol {:?} atol {:?} dt {:?} step-cap {} \
         long-steps {} model {:?} sets {:?} accuracy {:?} stations {:?} modes-as-given {} \
         moment-tolerance {:?} statistics-tolerance {:?} coordinates {} across-samples {}",
        env!("CARGO_PKG_VERSION"),
        env!("TELESCOPIC_SOURCE_DIGEST"),
        o.method,
        o.rtol,
        o.atol,
        o.dt,
        o.step_cap,
        o.long_steps,
        o.model,
        o.models.set_names(),
        o.accuracy,
        o.stations,
        o.modes_as_given,
        o.moment_tolerance,
        o.statistics_tolerance,
        o.coordinates,
        o.steps_across_samples,
    );
    hex(&Sha256::digest(text.as_bytes()))
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
    hex(&hasher.finalize())
}

/// The record of `identity` in `dir`.
pub fn load(dir: &Path, identity: &str) -> Lookup {
    let path = record_path(dir, identity);
    let text = match std::fs::read_to_string(&path) {
        Ok(text) => text,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Lookup::Missing,
        Err(e) => return Lookup::Unreadable(format!("{}: {e}", path.display())),
    };
    match serde_json::from_str::<Record>(&text) {
        Ok(record) if record.version == env!("CARGO_PKG_VERSION") => {
            Lookup::Found(Box::new(record))
        }
        Ok(record) => Lookup::Unreadable(format!(
            "{}: written by telescopic {}",
            path.display(),
            record.version
        )),
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

/// Lower-case hex of `bytes`.
fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}
