//! What the two direct solvers share: the checks of their input (square, finite values,
//! right-hand side sizes) and output (finite solution), and the faer view of a [`CscMatrix`].

use super::csc::CscMatrix;
use crate::error::{Error, Result};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};

pub(super) fn check_square(a: &CscMatrix) -> Result<()> {
    if a.nrows != a.ncols {
        return Err(Error::SizeMismatch {
            what: "matrix (must be square)".into(),
            expected: a.nrows,
            got: a.ncols,
        });
    }
    Ok(())
}

/// A faer error of `what`: its allocation failures are [`Error::OutOfMemory`], the rest
/// [`Error::Internal`].
pub(super) fn faer_error(what: &str, e: faer::sparse::FaerError) -> Error {
    match e {
        faer::sparse::FaerError::OutOfMemory => Error::OutOfMemory {
            what: format!("the {what}"),
            needed: 0,
            available: crate::memory::available_bytes().unwrap_or(0.0) as u64,
        },
        e => Error::Internal {
            detail: format!("{what}: {e:?}"),
        },
    }
}

pub(super) fn faer_ref(a: &CscMatrix) -> SparseColMatRef<'_, usize, f64> {
    faer_ref_values(a, &a.val)
}

/// The pattern of `a` with other values (same length as `a.val`).
pub(super) fn faer_ref_values<'a>(
    a: &'a CscMatrix,
    val: &'a [f64],
) -> SparseColMatRef<'a, usize, f64> {
    let sym = SymbolicSparseColMatRef::new_checked(a.nrows, a.ncols, &a.col_ptr, None, &a.row_idx);
    SparseColMatRef::new(sym, val)
}

/// The matrix of a numeric factorisation: square, of the analysed size `n` and pattern
/// (`pattern`: its [`pattern_fingerprint`] at the analysis), finite values. A factor of another
/// pattern than the analysed one would be wrong without any error of faer's.
pub(super) fn check_factor_input(a: &CscMatrix, n: usize, pattern: u64) -> Result<()> {
    check_square(a)?;
    if a.nrows != n {
        return Err(Error::SizeMismatch {
            what: "matrix vs symbolic factorisation".into(),
            expected: n,
            got: a.nrows,
        });
    }
    if pattern_fingerprint(a) != pattern {
        return Err(Error::Internal {
            detail: "numeric factorisation of a pattern other than the analysed one".into(),
        });
    }
    check_values(a)
}

/// A hash of the pattern of `a` (its size, column pointers and row indices), kept by a symbolic
/// analysis so that each numeric factorisation can check that it gets the analysed pattern:
/// O(nnz), a small part of any factorisation.
pub(super) fn pattern_fingerprint(a: &CscMatrix) -> u64 {
    let mix = |h: u64, v: usize| {
        (h ^ v as u64)
            .wrapping_mul(0x9E37_79B9_7F4A_7C15)
            .rotate_left(29)
    };
    let h = mix(mix(0x243F_6A88_85A3_08D3, a.nrows), a.ncols);
    let h = a.col_ptr.iter().fold(h, |h, &v| mix(h, v));
    a.row_idx.iter().fold(h, |h, &v| mix(h, v))
}

pub(super) fn check_values(a: &CscMatrix) -> Result<()> {
    if let Some(k) = a.val.iter().position(|v| !v.is_finite()) {
        return Err(Error::invalid(
            "matrix entry",
            "finite values",
            format!("{} at position {k}", a.val[k]),
        ));
    }
    Ok(())
}

pub(super) fn check_rhs(n: usize, rhs: &[f64]) -> Result<usize> {
    if n == 0 {
        return Ok(0);
    }
    if rhs.len() % n != 0 {
        return Err(Error::SizeMismatch {
            what: "right-hand side length (multiple of n)".into(),
            expected: n,
            got: rhs.len(),
        });
    }
    if rhs.iter().any(|v| !v.is_finite()) {
        return Err(Error::invalid(
            "right-hand side",
            "finite values",
            "NaN/inf",
        ));
    }
    Ok(rhs.len() / n)
}

pub(super) fn check_solution(x: &[f64]) -> Result<()> {
    if x.iter().all(|v| v.is_finite()) {
        Ok(())
    } else {
        Err(Error::Singular {
            detail: "the solve produced non-finite values (zero pivot)".into(),
        })
    }
}

/// A fresh workspace of `req` for faer's kernels; one that cannot be had is
/// [`Error::OutOfMemory`] naming `what`, never an abort.
pub(super) fn workspace(
    req: faer::dyn_stack::StackReq,
    what: &str,
) -> Result<faer::dyn_stack::MemBuffer> {
    faer::dyn_stack::MemBuffer::try_new(req).map_err(|_| Error::OutOfMemory {
        what: what.into(),
        needed: req.size_bytes() as u64,
        available: crate::memory::available_bytes().unwrap_or(0.0) as u64,
    })
}
