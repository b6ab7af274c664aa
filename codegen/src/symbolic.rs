//! The one place that touches Symbolica.
//!
//! Symbolica runs here in *restricted mode*: one Symbolica thread per user. Measured on the
//! project's machine: a second thread that touches it aborts the process (exit 134), even
//! after the first thread finished its work; so does a second process while the first is
//! alive. Hence:
//!
//! * every Symbolica call in a process runs on one dedicated thread, started on first use
//!   and kept alive until the process exits ([`run`] sends it closures);
//! * before that thread first touches Symbolica it takes an exclusive lock on a per-user
//!   lock file and keeps it until the process exits, so a second generator process (another
//!   build script, a test binary, nextest's processes) waits instead of aborting;
//! * Symbolica's banner, printed on stdout at first use, is sent to stderr instead;
//! * Symbolica values never leave the thread: jobs return plain data ([`crate::expr::Expr`],
//!   strings, numbers).

use crate::CodegenError;
use crate::expr::Expr;
use std::fs::{File, OpenOptions};
use std::io::Write;
use std::path::PathBuf;
use std::sync::OnceLock;
use std::sync::mpsc::{Sender, channel, sync_channel};
use symbolica::atom::{AtomCore, AtomView};
use symbolica::coefficient::CoefficientView;

type Job = Box<dyn FnOnce() + Send>;

/// The lock file this process's Symbolica thread takes, when set before its first use.
static LOCK_FILE: OnceLock<PathBuf> = OnceLock::new();

/// The lock file: the one set by `Builder::symbolica_lock`, else
/// `telescopic-symbolica-<uid>.lock` in the temporary directory (what every cooperating
/// process shares).
pub fn lock_path() -> PathBuf {
    if let Some(p) = LOCK_FILE.get() {
        return p.clone();
    }
    // SAFETY: getuid has no preconditions and cannot fail.
    let uid = unsafe { libc::getuid() };
    std::env::temp_dir().join(format!("telescopic-symbolica-{uid}.lock"))
}

/// Makes `path` the lock file of this process's Symbolica thread. The thread takes its lock
/// once, at its first use: a later, different path is refused.
///
/// # Errors
/// A message naming both paths when another lock file is already in use.
pub fn use_lock_file(path: &std::path::Path) -> Result<(), String> {
    let chosen = LOCK_FILE.get_or_init(|| path.to_owned());
    if chosen != path {
        return Err(format!(
            "the Symbolica lock file of this process is {}, not {}: one process takes one lock",
            chosen.display(),
            path.display()
        ));
    }
    Ok(())
}

/// Takes the process-wide exclusive lock (blocking while another process holds it).
fn take_lock() -> Result<File, String> {
    let path = lock_path();
    let file = OpenOptions::new()
        .create(true)
        .truncate(false)
        .write(true)
        .open(&path)
        .map_err(|e| {
            format!(
                "cannot open the Symbolica lock file {}: {e}",
                path.display()
            )
        })?;
    file.lock()
        .map_err(|e| format!("cannot lock {}: {e}", path.display()))?;
    Ok(file)
}

/// Touches Symbolica for the first time with stdout pointing at stderr, so its banner never
/// reaches stdout (a build script's directives, a CLI's output, a test's expected output).
fn first_touch_quietly() {
    let _ = std::io::stdout().flush();
    // SAFETY: plain descriptor duplication; every return value is checked, and the
    // original stdout is restored before anything else is written by this thread.
    unsafe {
        let saved = libc::dup(1);
        if saved >= 0 && libc::dup2(2, 1) >= 0 {
            let _ = symbolica::parse!("x_banner_probe").expand();
            let _ = std::io::stdout().flush();
            libc::dup2(saved, 1);
        } else {
            let _ = symbolica::parse!("x_banner_probe").expand();
        }
        if saved >= 0 {
            libc::close(saved);
        }
    }
}

fn worker() -> &'static Result<Sender<Job>, String> {
    static WORKER: OnceLock<Result<Sender<Job>, String>> = OnceLock::new();
    WORKER.get_or_init(|| {
        let (tx, rx) = channel::<Job>();
        let (ready_tx, ready_rx) = sync_channel::<Result<(), String>>(1);
        std::thread::Builder::new()
            .name("symbolica".into())
            .spawn(move || {
                // held (and the thread kept alive) until the process exits
                let lock = take_lock();
                let ok = lock.as_ref().map(|_| ()).map_err(Clone::clone);
                if ok.is_ok() {
                    first_touch_quietly();
                }
                let _ = ready_tx.send(ok);
                let _lock = lock;
                for job in rx {
                    job();
                }
            })
            .map_err(|e| format!("cannot start the Symbolica thread: {e}"))?;
        ready_rx
            .recv()
            .map_err(|_| "the Symbolica thread died while starting".to_string())??;
        Ok(tx)
    })
}

