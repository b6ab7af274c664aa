//! The sweep file: a base scene, overrides for every run, and the runs: a grid (Cartesian
//! product), an explicit list, and a Latin-hypercube sample of ranges from a seed. Validated
//! as strictly as a scene, every run's scene included, before any run starts.

use crate::run::{MethodChoice, SimulationOptions, plan};
use crate::{Error, Result};
use rand::Rng;
use rand::SeedableRng;
use rand::seq::SliceRandom;
use rayon::prelude::*;
use serde::Deserialize;
use sha2::{Digest, Sha256};
use std::path::{Path, PathBuf};
use telescopic_runtime::Scene;
use telescopic_runtime::input::{MAX_TEXT_INPUT_BYTES, read_text};
use telescopic_runtime::scene::{SceneEdit, value_text};

/// Most runs of one sweep.
pub const MAX_RUNS: usize = 10_000_000;

/// Most runs checked as combinations before a sweep starts (all of a smaller sweep).
pub const VALIDATED_RUNS: usize = 10_000;

/// Most sampled keys whose range corners are checked (2^10 corners).
const MAX_CORNER_KEYS: usize = 10;

/// Keys that set the run rather than the scene.
pub const RUN_KEYS: [&str; 4] = ["method", "rtol", "atol", "dt"];

/// `[latin]`: a Latin-hypercube sample.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
struct LatinSpec {
    /// Number of samples.
    samples: usize,
    /// Seed of the generator (ChaCha8), for a reproducible sample.
    seed: u64,
    /// `KEY = [low, high]` for every sampled key.
    ranges: toml::Table,
}

/// A sweep file as written.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
struct SweepSpec {
    /// The base scene, relative to the sweep file.
    scene: String,
    /// Overrides of every run, `KEY=VALUE` as for `--set`.
    #[serde(default)]
    set: Vec<String>,
    /// `KEY = [values]`: the Cartesian product of every key's values.
    #[serde(default)]
    grid: toml::Table,
    /// Explicit runs: one table of `KEY = value` each.
    #[serde(default)]
    runs: Vec<toml::Table>,
    /// A Latin-hypercube sample.
    #[serde(default)]
    latin: Option<LatinSpec>,
}

/// One run: its index and its values, one per column key (`None`: the run leaves it at the
/// base).
#[derive(Debug, Clone, PartialEq)]
pub struct Run {
    /// Position in the sweep (0-based; rows are written in this order).
    pub index: usize,
    /// One value per [`Sweep::keys`] entry.
    pub values: Vec<Option<toml::Value>>,
}

/// A validated sweep.
#[derive(Debug, Clone)]
pub struct Sweep {
    /// The sweep file.
    pub path: PathBuf,
    /// The base scene's file.
    pub scene_path: PathBuf,
    /// The base scene, parsed, before any override.
    base: toml::Table,
    /// Edits of every run (`set`): scene values and run settings (`dt=5e-5`) alike.
    pub set: Vec<SceneEdit>,
    /// The column keys: grid keys (sorted), then those of the explicit runs, then the
    /// sampled ones.
    pub keys: Vec<String>,
    /// Every run, by index.
    pub runs: Vec<Run>,
    /// A hash of the sweep file and the base scene (16 hex digits): shards of one sweep
    /// carry the same.
    pub hash: String,
    /// The sampled keys: `(position in keys, low, high)`.
    sampled: Vec<(usize, f64, f64)>,
}

fn invalid(path: &Path, what: String) -> Error {
    Error::input("sweep file", format!("{}: {what}", path.display()))
}

impl Sweep {
    /// Reads and validates a sweep file: its own rules, then every run's scene and settings;
    /// its runs must fit the default memory budget.
    ///
    /// # Errors
    /// [`Error::Input`] naming the file, the key and the rule, or the run and its problem;
    /// [`Error::Scene`] for an unreadable or invalid base scene.
    pub fn load(path: &Path) -> Result<Self> {
        Self::load_within(path, crate::run::memory::DEFAULT_MEMORY_BUDGET)
    }

    /// [`Sweep::load`] with the runs' list within `memory_budget` (bytes).
    ///
    /// # Errors
    /// As [`Sweep::load`].
    pub fn load_within(path: &Path, memory_budget: u64) -> Result<Self> {
        let text = read_text(path, MAX_TEXT_INPUT_BYTES)
            .map_err(|e| invalid(path, format!("cannot be read: {e}")))?;
        let table: toml::Table = text
            .parse()
            .map_err(|e| invalid(path, format!("not valid TOML: {e}")))?;
        Self::from_table(table, path, memory_budget)
    }

