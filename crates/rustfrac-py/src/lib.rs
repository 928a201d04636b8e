//! PyO3 bindings of rustfrac: the native module `rustfrac._core`.
//!
//! Bindings only: every rule (ranges, defaults, derived values) lives in `rustfrac-core`. A scene
//! crosses as a plain dict, turned into the core's scene tree without knowing any key
//! ([`tree`]); the core reads it into a `Problem` and validates it ([`scene`]); [`run`] releases
//! the GIL around the driver of the problem's method, catches panics at the boundary
//! ([`errors`]) and returns the run's record (the core's `output`: every method's result as
//! named values in groups, with their table) as the dict `rustfrac.Result` stores, by one
//! generic conversion ([`record`]; the table is `result_schema`).
//! Progress: an optional callable `progress(done, total, message)`, throttled ([`progress`]).
//!
//! Adding a method: a module with `run(py, &Problem, &Progress)` returning its record, one arm
//! in [`run`], and the Python docs. Adding a result key touches only the core.

mod arrays;
mod errors;
mod fem;
#[cfg(feature = "test-hooks")]
mod hooks;
mod pd;
mod progress;
mod record;
mod scene;
mod tree;
mod xfem;

use progress::{Progress, PROGRESS_INTERVAL_S};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use rustfrac_core::problem::Method;

/// Runs a scene dict (the TOML layout of `rustfrac.Scene.to_dict()`): validates it in the core,
/// runs its method without the GIL and returns `{method, sigma22, cmod, n_dofs, wall_time_s,
/// fields, history, scalars, meta}`. `condition = False` skips the condition estimate of the FEM
/// and XFEM solves (2 extra solves each). Raising from `progress` stops the run and re-raises.
#[pyfunction]
#[pyo3(signature = (scene, progress = None, condition = true))]
fn run<'py>(
    py: Python<'py>,
    scene: &Bound<'py, PyAny>,
    progress: Option<Py<PyAny>>,
    condition: bool,
) -> PyResult<Bound<'py, PyDict>> {
    let p = scene::problem_of(py, scene, condition)?;
    let prog = Progress::new(progress);
    match &p.method {
        Method::Fem(_) => fem::run(py, &p, &prog),
        Method::Xfem(_) => xfem::run(py, &p, &prog),
        Method::Pd(_) | Method::CcmPd(_) => pd::run(py, &p, &prog),
    }
}

/// A panic inside the core becomes `rustfrac.InternalError` (caught at the boundary); the hook
/// prints one short line instead of the default report, whose backtrace printer allocates and
/// could deadlock when the panic came from an exhausted memory limit.
fn quiet_panics() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        std::panic::set_hook(Box::new(|info| {
            use std::io::Write;
            let _ = writeln!(std::io::stderr(), "rustfrac: internal panic: {info}");
        }));
    });
}

#[pymodule]
fn _core(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    // load NumPy's C API now: loading it later, while a Ctrl-C is pending, fails inside numpy's
    // import and panicked ("Failed to access NumPy array API capsule"). numpy is imported first
    // through the fallible path, so a failing import (a pending KeyboardInterrupt, numpy missing)
    // is this module's import error, never a panic inside the capsule access
    m.py().import("numpy")?;
    let _ = numpy::PyArray1::<f64>::zeros(m.py(), 0, false);
    quiet_panics();
    m.add("PROGRESS_INTERVAL_S", PROGRESS_INTERVAL_S)?;
    m.add("COND_WARN", rustfrac_core::la::COND_WARN)?;
    m.add("COND_SINGULAR", rustfrac_core::la::COND_SINGULAR)?;
    m.add(
        "WARNING_KINDS",
        rustfrac_core::WarningKind::ALL
            .iter()
            .map(|k| k.name())
            .collect::<Vec<_>>(),
    )?;
    m.add_function(wrap_pyfunction!(run, m)?)?;
    m.add_function(wrap_pyfunction!(scene::scene_schema, m)?)?;
    m.add_function(wrap_pyfunction!(record::result_schema, m)?)?;
    m.add_function(wrap_pyfunction!(scene::scene_constants, m)?)?;
    m.add_function(wrap_pyfunction!(scene::check_section, m)?)?;
    m.add_function(wrap_pyfunction!(scene::check_scene, m)?)?;
    m.add_function(wrap_pyfunction!(scene::crack_polylines, m)?)?;
    m.add_function(wrap_pyfunction!(scene::scene_warnings, m)?)?;
    m.add_function(wrap_pyfunction!(fem::solve_fem_grid, m)?)?;
    // the test hooks are attributes, not exports: `__all__` (and so the stub) is the same in
    // every build
    #[cfg(feature = "test-hooks")]
    {
        m.setattr(
            "_progress_demo",
            wrap_pyfunction!(hooks::_progress_demo, m)?,
        )?;
        m.setattr("_panic_demo", wrap_pyfunction!(hooks::_panic_demo, m)?)?;
    }
    Ok(())
}
