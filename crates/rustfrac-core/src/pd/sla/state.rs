//! The evolving state of an SLA run ([`RunState`]): the broken bonds, the groundings of the nodes
//! they detach (`grounding.rs`), the history and what it records per step.

use super::adaptive::{bond_interface_distance, damage_keys, node_key, step_keys, Keys};
use super::checkpoint;
use super::grounding::Grounding;
use super::result::{RegionSwitch, SlaStatus, SlaStep};
use crate::pd::damage;
use crate::pd::splice::{ProbeFunctional, SpliceModel, Spring};
use crate::problem::SlaParams;

/// The evolving state of a run: the broken bonds (pre-crack included), the groundings, the
/// history, the status and, for an adaptive region, its switches and the keys of what was
/// recorded (`adaptive.rs`).
pub(super) struct RunState {
    pub(super) broken: Vec<bool>,
    pub(super) grounding: Grounding,
    /// (step, node) of every grounding; step 0 = detached by the pre-crack
    pub(super) detached_nodes: Vec<(usize, usize)>,
    pub(super) history: Vec<SlaStep>,
    pub(super) damage_at: Vec<(usize, Vec<f64>)>,
    pub(super) status: SlaStatus,
    /// the scene's probes, recorded at every step
    pub(super) probes: Vec<ProbeFunctional>,
    pub(super) n_checkpoints: usize,
    /// the adaptive region's growths (the result's) and as a checkpoint stores them
    pub(super) switches: Vec<RegionSwitch>,
    pub(super) switch_centres: Vec<checkpoint::Switch>,
    /// the records by key, from the first switch on (None: one model, its own numbering)
    pub(super) keys: Option<Keys>,
    /// the smallest interface distance of a broken bond so far (length; infinite: none)
    pub(super) closest: f64,
    /// a bond broke within the margin because the region could not grow (warned once)
    pub(super) margin_violated: bool,
}

/// How far the interface distance of a broken bond is searched (horizons): beyond it the
/// closest approach is reported as "none within".
const INTERFACE_SEARCH: f64 = 10.0;

impl RunState {
    pub(super) fn new(model: &SpliceModel) -> Self {
        Self {
            broken: model.precrack_broken.clone(),
            grounding: Grounding::new(model.grid.n_nodes()),
            detached_nodes: Vec::new(),
            history: Vec::new(),
            damage_at: Vec::new(),
            status: SlaStatus::Completed,
            probes: Vec::new(),
            n_checkpoints: 0,
            switches: Vec::new(),
            switch_centres: Vec::new(),
            keys: None,
            closest: f64::INFINITY,
            margin_violated: false,
        }
    }

    /// The springs of the nodes the pre-crack already detaches (recorded as step 0).
    pub(super) fn ground_precrack(&mut self, model: &SpliceModel) -> Vec<Spring> {
        let mut springs0 = Vec::new();
        for (n, sp) in self.ground_touched(model) {
            if !self.detached_nodes.contains(&(0, n)) {
                self.detached_nodes.push((0, n));
            }
            springs0.push(sp);
        }
        springs0
    }

    /// The springs a grown region's model needs for the bonds broken so far (fresh groundings
    /// on the new model; the nodes were recorded when they were first detached).
    pub(super) fn ground_again(&mut self, model: &SpliceModel) -> Vec<Spring> {
        self.grounding = Grounding::new(model.grid.n_nodes());
        self.ground_touched(model)
            .into_iter()
            .map(|(_, sp)| sp)
            .collect()
    }

    /// The groundings of every PD node with a broken bond (only those can be loose: a
    /// fragment's nodes all lost a bond).
    fn ground_touched(&mut self, model: &SpliceModel) -> Vec<(usize, Spring)> {
        let touched: Vec<usize> = model
            .pd_nodes
            .iter()
            .copied()
            .filter(|&n| model.bonds_of(n).iter().any(|&b| self.broken[b as usize]))
            .collect();
        let mut out = Vec::new();
        for n in touched {
            out.extend(self.grounding.springs(model, n, &self.broken));
        }
        out
    }

    /// Appends a step to the history (its keys too, from the first switch on) and stores the
    /// damage field after it when it is one of `damage_at_steps`.
    pub(super) fn record(&mut self, model: &SpliceModel, sla: &SlaParams, st: SlaStep) {
        let step = st.step;
        if let Some(k) = self.keys.as_mut() {
            k.detached
                .extend(st.detached.iter().map(|&n| node_key(model, n)));
            k.steps.push(step_keys(model, &st));
        }
        self.history.push(st);
        if sla.damage_at_steps.contains(&step) {
            let d = damage(
                model.grid.n_nodes(),
                &model.bonds,
                &self.broken,
                &model.pd_nodes,
            );
            if let Some(k) = self.keys.as_mut() {
                k.damage_at.push(damage_keys(model, &d));
            }
            self.damage_at.push((step, d));
        }
    }

    /// Keeps the smallest interface distance of the bonds `sel` (CCM-PD; pure PD has none).
    pub(super) fn note_interface(&mut self, model: &SpliceModel, sel: &[usize]) {
        if model.all_pd {
            return;
        }
        // a node farther than the closest so far cannot lower it: search only that far
        let cap = self.closest.min(INTERFACE_SEARCH * model.pd.delta);
        for &b in sel {
            self.closest = self.closest.min(bond_interface_distance(model, b, cap));
        }
    }
}
