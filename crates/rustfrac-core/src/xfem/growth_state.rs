//! The whole plate at the critical states of a growth run ([`GrowthState`]): what a file or a
//! plot of one state shows (the standard displacements, the element stresses, the cut cells of
//! that state's cracks with their own displacements and stresses, the crack polylines), each at
//! that state's critical load. Which states are kept is `xfem.state_every`
//! ([`crate::problem::Growth::state_every`]): every k-th growth step and the last one, or none.

use super::model::XfemModel;
use super::patch::CutCells;
use crate::error::Result;

/// Sub-cells per direction of the cut cells of a state (the single solve's: 2 x 2 per element).
pub const STATE_CUT_CELLS: usize = 2;

/// One critical state of a growth run, the whole plate at its critical load (the reference
/// solution of that state's cracks scaled by the load factor).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct GrowthState {
    /// the history row the state belongs to (1 = the first critical state; row 0 is the
    /// unloaded origin, which has no state of its own)
    pub row: usize,
    /// the standard dofs, interleaved [u1, u2] per node (the shifted enrichments vanish at the
    /// nodes)
    pub u: Vec<f64>,
    /// every element's stress [s11, s22, s12]: the mean of the enriched stress at its 2 x 2
    /// Gauss points ([`XfemModel::gauss_stresses`])
    pub stress: Vec<[f64; 3]>,
    /// the enriched elements of this state's cracks as cells on each side of the crack
    /// ([`XfemModel::cut_cells`], [`STATE_CUT_CELLS`] per direction)
    pub cut: CutCells,
    /// the polylines of every crack of the state (the cracks its solve ran on)
    pub cracks: Vec<Vec<[f64; 2]>>,
    /// each node's enrichment for this state's cracks: 0 standard, 1 Heaviside, 2 tip
    pub enrichment: Vec<f64>,
}

impl GrowthState {
    /// The state of `model` solved at the reference load (`u`, all dofs) scaled by the load
    /// factor `lam`, for history row `row`.
    pub(super) fn new(model: &XfemModel, u: &[f64], lam: f64, row: usize) -> Result<Self> {
        let u: Vec<f64> = u.iter().map(|v| lam * v).collect();
        let (_, gauss) = model.gauss_stresses(&u);
        let n_el = model.mesh.n_elements();
        let per = gauss.len().checked_div(n_el).unwrap_or(1).max(1);
        let stress = gauss
            .chunks(per)
            .map(|c| {
                let n = c.len() as f64;
                let s = c
                    .iter()
                    .fold([0.0; 3], |a, q| [a[0] + q[0], a[1] + q[1], a[2] + q[2]]);
                [s[0] / n, s[1] / n, s[2] / n]
            })
            .collect();
        let enrichment = node_enrichment(
            model.mesh.coords.len(),
            model.heaviside_nodes.iter().flatten(),
            model.tip_nodes.iter().flatten(),
        );
        Ok(Self {
            row,
            enrichment,
            cut: model.cut_cells(&u, STATE_CUT_CELLS)?,
            stress,
            u: u[..model.n_std].to_vec(),
            cracks: model.cracks.iter().map(|c| c.points.clone()).collect(),
        })
    }
}

/// Each of `n_nodes` nodes' largest enrichment: 0 standard, 1 Heaviside (`heaviside`), 2 tip
/// (`tip`).
pub fn node_enrichment<'a>(
    n_nodes: usize,
    heaviside: impl IntoIterator<Item = &'a usize>,
    tip: impl IntoIterator<Item = &'a usize>,
) -> Vec<f64> {
    let mut out = vec![0.0; n_nodes];
    for &n in heaviside {
        out[n] = 1.0;
    }
    for &n in tip {
        out[n] = 2.0;
    }
    out
}

/// The states a growth run keeps: every `every`-th growth step (the first included) and the
/// last one; none with `every = 0`.
#[derive(Debug, Default)]
pub(super) struct KeptStates {
    every: usize,
    kept: Vec<GrowthState>,
    /// the latest state when it is not a kept one (kept at the end: the last state)
    last: Option<GrowthState>,
}

impl KeptStates {
    pub(super) fn new(every: usize) -> Self {
        Self {
            every,
            ..Self::default()
        }
    }

    /// Whether states are kept at all (no state is built otherwise).
    pub(super) fn any(&self) -> bool {
        self.every > 0
    }

    /// The state of growth step `step` (0-based).
    pub(super) fn push(&mut self, step: usize, state: GrowthState) {
        if step % self.every == 0 {
            self.kept.push(state);
            self.last = None;
        } else {
            self.last = Some(state);
        }
    }

    /// The kept states in history order, the last state included.
    pub(super) fn finish(mut self) -> Vec<GrowthState> {
        self.kept.extend(self.last.take());
        self.kept
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rows(every: usize, steps: usize) -> Vec<usize> {
        let mut k = KeptStates::new(every);
        for step in 0..steps {
            if k.any() {
                let state = GrowthState {
                    row: step + 1,
                    ..GrowthState::default()
                };
                k.push(step, state);
            }
        }
        k.finish().iter().map(|s| s.row).collect()
    }

    #[test]
    fn every_kth_step_and_the_last_are_kept() {
        assert_eq!(rows(1, 4), [1, 2, 3, 4]);
        assert_eq!(rows(2, 4), [1, 3, 4]);
        assert_eq!(rows(2, 5), [1, 3, 5]);
        assert_eq!(rows(10, 3), [1, 3]);
        assert_eq!(rows(3, 1), [1]);
        assert!(rows(0, 4).is_empty());
    }
}
