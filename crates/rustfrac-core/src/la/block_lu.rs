//! Dense block LU with the leading block eliminated first, so that a later change confined to the
//! trailing block costs only that block's factorisation.
//!
//! With A = [A11 A12; A21 A22] (A11 of order n1), partial pivoting within A11 gives
//! P1 A11 = L11 U11, then U12 = L11^{-1} P1 A12, L21 = A21 U11^{-1} and the Schur complement
//! A22' = A22 - L21 U12 ([`LeadingLu::new`]). A22 may then change by any D (the CCM-PD
//! condensation's -K_PF Z term lives only in this block): A22' + D is factorised,
//! P2 (A22' + D) = L22 U22, and L21 <- P2 L21 ([`LeadingLu::finish`]), which is the LU of
//! [A11 A12; A21 A22 + D] with the row permutation diag(P1, P2), in faer's storage, so
//! [`DenseLu`] solves with it. The pivots are sought within each block (block LU): stable when
//! A11 is well conditioned, as the stiffness of the PD nodes away from the FEM coupling is.

use super::checks::workspace;
use super::dense_lu::DenseLu;
use crate::error::{catch_panic, Error, Result};
use faer::dyn_stack::{MemStack, StackReq};
use faer::linalg::lu::partial_pivoting::factor;
use faer::linalg::matmul::matmul;
use faer::linalg::triangular_solve::{
    solve_lower_triangular_in_place, solve_unit_lower_triangular_in_place,
};
use faer::perm::{permute_rows_in_place, permute_rows_in_place_scratch, PermRef};
use faer::prelude::{Reborrow, ReborrowMut};
use faer::{Accum, Mat, MatMut, Par};

/// The first stage of the block LU: A11 factorised, A12, A21 transformed, A22 the Schur
/// complement, still open to changes ([`LeadingLu::trailing_mut`]).
pub struct LeadingLu {
    a: Mat<f64>,
    n1: usize,
    perm: Vec<usize>,
    perm_inv: Vec<usize>,
    order: Option<Vec<usize>>,
}

impl LeadingLu {
    /// Eliminates the leading `n1` x `n1` block of the square `a` on the threads `par`. When `a`
    /// is the reordered Q^T S Q of a matrix S, `order[i]` names S's unknown i (the solves of the
    /// finished [`DenseLu`] then take and return S's order).
    pub fn new(mut a: Mat<f64>, n1: usize, order: Option<Vec<usize>>, par: Par) -> Result<Self> {
        let n = a.nrows();
        if a.ncols() != n || n1 > n {
            return Err(Error::SizeMismatch {
                what: "a square matrix with its leading block inside it".into(),
                expected: n,
                got: if a.ncols() != n { a.ncols() } else { n1 },
            });
        }
        if let Some(o) = &order {
            if o.len() != n {
                return Err(Error::SizeMismatch {
                    what: "the order of the unknowns".into(),
                    expected: n,
                    got: o.len(),
                });
            }
        }
        let (mut perm, mut perm_inv) = (vec![0usize; n], vec![0usize; n]);
        let req = StackReq::any_of(&[
            factor::lu_in_place_scratch::<usize, f64>(n1, n1, par, Default::default()),
            permute_rows_in_place_scratch::<usize, f64>(n1, n - n1),
        ]);
        let mut mem = workspace(req, "the dense LU workspace")?;
        catch_panic("faer block LU (leading block)", || {
            let (top, bot) = a.as_mut().split_at_row_mut(n1);
            let (mut a11, mut a12) = top.split_at_col_mut(n1);
            let (mut a21, a22) = bot.split_at_col_mut(n1);
            let (p, pi) = (&mut perm[..n1], &mut perm_inv[..n1]);
            factor::lu_in_place(
                a11.rb_mut(),
                p,
                pi,
                par,
                MemStack::new(&mut mem),
                Default::default(),
            );
            let p1 = PermRef::new_checked(&perm[..n1], &perm_inv[..n1], n1);
            permute_rows_in_place(a12.rb_mut(), p1, MemStack::new(&mut mem));
            // U12 = L11^{-1} P1 A12; L21 = A21 U11^{-1} (L21^T = U11^{-T} A21^T)
            solve_unit_lower_triangular_in_place(a11.rb(), a12.rb_mut(), par);
            solve_lower_triangular_in_place(
                a11.rb().transpose(),
                a21.rb_mut().transpose_mut(),
                par,
            );
            matmul(a22, Accum::Add, a21.rb(), a12.rb(), -1.0, par);
            Ok(())
        })?;
        Ok(Self {
            a,
            n1,
            perm,
            perm_inv,
            order,
        })
    }

