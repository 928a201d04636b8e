//! The interface between the SLA driver and its two solvers ([`super::oracle`], [`super::fast`]):
//! the state at the reference load, the changes of the model between two solves (a bond broken,
//! a grounding spring added), and the diagnostics both use.

use crate::error::{Error, Result};
use crate::pd::splice::{SpliceModel, Spring};
use std::time::Instant;

/// A state of the model at the reference load.
pub(super) struct State {
    pub(super) sigma22: f64,
    pub(super) cmod: f64,
}

/// One change of the model between two solves: a bond removed, or a grounding spring added.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Update {
    Break(usize),
    Ground(Spring),
}

pub(super) trait Engine {
    fn state(&mut self) -> Result<State>;
    /// displacements of the last `state`, valid at least at the load displacement's and the
    /// probes' dofs, and at the ends of the bonds [`Self::stretches`] evaluated exactly
    fn u(&self) -> &[f64];
    /// The stretch of every bond of `model` in the last `state` into `out` (-inf when
    /// `broken`), or, when it returns true, only of the bonds it lists in `only` (in index
    /// order): every other bond then has a stretch whose ratio to its `scale` is below the
    /// largest such ratio divided by 1 + `tol`, so it can be neither critical nor tie with the
    /// critical one. This default evaluates all.
    fn stretches(
        &mut self,
        model: &SpliceModel,
        broken: &[bool],
        _scale: Option<&[f64]>,
        _tol: f64,
        out: &mut [f64],
        _only: &mut Vec<usize>,
    ) -> bool {
        all_stretches(model, broken, self.u(), out);
        false
    }
    /// Applies one change; Err(Separated) when the body separates.
    fn apply(&mut self, upd: Update) -> Result<()>;
    fn full_u(&mut self) -> Result<Vec<f64>>;
    fn n_refactorisations(&self) -> usize;
    /// largest number of stored low-rank update vectors so far (0: none kept)
    fn max_update_rank(&self) -> usize;
    /// columns of S_0^{-1} computed for the updates (sparse base, `fast/columns.rs`; else 0)
    fn inverse_columns(&self) -> usize {
        0
    }
    /// 1 when the sparse form fell back from the bordered Cholesky to the LU of S
    /// (`fast/base.rs`), else 0
    fn lu_fallbacks(&self) -> usize {
        0
    }
    /// steps screened and bonds evaluated exactly in them ([`Self::stretches`] returning true)
    fn screening(&self) -> (usize, usize) {
        (0, 0)
    }
}

/// The stretch of every bond of `model` in `u` into `out` (-inf when `broken`).
pub(super) fn all_stretches(model: &SpliceModel, broken: &[bool], u: &[f64], out: &mut [f64]) {
    for ((o, bond), &br) in out.iter_mut().zip(&model.bonds).zip(broken) {
        *o = if br {
            f64::NEG_INFINITY
        } else {
            bond.stretch(u)
        };
    }
}

/// A state whose displacements grew beyond this factor of the engine's first state's is not
/// accurate: a part of the body floats (its displacement set by round-off) or the updates of the
/// fast engine lost their accuracy. The oracle then reports a separation; the fast engine first
/// recomputes the state by a fresh condensation (the exact path) and separates only if that
/// state grew too.
pub(super) const U_GROWTH_SEPARATED: f64 = 1e4;

pub(super) fn separated(detail: String) -> Error {
    Error::Separated { detail }
}

pub(super) fn timing(what: &str, t0: Instant) {
    if std::env::var_os("RUSTFRAC_TIMING").is_some() {
        eprintln!(
            "[rustfrac timing] {what}: {:.3} s",
            t0.elapsed().as_secs_f64()
        );
    }
}
