//! How long-running library calls tell their caller what they are doing: a [`Reporter`]
//! given by the caller, so the library prints nothing itself and the caller decides (the CLI
//! draws a progress bar on a terminal and prints plain lines otherwise).

use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};

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

/// Two runs made at once (a run and its companion): the caller sees their progress as one,
/// the weighted sum of their fractions, so it only grows; the first run's start, one finish
/// once both have returned (whether or not they reported theirs), every note (prefixed by the run's name where it has one) and the caller's stop
/// request pass through. When the first run fails,
/// [`Pair::abandon`] stops the second at its next progress report.
pub struct Pair<'a> {
    inner: &'a dyn Reporter,
    /// Each run's share of the caller's progress (they sum to 1).
    weights: [f64; 2],
    /// Each run's fraction done, as bits of an `f64`.
    fractions: [AtomicU64; 2],
    /// The caller's fraction last reported: held while reporting, so that it only grows.
    reported: Mutex<f64>,
    /// Whether the first run's start was passed on: the caller is then owed one finish.
    started: AtomicBool,
    /// Set when the first run has failed: the second's result is not wanted.
    abandoned: AtomicBool,
}

impl<'a> Pair<'a> {
    /// Two runs reporting to `inner`, the first with the share `first` (0 to 1) of its
    /// progress, the second with the rest.
    pub fn new(inner: &'a dyn Reporter, first: f64) -> Self {
        Self {
            inner,
            weights: [first, 1.0 - first],
            fractions: [AtomicU64::new(0), AtomicU64::new(0)],
            reported: Mutex::new(0.0),
            started: AtomicBool::new(false),
            abandoned: AtomicBool::new(false),
        }
    }

    /// The reporter of run `index` (0 or 1).
    pub fn side(&self, index: usize) -> PairSide<'_, 'a> {
        PairSide {
            pair: self,
            index,
            name: None,
        }
    }

    /// The reporter of run `index` (0 or 1), whose notes start with `name` (one of several
    /// scenes run at once: interleaved lines stay readable).
    pub fn named_side<'p>(&'p self, index: usize, name: &'p str) -> PairSide<'p, 'a> {
        PairSide {
            pair: self,
            index,
            name: Some(name),
        }
    }

    /// Asks the second run to stop: the first has failed.
    pub fn abandon(&self) {
        self.abandoned.store(true, Ordering::Relaxed);
    }
}

/// One run's reporter in a [`Pair`].
pub struct PairSide<'p, 'a> {
    pair: &'p Pair<'a>,
    index: usize,
    /// The run's name, prefixed to its notes.
    name: Option<&'p str>,
}

impl Reporter for PairSide<'_, '_> {
    fn start(&self, what: &str) {
        if self.index == 0 && !self.pair.started.swap(true, Ordering::Relaxed) {
            self.pair.inner.start(what);
        }
    }
    fn progress(&self, fraction: f64) {
        let pair = self.pair;
        pair.fractions[self.index].store(fraction.clamp(0.0, 1.0).to_bits(), Ordering::Relaxed);
        let mut reported = pair.reported.lock().unwrap_or_else(|e| e.into_inner());
        let done: f64 = (0..2)
            .map(|k| pair.weights[k] * f64::from_bits(pair.fractions[k].load(Ordering::Relaxed)))
            .sum();
        if done > *reported {
            *reported = done;
            pair.inner.progress(done);
        }
    }
    /// A side's finish is the pair's only when both have returned: see [`both`].
    fn finish(&self) {}
    fn runs(&self, done: usize, total: usize) {
        self.pair.inner.runs(done, total);
    }
    fn note(&self, line: &str) {
        match self.name {
            Some(name) => self.pair.inner.note(&format!("{name}: {line}")),
            None => self.pair.inner.note(line),
        }
    }
    fn stop_requested(&self) -> bool {
        (self.index == 1 && self.pair.abandoned.load(Ordering::Relaxed))
            || self.pair.inner.stop_requested()
    }
}

/// Runs `first` and `second` at once where a core is free (rayon's `join`: in turn on a busy
/// pool), each with its side of a [`Pair`] over `reporter`; `first` has the share
/// `first_share` of the progress. When `first` fails, `second` is asked to stop.
pub fn both<A: Send, B: Send, E: Send>(
    reporter: &dyn Reporter,
    first_share: f64,
    first: impl FnOnce(&dyn Reporter) -> Result<A, E> + Send,
    second: impl FnOnce(&dyn Reporter) -> B + Send,
) -> (Result<A, E>, B) {
    let pair = Pair::new(reporter, first_share);
    join_sides(&pair, [pair.side(0), pair.side(1)], first, second)
}

