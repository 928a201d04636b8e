//! The oracle solver (`fast = false`): reassemble the splice matrix and refactorise it (sparse LU,
//! symbolic analysis reused) at every step. Slow, simple, the reference of the fast solver.

use super::engine::{separated, Engine, State, Update, U_GROWTH_SEPARATED};
use crate::error::Result;
use crate::la::Lu;
use crate::la::{CscMatrix, Reduction};
use crate::pd::splice::{SpliceModel, Spring};

/// Refactorise-every-step oracle.
pub(super) struct Oracle<'a> {
    model: &'a SpliceModel,
    red: Reduction,
    lu: Lu,
    k: CscMatrix,
    dirty: bool,
    broken: Vec<bool>,
    springs: Vec<Spring>,
    n_fact: usize,
    /// max |u| of the first solve, the scale for the separation test
    u_scale: f64,
    u: Vec<f64>,
}

impl<'a> Oracle<'a> {
    pub(super) fn new(
        model: &'a SpliceModel,
        broken: &[bool],
        springs: &[Spring],
        k: &CscMatrix,
    ) -> Result<Self> {
        let k = k.clone();
        let red = Reduction::new(&k, &model.mask)?;
        let kff = red.reduce(&k);
        let lu = Lu::new(&kff)?;
        Ok(Self {
            model,
            red,
            lu,
            k,
            dirty: false,
            broken: broken.to_vec(),
            springs: springs.to_vec(),
            n_fact: 1,
            u_scale: 0.0,
            u: Vec::new(),
        })
    }
    fn refresh(&mut self) -> Result<()> {
        if self.dirty {
            self.k = self.model.assemble_with(&self.broken, &self.springs);
            let kff = self.red.reduce(&self.k);
            self.lu.factorize(&kff)?;
            self.n_fact += 1;
            self.dirty = false;
        }
        Ok(())
    }
}

impl Engine for Oracle<'_> {
    fn state(&mut self) -> Result<State> {
        self.refresh()?;
        let s = crate::pd::splice::solve_with(self.model, &self.k, &self.red, &self.lu)
            .map_err(|e| separated(format!("oracle solve failed: {e}")))?;
        if s.residual.is_nan() || s.residual >= 1e-6 {
            return Err(separated(format!(
                "residual {:.3e} of the refactorised system (numerically singular)",
                s.residual
            )));
        }
        // a separated part floats: its displacement is set by round-off and is huge
        let umax = s.u.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        if self.u_scale == 0.0 {
            self.u_scale = umax;
        } else if umax > U_GROWTH_SEPARATED * self.u_scale {
            return Err(separated(format!(
                "displacements grew from {:.3e} to {umax:.3e} (singular system)",
                self.u_scale
            )));
        }
        self.u = s.u;
        Ok(State {
            sigma22: s.sigma22,
            cmod: s.cmod,
        })
    }
    fn apply(&mut self, upd: Update) -> Result<()> {
        match upd {
            Update::Break(b) => self.broken[b] = true,
            Update::Ground(s) => self.springs.push(s),
        }
        self.dirty = true;
        Ok(())
    }
    fn full_u(&mut self) -> Result<Vec<f64>> {
        self.state()?;
        Ok(self.u.clone())
    }
    fn u(&self) -> &[f64] {
        &self.u
    }
    fn n_refactorisations(&self) -> usize {
        self.n_fact
    }
    fn max_update_rank(&self) -> usize {
        0
    }
}
