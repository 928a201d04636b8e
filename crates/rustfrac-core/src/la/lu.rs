//! Sparse LU with partial pivoting (faer) of the non-symmetric splice-coupled CCM-PD systems
//! (DESIGN.md section 4): symbolic analysis (COLAMD) once, reused for every numeric
//! refactorisation with the same pattern; several right-hand sides at once; every failure an
//! [`Error`], never a NaN, and a panic inside faer caught.

use super::checks::{check_factor_input, check_rhs, check_solution, check_square, faer_ref};
use super::csc::CscMatrix;
use crate::error::{catch_panic, Error, Result};
use faer::prelude::*;
use faer::sparse::linalg::solvers::{Lu as FaerLu, SymbolicLu};
use faer::sparse::SymbolicSparseColMatRef;

/// Sparse LU with partial pivoting of a general square matrix.
pub struct Lu {
    n: usize,
    symbolic: SymbolicLu<usize>,
    numeric: Option<FaerLu<usize, f64>>,
}

impl Lu {
    /// Symbolic analysis (COLAMD ordering) of the pattern of `a`.
    pub fn analyze(a: &CscMatrix) -> Result<Self> {
        check_square(a)?;
        catch_panic("faer symbolic LU", || {
            let sym = SymbolicSparseColMatRef::new_checked(
                a.nrows, a.ncols, &a.col_ptr, None, &a.row_idx,
            );
            let symbolic = SymbolicLu::try_new(sym)
                .map_err(|e| super::checks::faer_error("symbolic LU", e))?;
            Ok(Self {
                n: a.nrows,
                symbolic,
                numeric: None,
            })
        })
    }

    /// Analyse and factorise in one call.
    pub fn new(a: &CscMatrix) -> Result<Self> {
        let mut l = Self::analyze(a)?;
        l.factorize(a)?;
        Ok(l)
    }

    /// Dimension.
    pub fn n(&self) -> usize {
        self.n
    }

    /// Numeric factorisation reusing the symbolic analysis.
    pub fn factorize(&mut self, a: &CscMatrix) -> Result<()> {
        check_factor_input(a, self.n)?;
        self.numeric = None;
        let sym = self.symbolic.clone();
        let lu = catch_panic("faer numeric LU", || {
            FaerLu::try_new_with_symbolic(sym, faer_ref(a)).map_err(|e| Error::Singular {
                detail: format!("LU factorisation failed: {e:?}"),
            })
        })?;
        self.numeric = Some(lu);
        Ok(())
    }

    /// Solves A X = B in place; `rhs` is column-major n x k.
    pub fn solve_in_place(&self, rhs: &mut [f64]) -> Result<()> {
        let lu = self.numeric.as_ref().ok_or_else(|| Error::Internal {
            detail: "Lu::solve called before a successful factorize".into(),
        })?;
        let k = check_rhs(self.n, rhs)?;
        if k == 0 {
            return Ok(());
        }
        let n = self.n;
        catch_panic("faer LU solve", || {
            let x = MatMut::from_column_major_slice_mut(rhs, n, k);
            lu.solve_in_place(x);
            Ok(())
        })?;
        check_solution(rhs)
    }

    /// Convenience: solve for one right-hand side.
    pub fn solve(&self, b: &[f64]) -> Result<Vec<f64>> {
        let mut x = b.to_vec();
        self.solve_in_place(&mut x)?;
        Ok(x)
    }
}
