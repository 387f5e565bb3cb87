//! A cancellation token: a run's loop asks it between steps, and whoever
//! holds a clone (a Ctrl-C handler, a Python thread watching for
//! KeyboardInterrupt, a sweep's supervisor) can ask the run to stop. Each
//! run has its own, so two runs in one process stop independently.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

/// Shared by clones: cancelling one cancels them all.
#[derive(Clone, Debug, Default)]
pub struct CancelToken {
    flag: Arc<AtomicBool>,
}

impl CancelToken {
    /// A token not cancelled.
    pub fn new() -> Self {
        Self::default()
    }

    /// Ask the runs holding this token (or a clone) to stop at their next step.
    pub fn cancel(&self) {
        self.flag.store(true, Ordering::Relaxed);
    }

    /// Whether [`CancelToken::cancel`] was called on it or a clone.
    pub fn is_cancelled(&self) -> bool {
        self.flag.load(Ordering::Relaxed)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clones_share_one_flag_and_tokens_are_independent() {
        let (a, b) = (CancelToken::new(), CancelToken::new());
        let a2 = a.clone();
        assert!(!a.is_cancelled() && !a2.is_cancelled());
        a2.cancel();
        assert!(a.is_cancelled() && a2.is_cancelled());
        assert!(!b.is_cancelled());
    }
}
