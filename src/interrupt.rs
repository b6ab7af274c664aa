//! A stop requested from outside (Ctrl-C), for the long multi-run commands that stop between
//! runs and keep what they finished. The caller's signal handler calls [`request`]; only
//! while a command has called [`stop_between_runs`] does a request count, otherwise the
//! handler does its usual (remove partial files, exit).

use std::sync::atomic::{AtomicBool, Ordering};

static GRACEFUL: AtomicBool = AtomicBool::new(false);
static REQUESTED: AtomicBool = AtomicBool::new(false);

/// From now on, a [`request`] asks the running command to stop between runs.
pub fn stop_between_runs() {
    REQUESTED.store(false, Ordering::SeqCst);
    GRACEFUL.store(true, Ordering::SeqCst);
}

/// Asks the running command to stop; returns whether one listens (else the caller should
/// stop the process itself). A second request while one is pending returns false.
pub fn request() -> bool {
    GRACEFUL.load(Ordering::SeqCst) && !REQUESTED.swap(true, Ordering::SeqCst)
}

/// Whether a stop was requested.
pub fn requested() -> bool {
    REQUESTED.load(Ordering::SeqCst)
}
