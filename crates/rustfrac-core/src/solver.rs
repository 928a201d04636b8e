//! Sparse direct solvers on top of faer: supernodal Cholesky for the SPD FEM/XFEM systems and
//! sparse LU (partial pivoting) for the non-symmetric splice-coupled CCM-PD systems (DESIGN.md
//! section 4).
//!
//! Both keep the symbolic analysis (fill-reducing ordering, elimination tree, supernodes) and reuse
//! it for every numeric refactorisation with the same pattern, solve several right-hand sides at
//! once (column-major n x k), and turn every failure into [`Error`]: a singular or indefinite matrix
//! is reported, never returned as NaN, and a panic inside faer is caught.
//!
//! Singularity in Cholesky is detected by a *relative* pivot test: a pivot below
//! `PIVOT_TOL * max|A_ii|` (faer's dynamic-regularisation hook replaces them by a sentinel we then count) means a rigid-body mode
//! or a separated part, which floating-point elimination would otherwise turn into a tiny positive
//! pivot and a huge, meaningless solution.

use crate::error::{catch_panic, Error, Result};
use crate::ordering::{inverse, nested_dissection};
use crate::sparse::CscMatrix;
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::LltRegularization;
use faer::perm::PermRef;
use faer::prelude::*;
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, LltRef, SymbolicCholesky, SymbolicCholeskyRaw, SymmetricOrdering,
};
use faer::sparse::linalg::solvers::{Lu as FaerLu, SymbolicLu};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, Side};

/// Relative pivot threshold below which a Cholesky pivot is taken as zero.
pub const PIVOT_TOL: f64 = 1e-13;
/// Value faer substitutes for a pivot below the threshold; its square root marks it in the factor.
const SENTINEL_PIVOT: f64 = 1e300;

fn check_square(a: &CscMatrix) -> Result<()> {
    if a.nrows != a.ncols {
        return Err(Error::SizeMismatch {
            what: "matrix (must be square)".into(),
            expected: a.nrows,
            got: a.ncols,
        });
    }
    Ok(())
}

fn faer_ref(a: &CscMatrix) -> SparseColMatRef<'_, usize, f64> {
    let sym = SymbolicSparseColMatRef::new_checked(a.nrows, a.ncols, &a.col_ptr, None, &a.row_idx);
    SparseColMatRef::new(sym, &a.val)
}

fn check_values(a: &CscMatrix) -> Result<()> {
    if let Some(k) = a.val.iter().position(|v| !v.is_finite()) {
        return Err(Error::invalid(
            "matrix entry",
            "finite values",
            format!("{} at position {k}", a.val[k]),
        ));
    }
    Ok(())
}

