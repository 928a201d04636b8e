//! Sparse LU with partial pivoting (faer) of the non-symmetric splice-coupled CCM-PD systems
//! (docs/design.md, "Matrix symmetry and solver strategy"): symbolic analysis (COLAMD) once,
//! reused for every numeric refactorisation with the same pattern; several right-hand sides
//! at once; every failure an [`Error`], never a NaN, and a panic inside faer caught.
//!
//! [`Lu::analyze_dense_last`] orders the matrix's dense columns last: COLAMD leaves a column with
//! more than a given number of entries out of its fill-reducing order and numbers it after the
//! others. The condensed CCM-PD matrix S = K_PP - K_PF Z is such a matrix: the PD stencil (about
//! 2 (pi m^2 + 1) entries a column) plus, in the PD columns of hybrid elements, a dense block
//! over every PD row coupled to the FEM ring. Ordered among the sparse columns, that block fills
//! the factor; ordered last, it becomes a dense trailing block, as in a bordered (two-stage) LU.

use super::checks::pattern_fingerprint;
use super::checks::{check_factor_input, check_rhs, check_solution, check_square, faer_ref};
use super::checks::{faer_error, workspace};
use super::csc::CscMatrix;
use crate::error::{catch_panic, Error, Result};
use faer::dyn_stack::MemStack;
use faer::prelude::*;
use faer::sparse::linalg::colamd;
use faer::sparse::linalg::lu::{
    factorize_symbolic_lu, LuRef, LuSymbolicParams, NumericLu, SymbolicLu,
};
use faer::sparse::SymbolicSparseColMatRef;
use faer::Conj;

/// A column is dense for [`Lu::analyze_dense_last`] when it has more than this many times the
/// median number of entries of the matrix's columns (and more than COLAMD's floor of 16).
pub const DENSE_COLUMN_FACTOR: usize = 4;

/// Sparse LU with partial pivoting of a general square matrix.
pub struct Lu {
    n: usize,
    /// the analysed pattern's [`pattern_fingerprint`]
    pattern: u64,
    symbolic: SymbolicLu<usize>,
    numeric: Option<NumericLu<usize, f64>>,
}

impl Lu {
    /// Symbolic analysis (COLAMD ordering, its default dense-column rule: more than half the
    /// rows) of the pattern of `a`.
    pub fn analyze(a: &CscMatrix) -> Result<Self> {
        Self::analyze_with(a, colamd::Control::default())
    }

    /// Symbolic analysis with the columns of more than [`DENSE_COLUMN_FACTOR`] times the median
    /// column count ordered last (see the module doc).
    pub fn analyze_dense_last(a: &CscMatrix) -> Result<Self> {
        let mut counts: Vec<usize> = a.col_ptr.windows(2).map(|w| w[1] - w[0]).collect();
        let mid = counts.len() / 2;
        let median = if counts.is_empty() {
            0
        } else {
            *counts.select_nth_unstable(mid).1
        };
        let limit = DENSE_COLUMN_FACTOR * median;
        // faer 0.24.4's COLAMD rule (its code; its doc says sqrt(n)): dense when
        // count > max(16, dense_col * n); the unit test below checks the effect
        let control = colamd::Control {
            dense_col: limit as f64 / a.nrows.max(1) as f64,
            ..Default::default()
        };
        Self::analyze_with(a, control)
    }

