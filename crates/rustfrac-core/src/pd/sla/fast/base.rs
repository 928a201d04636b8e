//! The base condensed system S_0 of the low-rank updates, in one of two forms
//! ([`crate::pd::cost`] chooses):
//! * **dense**: a dense LU of S_0 (n_P x n_P, in place: [`DenseLu`]), O(n_P^3) per
//!   condensation, O(n_P^2) memory; the columns of S_0^{-1} the updates need are solved with it
//!   (`columns.rs`), never the whole inverse.
//! * **sparse**: a sparse factor of S_0 = K_PP - K_PF Z, which is K_PP (the PD bonds, sparse)
//!   plus a dense block only on the PD rows coupled to the FEM ring x the PD columns of hybrid
//!   elements (`pc`); none for pure PD. Pure PD: K_PP is symmetric positive definite, sparse
//!   Cholesky ([`Cholesky`], nested dissection on the node positions); CCM-PD: S_0 is not
//!   symmetric (docs/design.md, "Matrix symmetry and solver strategy"), sparse LU ([`Lu`],
//!   COLAMD with the dense block's columns ordered last: [`Lu::analyze_dense_last`]). A solve
//!   with S_0 costs one pair of triangular solves (about 4 nnz(L) flops), the factorisation
//!   O(nnz(L)^2 / n_P). The
//!   pattern of S_0 does not change between condensations (broken bonds stay stored as zeros),
//!   so the symbolic analysis is done once.
//!
//! CCM-PD's sparse form is **bordered** when K_PP is symmetric positive definite (always so far:
//! its rows hold bonds only): S_0 = A + F E^T, A = K_PP by sparse Cholesky (nested dissection on
//! the node positions, the pure PD factor), F = -K_{P,ring} Z_ring the FEM coupling on the |pc|
//! columns E (dense). Woodbury: S_0^{-1} b = y - H M^{-1} y_pc with y = A^{-1} b, H = A^{-1} F
//! (|pc| solves) and M = I + H_pc (dense LU, |pc|^2), det S_0 = det A det M. Its factorisation is
//! the Cholesky of A and the |pc| solves; a column of S_0^{-1} is a sparse forward solve with A
//! plus a product with H. The LU of S_0 (its dense block of rows coupled to the ring x `pc` made
//! fill) took 3 to 5 times as long at each condensation of the adaptive run. A K_PP that is not
//! symmetric, or not positive definite, takes the LU.
//!
//! Both give w = S_0^{-1} a for the Sherman-Morrison-Woodbury update (`smw.rs`, from kept columns)
//! and
//! x_0 = S_0^{-1} g; separation is a singular S_0 (pivot test of the factorisation) or a
//! vanishing Schur pivot of the bordering, as before.

use crate::error::{Error, Result};
use crate::la::{unit_vectors, Cholesky, CscMatrix, DenseLu, Lu, SparseForward, DENSE_PIVOT_TOL};
use crate::pd::sla::engine::separated;
use faer::linalg::matmul::matmul;
use faer::{Accum, Mat, MatMut, MatRef, Par};
use rayon::prelude::*;

thread_local! {
    /// CCM-PD's sparse form is the LU of S_0 for every condensation made on this thread (tests).
    static FORCE_LU: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
}

/// Makes CCM-PD's sparse form the LU of S_0 (`on`) for every condensation made on this thread
/// from now on, as when K_PP is not symmetric positive definite: for tests, which check that
/// form against the oracle.
#[doc(hidden)]
pub fn force_lu_form(on: bool) {
    FORCE_LU.with(|f| f.set(on));
}

/// Whether [`force_lu_form`] is on for this thread.
pub(super) fn lu_form_forced() -> bool {
    FORCE_LU.with(|f| f.get())
}

/// The sparse factorisation of S_0.
pub(in crate::pd::sla) enum SparseFactor {
    /// with the elimination tree of its last factorisation, for columns of S_0^-1 by sparse
    /// forward solves ([`SparseForward::solve_unit_columns`])
    Cholesky(Cholesky, Option<SparseForward>),
    Lu(Lu),
    /// CCM-PD: A = K_PP by Cholesky, bordered by the FEM coupling (module doc)
    Bordered(Box<Bordered>),
}

/// Columns of a multi-column solve of the bordered form a thread takes at once (fixed: the
/// result does not depend on the threads; faer's supernodal solve of many columns keeps to one
/// core, so the columns go on all threads: the FEM border of the adaptive run's last model,
/// 580 columns, in 0.26-0.37 s instead of about 0.5 s).
const COLUMN_CHUNK: usize = 64;

