//! Throttled progress reports from the core's worker threads to a Python callable.
//!
//! Long runs take an optional callable `progress(done, total, message)`. It is called at most
//! every [`PROGRESS_INTERVAL_S`] seconds (plus the forced first and last reports), and the GIL
//! is acquired only for that call. If the callback raises (e.g. `KeyboardInterrupt`), the run is
//! asked to stop and the exception is re-raised afterwards, with the finished part of the run
//! attached as its `partial` attribute (the shaped result dict; XFEM growth and the SLA stop
//! with status "cancelled"). Without a callback the same reports check for a pending Ctrl-C.

use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::sync::Mutex;
use std::time::{Duration, Instant};

/// Minimum time between two progress callbacks.
pub const PROGRESS_INTERVAL_S: f64 = 0.1;

/// A progress sink usable from worker threads: forwards `(done, total, message)` to a Python
/// callable at most every [`PROGRESS_INTERVAL_S`] seconds, acquiring the GIL only then.
pub struct Progress {
    callback: Option<Py<PyAny>>,
    interval: Duration,
    state: Mutex<ProgressState>,
}

struct ProgressState {
    last: Option<Instant>,
    error: Option<PyErr>,
    calls: usize,
}

impl Progress {
    pub fn new(callback: Option<Py<PyAny>>) -> Self {
        Self {
            callback,
            interval: Duration::from_secs_f64(PROGRESS_INTERVAL_S),
            state: Mutex::new(ProgressState {
                last: None,
                error: None,
                calls: 0,
            }),
        }
    }

    /// Reports progress; `force` bypasses the throttle (first and last report). Returns `false`
    /// when the run should stop (the callback raised).
    pub fn report(&self, done: usize, total: usize, message: &str, force: bool) -> bool {
        // a throttled report from one of several worker threads never waits for another's callback
        let mut st = if force {
            self.state.lock().unwrap_or_else(|p| p.into_inner())
        } else {
            match self.state.try_lock() {
                Ok(g) => g,
                Err(std::sync::TryLockError::Poisoned(p)) => p.into_inner(),
                Err(std::sync::TryLockError::WouldBlock) => return true,
            }
        };
        if st.error.is_some() {
            return false;
        }
        let now = Instant::now();
        if !force
            && st
                .last
                .is_some_and(|t| now.duration_since(t) < self.interval)
        {
            return true;
        }
        st.last = Some(now);
        // without a callback, a pending Ctrl-C (SIGINT) still stops the run: the interpreter's
        // signal handlers run here (on the main thread) and raise KeyboardInterrupt
        let r = match &self.callback {
            Some(cb) => {
                st.calls += 1;
                Python::attach(|py| cb.call1(py, (done, total, message)).map(|_| ()))
            }
            None => Python::attach(|py| py.check_signals()),
        };
        match r {
            Ok(()) => true,
            Err(e) => {
                st.error = Some(e);
                false
            }
        }
    }

    /// Number of callbacks made so far (the test hooks report it).
    #[cfg(feature = "test-hooks")]
    pub fn calls(&self) -> usize {
        self.state.lock().map(|s| s.calls).unwrap_or(0)
    }

    /// The exception the callback raised, if any (to re-raise once the GIL is held again).
    pub fn take_error(&self) -> Option<PyErr> {
        self.state
            .lock()
            .unwrap_or_else(|p| p.into_inner())
            .error
            .take()
    }

    /// The shaped result of a finished run `r` (`shape`), or, when the callback raised or Ctrl-C
    /// came, that exception with the shaped finished part attached as `partial`.
    pub fn deliver<'py, T>(
        &self,
        py: Python<'py>,
        r: PyResult<T>,
        shape: impl FnOnce(T) -> PyResult<Bound<'py, PyDict>>,
    ) -> PyResult<Bound<'py, PyDict>> {
        match (self.take_error(), r) {
            (Some(e), Ok(r)) => {
                if let Ok(d) = shape(r) {
                    e.value(py).setattr("partial", d)?;
                }
                Err(e)
            }
            (Some(e), Err(_)) => Err(e),
            (None, r) => shape(r?),
        }
    }
}