    /// The trailing block (the Schur complement A22 - L21 U12), to be changed before
    /// [`LeadingLu::finish`].
    pub fn trailing_mut(&mut self) -> MatMut<'_, f64> {
        let n1 = self.n1;
        let n2 = self.a.nrows() - n1;
        self.a.as_mut().submatrix_mut(n1, n1, n2, n2)
    }

    /// Order of the leading block.
    pub fn n1(&self) -> usize {
        self.n1
    }

    /// Factorises the trailing block on the threads `par` and returns the whole LU; a pivot below
    /// `rel_tol` x the largest (or not finite) is [`Error::Singular`], as in [`DenseLu::new`].
    pub fn finish(mut self, rel_tol: f64, par: Par) -> Result<DenseLu> {
        let (n, n1) = (self.a.nrows(), self.n1);
        let n2 = n - n1;
        let req = StackReq::any_of(&[
            factor::lu_in_place_scratch::<usize, f64>(n2, n2, par, Default::default()),
            permute_rows_in_place_scratch::<usize, f64>(n2, n1),
        ]);
        let mut mem = workspace(req, "the dense LU workspace")?;
        let (perm, perm_inv) = (&mut self.perm, &mut self.perm_inv);
        catch_panic("faer block LU (trailing block)", || {
            let (_, bot) = self.a.as_mut().split_at_row_mut(n1);
            let (mut a21, mut a22) = bot.split_at_col_mut(n1);
            factor::lu_in_place(
                a22.rb_mut(),
                &mut perm[n1..],
                &mut perm_inv[n1..],
                par,
                MemStack::new(&mut mem),
                Default::default(),
            );
            let p2 = PermRef::new_checked(&perm[n1..], &perm_inv[n1..], n2);
            permute_rows_in_place(a21.rb_mut(), p2, MemStack::new(&mut mem));
            Ok(())
        })?;
        for i in n1..n {
            perm[i] += n1;
            perm_inv[i] += n1;
        }
        let (perm, perm_inv) = (std::mem::take(perm), std::mem::take(perm_inv));
        DenseLu::from_parts(self.a, (perm, perm_inv), self.order, rel_tol)
    }
}

impl DenseLu {
    /// Factorises `a` in place. A pivot below `rel_tol` x the largest pivot (or not finite) is
    /// [`Error::Singular`]. The one-stage LU is the two-stage one ([`LeadingLu`]) with an empty
    /// leading block.
    pub fn new(a: Mat<f64>, rel_tol: f64) -> Result<Self> {
        let n = a.nrows();
        if a.ncols() != n {
            return Err(Error::SizeMismatch {
                what: "columns of a square matrix".into(),
                expected: n,
                got: a.ncols(),
            });
        }
        let par = faer::get_global_parallelism();
        LeadingLu::new(a, 0, None, par)?.finish(rel_tol, par)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::la::DENSE_PIVOT_TOL;

    /// A non-symmetric matrix whose trailing block needs row pivoting.
    fn matrix(n: usize) -> Mat<f64> {
        Mat::<f64>::from_fn(n, n, |i, j| {
            let v = ((i * 7 + j * 3) % 11) as f64 - 5.0;
            if i == j && i < n / 2 {
                v + 25.0
            } else if i == n - 1 && j == n - 1 {
                0.0
            } else {
                v
            }
        })
    }

    fn matvec(a: &Mat<f64>, x: &[f64]) -> Vec<f64> {
        (0..a.nrows())
            .map(|i| (0..a.ncols()).map(|j| a[(i, j)] * x[j]).sum())
            .collect()
    }

    /// The block LU of [A11 A12; A21 A22 + D], D added after the leading stage, solves that
    /// matrix to round-off (residual and error against a chosen x), with and without a reordering
    /// of the unknowns, and agrees with the one-stage [`DenseLu`].
    #[test]
    fn block_lu_with_a_late_trailing_change_solves_the_whole_matrix() {
        let (n, n1) = (30, 18);
        let d = |i: usize, j: usize| ((i + 2 * j) % 5) as f64 * 0.7 - 1.1;
        for reorder in [false, true] {
            // S in its own order; the factorised matrix is Q^T S Q with `order`
            let order: Vec<usize> = if reorder {
                (0..n).map(|i| (i * 7) % n).collect()
            } else {
                (0..n).collect()
            };
            let m = matrix(n);
            let mut s = Mat::<f64>::zeros(n, n);
            for i in 0..n {
                for j in 0..n {
                    s[(order[i], order[j])] =
                        m[(i, j)] + if i >= n1 && j >= n1 { d(i, j) } else { 0.0 };
                }
            }
            let mut lead = LeadingLu::new(m.clone(), n1, Some(order.clone()), Par::Seq).unwrap();
            assert_eq!(lead.n1(), n1);
            let mut t = lead.trailing_mut();
            for i in 0..n - n1 {
                for j in 0..n - n1 {
                    t[(i, j)] += d(n1 + i, n1 + j);
                }
            }
            let lu = lead.finish(DENSE_PIVOT_TOL, Par::Seq).unwrap();
            let x_true: Vec<f64> = (0..2 * n).map(|i| (i as f64 * 0.37).sin()).collect();
            let mut b: Vec<f64> = x_true.chunks(n).flat_map(|xc| matvec(&s, xc)).collect();
            let b0 = b.clone();
            lu.solve_in_place(&mut b).unwrap();
            let err = b
                .iter()
                .zip(&x_true)
                .map(|(x, y)| (x - y).abs())
                .fold(0.0, f64::max);
            assert!(err < 1e-11, "reorder {reorder}: max error {err:e}");
            let one = DenseLu::new(s.clone(), DENSE_PIVOT_TOL).unwrap();
            let mut b1 = b0.clone();
            one.solve_in_place(&mut b1).unwrap();
            let diff = b
                .iter()
                .zip(&b1)
                .map(|(x, y)| (x - y).abs())
                .fold(0.0, f64::max);
            assert!(
                diff < 1e-11,
                "reorder {reorder}: block vs one-stage {diff:e}"
            );
        }
    }

    /// A trailing change that makes the matrix singular is an error at `finish`, never NaN.
    #[test]
    fn singular_after_the_trailing_change_is_an_error() {
        let (n, n1) = (12, 8);
        let m = matrix(n);
        let mut lead = LeadingLu::new(m, n1, None, Par::Seq).unwrap();
        // make the Schur complement zero: the whole matrix singular
        lead.trailing_mut().fill(0.0);
        assert!(matches!(
            lead.finish(DENSE_PIVOT_TOL, Par::Seq),
            Err(Error::Singular { .. })
        ));
    }
}