    /// A sweep from its keys as a parsed table (what a sweep file holds; Python's dict),
    /// validated as [`Sweep::load`] does. `path` names it in messages, and a relative
    /// `scene` is taken from its directory.
    ///
    /// # Errors
    /// As [`Sweep::load`].
    pub fn from_table(table: toml::Table, path: &Path, memory_budget: u64) -> Result<Self> {
        let hash_text = toml::to_string(&table).unwrap_or_default();
        let spec: SweepSpec = serde_path_to_error::deserialize(toml::Value::Table(table))
            .map_err(|e| invalid(path, format!("field `{}`: {}", e.path(), e.inner())))?;
        check_memory(path, &spec, memory_budget)?;
        let set = spec
            .set
            .iter()
            .map(|entry| SceneEdit::parse(entry).map_err(|e| Error::input("`set`", e.to_string())))
            .collect::<Result<Vec<_>>>()?;
        let (scene_path, scene_text, base) = read_base_scene(path, &spec)?;
        let mut keys: Vec<String> = Vec::new();
        let mut runs: Vec<Run> = Vec::new();
        grid_runs(path, &spec, &mut keys, &mut runs)?;
        explicit_runs(path, &spec, &mut keys, &mut runs)?;
        let sampled = match &spec.latin {
            Some(latin) => latin_runs(path, latin, &mut keys, &mut runs)?,
            None => Vec::new(),
        };
        // explicit runs and grid runs share the column list: pad earlier runs
        for run in &mut runs {
            run.values.resize(keys.len(), None);
        }
        check_run_count(path, runs.len())?;
        let mut hasher = Sha256::new();
        hasher.update(hash_text.as_bytes());
        hasher.update([0u8]);
        hasher.update(scene_text.as_bytes());
        let digest = hasher.finalize();
        let hash: String = digest[..8].iter().map(|b| format!("{b:02x}")).collect();
        let sweep = Sweep {
            path: path.to_owned(),
            scene_path,
            base,
            set,
            keys,
            runs,
            hash,
            sampled,
        };
        sweep.validate()?;
        Ok(sweep)
    }

    /// The scene of a run, and its simulation options.
    ///
    /// # Errors
    /// [`Error::Scene`] or [`Error::Input`] for the run's values.
    pub fn scene_of(&self, run: &Run) -> Result<(Scene, SimulationOptions)> {
        let mut edits = Vec::with_capacity(self.set.len() + self.keys.len());
        let mut options = SimulationOptions::default();
        // `set` holds scene edits and run settings (`dt=5e-5`) alike
        let mut settings: Vec<(String, toml::Value)> = Vec::new();
        for edit in &self.set {
            if RUN_KEYS.contains(&edit.key.as_str()) {
                settings.push((edit.key.clone(), edit.value.clone()));
            } else {
                edits.push(edit.clone());
            }
        }
        let run_values = self
            .keys
            .iter()
            .zip(&run.values)
            .filter_map(|(k, v)| v.as_ref().map(|v| (k.clone(), v.clone())));
        for (key, value) in settings.into_iter().chain(run_values) {
            let (key, value) = (&key, &value);
            let option = |rule: String| Error::input(format!("`{key}`"), rule);
            match key.as_str() {
                "method" => {
                    let name = value
                        .as_str()
                        .ok_or_else(|| option("a method name is a string".into()))?;
                    options.method = name.parse::<MethodChoice>().map_err(option)?;
                }
                "rtol" | "atol" | "dt" => {
                    let v = number(value).ok_or_else(|| option("must be a number".into()))?;
                    match key.as_str() {
                        "rtol" => options.rtol = Some(v),
                        "atol" => options.atol = Some(v),
                        _ => options.dt = Some(v),
                    }
                }
                _ => edits.push(SceneEdit::new(key.as_str(), value.clone())),
            }
        }
        let scene = Scene::from_table_edited(self.base.clone(), &self.scene_path, &edits)?;
        Ok((scene, options))
    }

