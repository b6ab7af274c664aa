//! The command line's [`Reporter`]: a progress bar on stderr when it is a terminal, notes as
//! plain lines on stderr either way.

use std::io::IsTerminal;
use std::sync::Mutex;
use telescopic::Reporter;

/// Progress on stderr.
pub struct Progress {
    terminal: bool,
    bar: Mutex<Option<indicatif::ProgressBar>>,
    /// Runs of a multi-run command: a bar on a terminal, else the last line's time and tenth.
    runs: Mutex<RunsProgress>,
}

/// Progress of a multi-run command.
#[derive(Default)]
struct RunsProgress {
    bar: Option<indicatif::ProgressBar>,
    started: Option<std::time::Instant>,
    last_line: Option<std::time::Instant>,
    last_tenth: usize,
    /// Runs already done at the first report (kept from before by `--resume`).
    first_done: usize,
}

impl Progress {
    /// A reporter for this process's stderr.
    pub fn new() -> Self {
        Progress {
            terminal: std::io::stderr().is_terminal(),
            bar: Mutex::new(None),
            runs: Mutex::new(RunsProgress::default()),
        }
    }

    fn bar(&self) -> std::sync::MutexGuard<'_, Option<indicatif::ProgressBar>> {
        self.bar.lock().unwrap_or_else(|e| e.into_inner())
    }
}

impl Reporter for Progress {
    fn start(&self, what: &str) {
        if !self.terminal {
            return;
        }
        let bar = indicatif::ProgressBar::new(1000);
        bar.set_style(
            indicatif::ProgressStyle::with_template(
                "{msg} [{bar:40}] {percent}% ({elapsed}, ETA {eta})",
            )
            .expect("a valid template")
            .progress_chars("=> "),
        );
        bar.set_message(what.to_string());
        *self.bar() = Some(bar);
    }

    fn progress(&self, fraction: f64) {
        if let Some(bar) = self.bar().as_ref() {
            bar.set_position((fraction.clamp(0.0, 1.0) * 1000.0) as u64);
        }
    }

    fn finish(&self) {
        if let Some(bar) = self.bar().take() {
            bar.finish_and_clear();
        }
    }

    fn runs(&self, done: usize, total: usize) {
        let mut r = self.runs.lock().unwrap_or_else(|e| e.into_inner());
        let now = std::time::Instant::now();
        if r.started.is_none() {
            r.started = Some(now);
            r.first_done = done;
        }
        let started = r.started.unwrap_or(now);
        if self.terminal {
            let bar = r.bar.get_or_insert_with(|| {
                let bar = indicatif::ProgressBar::new(total as u64);
                bar.set_style(
                    indicatif::ProgressStyle::with_template(
                        "runs [{bar:40}] {pos}/{len} ({per_sec}, ETA {eta})",
                    )
                    .expect("a valid template")
                    .progress_chars("=> "),
                );
                bar
            });
            bar.set_position(done as u64);
            if done >= total {
                bar.finish_and_clear();
            }
            return;
        }
        // not a terminal: a line at every tenth, and at least every 30 s between them
        let tenth = (10 * done).checked_div(total).unwrap_or(10);
        let due = r
            .last_line
            .is_none_or(|t| now.duration_since(t).as_secs() >= 30);
        if tenth > r.last_tenth || due || done == total {
            let elapsed = now.duration_since(started).as_secs_f64();
            let rate = (done - r.first_done.min(done)) as f64 / elapsed.max(1e-9);
            let eta = if rate > 0.0 {
                format!("{:.0} s", (total - done) as f64 / rate)
            } else {
                "unknown".into()
            };
            eprintln!("runs {done}/{total} ({rate:.1}/s, ETA {eta})");
            r.last_tenth = tenth;
            r.last_line = Some(now);
        }
    }

    fn note(&self, line: &str) {
        match self.bar().as_ref() {
            Some(bar) => bar.println(line),
            None => eprintln!("{line}"),
        }
    }
}
