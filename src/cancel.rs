//! A stop asked of a running call from outside (a signal handler, another thread). The call
//! checks it between units of work: a sweep starts no new run once it is asked, keeps every
//! finished row and returns [`Error::Interrupted`](crate::Error::Interrupted).

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

/// A shared stop request; clones share it. The default is never asked.
///
/// ```
/// let cancel = telescopic::Cancel::default();
/// let handler = cancel.clone(); // e.g. moved into a Ctrl-C handler
/// assert!(handler.request()); // the first request is the one that counts
/// assert!(!handler.request());
/// assert!(cancel.requested());
/// ```
#[derive(Clone, Debug, Default)]
pub struct Cancel(Arc<AtomicBool>);

/// Two handles are equal when they share one request.
impl PartialEq for Cancel {
    fn eq(&self, other: &Self) -> bool {
        Arc::ptr_eq(&self.0, &other.0)
    }
}

impl Cancel {
    /// Asks the call to stop; true for the first request, false when one was already made.
    pub fn request(&self) -> bool {
        !self.0.swap(true, Ordering::SeqCst)
    }

    /// Whether a stop was asked.
    pub fn requested(&self) -> bool {
        self.0.load(Ordering::SeqCst)
    }
}
