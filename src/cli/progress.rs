//! The command line's [`Reporter`]: a progress bar on stderr when it is a terminal, notes as
//! plain lines on stderr either way.

use std::io::IsTerminal;
use std::sync::Mutex;
use telescopic::Reporter;

/// Progress on stderr.
pub struct Progress {
    terminal: bool,
    bar: Mutex<Option<indicatif::ProgressBar>>,
}

impl Progress {
    /// A reporter for this process's stderr.
    pub fn new() -> Self {
        Progress {
            terminal: std::io::stderr().is_terminal(),
            bar: Mutex::new(None),
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

    fn note(&self, line: &str) {
        match self.bar().as_ref() {
            Some(bar) => bar.println(line),
            None => eprintln!("{line}"),
        }
    }
}