/// Relative asymmetry of K_PP (to its largest entry) up to which it is taken as symmetric for
/// the bordered form's Cholesky (its rows hold bonds only: symmetric to the last bit so far).
const SYMMETRY_TOL: f64 = 1e-13;

/// S_0 = A + F E^T by Woodbury (module doc).
pub(in crate::pd::sla) struct Bordered {
    /// A = K_PP, with its elimination tree once factorised (unit columns by forward solves)
    a: Cholesky,
    tree: Option<SparseForward>,
    /// the P indices of the columns E
    pc: Vec<usize>,
    /// H = A^{-1} F (column-major n_P x |pc|)
    h: Vec<f64>,
    /// the LU of M = I + H_pc
    m: Option<DenseLu>,
    /// K_PP was found symmetric (at the model's first condensation)
    symmetric_checked: bool,
    /// A was factorised ahead, beside the FEM part ([`Bordered::lead`]): the values of the K_PP
    /// it was factorised from, which the next [`Bordered::factorize`] takes the factor for when
    /// its K_PP has them (else it factorises its own)
    lead: Option<Vec<f64>>,
}

impl Bordered {
    /// Symbolic analysis of A = K_PP (pattern `kpp`) with nested dissection on `xy`.
    pub(in crate::pd::sla) fn analyze(
        kpp: &CscMatrix,
        xy: &[[f64; 2]],
        pc: &[usize],
    ) -> Result<Self> {
        Ok(Self {
            a: Cholesky::analyze_with(kpp, Some(xy))?,
            tree: None,
            pc: pc.to_vec(),
            h: Vec::new(),
            m: None,
            symmetric_checked: false,
            lead: None,
        })
    }

    /// Whether K_PP (`kpp`) is symmetric to [`SYMMETRY_TOL`], checked once a model: a broken
    /// bond or a grounding spring keeps the symmetry.
    pub(in crate::pd::sla) fn symmetric(&mut self, kpp: &CscMatrix) -> bool {
        if !self.symmetric_checked {
            if kpp.asymmetry() > SYMMETRY_TOL {
                return false;
            }
            self.symmetric_checked = true;
        }
        true
    }

    /// Factorises A = `kpp` ahead of the condensation (the model's first: its K_PP does not
    /// depend on the FEM part, so the engine makes it on the cost model's thread, on one thread
    /// beside the FEM part's Cholesky). Returns whether it took: not when K_PP is not
    /// symmetric ([`SYMMETRY_TOL`]) or not positive definite (the condensation then decides).
    pub(in crate::pd::sla) fn lead(&mut self, kpp: &CscMatrix) -> Result<bool> {
        if !self.symmetric(kpp) {
            return Ok(false);
        }
        self.lead = None;
        self.tree = None;
        match self.a.factorize_with(kpp, Par::Seq) {
            Ok(()) => {}
            Err(Error::NotPositiveDefinite { .. } | Error::Singular { .. }) => return Ok(false),
            Err(e) => return Err(e),
        }
        self.tree = Some(SparseForward::new(&self.a)?);
        self.lead = Some(kpp.val.clone());
        Ok(true)
    }

    /// Factorises A = `kpp` (unless [`Bordered::lead`] factorised this very K_PP ahead: the
    /// model's first condensation) and M from F (`f`, column-major n_P x |pc|, taken as H's storage).
    /// Ok(false): A is not positive definite (the caller takes the LU form); a singular M is a
    /// singular S_0 (separation).
    pub(in crate::pd::sla) fn factorize(&mut self, kpp: &CscMatrix, f: Vec<f64>) -> Result<bool> {
        let n = kpp.nrows;
        let npc = self.pc.len();
        self.m = None;
        let ahead = self.lead.take().is_some_and(|v| v == kpp.val);
        if !ahead {
            self.tree = None;
            match self.a.factorize(kpp) {
                Ok(()) => {}
                Err(Error::NotPositiveDefinite { .. } | Error::Singular { .. }) => {
                    return Ok(false)
                }
                Err(e) => return Err(e),
            }
            self.tree = Some(SparseForward::new(&self.a)?);
        }
        let mut h = f;
        if npc > 0 {
            // the |pc| columns in chunks on all threads (faer's supernodal solve of many
            // columns keeps to one core)
            let a = &self.a;
            h.par_chunks_mut(COLUMN_CHUNK * n)
                .map(|c| a.solve_in_place(c))
                .collect::<Result<Vec<()>>>()
                .map_err(solve_failed)?;
        }
        let mut m = Mat::<f64>::identity(npc, npc);
        for t in 0..npc {
            let col = &h[t * n..(t + 1) * n];
            for (r, &p) in self.pc.iter().enumerate() {
                m[(r, t)] += col[p];
            }
        }
        // M = I + H_pc is of order one: a pivot below the tolerance of 1 (or of its largest) is
        // a singular S_0, det S_0 = det A det M
        let singular = |detail: String| {
            separated(format!(
                "condensed PD matrix is singular (its FEM border: {detail})"
            ))
        };
        let lu = DenseLu::new(m, DENSE_PIVOT_TOL).map_err(|e| match e {
            Error::Singular { detail } => singular(detail),
            e => e,
        })?;
        if lu.min_pivot() <= DENSE_PIVOT_TOL {
            return Err(singular(format!("pivot {:.3e}", lu.min_pivot())));
        }
        self.h = h;
        self.m = Some(lu);
        Ok(true)
    }

