//! The memory a command may take: predicted before anything is allocated and refused above
//! a budget, naming the setting that drives it; a sweep's runs wait for their share of it.
//!
//! The budget is an option of each job (`memory_budget`, bytes; 2 GiB by default); the
//! faces set it (the command and the Python package from `TELESCOPIC_MEMORY_BUDGET`, parsed
//! by [`parse_budget`]).

use crate::{Error, OptionName, Result};
use std::sync::{Condvar, Mutex};
use telescopic_runtime::Scene;

/// The budget when none is given (bytes): 2 GiB.
pub const DEFAULT_MEMORY_BUDGET: u64 = 2 << 30;

/// Bytes a trajectory keeps per output value, its row vectors' overhead included (a row of
/// `c` values is a vector of `8 c` bytes plus 40 of header and allocation).
const BYTES_PER_VALUE: u64 = 8;

/// Bytes a trajectory keeps per row beyond its values.
const BYTES_PER_ROW: u64 = 40;

/// The memory budget (bytes) that `text` gives: bytes or with a binary suffix (`512M`,
/// `16G`); [`DEFAULT_MEMORY_BUDGET`] when it is not set.
///
/// # Errors
/// [`Error::Option`] naming [`OptionName::MemoryBudget`] when `text` is not a size.
pub fn parse_budget(text: Option<&str>) -> Result<u64> {
    match text {
        None => Ok(DEFAULT_MEMORY_BUDGET),
        Some(text) => parse_size(text).ok_or_else(|| {
            Error::option(
                OptionName::MemoryBudget,
                format!("{text:?} is not a size in bytes (e.g. 4000000000, 512M or 16G)"),
            )
        }),
    }
}

/// A size in bytes with an optional binary suffix (`K`, `M`, `G`, `T`).
fn parse_size(text: &str) -> Option<u64> {
    let text = text.trim();
    let (digits, shift) = match text.chars().last()?.to_ascii_uppercase() {
        'K' => (&text[..text.len() - 1], 10),
        'M' => (&text[..text.len() - 1], 20),
        'G' => (&text[..text.len() - 1], 30),
        'T' => (&text[..text.len() - 1], 40),
        _ => (text, 0),
    };
    digits
        .trim()
        .parse::<u64>()
        .ok()
        .filter(|&n| n > 0)
        .and_then(|n| n.checked_mul(1 << shift))
}

/// The bytes a simulation of `scene` keeps: its trajectory of every output at every sample.
pub fn trajectory_bytes(scene: &Scene) -> u64 {
    let samples = crate::run::budget::sample_count(&scene.time) as u64;
    let p = &scene.params;
    let motion = matches!(p.drive, telescopic_runtime::Drive::Motion(_));
    let columns = telescopic_runtime::scene::limits::output_columns(
        p.sections.len(),
        p.contact_points,
        motion,
    );
    samples.saturating_mul(columns * BYTES_PER_VALUE + BYTES_PER_ROW)
}

/// Refuses `bytes` above `budget` (bytes): `subject` is the scene or input the work belongs
/// to (and `option` the option that asks for it, if one does), `what` says what needs the
/// bytes, `remedy` what to change.
///
/// # Errors
/// [`Error::OverMemoryBudget`] naming the need, the budget and the remedy.
pub fn check(
    bytes: u64,
    budget: u64,
    (option, subject): (Option<OptionName>, String),
    what: String,
    remedy: &str,
) -> Result<()> {
    if bytes <= budget {
        return Ok(());
    }
    Err(Error::OverMemoryBudget {
        option,
        subject,
        what,
        bytes,
        budget,
        remedy: remedy.to_string(),
    })
}

/// Refuses runs whose trajectories, kept together, exceed `budget` (bytes).
///
/// # Errors
/// As [`check`], naming `time.sample`.
pub fn check_runs(scenes: &[&Scene], budget: u64) -> Result<()> {
    let bytes = scenes.iter().map(|s| trajectory_bytes(s)).sum();
    let name = scenes.first().map_or("", |s| s.name.as_str());
    let what = if scenes.len() == 1 {
        "the run's trajectory".to_string()
    } else {
        format!("the {} runs' trajectories", scenes.len())
    };
    check(
        bytes,
        budget,
        (None, format!("scene {name}")),
        what,
        "time.sample (a coarser output grid) or time.end",
    )
}

