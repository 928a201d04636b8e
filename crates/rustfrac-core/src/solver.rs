//! Sparse direct solvers on top of faer: supernodal Cholesky for the SPD FEM/XFEM systems and
//! sparse LU (partial pivoting) for the non-symmetric splice-coupled CCM-PD systems (DESIGN.md
//! section 4).
//!
//! Both keep the symbolic analysis (fill-reducing ordering, elimination tree, supernodes) and reuse
//! it for every numeric refactorisation with the same pattern, solve several right-hand sides at
//! once (column-major n x k), and turn every failure into [`Error`]: a singular or indefinite matrix
//! is reported, never returned as NaN, and a panic inside faer is caught.
//!
//! Singularity in Cholesky is detected by a *per-unknown* relative pivot test: the matrix is
//! factorised Jacobi-scaled, A^ = S A S with S = diag(2^k_i) the power of two nearest to
//! A_ii^(-1/2) (exact in floating point: the factor is S L bit for bit), so every A^_ii lies in
//! [1/2, 2) and a pivot below `PIVOT_TOL` (faer's dynamic-regularisation hook replaces it by a
//! sentinel we then count) is a pivot below ~1e-13 of *its own* diagonal entry. That means a
//! rigid-body mode or a separated part, which floating-point elimination would otherwise turn into
//! a tiny positive pivot and a huge, meaningless solution; unknowns of very different scales (any
//! ratio within the exponent range) do not trip it. Round-off pivots that land above it are
//! caught by [`COND_SINGULAR`] (see [`check_condition`]) and, for the plate models, by the
//! rigid-mode check [`crate::fem::Dirichlet::check_rigid_modes`].

use crate::error::{catch_panic, Error, Result};
use crate::ordering::{inverse, nested_dissection};
use crate::sparse::CscMatrix;
use crate::warning::{Warning, WarningKind};
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

/// Relative pivot threshold below which a Cholesky pivot is taken as zero: a pivot of the
/// Jacobi-scaled matrix (unit diagonal up to a factor 2), i.e. a pivot below ~1e-13 of the
/// unknown's own diagonal entry A_ii (the same meaning as before for a uniform mesh, where all
/// A_ii are alike; no longer relative to the largest A_ii). Pivots lie in [lambda_min,
/// lambda_max] of the scaled matrix, so one at the threshold already means a condition number of
/// ~1e13 or more; exactly singular plates measured far below it (tests/singular_detection.rs: the
/// sentinel or 0).
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
    faer_ref_values(a, &a.val)
}

/// The pattern of `a` with other values (same length as `a.val`).
fn faer_ref_values<'a>(a: &'a CscMatrix, val: &'a [f64]) -> SparseColMatRef<'a, usize, f64> {
    let sym = SymbolicSparseColMatRef::new_checked(a.nrows, a.ncols, &a.col_ptr, None, &a.row_idx);
    SparseColMatRef::new(sym, val)
}

