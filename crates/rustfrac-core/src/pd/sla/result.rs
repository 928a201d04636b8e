//! What a run records: one [`SlaStep`] per step (the history, also the content of a checkpoint)
//! and the [`CcmPdResult`] of the whole run. A leaf module.

use crate::fe::regions::SceneResponses;
use crate::pd::surface_correction::SurfaceSummary;
use crate::pd::PdConstants;
use crate::problem::{Calibration, Grip, PdVariant, SlaEngine};
use crate::warning::Warning;

/// One SLA step, recorded at the load that breaks its bond(s).
#[derive(Debug, Clone, PartialEq)]
pub struct SlaStep {
    /// 1-based step number
    pub step: usize,
    /// load factor lambda = min s0 / s
    pub lambda: f64,
    /// sigma22 at lambda
    pub sigma22: f64,
    /// CMOD at lambda
    pub cmod: f64,
    /// grip displacement lambda u0_ref
    pub u0: f64,
    /// bonds broken in this step (indices into the bond list; the first is the critical one)
    pub bonds: Vec<usize>,
    /// end nodes of the critical bond
    pub nodes: [usize; 2],
    /// PD nodes that lost all stiffness along some direction in this step (every bond broken, or
    /// the remaining ones parallel) and were grounded along it (they carry no force there)
    pub detached: Vec<usize>,
    /// crack length after the step
    pub crack_length: f64,
    /// the scene's probes at lambda (order of the scene's `[[probe]]`; empty without probes):
    /// a displacement (u1, u2) or a crack opening (normal, sliding)
    pub probes: Vec<[f64; 2]>,
}

impl SlaStep {
    /// The unloaded origin (row 0 of a history, so sigma22 against CMOD starts from (0, 0)): no
    /// load, the pre-crack's length `a0`, no bond (`nodes` = usize::MAX).
    pub fn origin(a0: f64) -> Self {
        Self {
            step: 0,
            lambda: 0.0,
            sigma22: 0.0,
            cmod: 0.0,
            u0: 0.0,
            bonds: Vec::new(),
            nodes: [usize::MAX; 2],
            detached: Vec::new(),
            crack_length: a0,
            probes: Vec::new(),
        }
    }
}

/// One growth of an adaptive PD region (`pd.region = "adaptive"`).
#[derive(Debug, Clone, PartialEq)]
pub struct RegionSwitch {
    /// the first step solved on the grown region
    pub step: usize,
    /// the PD rectangles from then on
    pub regions: Vec<[f64; 4]>,
    /// PD nodes and unknowns of the new model
    pub n_pd_nodes: usize,
    pub n_dofs: usize,
    /// seconds to build the new model and its solver (part of the run's `sla_seconds`)
    pub seconds: f64,
}

/// How an SLA run ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SlaStatus {
    /// every requested step ran
    Completed,
    /// the crack reached `stop_crack_length`
    CrackLengthReached,
    /// a part of the body is no longer held (the Schur pivot vanished or the load path is cut)
    Separated,
    /// no intact bond is in tension
    NoBondInTension,
    /// the critical bond ends at a node carrying an applied force (the step is not taken)
    LoadedBoundaryReached,
    /// the progress callback asked to stop
    Cancelled,
}

impl SlaStatus {
    /// The stable snake_case name (the bindings' `meta["status"]`).
    pub fn name(&self) -> &'static str {
        match self {
            SlaStatus::Completed => "completed",
            SlaStatus::CrackLengthReached => "crack_length_reached",
            SlaStatus::Separated => "separated",
            SlaStatus::NoBondInTension => "no_bond_in_tension",
            SlaStatus::LoadedBoundaryReached => "loaded_boundary_reached",
            SlaStatus::Cancelled => "cancelled",
        }
    }
}