/// [`both`] for two named runs (two scenes): each run's notes start with its name.
pub fn both_named<A: Send, B: Send, E: Send>(
    reporter: &dyn Reporter,
    first_share: f64,
    names: [&str; 2],
    first: impl FnOnce(&dyn Reporter) -> Result<A, E> + Send,
    second: impl FnOnce(&dyn Reporter) -> B + Send,
) -> (Result<A, E>, B) {
    let pair = Pair::new(reporter, first_share);
    let sides = [pair.named_side(0, names[0]), pair.named_side(1, names[1])];
    join_sides(&pair, sides, first, second)
}

/// Runs the two sides of `pair` at once; abandons the second when the first fails.
fn join_sides<A: Send, B: Send, E: Send>(
    pair: &Pair<'_>,
    [side0, side1]: [PairSide<'_, '_>; 2],
    first: impl FnOnce(&dyn Reporter) -> Result<A, E> + Send,
    second: impl FnOnce(&dyn Reporter) -> B + Send,
) -> (Result<A, E>, B) {
    let results = rayon::join(
        || {
            let result = first(&side0);
            if result.is_err() {
                pair.abandon();
            }
            result
        },
        || second(&side1),
    );
    if pair.started.load(Ordering::Relaxed) {
        pair.inner.finish();
    }
    results
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::atomic::AtomicUsize;

    /// Keeps what a pair reports.
    #[derive(Default)]
    struct Recorded {
        fractions: Mutex<Vec<f64>>,
        starts: AtomicUsize,
        finishes: AtomicUsize,
    }

    impl Reporter for Recorded {
        fn start(&self, _what: &str) {
            self.starts.fetch_add(1, Ordering::Relaxed);
        }
        fn progress(&self, fraction: f64) {
            self.fractions.lock().unwrap().push(fraction);
        }
        fn finish(&self) {
            self.finishes.fetch_add(1, Ordering::Relaxed);
        }
    }

    #[test]
    fn a_pair_reports_one_growing_progress_one_start_and_one_finish() {
        let recorded = Recorded::default();
        let (a, b) = both(
            &recorded,
            0.25,
            |r| {
                r.start("first");
                for k in 1..=100 {
                    r.progress(k as f64 / 100.0);
                }
                r.finish();
                Ok::<_, ()>(1)
            },
            |r| {
                r.start("second");
                for k in 1..=100 {
                    r.progress(k as f64 / 100.0);
                }
                r.finish();
                2
            },
        );
        assert_eq!((a, b), (Ok(1), 2));
        let fractions = recorded.fractions.lock().unwrap();
        assert!(fractions.windows(2).all(|w| w[1] >= w[0]), "{fractions:?}");
        assert!((fractions.last().unwrap() - 1.0).abs() < 1e-15);
        assert_eq!(recorded.starts.load(Ordering::Relaxed), 1);
        assert_eq!(recorded.finishes.load(Ordering::Relaxed), 1);
    }

    #[test]
    fn a_pair_whose_runs_fail_before_their_finish_still_finishes_once() {
        let recorded = Recorded::default();
        let (first, second) = both(
            &recorded,
            0.5,
            |r| {
                r.start("first");
                r.progress(0.5);
                Err::<(), _>("failed half way")
            },
            |r| {
                r.start("second");
                r.finish();
                2
            },
        );
        assert_eq!((first, second), (Err("failed half way"), 2));
        assert_eq!(recorded.starts.load(Ordering::Relaxed), 1);
        assert_eq!(recorded.finishes.load(Ordering::Relaxed), 1);
    }

    #[test]
    fn notes_of_named_runs_start_with_their_names() {
        #[derive(Default)]
        struct Notes(Mutex<Vec<String>>);
        impl Reporter for Notes {
            fn note(&self, line: &str) {
                self.0.lock().unwrap().push(line.to_owned());
            }
        }
        let notes = Notes::default();
        let _ = both_named(
            &notes,
            0.5,
            ["case-study", "twin"],
            |r| {
                r.note("picked 4x4");
                Ok::<_, ()>(())
            },
            |r| r.note("picked 6x6"),
        );
        let mut lines = notes.0.into_inner().unwrap();
        lines.sort();
        assert_eq!(lines, ["case-study: picked 4x4", "twin: picked 6x6"]);
    }

    #[test]
    fn when_the_first_run_fails_the_second_is_asked_to_stop() {
        let (first, second_stopped) = both(
            &Silent,
            0.5,
            |_| Err::<(), _>("failed"),
            // runs until asked to stop: after the first's failure, at once or when it
            // starts (rayon runs it after the first when no other thread takes it)
            |r| {
                while !r.stop_requested() {
                    std::thread::yield_now();
                }
                true
            },
        );
        assert_eq!(first, Err("failed"));
        assert!(second_stopped);
    }
}