/// Power of two nearest to d^(-1/2) (1 for a non-positive or non-finite d, which the pivot test
/// then reports): scaling by it is exact in floating point.
fn pow2_inv_sqrt(d: f64) -> f64 {
    if !(d.is_finite() && d > 0.0) {
        return 1.0;
    }
    let k = (-0.5 * d.log2()).round() as i32;
    2f64.powi(k)
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
    /// factor of the scaled matrix S A S (see the module doc)
    values: Vec<f64>,
    /// S = diag(2^k_i), k_i = round(-log2(A_ii) / 2)
    scale: Vec<f64>,
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
        // Jacobi scaling by powers of two: A^ = S A S has A^_ii in [1/2, 2)
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
        let eps = PIVOT_TOL;
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
                faer_ref_values(a, &scaled),
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

/// Relative-accuracy threshold on [`ConditionEstimate::cond1`] above which results carry a
/// warning. A backward-stable Cholesky solve has a forward error of about `cond eps` in the
/// norm of the equilibrated (Jacobi-scaled) unknowns (van der Sluis: the diagonal scaling is the
/// near-optimal one, so this is the number that governs the solve). With eps = 1.1e-16, cond = 1e12
/// allows errors of ~1e-4 in the displacements and hence in K, CMOD and sigma22: the size of the
/// discretisation error of the finest meshes we run (6.6e-4 at 352 x 665), so above it round-off can
/// no longer be told apart from discretisation error. Well-posed XFEM models measure 1e5-1e9.
pub const COND_WARN: f64 = 1e12;

/// Condition estimate (of the equilibrated matrix, [`ConditionEstimate::value`]) above which a
/// factorised system counts as numerically singular ([`check_condition`] turns it into
/// [`Error::Singular`] instead of a warning): the forward error bound cond eps then exceeds
/// 1e14 x 1.1e-16 ~ 1e-2 relative, so not even the leading digits of K, CMOD or sigma22 can be
/// trusted. The pivot test ([`PIVOT_TOL`]) catches pivots that collapse; this catches the near
/// singularity the pivots do not show (their ratio is only a lower bound of the condition
/// number): e.g. a near-null mode spread over n unknowns leaves a last pivot ~n lambda_min
/// (tests/singular_detection.rs: a grounded spring chain, cond 5e15, pivot ratio 2e12). The
/// worst well-posed model we run (a/W = 0.95 at 1e6 unknowns) measures 4.5e10, over 2000x below;
/// between [`COND_WARN`] and this the result carries a warning.
pub const COND_SINGULAR: f64 = 1e14;

/// [`Error::Singular`] ("numerically singular") when the condition estimate `c` exceeds
/// [`COND_SINGULAR`]; `what` names the solve.
pub fn check_condition(what: &str, c: f64) -> Result<()> {
    if c > COND_SINGULAR {
        return Err(Error::Singular {
            detail: format!(
                "{what}: numerically singular (condition estimate {c:.2e} of the equilibrated \
                 stiffness exceeds {COND_SINGULAR:.0e}, round-off would reach {:.0e} relative): a \
                 rigid-body mode is nearly free or a part of the body is (nearly) disconnected",
                c * f64::EPSILON
            ),
        });
    }
    Ok(())
}

/// Steps of Hager's iteration in [`Cholesky::condition_estimate`]. 0 = its first gradient step
/// only (2 solves): within 13 % of the exact cond_1 on every test matrix and 0.4 % of the 5-step
/// estimate on the 352 x 665 plate (tests/xfem_extremes.rs); a solve costs ~10 % of a
/// factorisation there, so each further step (2 solves, plus 1 for Higham's alternative vector)
/// is left to [`Cholesky::condition_estimate_with`].
pub const CONDITION_ITERATIONS: usize = 0;

/// Cheap condition estimate of a factorised SPD matrix A, for the *equilibrated* matrix
/// A^ = D^(-1/2) A D^(-1/2), D = diag(A) (unit diagonal). Working with A^ makes the numbers
/// dimensionless and invariant to the units of every unknown (Young's modulus, plate size, the
/// sqrt(length) units of the branch-function dofs), and A^ is what governs the accuracy of the
/// Cholesky solve (van der Sluis 1969; Demmel 1989).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ConditionEstimate {
    /// Hager-Higham estimate of the 1-norm condition number ||A^||_1 ||A^-1||_1 (Higham 1988,
    /// LAPACK xLACN2): a lower bound of the true cond_1(A^) that is in practice within a factor
    /// of 3 of it (usually exact), and an upper bound of cond_2(A^) up to that factor
    /// (cond_2 <= cond_1 for symmetric matrices).
    pub cond1: f64,
    /// ratio of the largest to the smallest pivot of the LDL^T factorisation of A^ (d_i = L_ii^2 /
    /// A_ii): a guaranteed lower bound of cond_2(A^) (every pivot lies in [lambda_min,
    /// lambda_max]); free, but may underestimate by orders of magnitude
    pub pivot_ratio: f64,
    /// number of solves with the factor the 1-norm estimate used
    pub solves: usize,
}

impl ConditionEstimate {
    /// The estimate reported and compared with [`COND_WARN`]: the larger of the two (both are
    /// lower bounds of cond_1(A^)).
    pub fn value(&self) -> f64 {
        self.cond1.max(self.pivot_ratio)
    }
}

impl Cholesky {
    /// The LDL^T pivots of A (squared diagonal of the factor of S A S, divided by S_ii^2) indexed
    /// by the *original* unknown.
    fn pivots(&self) -> Vec<f64> {
        let mut d = self.scaled_pivots();
        for (di, s) in d.iter_mut().zip(&self.scale) {
            *di /= s * s;
        }
        d
    }

