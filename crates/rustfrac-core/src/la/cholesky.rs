//! Supernodal sparse Cholesky L L^T (faer) of the SPD FEM/XFEM systems: symbolic analysis
//! (nested dissection or AMD, elimination tree, supernodes) once, reused for every numeric
//! refactorisation with the same pattern; several right-hand sides at once (column-major n x k);
//! every failure an [`Error`], never a NaN, and a panic inside faer caught.
//!
//! Singularity in Cholesky is detected by a *per-unknown* relative pivot test: the matrix is
//! factorised Jacobi-scaled, A^ = S A S with S = diag(2^k_i) the power of two nearest to
//! A_ii^(-1/2) (exact in floating point: the factor is S L bit for bit), so every A^_ii lies in
//! [1/2, 2) and a pivot below `PIVOT_TOL` (faer's dynamic-regularisation hook replaces it by a
//! sentinel we then count) is a pivot below ~1e-13 of *its own* diagonal entry. That means a
//! rigid-body mode or a separated part, which floating-point elimination would otherwise turn into
//! a tiny positive pivot and a huge, meaningless solution; unknowns of very different scales (any
//! ratio within the exponent range) do not trip it. Round-off pivots that land above it are
//! caught by [`crate::la::COND_SINGULAR`] (see [`crate::la::check_condition`]) and, for the plate
//! models, by the rigid-mode check [`crate::fe::Dirichlet::check_rigid_modes`].

use super::checks::{
    check_factor_input, check_rhs, check_solution, check_square, faer_ref_values,
    pattern_fingerprint, workspace,
};
use super::csc::CscMatrix;
use super::ordering::{inverse, nested_dissection};
use crate::error::{catch_panic, Error, Result};
use faer::dyn_stack::MemStack;
use faer::linalg::cholesky::llt::factor::LltRegularization;
use faer::perm::PermRef;
use faer::prelude::*;
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, LltRef, SymbolicCholesky, SymbolicCholeskyRaw, SymmetricOrdering,
};
use faer::sparse::SymbolicSparseColMatRef;
use faer::{Conj, Side};

/// Relative pivot threshold below which a Cholesky pivot is taken as zero: a pivot of the
/// Jacobi-scaled matrix (unit diagonal up to a factor 2), i.e. a pivot below ~1e-13 of the
/// unknown's own diagonal entry A_ii (the same meaning as before for a uniform mesh, where all
/// A_ii are alike; no longer relative to the largest A_ii). Pivots lie in [lambda_min,
/// lambda_max] of the scaled matrix, so one at the threshold already means a condition number of
/// ~1e13 or more; exactly singular plates measured far below it (tests/suite/singular_detection.rs: the
/// sentinel or 0).
pub const PIVOT_TOL: f64 = 1e-13;
/// Value faer substitutes for a pivot below the threshold; its square root marks it in the factor.
const SENTINEL_PIVOT: f64 = 1e300;

/// Power of two nearest to d^(-1/2) (1 for a non-positive or non-finite d, which the pivot test
/// then reports): scaling by it is exact in floating point.
fn pow2_inv_sqrt(d: f64) -> f64 {
    if !(d.is_finite() && d > 0.0) {
        return 1.0;
    }
    let k = (-0.5 * d.log2()).round() as i32;
    2f64.powi(k)
}

