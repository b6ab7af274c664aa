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
}

/// A [`Reporter`] that drops everything.
#[derive(Debug, Clone, Copy, Default)]
pub struct Silent;

impl Reporter for Silent {}
