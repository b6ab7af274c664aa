//! What the command does on Ctrl-C or SIGTERM. A sweep in progress is asked to stop between
//! runs (its finished rows stay in its work file, exit 130 when it has stopped); otherwise,
//! or on a second signal, the command removes the temporary files of its outputs and exits
//! with 130 at once.

use std::path::{Path, PathBuf};
use std::sync::{Mutex, OnceLock};

/// Directories the command writes outputs into (their temporary files are removed on a stop).
static OUTPUT_DIRS: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// The running sweep's stop request and its work file.
static SWEEP: OnceLock<(telescopic::Cancel, PathBuf)> = OnceLock::new();

/// Installs the handler; call once at the start.
pub fn install() {
    let _ = ctrlc::set_handler(|| {
        if let Some((cancel, _)) = SWEEP.get()
            && cancel.request()
        {
            eprintln!("\ninterrupt: stopping after the runs in progress (again to stop at once)");
            return;
        }
        let removed = remove_temporary_files();
        match SWEEP.get().map(|(_, work)| work).filter(|w| w.exists()) {
            Some(work) => eprintln!(
                "interrupted: the finished runs are kept in {} (run again with --resume)",
                work.display()
            ),
            None if removed == 0 => eprintln!("interrupted: no partial output file was left"),
            None => eprintln!("interrupted: {removed} partial output file(s) removed"),
        }
        std::process::exit(130);
    });
}

/// Notes that the command writes `path`, so that a stop removes its temporary file.
pub fn watch_output(path: &Path) {
    watch_output_dir(telescopic::io::output::parent_dir(path).to_path_buf());
}

/// Notes that the command writes files into `dir`.
pub fn watch_output_dir(dir: PathBuf) {
    let mut dirs = OUTPUT_DIRS.lock().unwrap_or_else(|e| e.into_inner());
    if !dirs.contains(&dir) {
        dirs.push(dir);
    }
}

/// Makes a first signal ask the sweep writing `work_file` to stop between runs; the returned
/// request goes into its options.
pub fn watch_sweep(work_file: PathBuf) -> telescopic::Cancel {
    let cancel = telescopic::Cancel::default();
    let _ = SWEEP.set((cancel.clone(), work_file));
    cancel
}

/// Removes this process's temporary output files in the watched directories; how many.
fn remove_temporary_files() -> usize {
    let dirs = OUTPUT_DIRS.lock().unwrap_or_else(|e| e.into_inner());
    dirs.iter()
        .filter_map(|dir| std::fs::read_dir(dir).ok())
        .flatten()
        .flatten()
        .filter(|entry| telescopic::io::output::is_temporary_of_this_process(&entry.path()))
        .filter(|entry| std::fs::remove_file(entry.path()).is_ok())
        .count()
}