    /// x <- x - H M^{-1} x_pc for the k columns of `x` (column-major n_P x k): from A^{-1} B to
    /// S_0^{-1} B.
    fn border(&self, x: &mut [f64]) -> Result<()> {
        let npc = self.pc.len();
        let m = self.m.as_ref().ok_or_else(|| Error::Internal {
            detail: "bordered condensed system used before its factorisation".into(),
        })?;
        let n = self.a.n();
        if npc == 0 || n == 0 {
            return Ok(());
        }
        let k = x.len() / n;
        let mut t = vec![0.0; npc * k];
        for (tj, xj) in t.chunks_exact_mut(npc).zip(x.chunks_exact(n)) {
            for (v, &p) in tj.iter_mut().zip(&self.pc) {
                *v = xj[p];
            }
        }
        m.solve_in_place(&mut t)?;
        matmul(
            MatMut::from_column_major_slice_mut(x, n, k),
            Accum::Add,
            MatRef::from_column_major_slice(&self.h, n, npc),
            MatRef::from_column_major_slice(&t, npc, k),
            -1.0,
            Par::Seq,
        );
        Ok(())
    }

    fn solve_in_place(&self, x: &mut [f64]) -> Result<()> {
        self.a.solve_in_place(x)?;
        self.border(x)
    }