    /// Checks the runs' scenes and settings before any run: first each key with each of its
    /// values alone (so a misspelt key or a bad value is named once; a sampled key at both
    /// ends of its range), then every run's combination, all of them up to
    /// [`VALIDATED_RUNS`]; of a larger sweep an evenly spaced [`VALIDATED_RUNS`] and the
    /// corners of its sampled ranges (the rest are checked as they run: an invalid one is
    /// recorded with status `invalid`).
    fn validate(&self) -> Result<()> {
        let mut problems: Vec<(usize, String)> = self
            .alone_runs()
            .par_iter()
            .filter_map(|run| {
                // a run setting alone is checked for its form only (a fixed-step method
                // alone lacks its dt): its combination is checked with its run's
                let checked = if RUN_KEYS.contains(&self.keys[run.index].as_str()) {
                    self.scene_of(run).map(|_| ())
                } else {
                    self.check(run)
                };
                checked.err().map(|e| {
                    (
                        run.index,
                        format!("{}: {}", self.describe(run), indented(&e)),
                    )
                })
            })
            .collect();
        // one problem per key is enough to name it
        problems.dedup_by_key(|(k, _)| *k);
        if !problems.is_empty() {
            return Err(invalid(
                &self.path,
                format!(
                    "{} of {} keys have a value the base scene does not take:\n{}",
                    problems.len(),
                    self.keys.len(),
                    problems
                        .iter()
                        .map(|(_, p)| format!("  - {p}"))
                        .collect::<Vec<_>>()
                        .join("\n")
                ),
            ));
        }
        let checked: Vec<Run> = self.runs_to_check();
        let problems: Vec<String> = checked
            .par_iter()
            .filter_map(|run| {
                self.check(run).err().map(|e| {
                    let which = if run.index == usize::MAX {
                        "the corner".to_string()
                    } else {
                        format!("run {}", run.index)
                    };
                    format!("{which} ({}): {}", self.describe(run), indented(&e))
                })
            })
            .collect();
        if problems.is_empty() {
            return Ok(());
        }
        let shown: Vec<&String> = problems.iter().take(5).collect();
        Err(invalid(
            &self.path,
            format!(
                "{} of {} runs{} are invalid, e.g.\n{}",
                problems.len(),
                checked.len(),
                if checked.len() < self.runs.len() {
                    format!(" checked (of {})", self.runs.len())
                } else {
                    String::new()
                },
                shown
                    .iter()
                    .map(|p| format!("  - {p}"))
                    .collect::<Vec<_>>()
                    .join("\n")
            ),
        ))
    }

    /// A run's scene and settings, checked.
    fn check(&self, run: &Run) -> Result<()> {
        self.scene_of(run)
            .and_then(|(scene, options)| plan(&scene, &options).map(|_| ()))
    }

    /// One run per key and value, the key set alone (`index` is the key's position); a
    /// sampled key at both ends of its range, other keys at up to [`VALIDATED_RUNS`] of
    /// their distinct values.
    fn alone_runs(&self) -> Vec<Run> {
        let mut alone: Vec<Run> = Vec::new();
        let single = |k: usize, value: toml::Value| {
            let mut values = vec![None; self.keys.len()];
            values[k] = Some(value);
            Run { index: k, values }
        };
        for k in 0..self.keys.len() {
            if let Some(&(_, lo, hi)) = self.sampled.iter().find(|(key, ..)| *key == k) {
                alone.push(single(k, toml::Value::Float(lo)));
                alone.push(single(k, toml::Value::Float(hi)));
                continue;
            }
            // by text (a TOML value has no hash): linear in the runs
            let mut seen = std::collections::HashSet::new();
            let step = (self.runs.len() / VALIDATED_RUNS).max(1);
            for value in self
                .runs
                .iter()
                .step_by(step)
                .filter_map(|r| r.values[k].as_ref())
            {
                if seen.insert(value_text(value)) {
                    alone.push(single(k, value.clone()));
                }
            }
        }
        alone
    }

    /// The runs checked as combinations: all, or for a large sweep an evenly spaced
    /// [`VALIDATED_RUNS`] of them and the corners of the sampled ranges (index `usize::MAX`).
    fn runs_to_check(&self) -> Vec<Run> {
        if self.runs.len() <= VALIDATED_RUNS {
            return self.runs.clone();
        }
        let step = self.runs.len().div_ceil(VALIDATED_RUNS);
        let mut checked: Vec<Run> = self.runs.iter().step_by(step).cloned().collect();
        let sampled = &self.sampled[..self.sampled.len().min(MAX_CORNER_KEYS)];
        for corner in 0..1usize << sampled.len() {
            let mut values = vec![None; self.keys.len()];
            for (bit, &(k, lo, hi)) in sampled.iter().enumerate() {
                let end = if corner >> bit & 1 == 0 { lo } else { hi };
                values[k] = Some(toml::Value::Float(end));
            }
            checked.push(Run {
                index: usize::MAX,
                values,
            });
        }
        checked
    }