impl std::fmt::Display for SlaStatus {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// The record of a run, grouped by concept: what ran ([`RunSummary`]), the model's sizes
/// ([`ModelCounts`]) and constants ([`Constants`]), its grid ([`Geometry`]), the reference state
/// before any break ([`ReferenceState`]), the history, the final state ([`FinalState`]), the PD
/// region ([`RegionRecord`]), the solver's work ([`SolverWork`]) and the timings ([`Timings`]).
/// `crate::output::pd` turns it into the record Python receives, group by group.
#[derive(Debug, Clone)]
pub struct CcmPdResult {
    pub run: RunSummary,
    pub counts: ModelCounts,
    pub constants: Constants,
    pub geometry: Geometry,
    pub reference: ReferenceState,
    /// one row per step (the origin is [`CcmPdResult::origin`])
    pub history: Vec<SlaStep>,
    pub final_state: FinalState,
    pub region: RegionRecord,
    pub work: SolverWork,
    pub timings: Timings,
    /// accuracy warnings (e.g. m < 2, detached nodes); the run went on
    pub warnings: Vec<Warning>,
}

/// What ran and how it ended.
#[derive(Debug, Clone)]
pub struct RunSummary {
    /// PD on the whole plate, or the splice coupling
    pub method: PdVariant,
    /// the grip that ran (None: supports and loads on regions)
    pub grip: Option<Grip>,
    /// the solver of the last model
    pub solver: SolverUsed,
    pub status: SlaStatus,
    /// steps replayed from `resume_from` (0 without resume)
    pub resumed_steps: usize,
    /// checkpoints written by this run
    pub n_checkpoints: usize,
}

/// The SLA's solver (`choice.rs`): the oracle, or the condensation in its dense or sparse
/// form.
#[derive(Debug, Clone, PartialEq)]
pub struct SolverUsed {
    /// [`SlaEngine::Oracle`], [`SlaEngine::Dense`] or [`SlaEngine::Sparse`] (never `Auto`: the
    /// form the cost model chose)
    pub engine: SlaEngine,
    /// what it is, and for the condensation why it was chosen and the cost model's estimates
    pub description: String,
    /// the re-condensation interval in use (0 for the oracle)
    pub refactor_interval: usize,
    /// models whose sparse form fell back from the bordered Cholesky to the LU of S (at the
    /// condensation where K_PP was not symmetric positive definite, and from then on)
    pub lu_fallbacks: usize,
}

impl SolverUsed {
    /// The description with its fallbacks (the record's `meta["solver"]`).
    pub fn describe(&self) -> String {
        if self.lu_fallbacks > 0 {
            format!(
                "{}; the LU of S in {} model(s), from the condensation where K_PP was not \
                 symmetric positive definite",
                self.description, self.lu_fallbacks
            )
        } else {
            self.description.clone()
        }
    }
}

/// The model's sizes (of the final model, after any growth of an adaptive region).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ModelCounts {
    pub n_nodes: usize,
    pub n_dofs: usize,
    pub n_pd_nodes: usize,
    pub n_bonds: usize,
    pub n_precrack_bonds: usize,
    pub n_removed_elements: usize,
    pub bytes_per_bond: usize,
}

/// The PD constants that ran, and how s0 and the bonds were corrected.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Constants {
    /// gamma, c, s0 (calibrated), delta, ... (eqs. 47, 48, 57)
    pub pd: PdConstants,
    /// the critical stretch's calibration that ran (`pd.s0_calibration`: s0 = factor x eq.
    /// 48's; [`crate::pd::calibration`])
    pub s0_calibration: Calibration,
    /// the surface correction's numbers (`pd.surface_correction = "energy"`, of the final
    /// model; [`crate::pd::surface_correction`]); None without it
    pub surface_correction: Option<SurfaceSummary>,
}

/// The final model's grid: its nodes, PD nodes, bonds and anchor.
#[derive(Debug, Clone, PartialEq)]
pub struct Geometry {
    pub node_xy: Vec<[f64; 2]>,
    pub pd_nodes: Vec<usize>,
    pub pd_node_xy: Vec<[f64; 2]>,
    /// bond end nodes
    pub bond_nodes: Vec<[usize; 2]>,
    /// the node carrying u1 = 0 (grip "free") and its coordinates
    pub anchor_node: usize,
    pub anchor_xy: [f64; 2],
}

/// The pre-cracked model at the reference load, before any SLA break.
#[derive(Debug, Clone)]
pub struct ReferenceState {
    /// displacements of all grid nodes (2 per node)
    pub u: Vec<f64>,
    pub sigma22: f64,
    pub cmod: f64,
    /// sum of all external nodal forces (x, y) (splice imbalance)
    pub out_of_balance: [f64; 2],
    /// supports, loads and probes of a general scene (empty for the grips); `scaled(lambda)`
    /// gives them at a step's load
    pub responses: SceneResponses,
    /// the pre-crack's length (the history's origin)
    pub crack_length: f64,
}