    /// Columns `cols` of S_0^{-1} (column-major n_P x k), in chunks on all threads.
    fn unit_columns(&self, cols: &[usize]) -> Result<Vec<f64>> {
        let parts = cols
            .par_chunks(COLUMN_CHUNK)
            .map(|cols| {
                let mut x = match &self.tree {
                    Some(tree) => tree.solve_unit_columns(&self.a, cols, &mut tree.work())?,
                    None => {
                        let mut x = unit_vectors(self.a.n(), cols);
                        self.a.solve_in_place(&mut x)?;
                        x
                    }
                };
                self.border(&mut x)?;
                Ok(x)
            })
            .collect::<Result<Vec<Vec<f64>>>>()?;
        Ok(parts.concat())
    }
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
            Self::Bordered(_) => Err(Error::Internal {
                detail: "the bordered S_0 is factorised from K_PP and F".into(),
            }),
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
            Self::Bordered(b) => b.solve_in_place(x),
        }
    }

    /// Number of stored values of the factor (Cholesky: L; LU: not known before the numeric
    /// factorisation, None).
    pub(in crate::pd::sla) fn factor_nnz(&self) -> Option<usize> {
        match self {
            Self::Cholesky(c, _) => Some(c.factor_nnz()),
            Self::Lu(_) | Self::Bordered(_) => None,
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
            match f.as_ref() {
                SparseFactor::Cholesky(c, Some(tree)) => {
                    return tree
                        .solve_unit_columns(c, cols, &mut tree.work())
                        .map_err(solve_failed);
                }
                SparseFactor::Bordered(b) => return b.unit_columns(cols).map_err(solve_failed),
                _ => {}
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

#[cfg(test)]
mod tests {
    use super::*;

    /// A = tridiagonal (SPD when `d` > 2), F's columns on `pc`: S_0 = A + F E^T, dense.
    fn case(n: usize, d: f64, pc: &[usize], f: &[f64]) -> (CscMatrix, Vec<Vec<f64>>) {
        let mut trip = Vec::new();
        for i in 0..n {
            trip.push((i, i, d));
            if i + 1 < n {
                trip.push((i, i + 1, -1.0));
                trip.push((i + 1, i, -1.0));
            }
        }
        let a = CscMatrix::from_triplets(n, n, &trip).unwrap();
        let mut s = a.to_dense();
        for (t, &c) in pc.iter().enumerate() {
            for (r, row) in s.iter_mut().enumerate() {
                row[c] += f[t * n + r];
            }
        }
        (a, s)
    }

    fn xy(n: usize) -> Vec<[f64; 2]> {
        (0..n).map(|i| [i as f64, 0.0]).collect()
    }

    /// The Woodbury form solves S_0 = A + F E^T (residual at round-off), for one right-hand side
    /// and for unit columns; A not positive definite is Ok(false); a singular M is a separation.
    #[test]
    fn bordered_solves_the_condensed_system() {
        let n = 40;
        let pc = [3, 17, 30];
        let f: Vec<f64> = (0..n * pc.len())
            .map(|i| ((i * 37 % 11) as f64 - 5.0) * 0.1)
            .collect();
        let (a, s) = case(n, 2.5, &pc, &f);
        let mut b = Bordered::analyze(&a, &xy(n), &pc).unwrap();
        assert!(b.factorize(&a, f.clone()).unwrap());
        let rhs: Vec<f64> = (0..n).map(|i| (i as f64 * 0.3).sin()).collect();
        // the largest |S_0 x - rhs| of the solve of `rhs` by `b`
        let residual = |b: &Bordered| {
            let mut x = rhs.clone();
            b.solve_in_place(&mut x).unwrap();
            (0..n)
                .map(|r| (s[r].iter().zip(&x).map(|(v, x)| v * x).sum::<f64>() - rhs[r]).abs())
                .fold(0.0, f64::max)
        };
        let res = residual(&b);
        assert!(res < 1e-12, "residual {res:.2e}");
        let cols = b.unit_columns(&[0, 17, 39]).unwrap();
        for (j, &c) in [0usize, 17, 39].iter().enumerate() {
            for (r, row) in s.iter().enumerate() {
                let sx: f64 = row.iter().zip(&cols[j * n..]).map(|(v, x)| v * x).sum();
                let want = if r == c { 1.0 } else { 0.0 };
                assert!((sx - want).abs() < 1e-12, "column {c} row {r}: {sx}");
            }
        }
        // A factorised ahead (`lead`, as beside the FEM part): the same solve; the lead is taken
        // by the next factorisation only
        let mut bl = Bordered::analyze(&a, &xy(n), &pc).unwrap();
        assert!(bl.lead(&a).unwrap());
        assert!(bl.lead.is_some());
        assert!(bl.factorize(&a, f.clone()).unwrap());
        assert!(bl.lead.is_none(), "the lead is taken once");
        let res_l = residual(&bl);
        assert!(res_l < 1e-12, "residual with the lead {res_l:.2e}");
        // a lead of another K_PP (the diagonal 3) is not taken: A is factorised from `a`
        let (a3, _) = case(n, 3.0, &pc, &f);
        let mut bx = Bordered::analyze(&a, &xy(n), &pc).unwrap();
        assert!(bx.lead(&a3).unwrap());
        assert!(bx.factorize(&a, f.clone()).unwrap());
        let res_x = residual(&bx);
        assert!(
            res_x < 1e-12,
            "residual after a lead of another K_PP {res_x:.2e}"
        );
        // after the lead's factorisation (of A with the diagonal 3), the next one factorises its
        // own matrix again: the solve is the one of `a`
        let mut b3 = Bordered::analyze(&a3, &xy(n), &pc).unwrap();
        assert!(b3.lead(&a3).unwrap());
        assert!(b3.factorize(&a3, f.clone()).unwrap());
        assert!(b3.factorize(&a, f.clone()).unwrap());
        let res_3 = residual(&b3);
        assert!(
            res_3 < 1e-12,
            "residual after a lead of another matrix {res_3:.2e}"
        );
        // A indefinite: the caller takes the LU (also when its lead was tried)
        let (a_bad, _) = case(n, -2.5, &pc, &f);
        let mut b = Bordered::analyze(&a_bad, &xy(n), &pc).unwrap();
        assert!(!b.lead(&a_bad).unwrap());
        assert!(!b.factorize(&a_bad, f.clone()).unwrap());
        // K_PP not symmetric: no lead, and the condensation's check says so
        let mut a_asym = a.clone();
        let k = a_asym.col_ptr[1];
        a_asym.val[k] += 1e-6;
        let mut b = Bordered::analyze(&a_asym, &xy(n), &pc).unwrap();
        assert!(!b.lead(&a_asym).unwrap());
        assert!(!b.symmetric(&a_asym));
        // M = I + H_pc singular: F = -A e_3 on column 3 makes S_0 e_3 = 0
        let mut f1 = vec![0.0; n];
        f1[2] = 1.0;
        f1[3] = -2.5;
        f1[4] = 1.0;
        let mut b = Bordered::analyze(&a, &xy(n), &[3]).unwrap();
        let e = b.factorize(&a, f1).unwrap_err();
        assert!(matches!(e, Error::Separated { .. }), "{e:?}");
    }
}