/// Most output stations of a run: each adds a moment and a stress column and a sum over the
/// modes at every sample.
pub const MAX_STATIONS: usize = 1000;

/// Refuses more than [`MAX_STATIONS`] output stations.
///
/// # Errors
/// [`Error::Option`] naming the stations.
pub fn check_station_count(stations: usize) -> Result<()> {
    if stations > MAX_STATIONS {
        return Err(Error::option(
            OptionName::Stations,
            format!(
                "{stations} stations; at most {MAX_STATIONS} (a moment and a stress column each)"
            ),
        ));
    }
    Ok(())
}

/// Refuses a run of `scene` with `stations` output stations and `coordinates` coordinate
/// columns whose trajectory, those columns included, exceeds `budget` (bytes).
///
/// # Errors
/// As [`check_station_count`] and [`check`] (naming the stations when there are any).
pub fn check_run(
    scene: &Scene,
    (stations, coordinates): (usize, usize),
    budget: u64,
) -> Result<()> {
    check_station_count(stations)?;
    if stations == 0 && coordinates == 0 {
        return check_runs(&[scene], budget);
    }
    let samples = crate::run::budget::sample_count(&scene.time) as u64;
    let columns = (2 * stations + coordinates) as u64 * BYTES_PER_VALUE;
    let bytes = trajectory_bytes(scene).saturating_add(samples.saturating_mul(columns));
    let (option, what, remedy) = if stations > 0 {
        (
            Some(OptionName::Stations),
            format!("the run's trajectory with {stations} stations' moments and stresses"),
            "the stations (fewer), time.sample (a coarser output grid) or time.end",
        )
    } else {
        (
            None,
            format!("the run's trajectory with its {coordinates} coordinates"),
            "time.sample (a coarser output grid) or time.end",
        )
    };
    check(
        bytes,
        budget,
        (option, format!("scene {}", scene.name)),
        what,
        remedy,
    )
}

/// The budget shared by runs in parallel: each takes its trajectory's share before it
/// starts and gives it back when done; a run waits while others hold too much.
#[derive(Debug)]
pub struct MemoryGate {
    free: Mutex<u64>,
    freed: Condvar,
    total: u64,
}

/// A share of a [`MemoryGate`], given back on drop.
#[derive(Debug)]
pub struct Share<'g> {
    gate: &'g MemoryGate,
    bytes: u64,
}

impl MemoryGate {
    /// The whole budget (bytes).
    pub fn total(&self) -> u64 {
        self.total
    }

    /// A gate over a budget of `total` bytes.
    pub fn new(total: u64) -> Self {
        MemoryGate {
            free: Mutex::new(total),
            freed: Condvar::new(),
            total,
        }
    }

    /// Takes `bytes` for a run of `scene`, waiting while other runs hold them.
    ///
    /// # Errors
    /// As [`check_runs`] when the run alone exceeds the whole budget.
    pub fn take(&self, scene: &Scene) -> Result<Share<'_>> {
        let bytes = trajectory_bytes(scene);
        if bytes > self.total {
            check_runs(&[scene], self.total)?;
        }
        let mut free = self.free.lock().unwrap_or_else(|e| e.into_inner());
        while *free < bytes {
            free = self.freed.wait(free).unwrap_or_else(|e| e.into_inner());
        }
        *free -= bytes;
        Ok(Share { gate: self, bytes })
    }
}

impl Drop for Share<'_> {
    fn drop(&mut self) {
        let mut free = self.gate.free.lock().unwrap_or_else(|e| e.into_inner());
        *free += self.bytes;
        self.gate.freed.notify_all();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_parse_with_binary_suffixes() {
        assert_eq!(parse_size("4096"), Some(4096));
        assert_eq!(parse_size("512M"), Some(512 << 20));
        assert_eq!(parse_size("16g"), Some(16 << 30));
        assert_eq!(parse_size("0"), None);
        assert_eq!(parse_size("lots"), None);
        assert_eq!(parse_size("99999999999T"), None);
    }
}