/// Sparse Cholesky L L^T of a symmetric positive definite matrix (lower triangle is read).
pub struct Cholesky {
    pub(super) n: usize,
    /// the analysed pattern's [`super::checks::pattern_fingerprint`]
    pub(super) pattern: u64,
    pub(super) symbolic: SymbolicCholesky<usize>,
    /// factor of the scaled matrix S A S (see the module doc)
    pub(super) values: Vec<f64>,
    /// S = diag(2^k_i), k_i = round(-log2(A_ii) / 2)
    pub(super) scale: Vec<f64>,
    pub(super) factorised: bool,
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
        Self::analyze_perm(a, perm)
    }

    /// Symbolic analysis with a given elimination order: `perm[k]` is the unknown eliminated
    /// k-th (a permutation of 0..n, else an error).
    pub fn analyze_with_order(a: &CscMatrix, perm: Vec<usize>) -> Result<Self> {
        check_square(a)?;
        let mut seen = vec![false; a.nrows];
        if perm.len() != a.nrows
            || perm
                .iter()
                .any(|&p| p >= a.nrows || std::mem::replace(&mut seen[p], true))
        {
            return Err(Error::Internal {
                detail: format!("elimination order is not a permutation of 0..{}", a.nrows),
            });
        }
        Self::analyze_perm(a, Some(perm))
    }

    /// Symbolic analysis with the permutation `perm` (AMD when none).
    fn analyze_perm(a: &CscMatrix, perm: Option<Vec<usize>>) -> Result<Self> {
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
                .map_err(|e| super::checks::faer_error("symbolic Cholesky", e))?;
            let len = symbolic.len_val();
            Ok(Self {
                n: a.nrows,
                pattern: pattern_fingerprint(a),
                symbolic,
                values: vec![0.0; len],
                scale: vec![1.0; a.nrows],
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
        self.factorize_with(a, faer::get_global_parallelism())
    }

    /// [`Cholesky::factorize`] on the threads `par` (`Par::Seq` when another thread works beside
    /// it: the supernodal factorisation's rayon workers then only compete for the cores).
    pub fn factorize_with(&mut self, a: &CscMatrix, par: Par) -> Result<()> {
        check_factor_input(a, self.n, self.pattern)?;
        self.factorised = false;
        let scaled = self.jacobi_scale(a)?;
        self.factor_scaled(a, &scaled, par)?;
        self.check_pivots()?;
        self.factorised = true;
        Ok(())
    }

    /// Phase 1 of [`Cholesky::factorize`]: the Jacobi scaling by powers of two, A^ = S A S with
    /// A^_ii in [1/2, 2). Sets `scale` (S) and returns the values of A^ (pattern of `a`).
    fn jacobi_scale(&mut self, a: &CscMatrix) -> Result<Vec<f64>> {
        let mut diag = vec![0.0; self.n];
        for (c, dc) in diag.iter_mut().enumerate() {
            if let Some(k) = a.find(c, c) {
                *dc = a.val[k];
            }
        }
        if self.n > 0 && diag.iter().all(|&d| d == 0.0) {
            return Err(Error::Singular {
                detail: "the matrix has an all-zero diagonal".into(),
            });
        }
        for (sc, &d) in self.scale.iter_mut().zip(&diag) {
            *sc = pow2_inv_sqrt(d);
        }
        let scale = &self.scale;
        let mut scaled = a.val.clone();
        for c in 0..a.ncols {
            for k in a.col_ptr[c]..a.col_ptr[c + 1] {
                scaled[k] *= scale[a.row_idx[k]] * scale[c];
            }
        }
        Ok(scaled)
    }

    /// Phase 2 of [`Cholesky::factorize`]: faer's numeric supernodal factorisation of A^ (values
    /// `scaled` on the pattern of `a`) into `values`, pivots below [`PIVOT_TOL`] replaced by
    /// [`SENTINEL_PIVOT`].
    fn factor_scaled(&mut self, a: &CscMatrix, scaled: &[f64], par: Par) -> Result<()> {
        let eps = PIVOT_TOL;
        let symbolic = &self.symbolic;
        let values = &mut self.values;
        catch_panic("faer numeric Cholesky", || {
            let req = symbolic.factorize_numeric_llt_scratch::<f64>(par, Default::default());
            let mut mem = workspace(req, "the Cholesky workspace")?;
            let reg = LltRegularization {
                dynamic_regularization_delta: SENTINEL_PIVOT,
                dynamic_regularization_epsilon: eps,
            };
            match symbolic.factorize_numeric_llt::<f64>(
                values,
                faer_ref_values(a, scaled),
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
        })
    }

    /// Phase 3 of [`Cholesky::factorize`]: the per-unknown pivot test (module doc) on the new
    /// factor; a pivot below [`PIVOT_TOL`] is [`Error::Singular`].
    fn check_pivots(&self) -> Result<()> {
        // faer's hook does not see every pivot: in the supernodal factor of the 60 x 110 plate
        // with the x1 translation free a pivot of 0 (4e-319 without the scaling) was left
        // unregularised and uncounted, so the factor's own diagonal is tested as well
        let count = self.regularised_pivots()
            + self
                .scaled_pivots()
                .iter()
                .filter(|&&d| d.is_nan() || d <= PIVOT_TOL)
                .count();
        if count > 0 {
            return Err(Error::Singular {
                detail: format!(
                    "{count} pivot(s) below {PIVOT_TOL:e} x their own diagonal entry: a rigid-body \
                     mode is not constrained or a part of the body is disconnected"
                ),
            });
        }
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
            let mut mem = workspace(req, "the solve workspace")?;
            // A^-1 = S (S A S)^-1 S
            for col in rhs.chunks_mut(n) {
                for (v, s) in col.iter_mut().zip(&self.scale) {
                    *v *= s;
                }
            }
            let x = MatMut::from_column_major_slice_mut(rhs, n, k);
            llt.solve_in_place_with_conj(Conj::No, x, par, MemStack::new(&mut mem));
            for col in rhs.chunks_mut(n) {
                for (v, s) in col.iter_mut().zip(&self.scale) {
                    *v *= s;
                }
            }
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

    /// Whether faer chose the supernodal storage (else simplicial).
    #[cfg(test)]
    pub(super) fn is_supernodal(&self) -> bool {
        matches!(self.symbolic.raw(), SymbolicCholeskyRaw::Supernodal(_))
    }

    /// The trailing m x m block of the factor L of S A S in the elimination order (dense lower
    /// triangle, zero above): with the last m unknowns eliminated last, L_II L_II^T is the Schur
    /// complement of the scaled matrix onto them.
    pub(super) fn trailing_factor(&self, m: usize) -> Mat<f64> {
        let n = self.n;
        let o = n - m.min(n);
        let mut l = Mat::<f64>::zeros(n - o, n - o);
        match self.symbolic.raw() {
            SymbolicCholeskyRaw::Supernodal(sn) => {
                let (begin, end, cpv) = (
                    sn.supernode_begin(),
                    sn.supernode_end(),
                    sn.col_ptr_for_val(),
                );
                for s in 0..sn.n_supernodes() {
                    let (b, e) = (begin[s], end[s]);
                    if e <= o {
                        continue;
                    }
                    let pat = sn.supernode(s).pattern();
                    let ncols = e - b;
                    let nrows = ncols + pat.len();
                    let block = &self.values[cpv[s]..cpv[s + 1]];
                    for j in o.saturating_sub(b)..ncols {
                        let col = &block[j * nrows..(j + 1) * nrows];
                        for i in j..ncols {
                            l[(b + i - o, b + j - o)] = col[i];
                        }
                        for (pi, &r) in pat.iter().enumerate() {
                            l[(r - o, b + j - o)] = col[ncols + pi];
                        }
                    }
                }
            }
            SymbolicCholeskyRaw::Simplicial(s) => {
                let (cp, ri) = (s.col_ptr(), s.row_idx());
                for j in o..n {
                    for k in cp[j]..cp[j + 1] {
                        if ri[k] >= j {
                            l[(ri[k] - o, j - o)] = self.values[k];
                        }
                    }
                }
            }
        }
        l
    }

    /// Squared diagonal of the factor of S A S, indexed by the original unknown.
    pub(super) fn scaled_pivots(&self) -> Vec<f64> {
        let mut d = vec![0.0; self.n];
        match self.symbolic.raw() {
            SymbolicCholeskyRaw::Simplicial(s) => {
                let (cp, ri) = (s.col_ptr(), s.row_idx());
                for (j, dj) in d.iter_mut().enumerate() {
                    let (lo, hi) = (cp[j], cp[j + 1]);
                    if let Some(k) = ri[lo..hi].iter().position(|&r| r == j) {
                        *dj = self.values[lo + k] * self.values[lo + k];
                    }
                }
            }
            SymbolicCholeskyRaw::Supernodal(s) => {
                let (begin, end, cpv) =
                    (s.supernode_begin(), s.supernode_end(), s.col_ptr_for_val());
                for sn in 0..s.n_supernodes() {
                    let ncols = end[sn] - begin[sn];
                    let nrows = s.supernode(sn).pattern().len() + ncols;
                    let block = &self.values[cpv[sn]..cpv[sn + 1]];
                    for k in 0..ncols {
                        let l = block[k * nrows + k];
                        d[begin[sn] + k] = l * l;
                    }
                }
            }
        }
        // pivot k of the permuted matrix belongs to original unknown perm_fwd[k]
        match self.symbolic.perm() {
            Some(p) => {
                let (fwd, _) = p.arrays();
                let mut out = vec![0.0; self.n];
                for (k, &o) in fwd.iter().enumerate() {
                    out[o] = d[k];
                }
                out
            }
            None => d,
        }
    }
}
