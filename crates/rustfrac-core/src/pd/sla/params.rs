//! The inputs of a CCM-PD / PD run: the model ([`ModelSpec`]) and the options of the sequentially
//! linear analysis ([`SlaParams`]), with the fast solver's automatic re-condensation interval
//! ([`auto_refactor_every`]). A leaf module: the checkpoint fingerprint reads these inputs.

use crate::error::{check_finite, check_positive, Error, Result};
use crate::pd::splice::ModelSpec;
use std::path::PathBuf;

/// Options of the sequentially linear analysis.
#[derive(Debug, Clone, PartialEq)]
pub struct SlaParams {
    /// number of SLA steps (bond-break events); 0 = only the linear solution
    pub max_steps: usize,
    /// stop when the crack (pre-crack + broken bonds, along the pre-crack direction) reaches this
    pub stop_crack_length: Option<f64>,
    /// break together every bond with load factor <= lambda (1 + tie_tol); 0 = one bond per step
    pub tie_tol: f64,
    /// fast solver: re-condense after this many low-rank updates (0 = automatic: when the stored
    /// update vectors reach [`auto_refactor_every`] of the condensed size, which bounds their
    /// memory by about 3/4 of the condensed inverse; see the module docs)
    pub refactor_every: usize,
    /// condensation + Sherman-Morrison-Woodbury (true) or refactorise every step (false, oracle)
    pub fast: bool,
    /// steps after which the damage field is stored (besides the final one)
    pub damage_at_steps: Vec<usize>,
    /// write a checkpoint to `checkpoint_path` after every this many steps (0 = never); a
    /// cancelled run writes one too
    pub checkpoint_every: usize,
    /// checkpoint file (written atomically: a temporary file in the same directory, then renamed)
    pub checkpoint_path: Option<PathBuf>,
    /// resume from this checkpoint: the model is rebuilt, the checkpoint's steps are replayed
    /// exactly (same low-rank updates in the same order) and the run continues; the history is the
    /// same bit for bit as an uninterrupted run's
    pub resume_from: Option<PathBuf>,
}

impl Default for SlaParams {
    fn default() -> Self {
        Self {
            max_steps: 500,
            stop_crack_length: None,
            tie_tol: 0.0,
            refactor_every: 0,
            fast: true,
            damage_at_steps: Vec::new(),
            checkpoint_every: 0,
            checkpoint_path: None,
            resume_from: None,
        }
    }
}

/// The automatic re-condensation interval of the fast solver for `n_p` condensed unknowns:
/// max(64, n_p / 2), at most 4096. Re-condensing costs O(n_p^3), a step with k stored updates
/// O(k n_p), so intervals of order n_p balance the two; n_p / 2 keeps the update vectors (k n_p)
/// and the capacitance inverse (k^2) below 3/4 of the condensed inverse (n_p^2), so the solver's
/// memory does not grow with the number of steps. The paper's case (n_p = 2080) never reaches it
/// in 500 steps.
pub fn auto_refactor_every(n_p: usize) -> usize {
    (n_p / 2).clamp(64, 4096)
}

/// Everything a CCM-PD / PD run needs: the model and the SLA options (the paper's values in
/// [`CcmPdParams::paper`]).
#[derive(Debug, Clone)]
pub struct CcmPdParams {
    /// plate, grid, horizon, material, G0, PD rectangles, pre-crack, load and method
    pub model: ModelSpec,
    pub sla: SlaParams,
}

impl CcmPdParams {
    /// The paper's benchmark ([`ModelSpec::paper`]) with the default SLA options.
    pub fn paper() -> Self {
        Self {
            model: ModelSpec::paper(),
            sla: SlaParams::default(),
        }
    }
}

impl SlaParams {
    /// Checks every option (the model is validated when it is built, [`crate::pd::splice::SpliceModel::new`]).
    pub fn validate(&self) -> Result<()> {
        if self.max_steps > 1_000_000 {
            return Err(Error::invalid("max_steps", "0..=1000000", self.max_steps));
        }
        if let Some(l) = self.stop_crack_length {
            check_positive("stop_crack_length", l)?;
        }
        check_finite("tie_tol", self.tie_tol)?;
        if !(0.0..1.0).contains(&self.tie_tol) {
            return Err(Error::invalid("tie_tol", "0 <= tie_tol < 1", self.tie_tol));
        }
        if self.checkpoint_every > 0 && self.checkpoint_path.is_none() {
            return Err(Error::invalid(
                "checkpoint_path",
                "a file path when checkpoint_every > 0",
                "none",
            ));
        }
        Ok(())
    }
}
