//! Ctrl-C inside one long library call (Lyapunov exponents, the continuation): the crate's
//! [`Progress`] observer, asked between units of work whether to stop, takes the GIL for a
//! moment at most every [`INTERVAL`] to run Python's signal handlers (`check_signals`). A
//! `KeyboardInterrupt` they raise stops the call, and is raised when it returns.

use std::sync::{Mutex, PoisonError};
use std::time::{Duration, Instant};

use jeffcott::analysis::Progress;
use pyo3::prelude::*;

/// How often the observer looks for a signal: short for a person, long against the GIL's
/// cost (a few microseconds a look).
const INTERVAL: Duration = Duration::from_millis(50);

/// The observer that stops a library call on Ctrl-C (any exception a signal handler raises).
pub struct CtrlC {
    /// When the handlers last ran.
    last: Mutex<Instant>,
    /// What they raised; once set, the call is asked to stop at every question.
    raised: Mutex<Option<PyErr>>,
}

impl CtrlC {
    /// An observer that looks first [`INTERVAL`] from now.
    pub fn new() -> Self {
        CtrlC {
            last: Mutex::new(Instant::now()),
            raised: Mutex::new(None),
        }
    }

    /// `Err` with what a signal handler raised (the `KeyboardInterrupt`), if one did: the
    /// call's own result is then only the stop it was asked for.
    pub fn raised(self) -> PyResult<()> {
        match self
            .raised
            .into_inner()
            .unwrap_or_else(PoisonError::into_inner)
        {
            Some(e) => Err(e),
            None => Ok(()),
        }
    }
}

impl Progress for CtrlC {
    fn update(&self, _done: usize, _total: usize) {}

    fn should_stop(&self) -> bool {
        let mut raised = self.raised.lock().unwrap_or_else(PoisonError::into_inner);
        if raised.is_some() {
            return true;
        }
        let mut last = self.last.lock().unwrap_or_else(PoisonError::into_inner);
        if last.elapsed() < INTERVAL {
            return false;
        }
        *last = Instant::now();
        // The GIL for a moment: the handlers run only in the main thread, where the
        // Python caller waits (the library call runs in it with the GIL released).
        if let Err(e) = Python::attach(|py| py.check_signals()) {
            *raised = Some(e);
        }
        raised.is_some()
    }
}