    /// Squared diagonal of the factor of S A S, indexed by the original unknown.
    fn scaled_pivots(&self) -> Vec<f64> {
        use faer::sparse::linalg::cholesky::SymbolicCholeskyRaw;
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

    /// Condition estimate of the factorised matrix `a` (the matrix passed to the last successful
    /// [`Cholesky::factorize`], full symmetric storage): see [`ConditionEstimate`].
    ///
    /// Cost: one pass over `a` and the factor's diagonal, plus 2 solves with the factor
    /// ([`CONDITION_ITERATIONS`] = 0); no new factorisation. On the 352 x 665 XFEM plate 13 % of
    /// the factorisation time, reading K_ff in place (benches/RESULTS.md).
    pub fn condition_estimate(&self, a: &CscMatrix) -> Result<ConditionEstimate> {
        self.condition_estimate_with(a, CONDITION_ITERATIONS)
    }

    /// [`Cholesky::condition_estimate`] with at most `iterations` steps of Hager's iteration
    /// (LAPACK's xLACN2 allows 5; each step costs up to two solves, plus one for Higham's
    /// alternative vector when `iterations` > 0).
    pub fn condition_estimate_with(
        &self,
        a: &CscMatrix,
        iterations: usize,
    ) -> Result<ConditionEstimate> {
        if a.nrows != self.n || a.ncols != self.n {
            return Err(Error::SizeMismatch {
                what: "matrix vs factorisation (condition estimate)".into(),
                expected: self.n,
                got: a.nrows,
            });
        }
        let diag: Vec<f64> = (0..self.n)
            .map(|c| a.find(c, c).map_or(0.0, |k| a.val[k]))
            .collect();
        self.estimate(&diag, iterations, |s| {
            // ||A^||_1: largest scaled column sum
            let mut norm = 0.0f64;
            for c in 0..a.ncols {
                let mut sum = 0.0;
                for k in a.col_ptr[c]..a.col_ptr[c + 1] {
                    sum += a.val[k].abs() * s[a.row_idx[k]];
                }
                norm = norm.max(sum * s[c]);
            }
            norm
        })
    }

    /// [`Cholesky::condition_estimate`] of the free-free block K_ff of a full matrix, read in
    /// place through `map` (full dof -> free index or `usize::MAX`) and `free` (free index -> full
    /// dof), i.e. without gathering K_ff again (see [`crate::sparse::Reduction`]).
    pub fn condition_estimate_free(
        &self,
        full: &CscMatrix,
        map: &[usize],
        free: &[usize],
        iterations: usize,
    ) -> Result<ConditionEstimate> {
        if free.len() != self.n || map.len() != full.ncols {
            return Err(Error::SizeMismatch {
                what: "free dofs vs factorisation (condition estimate)".into(),
                expected: self.n,
                got: free.len(),
            });
        }
        let diag: Vec<f64> = free
            .iter()
            .map(|&c| full.find(c, c).map_or(0.0, |k| full.val[k]))
            .collect();
        self.estimate(&diag, iterations, |s| {
            let mut norm = 0.0f64;
            for (i, &c) in free.iter().enumerate() {
                let mut sum = 0.0;
                for k in full.col_ptr[c]..full.col_ptr[c + 1] {
                    let r = map[full.row_idx[k]];
                    if r != usize::MAX {
                        sum += full.val[k].abs() * s[r];
                    }
                }
                norm = norm.max(sum * s[i]);
            }
            norm
        })
    }

    /// [`ConditionEstimate::pivot_ratio`] alone (free: no solve), given s = D^-1/2.
    fn pivot_ratio_scaled(&self, s: &[f64]) -> f64 {
        // pivots of A^: d_i / A_ii
        let piv = self.pivots();
        let (mut dmin, mut dmax) = (f64::INFINITY, 0.0f64);
        for (i, &d) in piv.iter().enumerate() {
            let dh = d * s[i] * s[i];
            dmin = dmin.min(dh);
            dmax = dmax.max(dh);
        }
        dmax / dmin
    }

    /// [`ConditionEstimate::pivot_ratio`] of the factorised matrix (a guaranteed lower bound of
    /// cond_2 of the equilibrated matrix) without the 1-norm estimate's solves: the diagonal of A
    /// is `diag`.
    pub fn pivot_ratio(&self, diag: &[f64]) -> Result<f64> {
        if !self.factorised || diag.len() != self.n {
            return Err(Error::Internal {
                detail: "pivot_ratio needs a factorised matrix and its diagonal".into(),
            });
        }
        if self.n == 0 {
            return Ok(1.0);
        }
        let s: Vec<f64> = diag.iter().map(|&d| 1.0 / d.sqrt()).collect();
        let r = self.pivot_ratio_scaled(&s);
        if r.is_finite() {
            Ok(r)
        } else {
            Err(Error::Singular {
                detail: format!("pivot ratio {r:e} is not finite"),
            })
        }
    }

    /// The estimator itself, given the diagonal of A and ||D^-1/2 A D^-1/2||_1 as a function of
    /// s = D^-1/2.
    fn estimate(
        &self,
        diag: &[f64],
        iterations: usize,
        scaled_norm1: impl Fn(&[f64]) -> f64,
    ) -> Result<ConditionEstimate> {
        if !self.factorised {
            return Err(Error::Internal {
                detail: "condition_estimate called before a successful factorize".into(),
            });
        }
        let n = self.n;
        if n == 0 {
            return Ok(ConditionEstimate {
                cond1: 1.0,
                pivot_ratio: 1.0,
                solves: 0,
            });
        }
        let mut s = vec![0.0; n]; // D^(-1/2)
        for (c, (sc, &dc)) in s.iter_mut().zip(diag).enumerate() {
            if dc.is_nan() || dc <= 0.0 {
                return Err(Error::NotPositiveDefinite {
                    detail: format!("diagonal entry {c} is {dc}"),
                });
            }
            *sc = 1.0 / dc.sqrt();
        }
        let norm_a = scaled_norm1(&s);
        let pivot_ratio = self.pivot_ratio_scaled(&s);
        // Hager-Higham on B = A^-1^ = D^(1/2) A^-1 D^(1/2) (symmetric, so B^T = B). One
        // right-hand side per solve: faer's two-column solve measured 7x slower than two
        // single ones on the 352 x 665 plate.
        let mut solves = 0;
        let mut apply = |x: &mut [f64]| -> Result<()> {
            for (v, si) in x.iter_mut().zip(&s) {
                *v /= si;
            }
            self.solve_in_place(x)?;
            for (v, si) in x.iter_mut().zip(&s) {
                *v /= si;
            }
            solves += 1;
            Ok(())
        };
        let norm1 = |y: &[f64]| y.iter().map(|v| v.abs()).sum::<f64>();
        let sign = |y: &[f64]| -> Vec<f64> {
            y.iter()
                .map(|&v| if v >= 0.0 { 1.0 } else { -1.0 })
                .collect()
        };
        // Hager's start x = 1/n: ||B x||_1 and ||B sign(B x)||_inf are both lower bounds of
        // ||B||_1 (the second is a column sum of |B| at most); with `iterations` > 0, Higham's
        // alternating vector x_i = (-1)^i (1 + i / (n - 1)) and Hager's steps x = e_j follow
        let mut x = vec![1.0 / n as f64; n];
        apply(&mut x)?;
        let mut est = norm1(&x);
        if n > 1 {
            let mut xi = sign(&x);
            let mut z = xi.clone();
            apply(&mut z)?;
            est = est.max(z.iter().map(|v| v.abs()).fold(0.0, f64::max));
            if iterations > 0 {
                let mut alt: Vec<f64> = (0..n)
                    .map(|i| {
                        let m = 1.0 + i as f64 / (n - 1) as f64;
                        if i % 2 == 0 {
                            m
                        } else {
                            -m
                        }
                    })
                    .collect();
                apply(&mut alt)?;
                est = est.max(2.0 * norm1(&alt) / (3.0 * n as f64));
            }
            let mut jlast = usize::MAX;
            for it in 0..iterations {
                let j = (0..n)
                    .max_by(|&a, &b| z[a].abs().total_cmp(&z[b].abs()))
                    .unwrap_or(0);
                if j == jlast {
                    break;
                }
                jlast = j;
                let mut y = vec![0.0; n];
                y[j] = 1.0;
                apply(&mut y)?;
                let new = norm1(&y);
                let sy = sign(&y);
                if sy == xi || new <= est || it + 1 == iterations {
                    est = est.max(new);
                    break;
                }
                est = new;
                xi = sy;
                z.clone_from(&xi);
                apply(&mut z)?;
                let zmax = z.iter().map(|v| v.abs()).fold(0.0, f64::max);
                if zmax <= z[j].abs() {
                    break;
                }
            }
        }
        let cond1 = norm_a * est;
        if !(cond1.is_finite() && pivot_ratio.is_finite()) {
            return Err(Error::Singular {
                detail: format!(
                    "condition estimate is not finite (cond1 {cond1:e}, pivot ratio {pivot_ratio:e})"
                ),
            });
        }
        Ok(ConditionEstimate {
            cond1,
            pivot_ratio,
            solves,
        })
    }
}

/// The warning a result carries when a solve's condition estimate exceeds [`COND_WARN`] (None
/// otherwise); `what` names the solve (e.g. "growth step 12").
pub fn condition_warning(what: &str, c: &ConditionEstimate) -> Option<Warning> {
    (c.value() > COND_WARN).then(|| {
        Warning::new(
            WarningKind::IllConditioned,
            format!(
            "{what}: condition estimate {:.2e} of the equilibrated stiffness exceeds {COND_WARN:.0e}: \
             round-off may reach {:.0e} relative in the solution (refine or coarsen the mesh near \
             the crack, or raise area_threshold)",
            c.value(),
                c.value() * f64::EPSILON
            ),
        )
    })
}
