//! Ctrl-C while the GIL is released: Python's signal handlers run only when Python code does,
//! so a long run polls them itself, every [`POLL`] of wall time at most.

use std::time::{Duration, Instant};

use pyo3::prelude::*;

/// How often a run looks for a pending signal: often enough that Ctrl-C feels immediate, rarely
/// enough that re-acquiring the GIL costs nothing measurable.
pub const POLL: Duration = Duration::from_millis(50);

/// How many calls [`Watch::interrupted`] lets pass between looks at the clock.
const CALLS_PER_CLOCK: u32 = 64;

/// Looks for a pending signal now and then; keeps the exception its handler raised.
#[derive(Debug)]
pub struct Watch {
    last: Instant,
    calls: u32,
    error: Option<PyErr>,
}

impl Default for Watch {
    fn default() -> Self {
        Self::new()
    }
}

impl Watch {
    /// A watch that looks first after [`POLL`].
    pub fn new() -> Self {
        Self {
            last: Instant::now(),
            calls: 0,
            error: None,
        }
    }

    /// Whether a signal handler raised (KeyboardInterrupt for Ctrl-C): polled at every step,
    /// it takes the GIL only once per [`POLL`].
    pub fn interrupted(&mut self) -> bool {
        if self.error.is_some() {
            return true;
        }
        self.calls = self.calls.wrapping_add(1);
        if !self.calls.is_multiple_of(CALLS_PER_CLOCK) || self.last.elapsed() < POLL {
            return false;
        }
        self.last = Instant::now();
        self.error = Python::attach(|py| py.check_signals()).err();
        self.error.is_some()
    }

    /// The exception a signal handler raised, if any.
    pub fn take(&mut self) -> Option<PyErr> {
        self.error.take()
    }
}
