//! Parameter studies: a sweep file's runs on every core (rayon), one CSV row per run with
//! the summary metrics, resumable, and shardable over a cluster's job array with no
//! coordinator (`index % N == I`), with a merge that checks the shards belong together.
//!
//! ```no_run
//! use telescopic::sweep::{Shard, Sweep, SweepOptions, run_sweep};
//! use telescopic::Silent;
//!
//! let sweep = Sweep::load("examples/sweeps/clearance.toml".as_ref())?;
//! let done = run_sweep(&sweep, &SweepOptions {
//!     out: "results.csv".into(),
//!     jobs: 2,
//!     shard: Shard::whole(),
//!     resume: false,
//!     memory_budget: telescopic::run::memory::DEFAULT_MEMORY_BUDGET,
//!     cancel: Default::default(),
//! }, &Silent)?;
//! println!("{} runs, {} failed", done.written, done.failed);
//! # Ok::<(), telescopic::Error>(())
//! ```

#[cfg(feature = "plot")]
mod chart;
mod file;
mod merge;
mod run;
mod shard;
mod table;

#[cfg(feature = "plot")]
pub use chart::{SweepChart, chart};
pub use file::{MAX_RUNS, RUN_KEYS, Run, Sweep};
pub use merge::merge_shards;
pub use run::{
    MAX_JOBS, SweepOptions, SweepOutcome, check_jobs, discard_sweep, partial_path, run_sweep,
};
pub use shard::Shard;
pub use table::{MAX_RESULT_BYTES, METRIC_COLUMNS, STATUSES, SweepTable, read_table, split_csv};
pub use telescopic_runtime::scene::value_text;
