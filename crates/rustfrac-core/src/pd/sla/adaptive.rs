//! The adaptive PD region in the SLA (`pd.region = "adaptive"`): the interface distance of a
//! bond, the growth trigger, and the state carried from one model to the next (docs/design.md,
//! "The adaptive region").
//!
//! * **Interface distance** of a node: the distance to the nearest FEM node (a material node
//!   that is not PD; the plate's edges and holes are not an interface). Of a bond: the smaller
//!   of its end nodes'. Every CCM-PD run reports the smallest over the bonds the SLA broke
//!   (`interface_distance_min`, in horizons): the splice coupling is not in balance near the
//!   interface (Ongaro et al. 2021), so a bond breaking there is suspect.
//! * **Trigger**: before a step breaks its bond(s), a bond within `pd.adapt_margin` horizons of
//!   the interface grows the region ([`crate::problem::pd_region::grown`]); the model is rebuilt
//!   with the new rectangles and the step is solved again on it. Each SLA step is a fresh linear
//!   solve of the current bond state, so nothing but the broken bonds carries over: they are
//!   found in the new model by their end nodes' positions on the PD lattice ([`Keys`]; the PD
//!   nodes of every model lie on the lattice x = i dx, y = j dx, graded FEM grids included).
//! * **Numbering**: bond and node indices are those of the model a step ran on; a checkpoint
//!   stores them so, with the table of region switches. When the region switched, the result's
//!   history, detached nodes and damage snapshots are translated to the final model by the keys.

use super::result::SlaStep;
use crate::error::{Error, Result};
use crate::pd::splice::SpliceModel;
use std::collections::HashMap;

/// A node's place on the PD lattice (i, j): x = i dx, y = j dx.
pub(super) type NodeKey = [i64; 2];
/// A bond by its end nodes' keys (ordered).
pub(super) type BondKey = [NodeKey; 2];

/// The lattice key of node `n` of `model`.
pub(super) fn node_key(model: &SpliceModel, n: usize) -> NodeKey {
    model.grid.lattice_key(n)
}

/// The key of bond `b` of `model`.
pub(super) fn bond_key(model: &SpliceModel, b: usize) -> BondKey {
    let bond = &model.bonds[b];
    let (p, q) = (
        node_key(model, bond.i as usize),
        node_key(model, bond.j as usize),
    );
    if p <= q {
        [p, q]
    } else {
        [q, p]
    }
}

/// The bonds and nodes of a model by key.
pub(super) struct Index {
    bonds: HashMap<BondKey, usize>,
    nodes: HashMap<NodeKey, usize>,
}

impl Index {
    pub(super) fn new(model: &SpliceModel) -> Self {
        let bonds = (0..model.bonds.len())
            .map(|b| (bond_key(model, b), b))
            .collect();
        // the nodes on the lattice (PD nodes and the uniform band around them)
        let dx = model.grid.dx;
        let on_lattice = |v: f64| ((v / dx) - (v / dx).round()).abs() < 1e-6;
        let nodes = (0..model.grid.n_nodes())
            .filter(|&n| model.grid.xy(n).iter().all(|&v| on_lattice(v)))
            .map(|n| (node_key(model, n), n))
            .collect();
        Self { bonds, nodes }
    }

    pub(super) fn bond(&self, k: &BondKey) -> Result<usize> {
        self.bonds.get(k).copied().ok_or_else(|| lost("bond", k))
    }

    pub(super) fn node(&self, k: &NodeKey) -> Result<usize> {
        self.nodes.get(k).copied().ok_or_else(|| lost("node", k))
    }
}

/// A PD bond or node missing from a grown region: the region only grows, so this is a bug.
fn lost(what: &str, k: &impl std::fmt::Debug) -> Error {
    Error::invalid(
        "pd.region",
        &format!("an adaptive region that keeps every PD {what} (internal rule)"),
        format!("{what} {k:?} lost by the growth"),
    )
}

/// The distance from node `n` to the nearest FEM node, searched within `cap` (returned when
/// there is none that close).
pub(super) fn node_interface_distance(model: &SpliceModel, n: usize, cap: f64) -> f64 {
    let g = &model.grid;
    let (i, j) = g.ij(n);
    let p = g.xy(n);
    // graded lines are at least dx apart: a window of r lines each way covers r dx
    let r = (cap / g.dx).ceil() as usize + 1;
    let mut best = cap;
    for jj in j.saturating_sub(r)..=(j + r).min(g.ny) {
        for ii in i.saturating_sub(r)..=(i + r).min(g.nx) {
            let q = g.node(ii, jj);
            if model.is_pd[q] || !model.material[q] {
                continue;
            }
            let x = g.xy(q);
            best = best.min(((x[0] - p[0]).powi(2) + (x[1] - p[1]).powi(2)).sqrt());
        }
    }
    best
}

/// The interface distance of bond `b` (its end nodes' smaller), searched within `cap`.
pub(super) fn bond_interface_distance(model: &SpliceModel, b: usize, cap: f64) -> f64 {
    let bond = &model.bonds[b];
    node_interface_distance(model, bond.i as usize, cap).min(node_interface_distance(
        model,
        bond.j as usize,
        cap,
    ))
}

/// The midpoint of bond `b`.
pub(super) fn bond_midpoint(model: &SpliceModel, b: usize) -> [f64; 2] {
    let bond = &model.bonds[b];
    let x = model.grid.xy(bond.i as usize);
    [x[0] + 0.5 * bond.xi[0], x[1] + 0.5 * bond.xi[1]]
}

/// The keys of what a step recorded (its bonds, its critical bond's nodes, its detached nodes),
/// kept when the region may switch so the result can be told in the final model's numbering.
#[derive(Debug, Clone, Default)]
pub(super) struct StepKeys {
    pub bonds: Vec<BondKey>,
    pub nodes: [NodeKey; 2],
    pub detached: Vec<NodeKey>,
}

/// What an adaptive run records besides the history, by key.
#[derive(Debug, Clone, Default)]
pub(super) struct Keys {
    /// per history step
    pub steps: Vec<StepKeys>,
    /// per entry of `detached_nodes`
    pub detached: Vec<NodeKey>,
    /// per damage snapshot: the damaged PD nodes and their damage
    pub damage_at: Vec<Vec<(NodeKey, f64)>>,
}

/// The keys of a step's records on the model it ran on.
pub(super) fn step_keys(model: &SpliceModel, st: &SlaStep) -> StepKeys {
    StepKeys {
        bonds: st.bonds.iter().map(|&b| bond_key(model, b)).collect(),
        nodes: st.nodes.map(|n| node_key(model, n)),
        detached: st.detached.iter().map(|&n| node_key(model, n)).collect(),
    }
}

/// The damaged PD nodes of a damage field (order of the model's `pd_nodes`) by key.
pub(super) fn damage_keys(model: &SpliceModel, d: &[f64]) -> Vec<(NodeKey, f64)> {
    model
        .pd_nodes
        .iter()
        .zip(d)
        .filter(|(_, &v)| v != 0.0)
        .map(|(&n, &v)| (node_key(model, n), v))
        .collect()
}