/// The state after the last break.
#[derive(Debug, Clone, PartialEq)]
pub struct FinalState {
    /// displacements at the reference load (empty when the body separated)
    pub u: Vec<f64>,
    /// damage index of every PD node (order of `pd_nodes`)
    pub damage: Vec<f64>,
    /// (step, damage of every PD node after that step) for the requested steps
    pub damage_at: Vec<(usize, Vec<f64>)>,
    /// which bonds are broken (pre-crack included)
    pub broken: Vec<bool>,
    /// (step, node) of every grounding of a detached node; step 0 = detached by the pre-crack
    pub detached_nodes: Vec<(usize, usize)>,
}

/// The PD region: at the end, its growths, and the closest approach of a break to the FEM part.
#[derive(Debug, Clone, PartialEq)]
pub struct RegionRecord {
    /// the PD rectangles at the end (the problem's, or the adaptive region grown)
    pub regions: Vec<[f64; 4]>,
    /// the adaptive region's growths, in order (empty for a fixed region)
    pub switches: Vec<RegionSwitch>,
    /// the smallest distance, in horizons, from a bond the SLA broke to the nearest FEM node at
    /// the time of its break (None: pure PD, or no bond broke, or none within 10 horizons)
    pub interface_distance_min: Option<f64>,
}

/// The solver's work over the run.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct SolverWork {
    pub n_refactorisations: usize,
    /// largest number of low-rank update vectors the fast solver held at once (0 for the oracle);
    /// bounded by the re-condensation interval
    pub max_update_rank: usize,
    /// columns of S_0^{-1} the sparse engine computed, in batches, for its updates (0 for the
    /// dense engine and the oracle): far fewer than 4 per step when the crack reuses them
    pub inverse_columns: usize,
    /// SLA steps whose critical bond the bond screening found (fast solver on at least 4 096 PD
    /// unknowns, `fast/screening.rs`) and the bonds it evaluated exactly in them (the rest were
    /// cleared by their bound)
    pub screened_steps: usize,
    pub screened_bonds: usize,
}

/// Where the time and memory went.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Timings {
    pub setup_seconds: f64,
    pub sla_seconds: f64,
    /// peak resident memory of the process (VmHWM), if the OS reports it
    pub peak_memory_bytes: Option<u64>,
}

impl CcmPdResult {
    /// The history's unloaded origin ([`SlaStep::origin`] at the pre-crack's length).
    pub fn origin(&self) -> SlaStep {
        SlaStep::origin(self.reference.crack_length)
    }

    /// The bonds step `k` of the history (0-based) broke, by their end nodes' positions (in
    /// units of 1e-6 length; each pair and the list sorted): comparable between runs whose
    /// numberings differ (another PD region or grid). With `mirror_x2`, each bond counts as the
    /// smaller of itself and its mirror image across the line x2 = `mirror_x2` (mode I breaks
    /// mirror pairs at the same load, in an order the numbering decides).
    pub fn broken_positions(&self, k: usize, mirror_x2: Option<f64>) -> Vec<[[i64; 2]; 2]> {
        let key = |x: [f64; 2]| [(x[0] * 1e6).round() as i64, (x[1] * 1e6).round() as i64];
        let pair = |p: [f64; 2], q: [f64; 2]| {
            let mut e = [key(p), key(q)];
            e.sort_unstable();
            e
        };
        let mut v: Vec<_> = self.history[k]
            .bonds
            .iter()
            .map(|&b| {
                let [i, j] = self.geometry.bond_nodes[b];
                let (p, q) = (self.geometry.node_xy[i], self.geometry.node_xy[j]);
                let e = pair(p, q);
                match mirror_x2 {
                    Some(y) => e.min(pair([p[0], 2.0 * y - p[1]], [q[0], 2.0 * y - q[1]])),
                    None => e,
                }
            })
            .collect();
        v.sort_unstable();
        v
    }

    /// The bounding box [x0, y0, x1, y1] of the PD rectangles at the end (None: pure PD).
    pub fn regions_bounding_box(&self) -> Option<[f64; 4]> {
        let regions = &self.region.regions;
        let first = *regions.first()?;
        Some(regions.iter().fold(first, |b, q| {
            [
                b[0].min(q[0]),
                b[1].min(q[1]),
                b[2].max(q[2]),
                b[3].max(q[3]),
            ]
        }))
    }
}