    /// The run's values as `KEY=VALUE` text.
    pub fn describe(&self, run: &Run) -> String {
        let parts: Vec<String> = self
            .keys
            .iter()
            .zip(&run.values)
            .filter_map(|(k, v)| {
                v.as_ref()
                    .map(|v| SceneEdit::new(k.as_str(), v.clone()).to_string())
            })
            .collect();
        if parts.is_empty() {
            "the base scene".into()
        } else {
            parts.join(", ")
        }
    }
}

/// An error's text with its later lines indented under a list item.
fn indented(e: &Error) -> String {
    e.to_string().trim_end().replace('\n', "\n    ")
}

/// A TOML number as `f64`.
fn number(v: &toml::Value) -> Option<f64> {
    match v {
        toml::Value::Float(f) => Some(*f),
        toml::Value::Integer(i) => Some(*i as f64),
        _ => None,
    }
}

/// Bytes one run takes in memory before it is made: its index and values (measured with
/// 10^6 Latin samples of two keys).
const BYTES_PER_RUN: u64 = 64;

/// Bytes one value of a run takes.
const BYTES_PER_VALUE: u64 = 48;

/// Refuses, before any run is generated, a sweep whose runs would not fit the memory budget.
fn check_memory(path: &Path, spec: &SweepSpec, budget: u64) -> Result<()> {
    let grid = spec
        .grid
        .values()
        .map(|v| v.as_array().map_or(1, Vec::len) as u64)
        .try_fold(1u64, |n, len| n.checked_mul(len.max(1)))
        .unwrap_or(u64::MAX);
    let grid = if spec.grid.is_empty() { 0 } else { grid };
    let latin = spec.latin.as_ref().map_or(0, |l| l.samples as u64);
    let runs = grid
        .saturating_add(spec.runs.len() as u64)
        .saturating_add(latin);
    let keys = spec.grid.len()
        + spec.runs.iter().map(toml::Table::len).sum::<usize>()
        + spec.latin.as_ref().map_or(0, |l| l.ranges.len());
    let bytes = runs.saturating_mul(BYTES_PER_RUN + BYTES_PER_VALUE * keys as u64);
    crate::run::memory::check(
        bytes,
        budget,
        (None, format!("sweep file {}", path.display())),
        format!("{runs} runs of {keys} keys"),
        "[latin] samples or the [grid] (fewer runs), or split the sweep",
    )
}

/// Refuses a sweep without runs or with more than [`MAX_RUNS`].
fn check_run_count(path: &Path, runs: usize) -> Result<()> {
    if runs == 0 {
        return Err(invalid(
            path,
            "no runs: give [grid], [[runs]] or [latin]".into(),
        ));
    }
    if runs > MAX_RUNS {
        return Err(invalid(path, format!("{runs} runs, more than {MAX_RUNS}")));
    }
    Ok(())
}

/// The base scene named by the sweep file: its path, text and TOML table.
fn read_base_scene(path: &Path, spec: &SweepSpec) -> Result<(PathBuf, String, toml::Table)> {
    let scene_path = path.parent().unwrap_or(Path::new(".")).join(&spec.scene);
    let scene_text = read_text(&scene_path, MAX_TEXT_INPUT_BYTES).map_err(|e| {
        invalid(
            path,
            format!(
                "`scene` = {:?}: cannot read {}: {e}",
                spec.scene,
                scene_path.display()
            ),
        )
    })?;
    let base: toml::Table = scene_text.parse().map_err(|e: toml::de::Error| {
        invalid(
            path,
            format!("the scene {} is not valid TOML: {e}", scene_path.display()),
        )
    })?;
    Ok((scene_path, scene_text, base))
}

