//! The base condensed system S_0 of the low-rank updates, in one of two forms
//! ([`super::super::cost`] chooses):
//! * **dense**: a dense LU of S_0 (n_P x n_P, in place: [`DenseLu`]), O(n_P^3) per
//!   condensation, O(n_P^2) memory; the columns of S_0^{-1} the updates need are solved with it
//!   (`columns.rs`), never the whole inverse.
//! * **sparse**: a sparse factor of S_0 = K_PP - K_PF Z, which is K_PP (the PD bonds, sparse)
//!   plus a dense block only on the PD rows coupled to the FEM ring x the PD columns of hybrid
//!   elements (`pc`); none for pure PD. Pure PD: K_PP is symmetric positive definite, sparse
//!   Cholesky ([`Cholesky`], nested dissection on the node positions); CCM-PD: S_0 is not
//!   symmetric (DESIGN.md section 4), sparse LU ([`Lu`], COLAMD with the dense block's columns
//!   ordered last: [`Lu::analyze_dense_last`]). A solve with S_0 costs one
//!   pair of triangular solves (about 4 nnz(L) flops), the factorisation O(nnz(L)^2 / n_P). The
//!   pattern of S_0 does not change between condensations (broken bonds stay stored as zeros),
//!   so the symbolic analysis is done once.
//!
//! Both give w = S_0^{-1} a for the Sherman-Morrison-Woodbury update (`smw.rs`, from kept columns)
//! and
//! x_0 = S_0^{-1} g; separation is a singular S_0 (pivot test of the factorisation) or a
//! vanishing Schur pivot of the bordering, as before.

use crate::error::{Error, Result};
use crate::la::{unit_vectors, Cholesky, CscMatrix, DenseLu, Lu, SparseForward};
use crate::pd::sla::engine::separated;

/// The sparse factorisation of S_0.
pub(in crate::pd::sla) enum SparseFactor {
    /// with the elimination tree of its last factorisation, for columns of S_0^-1 by sparse
    /// forward solves ([`SparseForward::solve_unit_columns`])
    Cholesky(Cholesky, Option<SparseForward>),
    Lu(Lu),
}

/// S_0 in the form the update solves use.
pub(in crate::pd::sla) enum Base {
    /// not condensed yet
    None,
    /// the dense LU of S_0
    Dense(Box<DenseLu>),
    Sparse(Box<SparseFactor>),
}

impl SparseFactor {
    /// Symbolic analysis of the pattern of `s`: Cholesky with nested dissection on `xy` (the
    /// positions of the unknowns) when `symmetric`, LU (COLAMD, dense columns last) otherwise.
    pub(in crate::pd::sla) fn analyze(
        s: &CscMatrix,
        symmetric: bool,
        xy: &[[f64; 2]],
    ) -> Result<Self> {
        Ok(if symmetric {
            Self::Cholesky(Cholesky::analyze_with(s, Some(xy))?, None)
        } else {
            Self::Lu(Lu::analyze_dense_last(s)?)
        })
    }

    /// Numeric factorisation of `s` (the analysed pattern); a singular S_0 is a separation.
    pub(in crate::pd::sla) fn factorize(&mut self, s: &CscMatrix) -> Result<()> {
        let r = match self {
            Self::Cholesky(c, tree) => {
                *tree = None;
                c.factorize(s).and_then(|()| {
                    *tree = Some(SparseForward::new(c)?);
                    Ok(())
                })
            }
            Self::Lu(l) => l.factorize(s),
        };
        r.map_err(|e| match e {
            Error::Singular { detail } | Error::NotPositiveDefinite { detail } => {
                separated(format!("sparse condensed PD matrix is singular: {detail}"))
            }
            e => e,
        })
    }

    /// Solves S_0 X = B in place (`x` column-major, n_P x k).
    pub(in crate::pd::sla) fn solve_in_place(&self, x: &mut [f64]) -> Result<()> {
        match self {
            Self::Cholesky(c, _) => c.solve_in_place(x),
            Self::Lu(l) => l.solve_in_place(x),
        }
    }

    /// Number of stored values of the factor (Cholesky: L; LU: not known before the numeric
    /// factorisation, None).
    pub(in crate::pd::sla) fn factor_nnz(&self) -> Option<usize> {
        match self {
            Self::Cholesky(c, _) => Some(c.factor_nnz()),
            Self::Lu(_) => None,
        }
    }
}

impl Base {
    /// Solves S_0 X = B in place (`x` column-major, n_P x k); a failed solve is a separation.
    pub(super) fn solve_in_place(&self, x: &mut [f64]) -> Result<()> {
        let r = match self {
            Self::None => {
                return Err(Error::Internal {
                    detail: "condensed system used before the condensation".into(),
                })
            }
            Self::Dense(lu) => lu.solve_in_place(x),
            Self::Sparse(f) => f.solve_in_place(x),
        };
        r.map_err(solve_failed)
    }

    /// Columns `cols` of S_0^{-1} (column-major, n_P x k): by sparse forward solves for the
    /// sparse Cholesky, by a solve of the unit vectors otherwise.
    pub(super) fn unit_columns(&self, cols: &[usize], n: usize) -> Result<Vec<f64>> {
        if let Self::Sparse(f) = self {
            if let SparseFactor::Cholesky(c, Some(tree)) = f.as_ref() {
                return tree
                    .solve_unit_columns(c, cols, &mut tree.work())
                    .map_err(solve_failed);
            }
        }
        let mut x = unit_vectors(n, cols);
        self.solve_in_place(&mut x)?;
        Ok(x)
    }

    /// S_0^{-1} g.
    pub(super) fn solve(&self, g: &[f64]) -> Result<Vec<f64>> {
        let mut x = g.to_vec();
        self.solve_in_place(&mut x)?;
        Ok(x)
    }
}

/// A failed solve with S_0 is a separation.
fn solve_failed(e: Error) -> Error {
    separated(format!("solve with the condensed PD matrix: {e}"))
}
