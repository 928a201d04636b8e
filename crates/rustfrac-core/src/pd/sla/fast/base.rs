//! The base condensed system S_0 of the low-rank updates, in one of two forms
//! ([`super::super::cost`] chooses):
//! * **dense**: S_0^{-1} (n_P x n_P) from a dense LU: a column of it per nonzero of a, O(n_P^3)
//!   per condensation, O(n_P^2) memory.
//! * **sparse**: a sparse factor of S_0 = K_PP - K_PF Z, which is K_PP (the PD bonds, sparse)
//!   plus a dense block only on the PD rows coupled to the FEM ring x the PD columns of hybrid
//!   elements (`pc`); none for pure PD. Pure PD: K_PP is symmetric positive definite, sparse
//!   Cholesky ([`Cholesky`], nested dissection on the node positions); CCM-PD: S_0 is not
//!   symmetric (DESIGN.md section 4), sparse LU ([`Lu`], COLAMD). A solve with S_0 costs one
//!   pair of triangular solves (about 4 nnz(L) flops), the factorisation O(nnz(L)^2 / n_P). The
//!   pattern of S_0 does not change between condensations (broken bonds stay stored as zeros),
//!   so the symbolic analysis is done once.
//!
//! Both give w = S_0^{-1} a for the Sherman-Morrison-Woodbury update (`smw.rs`) and
//! x_0 = S_0^{-1} g; separation is a singular S_0 (pivot test of the factorisation) or a
//! vanishing Schur pivot of the bordering, as before.

use crate::error::{Error, Result};
use crate::la::{Cholesky, CscMatrix, Lu};
use crate::pd::sla::engine::separated;
use faer::Mat;

/// The sparse factorisation of S_0.
pub(in crate::pd::sla) enum SparseFactor {
    Cholesky(Cholesky),
    Lu(Lu),
}

/// S_0 in the form the update solves use.
pub(in crate::pd::sla) enum Base {
    /// not condensed yet
    None,
    /// S_0^{-1}
    Dense(Mat<f64>),
    Sparse(Box<SparseFactor>),
}

impl SparseFactor {
    /// Symbolic analysis of the pattern of `s`: Cholesky with nested dissection on `xy` (the
    /// positions of the unknowns) when `symmetric`, LU (COLAMD) otherwise.
    pub(in crate::pd::sla) fn analyze(
        s: &CscMatrix,
        symmetric: bool,
        xy: &[[f64; 2]],
    ) -> Result<Self> {
        Ok(if symmetric {
            Self::Cholesky(Cholesky::analyze_with(s, Some(xy))?)
        } else {
            Self::Lu(Lu::analyze(s)?)
        })
    }

    /// Numeric factorisation of `s` (the analysed pattern); a singular S_0 is a separation.
    pub(in crate::pd::sla) fn factorize(&mut self, s: &CscMatrix) -> Result<()> {
        let r = match self {
            Self::Cholesky(c) => c.factorize(s),
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
            Self::Cholesky(c) => c.solve_in_place(x),
            Self::Lu(l) => l.solve_in_place(x),
        }
    }

    /// Number of stored values of the factor (Cholesky: L; LU: not known before the numeric
    /// factorisation, None).
    pub(in crate::pd::sla) fn factor_nnz(&self) -> Option<usize> {
        match self {
            Self::Cholesky(c) => Some(c.factor_nnz()),
            Self::Lu(_) => None,
        }
    }
}

impl Base {
    /// S_0^{-1} g.
    pub(super) fn solve(&self, g: &[f64]) -> Result<Vec<f64>> {
        match self {
            Self::None => Err(Error::Internal {
                detail: "condensed system used before the condensation".into(),
            }),
            Self::Dense(sinv) => {
                let mut x = vec![0.0; g.len()];
                for (j, &gj) in g.iter().enumerate() {
                    if gj != 0.0 {
                        for (xi, &a) in x.iter_mut().zip(sinv.col_as_slice(j)) {
                            *xi += a * gj;
                        }
                    }
                }
                Ok(x)
            }
            Self::Sparse(f) => {
                let mut x = g.to_vec();
                f.solve_in_place(&mut x).map_err(|e| {
                    separated(format!("solve with the sparse condensed PD matrix: {e}"))
                })?;
                Ok(x)
            }
        }
    }

    /// w = S_0^{-1} a for a sparse a (index, value) on `n` unknowns.
    pub(super) fn solve_sparse(&self, a: &[(usize, f64)], n: usize) -> Result<Vec<f64>> {
        match self {
            Self::Dense(sinv) => {
                let mut w = vec![0.0; n];
                for &(p, val) in a {
                    for (wi, &s) in w.iter_mut().zip(sinv.col_as_slice(p)) {
                        *wi += s * val;
                    }
                }
                Ok(w)
            }
            _ => {
                let mut g = vec![0.0; n];
                for &(p, val) in a {
                    g[p] += val;
                }
                self.solve(&g)
            }
        }
    }
}
