//! The checkpoint glue of a run ([`super::checkpoint`] is the format): the bounds a checkpoint
//! is read with, the replay of its steps (the updates of the run that wrote it, in the same
//! order) and the writing of one.

use super::checkpoint;
use super::engine::Engine;
use super::result::{SlaStatus, SlaStep};
use super::state::RunState;
use super::steps::advance;
use crate::error::{Error, Result};
use crate::pd::splice::SpliceModel;
use crate::problem::SlaParams;

/// The bounds a checkpoint of this run is read with (bonds, nodes, probes): the model's, or for
/// an adaptive region the whole plate's (its region grows).
pub(super) fn checkpoint_sizes(
    model: &SpliceModel,
    adaptive: bool,
) -> Result<(usize, usize, usize)> {
    let n_probes = model.probe_functionals()?.len();
    if !adaptive {
        return Ok((model.bonds.len(), model.grid.n_nodes(), n_probes));
    }
    let d = &model.problem.domain;
    let nodes = ((d.width / model.grid.dx).round() as usize + 1)
        * ((d.height / model.grid.dx).round() as usize + 1);
    let fam = crate::pd::family_stencil(model.pd_method().m).len();
    Ok((nodes * fam, nodes, n_probes))
}

/// The steps and switches of a checkpoint still to replay.
pub(super) struct Replay {
    pub(super) steps: std::collections::VecDeque<SlaStep>,
    pub(super) switches: Vec<checkpoint::Switch>,
}

impl RunState {
    /// Replays the checkpoint's steps on `model` (exactly the updates of the run that wrote it,
    /// in the same order; the recorded numbers come from their stored bits) up to its next
    /// region switch: returns the midpoints of the bonds that grew the region there, or None
    /// when every step is replayed.
    pub(super) fn replay(
        &mut self,
        sla: &SlaParams,
        model: &SpliceModel,
        engine: &mut dyn Engine,
        rp: &mut Replay,
    ) -> Result<Option<Vec<[f64; 2]>>> {
        loop {
            if let Some(sw) = rp.switches.first() {
                if sw.0 == self.history.len() + 1 {
                    return Ok(Some(rp.switches.remove(0).1));
                }
            }
            let Some(st) = rp.steps.pop_front() else {
                return Ok(None);
            };
            let n_bonds = model.bonds.len();
            if st.bonds.iter().any(|&b| b >= n_bonds || self.broken[b]) {
                return Err(Error::invalid(
                    "pd.resume_from",
                    "a checkpoint breaking every bond of the model once",
                    format!("step {} breaks a bond twice or names no bond", st.step),
                ));
            }
            self.note_interface(model, &st.bonds);
            let (det, sep) = advance(
                model,
                engine,
                &mut self.broken,
                &mut self.grounding,
                &st.bonds,
            )?;
            self.detached_nodes
                .extend(det.iter().map(|&n| (st.step, n)));
            self.record(model, sla, st);
            if sep {
                self.status = SlaStatus::Separated;
                rp.steps.clear();
                return Ok(None);
            }
        }
    }

    /// Writes the history so far (and the region switches) to `checkpoint_path` when set.
    pub(super) fn checkpoint(&mut self, sla: &SlaParams, fp: u64) -> Result<()> {
        if let Some(path) = &sla.checkpoint_path {
            checkpoint::write(path, fp, &self.history, &self.switch_centres)?;
            self.n_checkpoints += 1;
        }
        Ok(())
    }
}
