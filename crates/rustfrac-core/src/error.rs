//! One error type for the whole core. Every fallible public entry point returns [`Result`].

use std::fmt;

/// Errors raised by the numerical core.
#[derive(Debug, Clone, PartialEq)]
pub enum Error {
    /// A parameter is outside its valid range. `param` names it, `expected` states the range.
    InvalidInput {
        param: String,
        expected: String,
        got: String,
    },
    /// A scene value has the wrong kind (a string where a number is expected). `param` is the
    /// scene key (`section.key`); `expected` says the kind and the range.
    InvalidType {
        param: String,
        expected: String,
        got: String,
    },
    /// A scene holds a key the core does not know (most often a typo); `param` is the key,
    /// `message` says which keys are allowed.
    UnknownKey { param: String, message: String },
    /// A scene lacks a key it must state (`method`, a hole's radius: the schema's `required`);
    /// `param` is the key, `message` says what needs it.
    MissingKey { param: String, message: String },
    /// Array or matrix sizes do not match.
    SizeMismatch {
        what: String,
        expected: usize,
        got: usize,
    },
    /// The system matrix is singular: a rigid-body mode is not removed, or the body separated.
    Singular { detail: String },
    /// A matrix expected to be symmetric positive definite is not (numerically).
    NotPositiveDefinite { detail: String },
    /// The body has separated into parts (SLA runs end with this status, never with NaN).
    Separated { detail: String },
    /// An internal failure (a caught panic of a dependency, an allocation failure).
    Internal { detail: String },
    /// A file could not be read or written (checkpoints).
    Io { path: String, detail: String },
    /// A run (or one of its large buffers) needs more memory than the machine or the process's
    /// limit leaves ([`crate::memory`]).
    OutOfMemory {
        what: String,
        /// estimated bytes (0: unknown, a failed allocation of a solver library)
        needed: u64,
        available: u64,
    },
}

pub type Result<T> = std::result::Result<T, Error>;

impl Error {
    /// The scene key (or core parameter name) an input error names, if it is one.
    pub fn param(&self) -> Option<&str> {
        match self {
            Error::InvalidInput { param, .. }
            | Error::InvalidType { param, .. }
            | Error::UnknownKey { param, .. }
            | Error::MissingKey { param, .. } => Some(param),
            _ => None,
        }
    }

    /// Shorthand for [`Error::InvalidInput`].
    pub fn invalid(param: &str, expected: &str, got: impl fmt::Display) -> Self {
        Error::InvalidInput {
            param: param.to_string(),
            expected: expected.to_string(),
            got: got.to_string(),
        }
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Error::InvalidInput {
                param,
                expected,
                got,
            } => write!(f, "invalid {param}: expected {expected}, got {got}"),
            Error::InvalidType {
                param,
                expected,
                got,
            } => write!(f, "{param} must be {expected}, got {got}"),
            Error::UnknownKey { message, .. } | Error::MissingKey { message, .. } => {
                f.write_str(message)
            }
            Error::SizeMismatch {
                what,
                expected,
                got,
            } => write!(f, "size mismatch in {what}: expected {expected}, got {got}"),
            Error::Singular { detail } => write!(f, "singular system: {detail}"),
            Error::NotPositiveDefinite { detail } => {
                write!(f, "matrix not positive definite: {detail}")
            }
            Error::Separated { detail } => write!(f, "body separated: {detail}"),
            Error::Internal { detail } => write!(f, "internal error: {detail}"),
            Error::Io { path, detail } => write!(f, "{path}: {detail}"),
            Error::OutOfMemory {
                what,
                needed,
                available,
            } => {
                let gib = |b: u64| b as f64 / 1073741824.0;
                let need = if *needed > 0 {
                    format!("needs about {:.2} GiB", gib(*needed))
                } else {
                    "could not be allocated".to_string()
                };
                write!(
                    f,
                    "out of memory: {what} {need}, {:.2} GiB available (free memory or the \
                     process's address-space limit); use a coarser grid or a smaller PD region",
                    gib(*available)
                )
            }
        }
    }
}

impl std::error::Error for Error {}

/// Smallest magnitude accepted for a dimensional value (length, modulus, stress, G0).
///
/// The models are scale invariant (tests/suite/scale_invariance.rs: lengths 1e-6..1e3 and E
/// 1e-6..1e12 give the same dimensionless results to 1e-9), so the only limit is double
/// precision: products such as the PD micromodulus E / (h delta^3) (eq. 47) or an energy E h L^2
/// must neither overflow nor underflow, which holds while every input lies within
/// [`MAG_MIN`, `MAG_MAX`]. Any consistent unit system fits (SI steel: E = 2e11 Pa, L = 1e-3 m).
pub const MAG_MIN: f64 = 1e-30;
/// Largest magnitude accepted for a dimensional value (see [`MAG_MIN`]).
pub const MAG_MAX: f64 = 1e30;

/// Check that the dimensional value `v` is finite and positive, within [`MAG_MIN`, `MAG_MAX`].
pub fn check_positive(param: &str, v: f64) -> Result<()> {
    if v.is_finite() && (MAG_MIN..=MAG_MAX).contains(&v) {
        Ok(())
    } else {
        Err(Error::invalid(param, "a finite number in [1e-30, 1e30]", v))
    }
}

/// Check that `v` is finite, with |v| <= [`MAG_MAX`].
pub fn check_finite(param: &str, v: f64) -> Result<()> {
    if v.is_finite() && v.abs() <= MAG_MAX {
        Ok(())
    } else {
        Err(Error::invalid(
            param,
            "a finite number with |value| <= 1e30",
            v,
        ))
    }
}

/// Run `f`, turning a panic inside it (e.g. from a dependency) into [`Error::Internal`].
pub fn catch_panic<T>(what: &str, f: impl FnOnce() -> Result<T>) -> Result<T> {
    match std::panic::catch_unwind(std::panic::AssertUnwindSafe(f)) {
        Ok(r) => r,
        Err(p) => {
            let msg = if let Some(s) = p.downcast_ref::<&str>() {
                s.to_string()
            } else if let Some(s) = p.downcast_ref::<String>() {
                s.clone()
            } else {
                "unknown panic".to_string()
            };
            Err(Error::Internal {
                detail: format!("{what}: {msg}"),
            })
        }
    }
}