    fn analyze_with(a: &CscMatrix, control: colamd::Control) -> Result<Self> {
        check_square(a)?;
        catch_panic("faer symbolic LU", || {
            let sym = SymbolicSparseColMatRef::new_checked(
                a.nrows, a.ncols, &a.col_ptr, None, &a.row_idx,
            );
            let params = LuSymbolicParams {
                colamd_params: control,
                ..Default::default()
            };
            let symbolic =
                factorize_symbolic_lu(sym, params).map_err(|e| faer_error("symbolic LU", e))?;
            Ok(Self {
                n: a.nrows,
                pattern: pattern_fingerprint(a),
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
        check_factor_input(a, self.n, self.pattern)?;
        let mut numeric = self.numeric.take().unwrap_or_default();
        let par = faer::get_global_parallelism();
        let req = self
            .symbolic
            .factorize_numeric_lu_scratch::<f64>(par, Default::default());
        let mut mem = workspace(req, "the LU workspace")?;
        let symbolic = &self.symbolic;
        catch_panic("faer numeric LU", || {
            symbolic
                .factorize_numeric_lu(
                    &mut numeric,
                    faer_ref(a),
                    par,
                    MemStack::new(&mut mem),
                    Default::default(),
                )
                .map(|_| ())
                .map_err(|e| Error::Singular {
                    detail: format!("LU factorisation failed: {e:?}"),
                })
        })?;
        self.numeric = Some(numeric);
        Ok(())
    }

    /// Solves A X = B in place; `rhs` is column-major n x k.
    pub fn solve_in_place(&self, rhs: &mut [f64]) -> Result<()> {
        let numeric = self.numeric.as_ref().ok_or_else(|| Error::Internal {
            detail: "Lu::solve called before a successful factorize".into(),
        })?;
        let k = check_rhs(self.n, rhs)?;
        if k == 0 {
            return Ok(());
        }
        let n = self.n;
        let par = faer::get_global_parallelism();
        let req = self.symbolic.solve_in_place_scratch::<f64>(k, par);
        let mut mem = workspace(req, "the LU solve workspace")?;
        catch_panic("faer LU solve", || {
            let x = MatMut::from_column_major_slice_mut(rhs, n, k);
            LuRef::new_unchecked(&self.symbolic, numeric).solve_in_place_with_conj(
                Conj::No,
                x,
                par,
                MemStack::new(&mut mem),
            );
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

#[cfg(test)]
mod tests {
    use super::*;

    /// A non-symmetric 5-point stencil on an `nx` x `ny` grid (diagonally dominant) plus a dense
    /// block: rows `0..nr` x the columns `pc` (the shape of the condensed CCM-PD S).
    fn bordered(nx: usize, ny: usize, nr: usize, pc: &[usize]) -> CscMatrix {
        let n = nx * ny;
        let mut t = Vec::new();
        for j in 0..ny {
            for i in 0..nx {
                let r = j * nx + i;
                t.push((r, r, 9.0 + (r % 3) as f64));
                if i > 0 {
                    t.push((r, r - 1, -1.0 - 0.1 * (r % 5) as f64));
                }
                if i + 1 < nx {
                    t.push((r, r + 1, -1.2));
                }
                if j > 0 {
                    t.push((r, r - nx, -0.9));
                }
                if j + 1 < ny {
                    t.push((r, r + nx, -1.1 + 0.05 * (r % 7) as f64));
                }
            }
        }
        for r in 0..nr {
            for (k, &c) in pc.iter().enumerate() {
                t.push((r, c, 0.01 * (((r + 3 * k) % 13) as f64 - 6.0)));
            }
        }
        CscMatrix::from_triplets(n, n, &t).unwrap()
    }

    /// The dense columns are numbered last, and the factor solves the matrix as the default
    /// ordering's does (residual and agreement to round-off).
    #[test]
    fn dense_columns_are_ordered_last_and_solve_the_same_system() {
        let pc: Vec<usize> = (0..40).map(|k| 37 + 11 * k).collect();
        let a = bordered(24, 30, 300, &pc);
        let n = a.nrows;
        let b: Vec<f64> = (0..n).map(|i| ((i * 5) % 17) as f64 - 8.0).collect();

        let mut dense_last = Lu::analyze_dense_last(&a).unwrap();
        let (fwd, _) = dense_last.symbolic.col_perm().arrays();
        let mut tail: Vec<usize> = fwd[n - pc.len()..].to_vec();
        tail.sort_unstable();
        assert_eq!(tail, pc, "the dense columns are the last ones eliminated");

        dense_last.factorize(&a).unwrap();
        let x = dense_last.solve(&b).unwrap();
        let y = Lu::new(&a).unwrap().solve(&b).unwrap();
        let scale = b.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let res = a
            .matvec(&x)
            .iter()
            .zip(&b)
            .fold(0.0f64, |m, (ax, bi)| m.max((ax - bi).abs()));
        assert!(res <= 1e-12 * scale, "residual {res}");
        let diff = x
            .iter()
            .zip(&y)
            .fold(0.0f64, |m, (p, q)| m.max((p - q).abs()));
        assert!(
            diff <= 1e-12 * scale,
            "dense-last vs default ordering: {diff}"
        );
    }

    /// Without dense columns the rule flags none: the default COLAMD order.
    #[test]
    fn without_dense_columns_the_order_is_colamds() {
        let a = bordered(20, 20, 0, &[]);
        let p = Lu::analyze_dense_last(&a).unwrap();
        let q = Lu::analyze(&a).unwrap();
        assert_eq!(
            p.symbolic.col_perm().arrays().0,
            q.symbolic.col_perm().arrays().0
        );
    }

    /// A symmetric, diagonally dominant path of `n` unknowns coupled to the next one, or (`moved`)
    /// with unknown 0 coupled to unknown 2 instead of 1: the same size and entry count, another
    /// pattern.
    fn path(n: usize, moved: bool) -> CscMatrix {
        let mut t = Vec::new();
        for i in 0..n {
            t.push((i, i, 4.0));
        }
        for i in 0..n - 1 {
            let j = if moved && i == 0 { 2 } else { i + 1 };
            t.push((i, j, -1.0));
            t.push((j, i, -1.0));
        }
        CscMatrix::from_triplets(n, n, &t).unwrap()
    }

    /// A numeric factorisation of another pattern than the analysed one (same size, same number
    /// of entries) is refused, by the LU and the Cholesky factorisation alike; the analysed
    /// pattern with new values is factorised.
    #[test]
    fn a_factorisation_of_another_pattern_is_refused() {
        let (a, other) = (path(30, false), path(30, true));
        assert_eq!(a.row_idx.len(), other.row_idx.len());
        let mut lu = Lu::analyze(&a).unwrap();
        let mut ch = super::super::Cholesky::analyze(&a).unwrap();
        for e in [lu.factorize(&other), ch.factorize(&other)] {
            assert!(
                matches!(&e, Err(Error::Internal { detail }) if detail.contains("analysed")),
                "{e:?}"
            );
        }
        let mut b = a.clone();
        b.val.iter_mut().for_each(|v| *v *= 2.0);
        lu.factorize(&b).unwrap();
        ch.factorize(&b).unwrap();
    }
}
