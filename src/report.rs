//! How long-running library calls tell their caller what they are doing: a [`Reporter`]
//! given by the caller, so the library prints nothing itself and the caller decides (the CLI
//! draws a progress bar on a terminal and prints plain lines otherwise).

/// Receives progress and notes from long-running calls. Every method has a silent default.
pub trait Reporter: Sync {
    /// A run of `what` starts (e.g. `simulating case-study`).
    fn start(&self, what: &str) {
        let _ = what;
    }

    /// The current run has done `fraction` (0 to 1) of its work.
    fn progress(&self, fraction: f64) {
        let _ = fraction;
    }

    /// The current run has ended (successfully or not).
    fn finish(&self) {}

    /// A multi-run command has finished `done` of `total` runs.
    fn runs(&self, done: usize, total: usize) {
        let _ = (done, total);
    }

    /// A line worth showing a user (a reference run's result, a note on the model used).
    fn note(&self, line: &str) {
        let _ = line;
    }

    /// Whether the caller asks the current run to stop (checked with each progress report: a
    /// run then ends with a [`SimError::Stopped`](telescopic_runtime::SimError::Stopped)).
    fn stop_requested(&self) -> bool {
        false
    }
}

/// One phase of a call made of consecutive runs (a run and its companion): its progress is
/// the share `from..to` of the caller's, so the caller's fraction only grows; the caller
/// sees the first phase's start and the last one's finish.
pub struct Phase<'a> {
    /// The caller's reporter.
    pub inner: &'a dyn Reporter,
    /// Where this phase's progress starts and ends in the caller's (0 to 1).
    pub share: (f64, f64),
}

impl Reporter for Phase<'_> {
    fn start(&self, what: &str) {
        if self.share.0 == 0.0 {
            self.inner.start(what);
        }
    }
    fn progress(&self, fraction: f64) {
        let (from, to) = self.share;
        self.inner
            .progress(from + (to - from) * fraction.clamp(0.0, 1.0));
    }
    fn finish(&self) {
        if self.share.1 == 1.0 {
            self.inner.finish();
        }
    }
    fn runs(&self, done: usize, total: usize) {
        self.inner.runs(done, total);
    }
    fn note(&self, line: &str) {
        self.inner.note(line);
    }
    fn stop_requested(&self) -> bool {
        self.inner.stop_requested()
    }
}

/// A [`Reporter`] that drops everything.
#[derive(Debug, Clone, Copy, Default)]
pub struct Silent;

impl Reporter for Silent {}

/// A [`Reporter`] that drops everything but the caller's stop request: for runs inside a
/// larger call (a plan's candidates on each plant) whose own progress would confuse the
/// caller's, but which must stop when the caller asks.
#[derive(Clone, Copy)]
pub struct StopOnly<'a>(pub &'a dyn Reporter);

impl Reporter for StopOnly<'_> {
    fn stop_requested(&self) -> bool {
        self.0.stop_requested()
    }
}
