//! Running a sweep: the shard's runs in parallel, each a row appended whole to a work file
//! (`<out>.partial`) as it finishes; when every row of the shard is there, the rows are
//! sorted by index and the file renamed into place, so `<out>` is only ever complete.
//! `--resume` continues a work file (a torn last line, from a killed process, is dropped).

use super::file::{Run, Sweep};
use super::shard::Shard;
use crate::OptionName;
use crate::analysis::metrics::{drive_stop, metrics, peak_and_rms};
use crate::io::output::csv_number;
use crate::report::{Reporter, Silent};
use crate::run::PreparedRun;
use crate::run::memory::MemoryGate;
use crate::{Error, Result};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::time::Instant;
use telescopic_runtime::{Output, SimError, modal_analysis};

use super::table::METRIC_COLUMNS;

/// Options of [`run_sweep`].
#[derive(Debug, Clone, PartialEq)]
pub struct SweepOptions {
    /// The result file.
    pub out: PathBuf,
    /// Runs at once (threads), 1 or more.
    pub jobs: usize,
    /// Which runs.
    pub shard: Shard,
    /// Continue `<out>.partial` (or find `<out>` complete) instead of starting afresh.
    pub resume: bool,
    /// The memory the runs in progress may take together (bytes,
    /// [`crate::run::memory::DEFAULT_MEMORY_BUDGET`] for the default).
    pub memory_budget: u64,
    /// Asked to stop: no new run starts, the finished rows are kept in the work file.
    pub cancel: crate::Cancel,
}

/// What a sweep did.
#[derive(Debug, Clone, PartialEq)]
pub struct SweepOutcome {
    /// Runs of the shard.
    pub total: usize,
    /// Rows written by this call.
    pub written: usize,
    /// Rows found in a work file and kept (`--resume`).
    pub resumed: usize,
    /// Rows of this call whose run failed (recorded with their error).
    pub failed: usize,
    /// Wall time of this call (s).
    pub wall: f64,
}

/// The first line of a result file: which sweep, how many runs, which shard.
pub(super) fn header_line(sweep: &Sweep, shard: Shard) -> String {
    format!(
        "# telescopic sweep {}; sweep {}; runs {}; shard {}/{}; file {}; scene {}",
        env!("CARGO_PKG_VERSION"),
        sweep.hash,
        sweep.runs.len(),
        shard.index,
        shard.count,
        sweep.path.display(),
        sweep.scene_path.display()
    )
}

/// The column line of a result file.
pub(super) fn column_line(sweep: &Sweep) -> String {
    let mut cols = vec!["index".to_string()];
    cols.extend(sweep.keys.iter().map(|k| csv_text(k)));
    cols.extend(METRIC_COLUMNS.iter().map(|c| c.to_string()));
    cols.join(",")
}

/// A CSV cell: quoted when it holds a comma, a quote or a line break.
pub(super) fn csv_text(s: &str) -> String {
    if s.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", s.replace('"', "\"\"").replace(['\n', '\r'], " "))
    } else {
        s.to_string()
    }
}

/// The error kind in the `status` column.
fn status_of(e: &Error) -> &'static str {
    match e {
        Error::Scene(_) => "invalid",
        Error::Option { .. } | Error::Input { .. } => "option",
        Error::Model(_) | Error::Assembly(_) | Error::Linear(_) | Error::Elements(_) => "model",
        Error::Unaffordable { .. } | Error::OverMemoryBudget { .. } => "unaffordable",
        Error::Simulation { error, .. } => match error {
            SimError::Diverged { .. } => "diverged",
            SimError::StepUnderflow { .. } => "step-underflow",
            SimError::NewtonFailure { .. } => "newton",
            SimError::PositionOutOfRange { .. } => "position",
            SimError::TooManySteps { .. } => "step-limit",
            SimError::OverBudget { .. } => "over-budget",
            SimError::Settings(_) => "settings",
            SimError::Stopped { .. } => "stopped",
        },
        Error::NonFiniteOutput { .. } => "non-finite",
        Error::Eigen { .. } | Error::Modes(_) => "eigen",
        Error::Panicked(_) => "panic",
        _ => "error",
    }
}

/// Where a sweep's progress stands: `done` of `total` runs finished, told to `reporter`.
struct Progress<'r> {
    total: usize,
    done: usize,
    reporter: &'r dyn Reporter,
}

