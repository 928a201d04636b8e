//! Partial Cholesky onto interface unknowns: the block of A^{-1} at a few unknowns I for the cost
//! of one sparse factorisation.
//!
//! With the unknowns ordered [O, I] (AMD on A_OO, then I last), the factor of the SPD matrix is
//! L = [L_OO 0; L_IO L_II] and its trailing dense block gives the Schur complement
//! A_II - A_IO A_OO^{-1} A_OI = L_II L_II^T, hence (A^{-1})_II = (L_II L_II^T)^{-1} (block
//! inversion). With the Jacobi scaling of [`Cholesky`] (the factor is that of D A D, D diagonal),
//! (A^{-1})_II = D_I L_II^{-T} L_II^{-1} D_I. The same factor solves the full system as usual.

use super::checks::{faer_error, workspace};
use super::cholesky::Cholesky;
use super::csc::CscMatrix;
use super::ordering::nested_dissection;
use crate::error::{catch_panic, Error, Result};
use faer::dyn_stack::MemStack;
use faer::linalg::triangular_solve::{
    solve_lower_triangular_in_place, solve_upper_triangular_in_place,
};
use faer::prelude::ReborrowMut;
use faer::sparse::linalg::amd;
use faer::sparse::SymbolicSparseColMatRef;
use faer::{Mat, MatMut, Par};

/// Sparse Cholesky of A with the interface unknowns eliminated last, and the factor's dense
/// trailing block L_II.
pub struct InterfaceCholesky {
    chol: Cholesky,
    /// the interface unknowns, in the order of L_II's rows
    iface: Vec<usize>,
    l_ii: Mat<f64>,
}

impl InterfaceCholesky {
    /// Orders `iface` (distinct unknowns of `a`) last, the rest by geometric nested dissection of
    /// A_OO when the unknowns' positions `xy` are given (less fill on large meshes), AMD
    /// otherwise, and factorises on the threads `par` ([`Cholesky::factorize_with`]).
    pub fn new(a: &CscMatrix, iface: &[usize], xy: Option<&[[f64; 2]]>, par: Par) -> Result<Self> {
        let n = a.nrows;
        let mut pos = vec![0usize; n];
        for &d in iface {
            if d >= n || pos[d] == usize::MAX {
                return Err(Error::Internal {
                    detail: format!("interface unknown {d} repeated or not below {n}"),
                });
            }
            pos[d] = usize::MAX;
        }
        let rest: Vec<usize> = (0..n).filter(|&d| pos[d] != usize::MAX).collect();
        for (k, &d) in rest.iter().enumerate() {
            pos[d] = k;
        }
        if let Some(xy) = xy {
            if xy.len() != n {
                return Err(Error::SizeMismatch {
                    what: "unknown positions for the ordering".into(),
                    expected: n,
                    got: xy.len(),
                });
            }
        }
        let order = rest_order(a, &rest, &pos, xy)?;
        let perm: Vec<usize> = order
            .iter()
            .map(|&k| rest[k])
            .chain(iface.iter().copied())
            .collect();
        let mut chol = Cholesky::analyze_with_order(a, perm)?;
        chol.factorize_with(a, par)?;
        let l_ii = chol.trailing_factor(iface.len());
        Ok(Self {
            chol,
            iface: iface.to_vec(),
            l_ii,
        })
    }

    /// The whole factorisation (solves with A).
    pub fn cholesky(&self) -> &Cholesky {
        &self.chol
    }

    /// The whole factorisation, consumed.
    pub fn into_cholesky(self) -> Cholesky {
        self.chol
    }

    /// B <- (A^{-1})_II B for B with |I| rows in the order of `iface`.
    pub fn apply_inverse_ii(&self, mut b: MatMut<'_, f64>) {
        let par = faer::get_global_parallelism();
        let scale: Vec<f64> = self.iface.iter().map(|&d| self.chol.scale[d]).collect();
        let rescale = |b: &mut MatMut<'_, f64>| {
            for j in 0..b.ncols() {
                for (i, s) in scale.iter().enumerate() {
                    b[(i, j)] *= s;
                }
            }
        };
        rescale(&mut b);
        solve_lower_triangular_in_place(self.l_ii.as_ref(), b.rb_mut(), par);
        solve_upper_triangular_in_place(self.l_ii.transpose(), b.rb_mut(), par);
        rescale(&mut b);
    }
}