/// The runs of `[grid]`: keys in sorted order, the last varying fastest.
fn grid_runs(
    path: &Path,
    spec: &SweepSpec,
    keys: &mut Vec<String>,
    runs: &mut Vec<Run>,
) -> Result<()> {
    // the grid: keys in sorted order, the last varying fastest
    let mut axes: Vec<(String, Vec<toml::Value>)> = Vec::new();
    for (key, values) in &spec.grid {
        let list = values
            .as_array()
            .ok_or_else(|| invalid(path, format!("[grid] `{key}`: must be a list of values")))?;
        if list.is_empty() {
            return Err(invalid(path, format!("[grid] `{key}`: the list is empty")));
        }
        axes.push((key.clone(), list.clone()));
    }
    let grid_runs = axes
        .iter()
        .try_fold(1usize, |n, (_, v)| n.checked_mul(v.len()))
        .filter(|&n| n <= MAX_RUNS)
        .ok_or_else(|| invalid(path, format!("[grid] makes more than {MAX_RUNS} runs")))?;
    keys.extend(axes.iter().map(|(k, _)| k.clone()));
    if !axes.is_empty() {
        for i in 0..grid_runs {
            let mut rest = i;
            let mut values = vec![None; axes.len()];
            for (a, (_, list)) in axes.iter().enumerate().rev() {
                values[a] = Some(list[rest % list.len()].clone());
                rest /= list.len();
            }
            runs.push(Run {
                index: runs.len(),
                values,
            });
        }
    }
    Ok(())
}

/// The `[[runs]]` entries, each setting some of the keys.
fn explicit_runs(
    path: &Path,
    spec: &SweepSpec,
    keys: &mut Vec<String>,
    runs: &mut Vec<Run>,
) -> Result<()> {
    for (r, table) in spec.runs.iter().enumerate() {
        for key in table.keys() {
            if spec.grid.contains_key(key) {
                return Err(invalid(
                    path,
                    format!(
                        "[[runs]] entry {}: `{key}` is also a [grid] key; a key is varied in one \
                         place only",
                        r + 1
                    ),
                ));
            }
            if !keys.contains(key) {
                keys.push(key.clone());
            }
        }
    }
    for (r, table) in spec.runs.iter().enumerate() {
        if table.is_empty() {
            return Err(invalid(
                path,
                format!("[[runs]] entry {}: sets nothing", r + 1),
            ));
        }
        let values = keys.iter().map(|k| table.get(k).cloned()).collect();
        runs.push(Run {
            index: runs.len(),
            values,
        });
    }
    Ok(())
}

/// The `[latin]` samples: every range cut into `samples` strata, one sample per stratum,
/// strata paired by a random permutation per key.
fn latin_runs(
    path: &Path,
    latin: &LatinSpec,
    keys: &mut Vec<String>,
    runs: &mut Vec<Run>,
) -> Result<Vec<(usize, f64, f64)>> {
    if !(1..=MAX_RUNS).contains(&latin.samples) {
        return Err(invalid(
            path,
            format!(
                "[latin] `samples` must be 1 to {MAX_RUNS} (got {})",
                latin.samples
            ),
        ));
    }
    if latin.ranges.is_empty() {
        return Err(invalid(path, "[latin] `ranges` is empty".into()));
    }
    let first = keys.len();
    let mut sampled = Vec::new();
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(latin.seed);
    let mut columns: Vec<Vec<f64>> = Vec::new();
    for (key, range) in &latin.ranges {
        let bounds: Option<(f64, f64)> = range.as_array().and_then(|a| match a.as_slice() {
            [lo, hi] => Some((number(lo)?, number(hi)?)),
            _ => None,
        });
        let Some((lo, hi)) = bounds.filter(|(lo, hi)| lo.is_finite() && hi.is_finite() && lo < hi)
        else {
            return Err(invalid(
                path,
                format!("[latin.ranges] `{key}`: must be [low, high] with low < high"),
            ));
        };
        if keys.contains(key) {
            return Err(invalid(
                path,
                format!("[latin.ranges] `{key}`: already varied elsewhere"),
            ));
        }
        sampled.push((keys.len(), lo, hi));
        keys.push(key.clone());
        let n = latin.samples;
        let mut strata: Vec<usize> = (0..n).collect();
        strata.shuffle(&mut rng);
        columns.push(
            strata
                .iter()
                .map(|&s| lo + (hi - lo) * (s as f64 + rng.random::<f64>()) / n as f64)
                .collect(),
        );
    }
    for i in 0..latin.samples {
        let mut values = vec![None; keys.len()];
        for (c, column) in columns.iter().enumerate() {
            values[first + c] = Some(toml::Value::Float(column[i]));
        }
        runs.push(Run {
            index: runs.len(),
            values,
        });
    }
    Ok(sampled)
}