/// Runs `pending` on `options.jobs` threads, each row appended to `work` (flushed) as its
/// run finishes, until all are done, `options.cancel` is asked or a write fails: the work
/// file and the counts `(finished, written, failed)`.
fn run_pending(
    sweep: &Sweep,
    pending: &[&Run],
    options: &SweepOptions,
    work: WorkFile,
    gate: &MemoryGate,
    progress: &Progress,
    partial: &Path,
) -> Result<(WorkFile, (usize, usize, usize))> {
    use rayon::prelude::*;
    let writer = Mutex::new(work);
    let counts = Mutex::new((progress.done, 0usize, 0usize)); // (finished, written, failed)
    let write_failure: Mutex<Option<std::io::Error>> = Mutex::new(None);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(options.jobs.min(pending.len()).max(1))
        .build()
        .map_err(|e| Error::option(OptionName::Jobs, e.to_string()))?;
    pool.install(|| {
        pending.par_iter().for_each(|run| {
            // after an interrupt or a failed write, no new run starts
            let write_failed = || write_failure.lock().map_or(true, |f| f.is_some());
            if options.cancel.requested() || write_failed() {
                return;
            }
            let (line, failed) = row(sweep, run, gate);
            // one write of a whole line, then flushed: a kill leaves whole rows or a torn
            // last one, which --resume cuts off
            let result = {
                let mut f = writer.lock().unwrap_or_else(|e| e.into_inner());
                f.write_all(line.as_bytes()).and_then(|()| f.flush())
            };
            if let Err(e) = result {
                *write_failure.lock().unwrap_or_else(|e| e.into_inner()) = Some(e);
                return;
            }
            let mut c = counts.lock().unwrap_or_else(|e| e.into_inner());
            c.0 += 1;
            c.1 += 1;
            c.2 += usize::from(failed);
            progress.reporter.runs(c.0, progress.total);
        })
    });
    let work = writer.into_inner().unwrap_or_else(|e| e.into_inner());
    if let Some(error) = write_failure
        .into_inner()
        .unwrap_or_else(|e| e.into_inner())
    {
        return Err(Error::Write {
            path: partial.to_path_buf(),
            error,
        });
    }
    Ok((work, counts.into_inner().unwrap_or_else(|e| e.into_inner())))
}

/// One run, as its CSV row.
fn row(sweep: &Sweep, run: &Run, gate: &MemoryGate) -> (String, bool) {
    let start = Instant::now();
    let measure = || -> Result<(Vec<String>, Option<String>)> {
        let (scene, mut options) = sweep.scene_of(run)?;
        options.memory_budget = gate.total();
        // the run's trajectory's share of the memory budget, held until its row is made
        let _share = gate.take(&scene)?;
        let run = PreparedRun::new(&scene, &options, &Silent)?;
        let model = run.model();
        let traj = run.integrate(&Silent)?;
        let tip = traj
            .column_of(Output::TipRel)
            .expect("every run has tip_rel");
        let (tip_max, tip_rms) = peak_and_rms(&tip);
        let force_max = traj
            .columns_where(Output::is_contact_force)
            .into_iter()
            .flat_map(|i| traj.rows.iter().map(move |r| r[i].abs()))
            .fold(0.0, f64::max);
        let residual = metrics(&scene, &traj, drive_stop(&scene)).residual_std;
        // f1 at the final position; a failure here leaves the run's other figures standing
        let (f1, note) = match modal_analysis(model, scene.time.end) {
            Ok(m) => (m.frequencies_hz.first().copied().unwrap_or(f64::NAN), None),
            Err(e) => (f64::NAN, Some(format!("f1: {e}"))),
        };
        let s = &traj.stats;
        let cells = [tip_max, tip_rms, force_max]
            .iter()
            .map(|v| csv_number(*v))
            .chain([s.switches.to_string()])
            .chain([residual, f1].iter().map(|v| {
                if v.is_finite() {
                    csv_number(*v)
                } else {
                    String::new()
                }
            }))
            .chain(
                [
                    s.steps,
                    s.rejected,
                    s.rhs_evals,
                    s.jacobian_evals,
                    s.factorizations,
                ]
                .iter()
                .map(u64::to_string),
            )
            .collect();
        Ok((cells, note))
    };
    // a panic in one run (a bug) is that run's error, not the end of the sweep
    let outcome = std::panic::catch_unwind(std::panic::AssertUnwindSafe(measure))
        .unwrap_or_else(|payload| Err(Error::from_panic(payload.as_ref())));
    let mut cells = vec![run.index.to_string()];
    cells.extend(run.values.iter().map(|v| match v {
        Some(toml::Value::String(s)) => csv_text(s),
        Some(v) => csv_text(&telescopic_runtime::scene::value_text(v)),
        None => String::new(),
    }));
    let failed = outcome.is_err();
    match outcome {
        Ok((metrics, note)) => {
            cells.extend(metrics);
            cells.push("ok".into());
            cells.push(note.map(|n| csv_text(&n)).unwrap_or_default());
        }
        Err(e) => {
            cells.extend(std::iter::repeat_n(String::new(), METRIC_COLUMNS.len() - 3));
            cells.push(status_of(&e).into());
            cells.push(csv_text(&e.to_string()));
        }
    }
    cells.push(format!("{:.6}", start.elapsed().as_secs_f64()));
    (cells.join(",") + "\n", failed)
}

