//! The adaptive region's switches (`pd.region = "adaptive"`, `adaptive.rs`): when the region must
//! grow before a step, the grown model, the broken bonds carried over to it by key, and the
//! records of the run renumbered into the final model at the end.

use super::adaptive::{
    bond_interface_distance, bond_key, bond_midpoint, damage_keys, node_key, step_keys, Index, Keys,
};
use super::engine::timing;
use super::result::RegionSwitch;
use super::state::RunState;
use crate::error::Result;
use crate::pd::splice::SpliceModel;
use crate::problem::{pd_region, AdaptiveRegion};
use std::time::Instant;

impl RunState {
    /// Grows the adaptive region `a` around `centres` (the midpoints [`Self::growth`] found)
    /// before step `history.len() + 1`: the model with the new rectangles, this state carried
    /// over to it, the switch recorded (`ts`: when the switch began).
    pub(super) fn switch(
        &mut self,
        model: &SpliceModel,
        a: AdaptiveRegion,
        centres: Vec<[f64; 2]>,
        ts: Instant,
    ) -> Result<SpliceModel> {
        let pm = model.pd_method();
        let regions = pd_region::grown(
            &model.problem.domain,
            model.grid.dx,
            model.pd.delta,
            &a,
            &pm.regions,
            &centres,
        );
        let new = model.with_regions(regions.clone())?;
        self.carry_over(model, &new)?;
        let step = self.history.len() + 1;
        self.switch_centres.push((step, centres));
        self.switches.push(RegionSwitch {
            step,
            regions,
            n_pd_nodes: new.pd_nodes.len(),
            n_dofs: new.n_dofs(),
            seconds: ts.elapsed().as_secs_f64(),
        });
        timing("adaptive region grown (model)", ts);
        Ok(new)
    }

    /// Carries the broken bonds from `old` to the grown region's model `new` (by key), and
    /// from the first switch on keeps the records by key.
    fn carry_over(&mut self, old: &SpliceModel, new: &SpliceModel) -> Result<()> {
        if self.keys.is_none() {
            // everything so far ran on `old`, the first model
            let keys = Keys {
                steps: self.history.iter().map(|st| step_keys(old, st)).collect(),
                detached: self
                    .detached_nodes
                    .iter()
                    .map(|&(_, n)| node_key(old, n))
                    .collect(),
                damage_at: self
                    .damage_at
                    .iter()
                    .map(|(_, d)| damage_keys(old, d))
                    .collect(),
            };
            self.keys = Some(keys);
        }
        let index = Index::new(new);
        let mut broken = new.precrack_broken.clone();
        for b in (0..old.bonds.len()).filter(|&b| self.broken[b]) {
            broken[index.bond(&bond_key(old, b))?] = true;
        }
        self.broken = broken;
        Ok(())
    }

    /// Whether the adaptive region must grow before the bonds `sel` break: the midpoints of
    /// those within `pd.adapt_margin` horizons of the interface, when growing around them
    /// changes the region (else they break where they are: the plate's edge or a hole stops
    /// the growth, and the run warns).
    pub(super) fn growth(&mut self, model: &SpliceModel, sel: &[usize]) -> Option<Vec<[f64; 2]>> {
        let pm = model.pd_method();
        let a = pm.adaptive?;
        let delta = model.pd.delta;
        let margin = a.margin * delta * (1.0 - 1e-9);
        let centres: Vec<[f64; 2]> = sel
            .iter()
            .filter(|&&b| bond_interface_distance(model, b, margin) < margin)
            .map(|&b| bond_midpoint(model, b))
            .collect();
        if centres.is_empty() {
            return None;
        }
        let d = &model.problem.domain;
        let grown = pd_region::grown(d, model.grid.dx, delta, &a, &pm.regions, &centres);
        if grown == pm.regions {
            self.margin_violated = true;
            return None;
        }
        Some(centres)
    }
}

/// The records of a run whose region switched, in the final model's numbering (by key).
pub(super) fn in_final_numbering(
    model: &SpliceModel,
    st: &mut RunState,
    keys: &Keys,
) -> Result<()> {
    let index = Index::new(model);
    for (row, k) in st.history.iter_mut().zip(&keys.steps) {
        row.bonds = k
            .bonds
            .iter()
            .map(|b| index.bond(b))
            .collect::<Result<_>>()?;
        row.nodes = [index.node(&k.nodes[0])?, index.node(&k.nodes[1])?];
        row.detached = k
            .detached
            .iter()
            .map(|n| index.node(n))
            .collect::<Result<_>>()?;
    }
    for (d, k) in st.detached_nodes.iter_mut().zip(&keys.detached) {
        d.1 = index.node(k)?;
    }
    let slot: std::collections::HashMap<usize, usize> = model
        .pd_nodes
        .iter()
        .enumerate()
        .map(|(s, &n)| (n, s))
        .collect();
    for ((_, d), k) in st.damage_at.iter_mut().zip(&keys.damage_at) {
        let mut full = vec![0.0; model.pd_nodes.len()];
        for (key, v) in k {
            let n = index.node(key)?;
            if let Some(&s) = slot.get(&n) {
                full[s] = *v;
            }
        }
        *d = full;
    }
    Ok(())
}
