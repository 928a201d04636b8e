//! Dense LU with partial pivoting, factorised in the matrix's own storage (faer's `lu_in_place`):
//! no second n x n matrix, no explicit inverse. Used for the condensed CCM-PD system S of the
//! paper's case (n_P = 2080: 35 MB a matrix; the inverse cost twice the factorisation and one more
//! matrix of fresh pages), whose SLA needs S^{-1} only at the ends of the bonds it breaks
//! (`pd::sla::fast::columns`).

use super::checks::{check_rhs, check_solution, workspace};
use crate::error::{catch_panic, Error, Result};
use faer::dyn_stack::MemStack;
use faer::linalg::lu::partial_pivoting::solve;
use faer::perm::PermRef;
use faer::{Mat, MatMut, Par};

/// P A = L U of a square matrix, L and U in the storage of A; or of Q^T A Q, the unknowns
/// reordered (`order`, from [`super::LeadingLu`]). Made by [`DenseLu::new`] or
/// [`super::LeadingLu::finish`] (`block_lu.rs`).
pub struct DenseLu {
    lu: Mat<f64>,
    perm: Vec<usize>,
    perm_inv: Vec<usize>,
    /// the factorised matrix is Q^T A Q: its unknown i is A's unknown `order[i]`
    order: Option<Vec<usize>>,
}

/// The dense LU's pivot test: a pivot below this fraction of the largest pivot is zero (the
/// condensed PD matrix of a separated body: `tests/suite/sla_validation.rs`
/// `separation_is_a_status_not_nan`, `tests/suite/pd_extremes_validation.rs`).
pub const DENSE_PIVOT_TOL: f64 = 1e-13;

impl DenseLu {
    /// The factorisation from its parts (L and U in `lu`, the row permutation), after the pivot
    /// test: a pivot below `rel_tol` x the largest pivot (or not finite) is [`Error::Singular`].
    pub(super) fn from_parts(
        lu: Mat<f64>,
        (perm, perm_inv): (Vec<usize>, Vec<usize>),
        order: Option<Vec<usize>>,
        rel_tol: f64,
    ) -> Result<Self> {
        let n = lu.nrows();
        let (mut dmin, mut dmax) = (f64::INFINITY, 0.0f64);
        for i in 0..n {
            let d = lu[(i, i)].abs();
            dmin = dmin.min(d);
            dmax = dmax.max(d);
        }
        if n > 0 && (dmin.is_nan() || dmin <= rel_tol * dmax) {
            return Err(Error::Singular {
                detail: format!("pivot ratio {:.3e} of the dense LU", dmin / dmax),
            });
        }
        Ok(Self {
            lu,
            perm,
            perm_inv,
            order,
        })
    }

    /// Solves A X = B in place (`x` column-major, n x k).
    pub fn solve_in_place(&self, x: &mut [f64]) -> Result<()> {
        let n = self.lu.nrows();
        let k = check_rhs(n, x)?;
        if k == 0 {
            return Ok(());
        }
        if let Some(order) = &self.order {
            // Q^T A Q (Q^T x) = Q^T b
            let mut y = vec![0.0; n * k];
            for (yc, xc) in y.chunks_exact_mut(n).zip(x.chunks_exact(n)) {
                for (yi, &o) in yc.iter_mut().zip(order) {
                    *yi = xc[o];
                }
            }
            self.solve_ordered(&mut y, k)?;
            for (yc, xc) in y.chunks_exact(n).zip(x.chunks_exact_mut(n)) {
                for (&yi, &o) in yc.iter().zip(order) {
                    xc[o] = yi;
                }
            }
        } else {
            self.solve_ordered(x, k)?;
        }
        check_solution(x)
    }

    /// Solves with the factorised matrix itself (Q^T A Q when reordered), `k` columns.
    fn solve_ordered(&self, x: &mut [f64], k: usize) -> Result<()> {
        let n = self.lu.nrows();
        catch_panic("faer dense LU solve", || {
            // one thread: the solves are a few columns at a time, called from the SLA's steps
            let par = Par::Seq;
            let req = solve::solve_in_place_scratch::<usize, f64>(n, k, par);
            let mut mem = workspace(req, "the dense LU solve workspace")?;
            let perm = PermRef::new_checked(&self.perm, &self.perm_inv, n);
            solve::solve_in_place(
                self.lu.as_ref(),
                self.lu.as_ref(),
                perm,
                MatMut::from_column_major_slice_mut(x, n, k),
                par,
                MemStack::new(&mut mem),
            );
            Ok(())
        })
    }

    /// Order of the matrix.
    pub fn n(&self) -> usize {
        self.lu.nrows()
    }

    /// The smallest |pivot| of U (infinity for an empty matrix).
    pub fn min_pivot(&self) -> f64 {
        (0..self.n())
            .map(|i| self.lu[(i, i)].abs())
            .fold(f64::INFINITY, f64::min)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A non-symmetric matrix that needs row pivoting (zero leading entry): the solve reproduces
    /// a chosen x (residual and error to round-off), several right-hand sides at once.
    #[test]
    fn solves_a_pivoting_system_to_round_off() {
        let n = 40;
        let a = Mat::<f64>::from_fn(n, n, |i, j| {
            if i == 0 && j == 0 {
                0.0
            } else {
                ((i * 7 + j * 3) % 11) as f64 - 5.0 + if i == j { 20.0 } else { 0.0 }
            }
        });
        let x_true: Vec<f64> = (0..2 * n).map(|i| (i as f64 * 0.37).sin()).collect();
        let mut b = vec![0.0; 2 * n];
        for c in 0..2 {
            for i in 0..n {
                b[c * n + i] = (0..n).map(|j| a[(i, j)] * x_true[c * n + j]).sum();
            }
        }
        let b0 = b.clone();
        let lu = DenseLu::new(a.clone(), DENSE_PIVOT_TOL).unwrap();
        assert_eq!(lu.n(), n);
        lu.solve_in_place(&mut b).unwrap();
        let err = b
            .iter()
            .zip(&x_true)
            .map(|(x, y)| (x - y).abs())
            .fold(0.0, f64::max);
        assert!(err < 1e-12, "max error {err:e}");
        let mut res = 0.0_f64;
        for c in 0..2 {
            for i in 0..n {
                let ax: f64 = (0..n).map(|j| a[(i, j)] * b[c * n + j]).sum();
                res = res.max((ax - b0[c * n + i]).abs());
            }
        }
        assert!(res < 1e-11, "max residual {res:e}");
    }

    /// A singular matrix (rows 0 and 1 equal) is an error, never NaN.
    #[test]
    fn singular_matrix_is_an_error() {
        let a = Mat::<f64>::from_fn(3, 3, |i, j| (i.max(1) * 3 + j + 1) as f64);
        assert!(matches!(
            DenseLu::new(a, DENSE_PIVOT_TOL),
            Err(Error::Singular { .. })
        ));
    }
}