/// Removes a sweep's result `out` and its work file (`<out>.partial`), whichever exist: what
/// a caller that does not resume (the Python package) leaves after a failed or stopped sweep.
pub fn discard_sweep(out: &Path) {
    for path in [out.to_path_buf(), partial_path(out)] {
        let _ = std::fs::remove_file(path);
    }
}

/// The work file beside `out` (`<out>.partial`) that keeps a sweep's finished rows.
pub fn partial_path(out: &Path) -> PathBuf {
    let mut name = out
        .file_name()
        .map(|n| n.to_os_string())
        .unwrap_or_default();
    name.push(".partial");
    out.with_file_name(name)
}

/// Most runs at once: threads beyond the cores only cost memory and start-up time.
pub const MAX_JOBS: usize = 256;

/// Checks a number of runs at once: 1 to [`MAX_JOBS`].
///
/// # Errors
/// [`Error::Option`] naming `SweepOptions::jobs`.
pub fn check_jobs(jobs: usize) -> Result<()> {
    if !(1..=MAX_JOBS).contains(&jobs) {
        return Err(Error::option(
            OptionName::Jobs,
            format!("must be 1 to {MAX_JOBS} (got {jobs})"),
        ));
    }
    Ok(())
}

/// Where the finished rows go while the sweep runs.
enum WorkFile {
    /// `<out>.partial`, locked against a second sweep, appended row by row.
    Partial { path: PathBuf, file: std::fs::File },
    /// In memory, for an output that is a stream (no work file beside a device).
    Memory(Vec<u8>),
}

impl Write for WorkFile {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        match self {
            WorkFile::Partial { file, .. } => file.write(buf),
            WorkFile::Memory(bytes) => bytes.write(buf),
        }
    }

    fn flush(&mut self) -> std::io::Result<()> {
        match self {
            WorkFile::Partial { file, .. } => file.flush(),
            WorkFile::Memory(_) => Ok(()),
        }
    }
}

/// Opens the work file of `out` and takes its lock; returns it with the indices of the rows
/// it keeps (`resume`), after checking every row like a shard's. Without `resume`, a work
/// file that holds rows is refused rather than discarded.
fn open_work_file(
    out: &Path,
    header: &str,
    columns: &str,
    resume: bool,
) -> Result<(WorkFile, Vec<usize>)> {
    use crate::io::output::Destination;
    let first_lines = format!("{header}\n{columns}\n");
    if matches!(Destination::of(out), Ok(Destination::Stream(_))) {
        if resume {
            return Err(Error::option(
                OptionName::Resume,
                format!(
                    "{} is a stream, which keeps no rows to resume",
                    out.display()
                ),
            ));
        }
        return Ok((WorkFile::Memory(first_lines.into_bytes()), Vec::new()));
    }
    let path = partial_path(out);
    let write_error = |error| Error::Write {
        path: path.clone(),
        error,
    };
    let file = std::fs::OpenOptions::new()
        .read(true)
        .write(true)
        .create(true)
        .truncate(false)
        .open(&path)
        .map_err(write_error)?;
    if let Err(e) = file.try_lock() {
        return Err(Error::option(
            OptionName::SweepOut,
            format!(
                "another sweep is writing {} (its work file {} is locked: {e}); wait for it or \
                 choose another output",
                out.display(),
                path.display()
            ),
        ));
    }
    let kept = kept_rows(&path, &file, header, columns, resume)?;
    let done = match kept {
        Some((rows, whole)) => {
            file.set_len(whole as u64).map_err(write_error)?;
            rows
        }
        None => {
            file.set_len(0).map_err(write_error)?;
            (&file)
                .write_all(first_lines.as_bytes())
                .map_err(write_error)?;
            Vec::new()
        }
    };
    use std::io::Seek;
    (&file)
        .seek(std::io::SeekFrom::End(0))
        .map_err(write_error)?;
    Ok((WorkFile::Partial { path, file }, done))
}

