//! Long calls off the interpreter: the work runs on a thread of its own without the GIL
//! (two Python threads simulating at once use two cores), while the calling thread wakes
//! every 50 ms to hand progress to the caller's callable and to check for Ctrl-C. A Ctrl-C
//! asks the call to stop (its [`telescopic::Cancel`]: a sweep stops between runs) and, once the work has
//! stopped, raises `KeyboardInterrupt`; a panic in the work becomes a `TelescopicError`.

use pyo3::prelude::*;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::sync::Mutex;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Duration;
use telescopic::report::Reporter;

/// How often the waiting thread wakes when the work goes on: the bound on Ctrl-C's latency
/// besides a run's own, and the progress callable's rate. The end of the work wakes it at
/// once.
const POLL: Duration = Duration::from_millis(50);

/// A [`Reporter`] that keeps the latest progress for the waiting thread to pass on.
#[derive(Default)]
pub struct Progress {
    /// The fraction done of the current run, as bits of an `f64`.
    fraction: AtomicU64,
    /// Finished runs of a multi-run call, and their total.
    runs: Mutex<(usize, usize)>,
    /// The current run's name.
    what: Mutex<String>,
    /// This call's stop request (a Ctrl-C, or an exception of the progress callable).
    pub cancel: telescopic::Cancel,
    /// The work's notes not yet written to `sys.stderr`, when the call shows them.
    notes: Mutex<Vec<String>>,
    /// Whether the call shows the work's notes.
    shows_notes: bool,
}

impl Reporter for Progress {
    fn start(&self, what: &str) {
        *self.what.lock().unwrap_or_else(|e| e.into_inner()) = what.to_string();
        self.fraction.store(0f64.to_bits(), Ordering::Relaxed);
    }
    fn progress(&self, fraction: f64) {
        self.fraction.store(fraction.to_bits(), Ordering::Relaxed);
    }
    fn runs(&self, done: usize, total: usize) {
        *self.runs.lock().unwrap_or_else(|e| e.into_inner()) = (done, total);
    }
    fn note(&self, line: &str) {
        if self.shows_notes {
            let mut notes = self.notes.lock().unwrap_or_else(|e| e.into_inner());
            notes.push(line.to_string());
        }
    }
    fn stop_requested(&self) -> bool {
        self.cancel.requested()
    }
}

impl Progress {
    /// The fraction of the whole call done: runs done plus the current run's share.
    fn overall(&self) -> f64 {
        let (done, total) = *self.runs.lock().unwrap_or_else(|e| e.into_inner());
        let current = f64::from_bits(self.fraction.load(Ordering::Relaxed)).clamp(0.0, 1.0);
        if total > 0 {
            (done as f64 / total as f64).clamp(0.0, 1.0)
        } else {
            current
        }
    }

    /// Writes the notes that came since the last call to `sys.stderr` (where a notebook shows
    /// them), each with the fraction done, as the command line's log lines do.
    fn write_notes(&self, py: Python<'_>) -> PyResult<()> {
        let notes: Vec<String> =
            std::mem::take(&mut *self.notes.lock().unwrap_or_else(|e| e.into_inner()));
        if notes.is_empty() {
            return Ok(());
        }
        let stderr = py.import("sys")?.getattr("stderr")?;
        let done = 100.0 * self.overall();
        for line in notes {
            stderr.call_method1("write", (format!("[{done:3.0} %] {line}\n"),))?;
        }
        stderr.call_method0("flush")?;
        Ok(())
    }
}

/// Runs `work` (given the reporter) off the GIL, passing progress to `callback(fraction)`
/// (a Python callable, or `None`), raising `KeyboardInterrupt` after a Ctrl-C.
pub fn run<T: Send>(
    py: Python<'_>,
    callback: Option<&Bound<'_, PyAny>>,
    work: impl FnOnce(&Progress) -> Result<T, telescopic::Error> + Send,
) -> PyResult<T> {
    run_showing(py, callback, false, work)
}

/// [`run`], writing the work's notes (what it does now, e.g. a plan's "evaluating ZVD on
/// 10 plants") to `sys.stderr` as they come when `shows_notes`.
pub fn run_showing<T: Send>(
    py: Python<'_>,
    callback: Option<&Bound<'_, PyAny>>,
    shows_notes: bool,
    work: impl FnOnce(&Progress) -> Result<T, telescopic::Error> + Send,
) -> PyResult<T> {
    let progress = Progress {
        shows_notes,
        ..Progress::default()
    };
    let mut interrupted = false;
    // an exception of the progress callable: the work is asked to stop, then it is raised
    let mut callback_error: Option<PyErr> = None;
    let outcome = std::thread::scope(|scope| {
        let (done, mut finished) = std::sync::mpsc::channel();
        let progress = &progress;
        scope.spawn(move || {
            let _ = done.send(catch_unwind(AssertUnwindSafe(|| work(progress))));
        });
        let mut last = -1.0;
        loop {
            // the GIL is released while waiting; the result wakes the wait at once
            // the receiver travels into the GIL-free wait and back (it is Send, not Sync)
            let (received, back) = py.detach(move || (finished.recv_timeout(POLL), finished));
            finished = back;
            match received {
                Ok(result) => break Ok(result),
                Err(std::sync::mpsc::RecvTimeoutError::Disconnected) => {
                    break Err(crate::errors::TelescopicError::new_err(
                        "internal error: the worker thread ended without a result",
                    ));
                }
                Err(std::sync::mpsc::RecvTimeoutError::Timeout) => {}
            }
            if let Err(error) = py.check_signals() {
                if error.is_instance_of::<pyo3::exceptions::PyKeyboardInterrupt>(py) {
                    // a sweep stops between runs; a single run finishes first
                    progress.cancel.request();
                    interrupted = true;
                } else {
                    return Err(error);
                }
            }
            progress.write_notes(py)?;
            if let (Some(cb), None) = (callback, &callback_error) {
                // the callable sees the fraction done grow, never go back (a new run's
                // start reads 0 until its first progress)
                let f = progress.overall();
                if f > last {
                    last = f;
                    if let Err(error) = cb.call1((f,)) {
                        // a Ctrl-C while the callable runs arrives as its exception
                        if error.is_instance_of::<pyo3::exceptions::PyKeyboardInterrupt>(py) {
                            interrupted = true;
                        } else {
                            callback_error = Some(error);
                        }
                        progress.cancel.request();
                    }
                }
            }
        }
    })?;
    if let Some(error) = callback_error {
        return Err(error);
    }
    if interrupted {
        return Err(pyo3::exceptions::PyKeyboardInterrupt::new_err(
            "interrupted (the call stopped; nothing was written)",
        ));
    }
    progress.write_notes(py)?;
    match outcome {
        Ok(Ok(value)) => {
            if let Some(cb) = callback {
                cb.call1((1.0,))?;
            }
            Ok(value)
        }
        Ok(Err(error)) => Err(crate::errors::to_python(error)),
        Err(panic) => Err(crate::errors::TelescopicError::new_err(
            telescopic::Error::from_panic(panic.as_ref()).to_string(),
        )),
    }
}
