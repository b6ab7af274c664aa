//! `telescopic sweep`, `sweep-merge` and `plot-sweep`: parameter studies on every core or
//! a cluster's job array, and their charts.

use super::check_chart;
use super::progress::Progress;
use clap::Args;
use std::path::PathBuf;
use telescopic::io::output::write_atomically;
use telescopic::sweep::{Shard, Sweep, SweepOptions, merge_shards, run_sweep};

/// Options of `telescopic sweep`.
#[derive(Debug, Args)]
pub struct SweepArgs {
    /// The sweep file (TOML; docs/sweeps.md).
    pub sweep: PathBuf,
    /// Runs at once, 1 to 256 (default: every core; never more than the runs left).
    #[arg(long, value_name = "N")]
    pub jobs: Option<usize>,
    /// Make only the runs with index % N == I: `I/N`, or `auto` from a Slurm job array
    /// (SLURM_ARRAY_TASK_ID, SLURM_ARRAY_TASK_COUNT) or a Kubernetes indexed job
    /// (JOB_COMPLETION_INDEX with --shard-count).
    #[arg(long, value_name = "I/N|auto")]
    pub shard: Option<String>,
    /// The number of shards for `--shard auto` where the environment does not say it.
    #[arg(long, value_name = "N")]
    pub shard_count: Option<usize>,
    /// The result file (CSV, written whole when every run is done; rows collect in
    /// FILE.partial until then).
    #[arg(long, default_value = "results.csv", value_name = "FILE")]
    pub out: PathBuf,
    /// Continue FILE.partial: skip the runs already there, make the rest.
    #[arg(long)]
    pub resume: bool,
}

/// Runs `telescopic sweep`.
pub fn sweep(args: &SweepArgs) -> anyhow::Result<()> {
    super::check_output("--out", Some(&args.out), &[&args.sweep])?;
    let shard = match args.shard.as_deref() {
        None => Shard::whole(),
        Some("auto") => Shard::of_job_array(|name| std::env::var(name).ok(), args.shard_count)?,
        Some(s) => s
            .parse::<Shard>()
            .map_err(|e| anyhow::anyhow!("--shard {s}: {e}"))?,
    };
    let jobs = args.jobs.unwrap_or_else(|| {
        std::thread::available_parallelism()
            .map_or(1, |n| n.get())
            .min(telescopic::sweep::MAX_JOBS)
    });
    telescopic::sweep::check_jobs(jobs)?;
    let memory_budget = crate::memory_budget()?;
    let sweep = Sweep::load_within(&args.sweep, memory_budget)?;
    let mine = sweep.runs.iter().filter(|r| shard.owns(r.index)).count();
    eprintln!(
        "{}: {} runs ({} in shard {}/{}), {} at once, sweep {}",
        args.sweep.display(),
        sweep.runs.len(),
        mine,
        shard.index,
        shard.count,
        jobs.min(mine.max(1)),
        sweep.hash
    );
    let cancel = crate::signals::watch_sweep(telescopic::sweep::partial_path(&args.out));
    let outcome = run_sweep(
        &sweep,
        &SweepOptions {
            out: args.out.clone(),
            jobs,
            shard,
            resume: args.resume,
            memory_budget,
            cancel,
        },
        &Progress::new(),
    )?;
    eprintln!(
        "{} runs: {} made now ({} failed, recorded with their error), {} kept from before, \
         {:.2} s; wrote {}",
        outcome.total,
        outcome.written,
        outcome.failed,
        outcome.resumed,
        outcome.wall,
        args.out.display()
    );
    Ok(())
}

/// Options of `telescopic sweep-merge`.
#[derive(Debug, Args)]
pub struct MergeArgs {
    /// The shard files.
    #[arg(required = true)]
    pub shards: Vec<PathBuf>,
    /// The merged file.
    #[arg(long, value_name = "FILE")]
    pub out: PathBuf,
}

/// Runs `telescopic sweep-merge`.
pub fn merge(args: &MergeArgs) -> anyhow::Result<()> {
    let paths: Vec<&std::path::Path> = args.shards.iter().map(PathBuf::as_path).collect();
    super::check_output("--out", Some(&args.out), &paths)?;
    let table = merge_shards(&paths)?;
    write_atomically(&args.out, |w| table.write(w))?;
    eprintln!(
        "merged {} shard(s), {} runs; wrote {}",
        args.shards.len(),
        table.rows.len(),
        args.out.display()
    );
    Ok(())
}

/// Options of `telescopic plot-sweep`.
#[derive(Debug, Args)]
pub struct PlotArgs {
    /// A result file of `telescopic sweep` (or `sweep-merge`).
    pub results: PathBuf,
    /// The column on the x axis (an override key).
    #[arg(long, value_name = "KEY")]
    pub x: String,
    /// The column plotted (a metric, e.g. tip_rel_max or residual_std).
    #[arg(long, value_name = "METRIC")]
    pub y: String,
    /// One line per value of this column.
    #[arg(long, value_name = "KEY")]
    pub color: Option<String>,
    /// A heat map of y over x and the --color column instead of lines.
    #[arg(long, requires = "color")]
    pub heatmap: bool,
    /// The chart (SVG or PNG by extension).
    #[arg(long, value_name = "FILE.svg|FILE.png")]
    pub out: PathBuf,
}

/// Runs `telescopic plot-sweep`.
pub fn plot(args: &PlotArgs) -> anyhow::Result<()> {
    check_chart("--out", Some(&args.out), &[&args.results])?;
    let table = telescopic::sweep::read_table(&args.results)?;
    let chart = telescopic::sweep::chart(
        &table,
        &args.x,
        &args.y,
        args.color.as_deref(),
        args.heatmap,
    )?;
    telescopic::plot::save(&chart, &args.out)?;
    eprintln!("wrote {}", args.out.display());
    Ok(())
}
