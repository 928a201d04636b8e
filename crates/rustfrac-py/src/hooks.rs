//! Test hooks of the bindings, compiled only with the `test-hooks` feature (the test suite's
//! build): they exercise the progress throttle and the panic boundary without a model.

use crate::errors::detached;
use crate::progress::Progress;
use pyo3::prelude::*;
use rustfrac_core::error::Error as CoreError;
use std::time::Duration;

/// Exercises the progress mechanism: `steps` steps of `step_s` seconds each without the GIL,
/// reporting every step through the throttle. Returns the number of callbacks made.
#[pyfunction]
#[pyo3(signature = (steps, step_s, progress = None))]
pub fn _progress_demo(
    py: Python<'_>,
    steps: usize,
    step_s: f64,
    progress: Option<Py<PyAny>>,
) -> PyResult<usize> {
    let prog = Progress::new(progress);
    let dt = Duration::from_secs_f64(step_s.max(0.0));
    detached(py, "progress demo", || {
        for i in 0..steps {
            std::thread::sleep(dt);
            if !prog.report(i + 1, steps, "demo", i + 1 == steps) {
                break;
            }
        }
        Ok(())
    })?;
    if let Some(err) = prog.take_error() {
        return Err(err);
    }
    Ok(prog.calls())
}

/// Raises a Rust panic inside the detached region (tests that it reaches Python as
/// `InternalError`, not as a crash).
#[pyfunction]
pub fn _panic_demo(py: Python<'_>) -> PyResult<()> {
    detached(py, "panic demo", || -> Result<(), CoreError> {
        panic!("deliberate panic for testing")
    })
}
