//! The interface between the SLA driver and its two solvers ([`super::oracle`], [`super::fast`]):
//! the state at the reference load, the changes of the model between two solves (a bond broken,
//! a grounding spring added), and the diagnostics both use.

use crate::error::{Error, Result};
use crate::pd::splice::Spring;
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
    /// displacements of the last `state`, valid at least at every bond end dof
    fn u(&self) -> &[f64];
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
}

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
