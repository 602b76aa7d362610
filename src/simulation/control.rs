//! Control of a run from outside its thread: a stop request that a signal
//! handler or Python's Ctrl-C check may set at any time, and the step the
//! run has reached. The run loop polls the request after every step, so a
//! run stops at the end of the step in progress, with its outputs flushed
//! and closed ([`super::Stop::Interrupted`]).

use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};

/// A stop request and the step reached, shared between a run and whoever
/// may stop it.
#[derive(Debug, Default)]
pub struct Control {
    stop: AtomicBool,
    step: AtomicU64,
}

impl Control {
    /// No stop requested, step 0.
    pub fn new() -> Control {
        Control::default()
    }

    /// Asks the run to stop at the end of the current step.
    pub fn request_stop(&self) {
        self.stop.store(true, Ordering::SeqCst);
    }

    /// Whether a stop was requested.
    pub fn stop_requested(&self) -> bool {
        self.stop.load(Ordering::Relaxed)
    }

    /// The last step the run completed.
    pub fn step(&self) -> u64 {
        self.step.load(Ordering::Relaxed)
    }

    /// Records the step reached (by the run loops).
    pub(crate) fn set_step(&self, step: u64) {
        self.step.store(step, Ordering::Relaxed);
    }
}
