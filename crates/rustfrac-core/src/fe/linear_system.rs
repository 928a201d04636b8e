//! The linear static problem K u = f with Dirichlet elimination (K_ff u_f = f_f - K_fc u_c),
//! factorised once by Cholesky and solved for any load: displacements, reactions K u - f, strain
//! energy and residual, and the condition check every plate solve makes.

use crate::error::{Error, Result};
use crate::fe::dirichlet::Dirichlet;
use crate::la::{check_condition, Cholesky, ConditionEstimate, CscMatrix, Reduction};

/// A linear system K u = f with Dirichlet elimination, factorised once by Cholesky, reusable for
/// new loads (several right-hand sides) and refactorisable with new values on the same pattern.
pub struct LinearSystem {
    pub k: CscMatrix,
    pub reduction: Reduction,
    pub prescribed: Vec<f64>,
    chol: Cholesky,
}

/// Solution of a linear static problem.
#[derive(Debug, Clone)]
pub struct Solution {
    /// displacements, all dofs
    pub u: Vec<f64>,
    /// reactions K u - f, all dofs (zero up to round-off at free dofs)
    pub reactions: Vec<f64>,
    /// strain energy 1/2 u^T K u
    pub energy: f64,
    /// relative residual ||K_ff u_f - rhs_f|| / ||rhs_f||
    pub residual: f64,
}

impl LinearSystem {
    /// Eliminates the Dirichlet dofs and factorises K_ff (SPD) with Cholesky (AMD ordering).
    pub fn new(k: CscMatrix, bc: &Dirichlet) -> Result<Self> {
        Self::with_positions(k, bc, None)
    }

    /// As [`LinearSystem::new`], with the position of every dof for a nested-dissection ordering
    /// (recommended above ~1e4 unknowns).
    pub fn with_positions(
        k: CscMatrix,
        bc: &Dirichlet,
        dof_xy: Option<&[[f64; 2]]>,
    ) -> Result<Self> {
        let (mask, prescribed) = bc.to_mask(k.ncols)?;
        let mut reduction = Reduction::new(&k, &mask)?;
        let free_xy: Option<Vec<[f64; 2]>> =
            dof_xy.map(|xy| reduction.free.iter().map(|&d| xy[d]).collect());
        let chol = reduction.with_reduced(&k, |kff| Cholesky::new_with(kff, free_xy.as_deref()))?;
        Ok(Self {
            k,
            reduction,
            prescribed,
            chol,
        })
    }

    /// Replaces the matrix values (same pattern) and refactorises, reusing the symbolic analysis.
    pub fn refactor(&mut self, k: CscMatrix) -> Result<()> {
        let chol = &mut self.chol;
        self.reduction.with_reduced(&k, |kff| chol.factorize(kff))?;
        self.k = k;
        Ok(())
    }

    /// Condition estimate of the factorised K_ff (see [`ConditionEstimate`]; two extra solves
    /// with the factor, K_ff read in place, no refactorisation).
    pub fn condition_estimate(&self) -> Result<ConditionEstimate> {
        self.chol.condition_estimate_free(
            &self.k,
            &self.reduction.map,
            &self.reduction.free,
            crate::la::CONDITION_ITERATIONS,
        )
    }

    /// The condition check every plate solve makes after factorising: with `estimate`, the
    /// condition estimate (2 extra solves) is returned; without, only the free pivot ratio (a
    /// lower bound of the same number, [`ConditionEstimate::pivot_ratio`]) is computed and None
    /// returned. Either above [`crate::la::COND_SINGULAR`] is [`Error::Singular`]
    /// ("numerically singular", [`crate::la::check_condition`]); `what` names the solve.
    pub fn checked_condition(
        &self,
        what: &str,
        estimate: bool,
    ) -> Result<Option<ConditionEstimate>> {
        if estimate {
            let c = self.condition_estimate()?;
            check_condition(what, c.value())?;
            Ok(Some(c))
        } else {
            let diag: Vec<f64> = self
                .reduction
                .free
                .iter()
                .map(|&c| self.k.find(c, c).map_or(0.0, |k| self.k.val[k]))
                .collect();
            check_condition(what, self.chol.pivot_ratio(&diag)?)?;
            Ok(None)
        }
    }

    /// Solves for external forces `f` with the prescribed values scaled by `scale`.
    pub fn solve(&self, f: &[f64], scale: f64) -> Result<Solution> {
        let n = self.k.ncols;
        if f.len() != n {
            return Err(Error::SizeMismatch {
                what: "force vector".into(),
                expected: n,
                got: f.len(),
            });
        }
        let up: Vec<f64> = self.prescribed.iter().map(|v| v * scale).collect();
        let rhs = self.reduction.rhs(&self.k, f, &up);
        let uf = self.chol.solve(&rhs)?;
        let u = self.reduction.expand(&uf, &up);
        let ku = self.k.matvec(&u);
        let reactions: Vec<f64> = ku.iter().zip(f).map(|(a, b)| a - b).collect();
        let energy = 0.5 * u.iter().zip(&ku).map(|(a, b)| a * b).sum::<f64>();
        let (mut rn, mut bn) = (0.0f64, 0.0f64);
        for (i, &d) in self.reduction.free.iter().enumerate() {
            rn += reactions[d] * reactions[d];
            bn += rhs[i] * rhs[i];
        }
        let residual = if bn > 0.0 {
            (rn / bn).sqrt()
        } else {
            rn.sqrt()
        };
        if u.iter().any(|v| !v.is_finite()) {
            return Err(Error::Singular {
                detail: "non-finite displacements".into(),
            });
        }
        Ok(Solution {
            u,
            reactions,
            energy,
            residual,
        })
    }
}
