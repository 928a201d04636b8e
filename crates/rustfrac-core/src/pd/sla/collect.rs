//! The result of a run ([`results`]): the model's counts and constants, the reference solution,
//! the history and the damage gathered into a [`CcmPdResult`], with the run's warnings.

use super::grounding::DEBRIS_LIMIT;
use super::memory::peak_memory_bytes;
use super::result::{
    CcmPdResult, Constants, FinalState, Geometry, ModelCounts, ReferenceState, RegionRecord,
    RunSummary, SolverUsed, SolverWork, Timings,
};
use super::state::RunState;
use super::switch::in_final_numbering;
use crate::error::{Error, Result};
use crate::pd::splice::{SpliceModel, StaticSolution};
use crate::pd::{damage, BYTES_PER_BOND};
use crate::warning::{Warning, WarningKind};

/// What the driver knows of a run besides its state: the solver, its work and the timings.
#[derive(Default)]
pub(super) struct RunInfo {
    /// the last model's solver (its `lu_fallbacks` are counted in the field below)
    pub(super) solver: Option<SolverUsed>,
    pub(super) work: SolverWork,
    /// models whose sparse form fell back from the bordered Cholesky to the LU of S
    pub(super) lu_fallbacks: usize,
    pub(super) resumed_steps: usize,
    pub(super) n_checkpoints: usize,
    pub(super) setup_seconds: f64,
    pub(super) sla_seconds: f64,
}

/// The result of a run: the model's counts and constants, the reference solution `sol0`, the
/// final displacements, the history, the damage, and a warning when nodes were grounded.
pub(super) fn results(
    model: &SpliceModel,
    st: RunState,
    sol0: StaticSolution,
    u_final: Vec<f64>,
    info: RunInfo,
) -> Result<CcmPdResult> {
    let mut st = st;
    if let Some(keys) = st.keys.take() {
        in_final_numbering(model, &mut st, &keys)?;
    }
    let mut warnings = model.warnings.clone();
    if st.margin_violated {
        let a = model.pd_method().adaptive.map_or(0.0, |a| a.margin);
        warnings.push(Warning::new(
            WarningKind::Discretisation,
            format!(
                "the adaptive PD region could not grow (the plate's edge): bonds broke within \
                 pd.adapt_margin = {a} horizons of the FEM part (closest approach: \
                 interface_distance_min)"
            ),
        ));
    }
    let detached_nodes = st.detached_nodes;
    if !detached_nodes.is_empty() {
        let n_pre = detached_nodes.iter().filter(|d| d.0 == 0).count();
        warnings.push(Warning::new(
            WarningKind::Discretisation,
            format!(
                "{} PD node(s) lost all stiffness along some direction (every bond broken, the \
             remaining ones parallel, or a loose fragment of at most {DEBRIS_LIMIT} nodes) and \
             were grounded there ({n_pre} by the pre-crack, the others during the SLA); they \
             carry no force along it (see detached_nodes)",
                detached_nodes.len()
            ),
        ));
    }
    let nn = model.grid.n_nodes();
    let p = &model.problem;
    Ok(CcmPdResult {
        run: RunSummary {
            method: p.method.pd_variant().ok_or_else(|| Error::Internal {
                detail: "an SLA run of a method other than PD or CCM-PD".into(),
            })?,
            grip: p.boundary.grips().map(|l| l.grip),
            solver: SolverUsed {
                lu_fallbacks: info.lu_fallbacks,
                ..info.solver.ok_or_else(|| Error::Internal {
                    detail: "an SLA run without a solver".into(),
                })?
            },
            status: st.status,
            resumed_steps: info.resumed_steps,
            n_checkpoints: info.n_checkpoints,
        },
        counts: ModelCounts {
            n_nodes: nn,
            n_dofs: model.n_dofs(),
            n_pd_nodes: model.pd_nodes.len(),
            n_bonds: model.bonds.len(),
            n_precrack_bonds: model.precrack_broken.iter().filter(|&&b| b).count(),
            n_removed_elements: model.n_removed_elements,
            bytes_per_bond: BYTES_PER_BOND,
        },
        constants: Constants {
            pd: model.pd,
            s0_calibration: model.s0_calibration,
            surface_correction: model.surface.as_ref().map(|s| s.summary),
        },
        geometry: Geometry {
            node_xy: (0..nn).map(|n| model.grid.xy(n)).collect(),
            pd_nodes: model.pd_nodes.clone(),
            pd_node_xy: model.pd_nodes.iter().map(|&n| model.grid.xy(n)).collect(),
            bond_nodes: model
                .bonds
                .iter()
                .map(|b| [b.i as usize, b.j as usize])
                .collect(),
            anchor_node: model.anchor,
            anchor_xy: model.grid.xy(model.anchor),
        },
        reference: ReferenceState {
            u: sol0.u,
            sigma22: sol0.sigma22,
            cmod: sol0.cmod,
            out_of_balance: sol0.out_of_balance,
            responses: Default::default(),
            crack_length: p.cracks.first().map_or(0.0, |c| c.a0),
        },
        history: st.history,
        final_state: FinalState {
            u: u_final,
            damage: damage(nn, &model.bonds, &st.broken, &model.pd_nodes),
            damage_at: st.damage_at,
            broken: st.broken,
            detached_nodes,
        },
        region: RegionRecord {
            regions: model.pd_method().regions.clone(),
            switches: st.switches,
            interface_distance_min: st.closest.is_finite().then(|| st.closest / model.pd.delta),
        },
        work: info.work,
        timings: Timings {
            setup_seconds: info.setup_seconds,
            sla_seconds: info.sla_seconds,
            peak_memory_bytes: peak_memory_bytes(),
        },
        warnings,
    })
}
