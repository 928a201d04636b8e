//! Core errors as the exception classes of `rustfrac.errors`, and the GIL-free call that catches
//! panics at the boundary.
//!
//! | core error                              | Python exception                              |
//! |-----------------------------------------|-----------------------------------------------|
//! | `InvalidInput` / `SizeMismatch`         | `InvalidParameterError` (a `ValueError`)      |
//! | `InvalidType`                           | `InvalidTypeError` (also a `TypeError`)       |
//! | `UnknownKey`                            | `UnknownParameterError`                       |
//! | `MissingKey`                            | `MissingParameterError`                       |
//! | `Singular` / `NotPositiveDefinite`      | `SingularSystemError`                         |
//! | `Separated`                             | `SeparatedError` (a `SingularSystemError`)    |
//! | `Internal`, caught panic                | `InternalError`                               |
//! | `Io`                                    | `CheckpointIOError` (an `OSError`)            |
//!
//! Input errors carry the scene key of the refused parameter as the exception's `param`.

use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use rustfrac_core::error::Error as CoreError;

/// Raises `rustfrac.errors.<name>(msg, param)`, falling back to a builtin if the package is
/// missing.
pub fn py_error(py: Python<'_>, name: &str, msg: String, param: Option<&str>) -> PyErr {
    let made = py
        .import("rustfrac.errors")
        .and_then(|m| m.getattr(name))
        .and_then(|cls| match param {
            Some(p) => cls.call1((msg.clone(), p)),
            None => cls.call1((msg.clone(),)),
        });
    match made {
        Ok(inst) => PyErr::from_value(inst),
        Err(_) if name.starts_with("Invalid") || name.starts_with("Unknown") => {
            PyValueError::new_err(msg)
        }
        Err(_) => PyRuntimeError::new_err(msg),
    }
}

/// The Python exception of a core error.
pub fn core_err(py: Python<'_>, e: CoreError) -> PyErr {
    let msg = e.to_string();
    let param = match &e {
        CoreError::SizeMismatch { what, .. } => Some(what.clone()),
        _ => e.param().map(str::to_string),
    };
    let name = match e {
        CoreError::InvalidInput { .. } | CoreError::SizeMismatch { .. } => "InvalidParameterError",
        CoreError::InvalidType { .. } => "InvalidTypeError",
        CoreError::UnknownKey { .. } => "UnknownParameterError",
        CoreError::MissingKey { .. } => "MissingParameterError",
        CoreError::Singular { .. } | CoreError::NotPositiveDefinite { .. } => "SingularSystemError",
        CoreError::Separated { .. } => "SeparatedError",
        CoreError::Internal { .. } => "InternalError",
        CoreError::Io { .. } => "CheckpointIOError",
        CoreError::OutOfMemory { .. } => "OutOfMemoryError",
    };
    py_error(py, name, msg, param.as_deref())
}

/// Runs `f` without the GIL, turning a panic into `CoreError::Internal`.
pub fn detached<T: Send>(
    py: Python<'_>,
    what: &str,
    f: impl FnOnce() -> Result<T, CoreError> + Send,
) -> PyResult<T> {
    let r = py.detach(|| rustfrac_core::error::catch_panic(what, f));
    r.map_err(|e| core_err(py, e))
}