/// The rows a work file keeps (their indices and the length of its whole lines) when
/// resuming; `None` to start afresh. A work file of another sweep, one with a bad row, or
/// one with finished rows when not resuming is refused.
fn kept_rows(
    path: &Path,
    file: &std::fs::File,
    header: &str,
    columns: &str,
    resume: bool,
) -> Result<Option<(Vec<usize>, usize)>> {
    let length = file
        .metadata()
        .map_err(|error| Error::Write {
            path: path.to_owned(),
            error,
        })?
        .len();
    if length == 0 {
        return Ok(None);
    }
    let refuse = |why: String| Err(Error::option(OptionName::Resume, why));
    let foreign = |found: &str| {
        refuse(format!(
            "{} belongs to another sweep or shard (its header: {}); remove it to start afresh",
            path.display(),
            super::table::quoted(found)
        ))
    };
    let first_line = first_line(file);
    if first_line != header {
        return foreign(&first_line);
    }
    let (table, whole) = match super::table::read_work_file(path) {
        Ok(found) => found,
        Err(e) => return refuse(format!("{e}; remove the work file to start afresh")),
    };
    if table.columns != columns {
        return foreign(&table.header);
    }
    match (resume, table.rows.len()) {
        (true, _) => Ok(Some((table.rows.iter().map(|(i, _)| *i).collect(), whole))),
        (false, 0) => Ok(None),
        (false, n) => refuse(format!(
            "{} holds {n} finished run(s) of this sweep: resume to keep them, or remove it to \
             start afresh",
            path.display()
        )),
    }
}

/// The first line of a file (at most 4 KiB of it), without its line break.
fn first_line(file: &std::fs::File) -> String {
    use std::io::{BufRead, Read, Seek};
    let mut reader = file;
    let _ = reader.seek(std::io::SeekFrom::Start(0));
    let mut line = String::new();
    let _ = std::io::BufReader::new(reader.take(4096)).read_line(&mut line);
    line.trim_end_matches('\n').to_string()
}

/// The finished sweep's rows, sorted by index, from its work file.
fn finished_table(work: &WorkFile) -> Result<super::table::SweepTable> {
    let mut table = match work {
        WorkFile::Partial { path, .. } => super::table::read_work_file(path)?.0,
        // the rows in memory read like a work file, every row checked the same way
        WorkFile::Memory(bytes) => super::table::read_work_bytes(Path::new("(in memory)"), bytes)?,
    };
    table.rows.sort_by_key(|(i, _)| *i);
    Ok(table)
}

/// Runs `sweep` (the shard's runs) with `options`, reporting the count of finished runs.
///
/// # Errors
/// [`Error::Option`] for bad options or a work file of another sweep; [`Error::Write`];
/// [`Error::Interrupted`] when `options.cancel` is asked (every finished row kept).
pub fn run_sweep(
    sweep: &Sweep,
    options: &SweepOptions,
    reporter: &dyn Reporter,
) -> Result<SweepOutcome> {
    let started = Instant::now();
    check_jobs(options.jobs)?;
    crate::io::output::check_not_an_input(&options.out, &[&sweep.path, &sweep.scene_path])
        .map_err(|e| Error::option(OptionName::SweepOut, e.to_string()))?;
    let header = header_line(sweep, options.shard);
    let columns = column_line(sweep);
    let mine: Vec<&Run> = sweep
        .runs
        .iter()
        .filter(|r| options.shard.owns(r.index))
        .collect();
    let partial = partial_path(&options.out);
    // a complete file of this sweep and shard: nothing to do
    if options.resume && !partial.exists() && options.out.is_file() {
        let table = super::table::read_table(&options.out)?;
        if table.header == header && table.rows.len() == mine.len() {
            return Ok(SweepOutcome {
                total: mine.len(),
                written: 0,
                resumed: mine.len(),
                failed: 0,
                wall: 0.0,
            });
        }
    }
    let (work, done) = open_work_file(&options.out, &header, &columns, options.resume)?;
    let finished_before: std::collections::HashSet<usize> = done.iter().copied().collect();
    let pending: Vec<&Run> = mine
        .iter()
        .copied()
        .filter(|r| !finished_before.contains(&r.index))
        .collect();
    let gate = MemoryGate::new(options.memory_budget);
    let total = mine.len();
    reporter.runs(done.len(), total);
    let progress = Progress {
        total,
        done: done.len(),
        reporter,
    };
    let (work, (finished, written, failed)) =
        run_pending(sweep, &pending, options, work, &gate, &progress, &partial)?;
    let write_error = |error| Error::Write {
        path: partial.clone(),
        error,
    };
    if finished < total {
        let kept = match &work {
            WorkFile::Partial { path, .. } => Some(path.clone()),
            WorkFile::Memory(_) => None,
        };
        return Err(Error::Interrupted {
            finished,
            total,
            kept,
        });
    }
    // every row is there: sorted by index into the result file, written whole
    let table = finished_table(&work)?;
    crate::io::output::write_atomically(&options.out, |w| table.write(w))?;
    if let WorkFile::Partial { path, .. } = &work {
        std::fs::remove_file(path).map_err(write_error)?;
    }
    Ok(SweepOutcome {
        total,
        written,
        resumed: done.len(),
        failed,
        wall: started.elapsed().as_secs_f64(),
    })
}
