//! Condition of a factorised SPD system: the Hager-Higham 1-norm estimate of the equilibrated
//! matrix and the free LDL^T pivot ratio ([`ConditionEstimate`]), the thresholds [`COND_WARN`]
//! (a warning) and [`COND_SINGULAR`] (numerically singular, [`check_condition`]) and the warning
//! text ([`condition_warning`]).

use super::cholesky::Cholesky;
use super::csc::CscMatrix;
use crate::error::{Error, Result};
use crate::warning::{Warning, WarningKind};

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
/// trusted. The pivot test ([`crate::la::PIVOT_TOL`]) catches pivots that collapse; this
/// catches the near singularity the pivots do not show (their ratio is only a lower bound of the
/// condition number): e.g. a near-null mode spread over n unknowns leaves a last pivot
/// ~n lambda_min (tests/suite/singular_detection.rs: a grounded spring chain, cond 5e15, pivot ratio
/// 2e12). The worst well-posed model we run (a/W = 0.95 at 1e6 unknowns) measures 4.5e10, over
/// 2000x below; between [`COND_WARN`] and this the result carries a warning.
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
/// estimate on the 352 x 665 plate (tests/suite/xfem_extremes.rs); a solve costs ~10 % of a
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
    /// dof), i.e. without gathering K_ff again (see [`crate::la::Reduction`]).
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
        let (dmin, dmax) = self.pivot_range_scaled(s);
        dmax / dmin
    }

    /// Smallest and largest LDL^T pivot of A^ = D^-1/2 A D^-1/2, given s = D^-1/2.
    fn pivot_range_scaled(&self, s: &[f64]) -> (f64, f64) {
        // pivots of A^: d_i / A_ii
        let piv = self.pivots();
        let (mut dmin, mut dmax) = (f64::INFINITY, 0.0f64);
        for (i, &d) in piv.iter().enumerate() {
            let dh = d * s[i] * s[i];
            dmin = dmin.min(dh);
            dmax = dmax.max(dh);
        }
        (dmin, dmax)
    }

    /// Smallest and largest LDL^T pivot of the equilibrated matrix A^ = D^-1/2 A D^-1/2 (the
    /// diagonal of A is `diag`), e.g. to combine them with the pivots of a Schur complement.
    pub fn pivot_range(&self, diag: &[f64]) -> Result<(f64, f64)> {
        let s = equilibration(diag)?;
        Ok(self.pivot_range_scaled(&s))
    }

    /// Hager-Higham estimate of ||A^^-1||_1 of the equilibrated matrix (diagonal of A: `diag`),
    /// with [`CONDITION_ITERATIONS`] steps (2 solves): the inverse-norm half of
    /// [`Cholesky::condition_estimate`].
    pub fn inverse_norm_estimate(&self, diag: &[f64]) -> Result<f64> {
        let s = equilibration(diag)?;
        hager_higham(
            self.n,
            CONDITION_ITERATIONS,
            |x: &mut [f64]| -> Result<()> {
                for (v, si) in x.iter_mut().zip(&s) {
                    *v /= si;
                }
                self.solve_in_place(x)?;
                for (v, si) in x.iter_mut().zip(&s) {
                    *v /= si;
                }
                Ok(())
            },
        )
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
        let s = equilibration(diag)?;
        let norm_a = scaled_norm1(&s);
        let pivot_ratio = self.pivot_ratio_scaled(&s);
        // Hager-Higham on B = A^-1^ = D^(1/2) A^-1 D^(1/2) (symmetric, so B^T = B). One
        // right-hand side per solve: faer's two-column solve measured 7x slower than two
        // single ones on the 352 x 665 plate.
        let mut solves = 0;
        let est = hager_higham(n, iterations, |x: &mut [f64]| -> Result<()> {
            for (v, si) in x.iter_mut().zip(&s) {
                *v /= si;
            }
            self.solve_in_place(x)?;
            for (v, si) in x.iter_mut().zip(&s) {
                *v /= si;
            }
            solves += 1;
            Ok(())
        })?;
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

/// s = D^(-1/2) of the equilibration A^ = D^(-1/2) A D^(-1/2), D = diag(A) = `diag`; a
/// non-positive entry is [`Error::NotPositiveDefinite`].
fn equilibration(diag: &[f64]) -> Result<Vec<f64>> {
    let mut s = vec![0.0; diag.len()]; // D^(-1/2)
    for (c, (sc, &dc)) in s.iter_mut().zip(diag).enumerate() {
        if dc.is_nan() || dc <= 0.0 {
            return Err(Error::NotPositiveDefinite {
                detail: format!("diagonal entry {c} is {dc}"),
            });
        }
        *sc = 1.0 / dc.sqrt();
    }
    Ok(s)
}

/// Hager-Higham estimate of ||B||_1 of a symmetric n x n matrix B (n > 0) given as `apply`
/// (x <- B x), with at most `iterations` of Hager's steps (Higham 1988, LAPACK xLACN2).
pub(crate) fn hager_higham(
    n: usize,
    iterations: usize,
    mut apply: impl FnMut(&mut [f64]) -> Result<()>,
) -> Result<f64> {
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
    Ok(est)
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