/// Runs `job` on the Symbolica thread and returns its (plain-data) result. Safe to call from
/// any number of threads: jobs run one at a time.
///
/// # Errors
/// [`CodegenError::Symbolica`] if the thread or the lock cannot be had, or the job panicked.
pub fn run<R: Send + 'static>(job: impl FnOnce() -> R + Send + 'static) -> Result<R, CodegenError> {
    let tx = worker()
        .as_ref()
        .map_err(|e| CodegenError::Symbolica(e.clone()))?;
    let (result_tx, result_rx) = sync_channel(1);
    tx.send(Box::new(move || {
        let r = std::panic::catch_unwind(std::panic::AssertUnwindSafe(job));
        let _ = result_tx.send(r);
    }))
    .map_err(|_| CodegenError::Symbolica("the Symbolica thread is gone".into()))?;
    match result_rx.recv() {
        Ok(Ok(r)) => Ok(r),
        Ok(Err(panic)) => {
            let msg = panic
                .downcast_ref::<String>()
                .cloned()
                .or_else(|| panic.downcast_ref::<&str>().map(|s| s.to_string()))
                .unwrap_or_else(|| "unknown panic".into());
            Err(CodegenError::Symbolica(format!(
                "a derivation step panicked: {msg}"
            )))
        }
        Err(_) => Err(CodegenError::Symbolica(
            "the Symbolica thread dropped a job".into(),
        )),
    }
}

/// `terms` in a canonical order (by content).
fn sorted(mut terms: Vec<Expr>) -> Vec<Expr> {
    terms.sort();
    terms
}

/// Converts a Symbolica expression into our own tree. Symbols whose names start with `K_`
/// are numeric constants; everything else is a symbol.
///
/// # Errors
/// A message for forms we do not emit (non-integer powers of non-`e` bases, complex or
/// floating-point numbers, unknown functions).
pub(crate) fn to_expr(view: AtomView<'_>) -> Result<Expr, String> {
    Ok(match view {
        AtomView::Num(n) => match n.get_coeff_view() {
            CoefficientView::Natural(num, den, 0, _) => Expr::Rational(num, den),
            other => return Err(format!("unsupported number {other:?}")),
        },
        AtomView::Var(v) => {
            let name = v.get_symbol().get_stripped_name().to_string();
            if name.starts_with("K_") {
                Expr::Constant(name)
            } else {
                Expr::Symbol(name)
            }
        }
        AtomView::Fun(f) => {
            let name = f.get_symbol().get_stripped_name().to_string();
            let args: Vec<AtomView> = f.iter().collect();
            if args.len() != 1 {
                return Err(format!("function {name} with {} arguments", args.len()));
            }
            let a = Box::new(to_expr(args[0])?);
            match name.as_str() {
                "cos" => Expr::Cos(a),
                "sin" => Expr::Sin(a),
                "exp" => Expr::Exp(a),
                _ => return Err(format!("unsupported function {name}")),
            }
        }
        AtomView::Pow(p) => {
            let (base, exp) = p.get_base_exp();
            if let AtomView::Var(v) = base
                && v.get_symbol().get_stripped_name() == "𝑒"
            {
                return Ok(Expr::Exp(Box::new(to_expr(exp)?)));
            }
            match to_expr(exp)? {
                Expr::Rational(n, 1) => Expr::Pow(Box::new(to_expr(base)?), n as i32),
                other => return Err(format!("non-integer power {}", other.to_text())),
            }
        }
        // Symbolica orders terms and factors by the order its symbols were first created in
        // the process, so the same configuration would come out differently after other
        // configurations; sorted by content, the output depends on the configuration alone
        AtomView::Mul(m) => Expr::Mul(sorted(m.iter().map(to_expr).collect::<Result<_, _>>()?)),
        AtomView::Add(a) => Expr::Add(sorted(a.iter().map(to_expr).collect::<Result<_, _>>()?)),
    })
}