fn check_rhs(n: usize, rhs: &[f64]) -> Result<usize> {
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

fn check_solution(x: &[f64]) -> Result<()> {
    if x.iter().all(|v| v.is_finite()) {
        Ok(())
    } else {
        Err(Error::Singular {
            detail: "the solve produced non-finite values (zero pivot)".into(),
        })
    }
}

/// Sparse Cholesky L L^T of a symmetric positive definite matrix (lower triangle is read).
pub struct Cholesky {
    n: usize,
    symbolic: SymbolicCholesky<usize>,
    values: Vec<f64>,
    factorised: bool,
}

impl Cholesky {
    /// Symbolic analysis (AMD ordering, supernodes) of the pattern of `a`.
    pub fn analyze(a: &CscMatrix) -> Result<Self> {
        Self::analyze_with(a, None)
    }

    /// Symbolic analysis with geometric nested dissection when the position of every unknown is
    /// given (much less fill than AMD on large meshes), AMD otherwise.
    pub fn analyze_with(a: &CscMatrix, xy: Option<&[[f64; 2]]>) -> Result<Self> {
        check_square(a)?;
        if let Some(xy) = xy {
            if xy.len() != a.nrows {
                return Err(Error::SizeMismatch {
                    what: "unknown positions for the ordering".into(),
                    expected: a.nrows,
                    got: xy.len(),
                });
            }
        }
        let perm = xy.map(|xy| nested_dissection(&a.col_ptr, &a.row_idx, xy));
        let inv = perm.as_ref().map(|p| inverse(p));
        catch_panic("faer symbolic Cholesky", || {
            let ord = match (&perm, &inv) {
                (Some(p), Some(i)) => {
                    SymmetricOrdering::Custom(PermRef::new_checked(p, i, a.nrows))
                }
                _ => SymmetricOrdering::Amd,
            };
            let sym = SymbolicSparseColMatRef::new_checked(
                a.nrows, a.ncols, &a.col_ptr, None, &a.row_idx,
            );
            let symbolic = factorize_symbolic_cholesky(sym, Side::Lower, ord, Default::default())
                .map_err(|e| Error::Internal {
                detail: format!("symbolic Cholesky: {e:?}"),
            })?;
            let len = symbolic.len_val();
            Ok(Self {
                n: a.nrows,
                symbolic,
                values: vec![0.0; len],
                factorised: false,
            })
        })
    }

    /// Analyse and factorise in one call.
    pub fn new(a: &CscMatrix) -> Result<Self> {
        Self::new_with(a, None)
    }

    /// Analyse (nested dissection when positions are given) and factorise in one call.
    pub fn new_with(a: &CscMatrix, xy: Option<&[[f64; 2]]>) -> Result<Self> {
        let mut c = Self::analyze_with(a, xy)?;
        c.factorize(a)?;
        Ok(c)
    }

    /// Dimension.
    pub fn n(&self) -> usize {
        self.n
    }

    /// Number of stored values of the factor L (fill measure).
    pub fn factor_nnz(&self) -> usize {
        self.symbolic.len_val()
    }

    /// Numeric factorisation reusing the symbolic analysis; `a` must have the analysed pattern.
    pub fn factorize(&mut self, a: &CscMatrix) -> Result<()> {
        check_square(a)?;
        if a.nrows != self.n {
            return Err(Error::SizeMismatch {
                what: "matrix vs symbolic factorisation".into(),
                expected: self.n,
                got: a.nrows,
            });
        }
        check_values(a)?;
        self.factorised = false;
        let mut dmax: f64 = 0.0;
        for c in 0..a.ncols {
            if let Some(k) = a.find(c, c) {
                dmax = dmax.max(a.val[k].abs());
            }
        }
        if self.n > 0 && dmax == 0.0 {
            return Err(Error::Singular {
                detail: "the matrix has an all-zero diagonal".into(),
            });
        }
        let eps = PIVOT_TOL * dmax;
        let symbolic = &self.symbolic;
        let values = &mut self.values;
        catch_panic("faer numeric Cholesky", || {
            let par = faer::get_global_parallelism();
            let req = symbolic.factorize_numeric_llt_scratch::<f64>(par, Default::default());
            let mut mem = MemBuffer::try_new(req).map_err(|_| Error::Internal {
                detail: "out of memory for the Cholesky workspace".into(),
            })?;
            let reg = LltRegularization {
                dynamic_regularization_delta: SENTINEL_PIVOT,
                dynamic_regularization_epsilon: eps,
            };
            match symbolic.factorize_numeric_llt::<f64>(
                values,
                faer_ref(a),
                Side::Lower,
                reg,
                par,
                MemStack::new(&mut mem),
                Default::default(),
            ) {
                Ok(_) => Ok(()),
                Err(e) => Err(Error::NotPositiveDefinite {
                    detail: format!("{e:?}"),
                }),
            }
        })?;
        let count = self.regularised_pivots();
        if count > 0 {
            return Err(Error::Singular {
                detail: format!(
                    "{count} pivot(s) below {PIVOT_TOL:e} x max diagonal: a rigid-body mode is not \
                     constrained or a part of the body is disconnected"
                ),
            });
        }
        self.factorised = true;
        Ok(())
    }

    /// Number of pivots faer replaced by [`SENTINEL_PIVOT`] (its count is not returned by the
    /// sparse API): the diagonal entries of L of that magnitude. In the supernodal storage each
    /// supernode is a dense column-major block whose leading square holds its diagonal; the
    /// simplicial storage is scanned whole.
    fn regularised_pivots(&self) -> usize {
        let big = SENTINEL_PIVOT.sqrt() * 0.5;
        match self.symbolic.raw() {
            SymbolicCholeskyRaw::Supernodal(sn) => {
                let (begin, end, cpv) = (
                    sn.supernode_begin(),
                    sn.supernode_end(),
                    sn.col_ptr_for_val(),
                );
                (0..sn.n_supernodes())
                    .map(|s| {
                        let ncols = end[s] - begin[s];
                        let nrows = (cpv[s + 1] - cpv[s]) / ncols.max(1);
                        (0..ncols)
                            .filter(|&j| self.values[cpv[s] + j * nrows + j].abs() >= big)
                            .count()
                    })
                    .sum()
            }
            SymbolicCholeskyRaw::Simplicial(_) => {
                self.values.iter().filter(|v| v.abs() >= big).count()
            }
        }
    }

    /// Solves A X = B in place; `rhs` is column-major n x k.
    pub fn solve_in_place(&self, rhs: &mut [f64]) -> Result<()> {
        if !self.factorised {
            return Err(Error::Internal {
                detail: "Cholesky::solve called before a successful factorize".into(),
            });
        }
        let k = check_rhs(self.n, rhs)?;
        if k == 0 {
            return Ok(());
        }
        let n = self.n;
        catch_panic("faer Cholesky solve", || {
            let par = faer::get_global_parallelism();
            let llt = LltRef::<usize, f64>::new(&self.symbolic, &self.values);
            let req = self.symbolic.solve_in_place_scratch::<f64>(k, par);
            let mut mem = MemBuffer::try_new(req).map_err(|_| Error::Internal {
                detail: "out of memory for the solve workspace".into(),
            })?;
            let x = MatMut::from_column_major_slice_mut(rhs, n, k);
            llt.solve_in_place_with_conj(Conj::No, x, par, MemStack::new(&mut mem));
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
            let symbolic = SymbolicLu::try_new(sym).map_err(|e| Error::Internal {
                detail: format!("symbolic LU: {e:?}"),
            })?;
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
        check_square(a)?;
        if a.nrows != self.n {
            return Err(Error::SizeMismatch {
                what: "matrix vs symbolic factorisation".into(),
                expected: self.n,
                got: a.nrows,
            });
        }
        check_values(a)?;
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