/// Fill-reducing order of the principal submatrix A_OO (`rest`, `pos[d]` = index of d in it):
/// nested dissection with positions, AMD without; a permutation of 0..|rest|.
fn rest_order(
    a: &CscMatrix,
    rest: &[usize],
    pos: &[usize],
    xy: Option<&[[f64; 2]]>,
) -> Result<Vec<usize>> {
    let mut cp = Vec::with_capacity(rest.len() + 1);
    cp.push(0);
    let mut ri = Vec::new();
    for &c in rest {
        for &r in &a.row_idx[a.col_ptr[c]..a.col_ptr[c + 1]] {
            if pos[r] != usize::MAX {
                ri.push(pos[r]);
            }
        }
        cp.push(ri.len());
    }
    let m = rest.len();
    if let Some(xy) = xy {
        let xy_rest: Vec<[f64; 2]> = rest.iter().map(|&d| xy[d]).collect();
        return Ok(nested_dissection(&cp, &ri, &xy_rest));
    }
    catch_panic("faer AMD of the non-interface block", || {
        let mut perm = vec![0usize; m];
        let mut inv = vec![0usize; m];
        let req = amd::order_maybe_unsorted_scratch::<usize>(m, ri.len());
        let mut mem = workspace(req, "the AMD workspace")?;
        let sym = SymbolicSparseColMatRef::new_checked(m, m, &cp, None, &ri);
        amd::order_maybe_unsorted(
            &mut perm,
            &mut inv,
            sym,
            amd::Control::default(),
            MemStack::new(&mut mem),
        )
        .map_err(|e| faer_error("AMD ordering", e))?;
        Ok(perm)
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use faer::linalg::solvers::Solve;

    /// The 5-point Laplacian on an m x m grid plus a small shift, rows/columns scaled by
    /// D = diag(10^(i mod 7 - 3)) (unknowns of very different scales): SPD.
    fn scaled_laplacian(m: usize) -> CscMatrix {
        let n = m * m;
        let d = |i: usize| 10f64.powi((i % 7) as i32 - 3);
        let mut trip = Vec::new();
        for i in 0..m {
            for j in 0..m {
                let a = i * m + j;
                trip.push((a, a, 4.1 * d(a) * d(a)));
                for (di, dj) in [(0i64, 1i64), (1, 0), (0, -1), (-1, 0)] {
                    let (ii, jj) = (i as i64 + di, j as i64 + dj);
                    if ii >= 0 && jj >= 0 && (ii as usize) < m && (jj as usize) < m {
                        let b = ii as usize * m + jj as usize;
                        trip.push((a, b, -d(a) * d(b)));
                    }
                }
            }
        }
        CscMatrix::from_triplets(n, n, &trip).unwrap()
    }

    /// (A^-1)_II B from the trailing factor block against a dense solve of the whole matrix.
    fn check(m: usize, supernodal: bool, geometric: bool) {
        let a = scaled_laplacian(m);
        let xy: Option<Vec<[f64; 2]>> = geometric.then(|| {
            (0..m * m)
                .map(|i| [(i % m) as f64, (i / m) as f64])
                .collect()
        });
        let n = a.nrows;
        // an interface in scrambled order, spread over the grid
        let iface: Vec<usize> = (0..n).map(|k| (k * 37 + 11) % n).step_by(9).collect();
        let ic = InterfaceCholesky::new(&a, &iface, xy.as_deref(), Par::Seq).unwrap();
        assert_eq!(ic.cholesky().is_supernodal(), supernodal, "m = {m}");
        let k = 3;
        let mut b = Mat::<f64>::from_fn(iface.len(), k, |i, j| ((i * 7 + j * 3) % 5) as f64 - 2.0);
        let mut full = Mat::<f64>::zeros(n, k);
        for (i, &d) in iface.iter().enumerate() {
            for j in 0..k {
                full[(d, j)] = b[(i, j)];
            }
        }
        let dense = Mat::<f64>::from_fn(n, n, |r, c| a.get(r, c));
        let x = dense.partial_piv_lu().solve(&full);
        ic.apply_inverse_ii(b.as_mut());
        let mut worst = 0.0f64;
        for (i, &d) in iface.iter().enumerate() {
            for j in 0..k {
                worst = worst.max((b[(i, j)] - x[(d, j)]).abs() / x[(d, j)].abs().max(1e-300));
            }
        }
        assert!(worst < 1e-9, "m = {m}: worst relative difference {worst:e}");
        // and the whole factorisation solves A as usual
        let rhs: Vec<f64> = (0..n).map(|i| (i % 3) as f64).collect();
        let y = ic.cholesky().solve(&rhs).unwrap();
        let ay = a.matvec(&y);
        let res: f64 = ay
            .iter()
            .zip(&rhs)
            .map(|(p, q)| (p - q).abs())
            .fold(0.0, f64::max);
        assert!(res < 1e-8, "m = {m}: residual {res:e}");
    }

    #[test]
    fn trailing_block_gives_the_interface_inverse_simplicial() {
        check(8, false, false);
        check(8, false, true);
    }

    #[test]
    fn trailing_block_gives_the_interface_inverse_supernodal() {
        check(40, true, false);
        check(40, true, true);
    }

    #[test]
    fn repeated_interface_unknown_is_an_error() {
        let a = scaled_laplacian(4);
        assert!(InterfaceCholesky::new(&a, &[1, 2, 1], None, Par::Seq).is_err());
    }
}
