//! The SLA driver ([`run`], section 3): build the model and the solver, replay a checkpoint, run
//! the steps, collect the results.
//!
//! Each step solves the current (linear) model once at the reference load, computes the stretch of
//! every intact bond, takes lambda = min s0 / s over the bonds in tension (each bond's own s0
//! under the surface correction), records (lambda, sigma22, CMOD, u0 = lambda u0_ref) at that
//! load, and breaks the critical bond (or, with
//! `tie_tol > 0`, every bond whose load factor is within that relative tolerance of lambda). Ties
//! closer than 1e-10 (mirror bonds in mode I) are broken deterministically: the lowest bond index
//! goes first, so two solvers that agree to round-off produce the same sequence. Before a bond
//! breaks, its end nodes are grounded where they need it (`grounding.rs`).

use super::adaptive::{
    bond_interface_distance, bond_key, bond_midpoint, node_key, Index, Keys, NodeKey, StepKeys,
};
use super::checkpoint;
use super::cost::{CostEstimate, EngineKind};
use super::engine::{timing, Engine, Update};
use super::fast::{
    bordered_analysis, dense_lead, schur_pattern, Fast, FemPart, SchurKind, SparseFactor,
};
use super::grounding::{Grounding, DEBRIS_LIMIT};
use super::memory::{keep_large_blocks_mmapped, peak_memory_bytes};
use super::oracle::Oracle;
use super::progress::SlaProgress;
use super::result::{CcmPdResult, RegionSwitch, SlaStatus, SlaStep};
use crate::error::{Error, Result};
use crate::la::{Cholesky, CscMatrix};
use crate::pd::splice::{ProbeFunctional, SpliceModel, Spring, StaticSolution};
use crate::pd::{damage, BYTES_PER_BOND};
use crate::problem::{pd_region, validate, Problem, SlaEngine, SlaParams};
use crate::warning::{Warning, WarningKind};
use faer::Par;
use std::sync::Arc;
use std::time::Instant;

/// Runs a CCM-PD (or pure PD) problem: linear solution at the reference load, then the SLA.
/// `progress(step, max_steps)` is called after every step; returning `false` stops the run
/// (status [`SlaStatus::Cancelled`], a checkpoint is written first when `checkpoint_path` is set).
pub fn run(p: &Problem, progress: &(dyn Fn(usize, usize) -> bool + Sync)) -> Result<CcmPdResult> {
    run_reporting(p, &|s: &SlaProgress| progress(s.step, s.max_steps))
}

/// [`run`] with a callback that reads the whole [`SlaProgress`] after every step (the crack's
/// advance towards `pd.stop_crack_length` besides the step).
pub fn run_reporting(
    p: &Problem,
    progress: &(dyn Fn(&SlaProgress) -> bool + Sync),
) -> Result<CcmPdResult> {
    validate::problem(p)?;
    validate::reference_load(p)?;
    keep_large_blocks_mmapped();
    let t0 = Instant::now();
    let model = SpliceModel::new(p)?;
    timing("model built", t0);
    run_from(&model, t0, progress)
}

/// [`run`] on a model built by hand ([`SpliceModel::with_precrack`]).
pub fn run_model(
    model: &SpliceModel,
    progress: &(dyn Fn(usize, usize) -> bool + Sync),
) -> Result<CcmPdResult> {
    validate::reference_load(&model.problem)?;
    keep_large_blocks_mmapped();
    run_from(model, Instant::now(), &|s: &SlaProgress| {
        progress(s.step, s.max_steps)
    })
}

fn run_from(
    model0: &SpliceModel,
    t0: Instant,
    progress: &(dyn Fn(&SlaProgress) -> bool + Sync),
) -> Result<CcmPdResult> {
    let sla = &model0.pd_method().sla;
    let adaptive = model0.pd_method().adaptive;
    let mut st = RunState::new(model0);
    let fp = checkpoint::fingerprint(
        &model0.problem,
        &model0.precrack,
        model0.n_dofs(),
        model0.bonds.len(),
    );
    // resume: the checkpoint's steps and region switches, replayed exactly
    let mut replay = match &sla.resume_from {
        Some(path) => {
            let sizes = checkpoint_sizes(model0, adaptive.is_some())?;
            let (steps, switches) = checkpoint::read(path, fp, sizes)?;
            let steps: std::collections::VecDeque<SlaStep> =
                steps.into_iter().take(sla.max_steps).collect();
            // only the switches before a replayed step (a later one is found again live)
            let last = steps.back().map_or(0, |s| s.step);
            let switches = switches.into_iter().filter(|s| s.0 <= last).collect();
            Some(Replay { steps, switches })
        }
        None => None,
    };
    let mut owned: Option<SpliceModel> = None;
    let mut sol0: Option<(StaticSolution, crate::fe::regions::SceneResponses)> = None;
    let mut info = RunInfo::default();
    let mut live: Option<Instant> = None;
    let mut switch_start: Option<Instant> = None;
    let u_final = loop {
        let model = owned.as_ref().unwrap_or(model0);
        let springs = match sol0 {
            None => st.ground_precrack(model),
            Some(_) => st.ground_again(model),
        };
        timing("groundings", t0);
        let k = Arc::new(model.assemble_with(&st.broken, &springs));
        timing("matrix assembled", t0);
        st.probes = model.probe_functionals()?;
        let probe_dofs: Vec<usize> = st.probes.iter().flat_map(|p| p.dofs()).collect();
        let (mut engine, solver, refactor_interval) =
            engine_for(model, sla, &k, (&st.broken, &springs), &probe_dofs)?;
        timing("engine ready", t0);
        if let (Some(ts), Some(sw)) = (switch_start.take(), st.switches.last_mut()) {
            // a switch costs the new model and its solver
            sw.seconds = ts.elapsed().as_secs_f64();
        }
        if sol0.is_none() {
            // reference solution before breaking (u from the engine, reactions from the matrix)
            let u0_full = engine.full_u()?;
            let s = model.postprocess(&k, u0_full, 0.0);
            let responses = model.scene_responses(&s.u, &s.reactions)?;
            sol0 = Some((s, responses));
        }
        drop(k);
        info.solver = solver;
        info.refactor_interval = refactor_interval;
        let sigma0 = sol0.as_ref().map_or(0.0, |s| s.0.sigma22);
        // the replayed steps of this model; then the next switch, or the live steps
        let grow = match replay.as_mut() {
            Some(rp) => st.replay(sla, model, engine.as_mut(), rp)?,
            None => None,
        };
        let grow = match grow {
            Some(g) => Some(g),
            None => {
                if live.is_none() {
                    // the set-up ends where the live steps begin (after any replay)
                    replay = None;
                    info.resumed_steps = st.history.len();
                    info.setup_seconds = t0.elapsed().as_secs_f64();
                    timing("setup done", t0);
                    live = Some(Instant::now());
                }
                st.steps(sla, model, engine.as_mut(), fp, sigma0, progress)?
            }
        };
        info.n_refactorisations += engine.n_refactorisations();
        info.max_update_rank = info.max_update_rank.max(engine.max_update_rank());
        info.inverse_columns += engine.inverse_columns();
        info.lu_fallbacks += engine.lu_fallbacks();
        let (ss, sb) = engine.screening();
        info.screened_steps += ss;
        info.screened_bonds += sb;
        let Some(centres) = grow else {
            break if st.status == SlaStatus::Separated {
                Vec::new()
            } else {
                engine.full_u()?
            };
        };
        drop(engine);
        // the adaptive region grows: the model with the new rectangles, the broken bonds found
        // in it by their end nodes (`adaptive.rs`)
        let ts = Instant::now();
        switch_start = Some(ts);
        let a = adaptive.expect("only an adaptive region grows");
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
        st.carry_over(model, &new)?;
        let step = st.history.len() + 1;
        st.switch_centres.push((step, centres));
        st.switches.push(RegionSwitch {
            step,
            regions,
            n_pd_nodes: new.pd_nodes.len(),
            n_dofs: new.n_dofs(),
            seconds: ts.elapsed().as_secs_f64(),
        });
        timing("adaptive region grown (model)", ts);
        owned = Some(new);
    };
    let model = owned.as_ref().unwrap_or(model0);
    info.sla_seconds = live.map_or(0.0, |t| t.elapsed().as_secs_f64());
    info.n_checkpoints = st.n_checkpoints;
    let (mut s0, responses) = sol0.expect("the reference solution of the first model");
    if model.grid != model0.grid {
        // a graded grid moved with the region: the reference field on the final grid
        s0.u = reference_field(model)?;
    }
    let mut r = results(model, st, s0, u_final, info)?;
    r.responses = responses;
    Ok(r)
}

/// The reference solution's displacements on `model` (pre-crack only, no SLA break).
fn reference_field(model: &SpliceModel) -> Result<Vec<f64>> {
    let mut st = RunState::new(model);
    let springs = st.ground_precrack(model);
    let k = model.assemble_with(&st.broken, &springs);
    Oracle::new(model, &st.broken, &springs, &k)?.full_u()
}

/// The bounds a checkpoint of this run is read with (bonds, nodes, probes): the model's, or for
/// an adaptive region the whole plate's (its region grows).
fn checkpoint_sizes(model: &SpliceModel, adaptive: bool) -> Result<(usize, usize, usize)> {
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
struct Replay {
    steps: std::collections::VecDeque<SlaStep>,
    switches: Vec<checkpoint::Switch>,
}

/// The solver ([`choose`]): the oracle when `fast = false` or `pd.engine = "oracle"`, else the
/// condensation with the form of the condensed system (dense LU or sparse factor) the scene
/// asks for or, for `"auto"`, the cheaper by the cost model ([`CostEstimate`]). Returns it, its
/// description (the choice and the estimates) and the re-condensation interval (0 for the oracle).
/// The cost model's symbolic analysis (then, for the dense form, the LU of S's PD block; for the
/// sparse CCM-PD form, K_PP's analysis and Cholesky, `fast/base.rs`) and the condensation's FEM part
/// ([`FemPart`]) do not depend on each other: they run at once, the analysis on its own thread
/// while the FEM part's ordering and symbolic phases leave a core idle.
fn engine_for<'a>(
    model: &'a SpliceModel,
    sla: &SlaParams,
    k0: &Arc<CscMatrix>,
    (broken, springs0): (&[bool], &[Spring]),
    probe_dofs: &[usize],
) -> Result<(Box<dyn Engine + 'a>, String, usize)> {
    if sla.engine == SlaEngine::Oracle {
        let solver = "oracle (sparse LU refactorised every step)".to_string();
        return Ok((
            Box::new(Oracle::new(model, broken, springs0, k0)?),
            solver,
            0,
        ));
    }
    // the choice, then the LU of the dense S's PD block (it does not depend on the FEM part);
    // pure PD has no FEM part to overlap: its whole LU is the leading stage, made on the main
    // thread with all cores at the condensation
    let choose = || {
        let c = cost_choice(model, sla, k0, probe_dofs)?;
        let lead = (c.kind == SchurKind::Dense && !model.all_pd)
            .then(|| dense_lead(model, k0, probe_dofs))
            .transpose()?;
        Ok::<_, Error>((c, lead))
    };
    let (choice, part) = std::thread::scope(|s| {
        let spawned = std::thread::Builder::new()
            .name("rustfrac cost model".into())
            .spawn_scoped(s, choose);
        // beside the cost model's thread the factorisation runs on one thread: rayon workers
        // would only compete with it for the cores (0.37 s against 0.48-0.55 s on the paper's
        // case; benches/RESULTS.md)
        let par = if spawned.is_ok() {
            Par::Seq
        } else {
            faer::get_global_parallelism()
        };
        let part = FemPart::new(model, k0, probe_dofs, par);
        let choice = match spawned {
            Ok(h) => h.join().map_err(|_| Error::Internal {
                detail: "the cost model's thread panicked".into(),
            }),
            // no thread to be had (a thread or memory limit): the same work, after the FEM part
            Err(_) => Ok(choose()),
        };
        (choice, part)
    });
    let (c, lead) = choice??;
    let f = Fast::new(
        model,
        Arc::clone(k0),
        (broken, springs0),
        part?,
        c.interval,
        (c.kind, c.analysed, c.first_s),
        lead,
    )?;
    let solver = format!("{}; {}; {}", c.name, c.why, c.est.describe());
    let refactor_interval = f.refactor_every;
    Ok((Box::new(f), solver, refactor_interval))
}

/// The form of the condensed system the cost model chose ([`engine_for`]).
struct Choice {
    kind: SchurKind,
    /// the sparse S's symbolic analysis, to reuse (sparse form)
    analysed: Option<SparseFactor>,
    /// pure PD's S itself (sparse form), for the first condensation
    first_s: Option<CscMatrix>,
    /// the re-condensation interval
    interval: usize,
    /// the engine's name
    name: &'static str,
    /// why it was chosen
    why: &'static str,
    est: CostEstimate,
}

/// The cost model's choice ([`engine_for`]) from the symbolic analysis of the sparse S.
fn cost_choice(
    model: &SpliceModel,
    sla: &SlaParams,
    k0: &CscMatrix,
    probe_dofs: &[usize],
) -> Result<Choice> {
    let t0 = Instant::now();
    let (pattern, symmetric, xy) = schur_pattern(model, k0, probe_dofs);
    // nnz(L) of the sparse form: its own analysis for the symmetric (pure PD) S, reused by the
    // engine; of the symmetrised pattern for the LU (L and U: twice that). A failed analysis
    // leaves the dense form (infinite sparse estimate), or reports the error when sparse is forced.
    let analysis = if symmetric {
        SparseFactor::analyze(&pattern, true, &xy).map(|f| {
            let nnz = f.factor_nnz().unwrap_or(0) as f64;
            (Some(f), nnz)
        })
    } else {
        Cholesky::analyze_with(&pattern.symmetrised_pattern(), Some(&xy))
            .map(|c| (None, 2.0 * c.factor_nnz() as f64))
    };
    let (analysed, factor_nnz) = match analysis {
        Ok(a) => a,
        Err(e) if sla.engine == SlaEngine::Sparse => return Err(e),
        Err(_) => (None, f64::INFINITY),
    };
    timing("engine: cost model (symbolic analysis of the sparse S)", t0);
    let est = CostEstimate::new(pattern.nrows, factor_nnz, sla.refactor_every);
    let (kind, why) = match sla.engine {
        SlaEngine::Dense => (EngineKind::Dense, "pd.engine = \"dense\""),
        SlaEngine::Sparse => (EngineKind::Sparse, "pd.engine = \"sparse\""),
        _ => (est.choice(), "auto: the cheaper estimate"),
    };
    Ok(match kind {
        EngineKind::Dense => Choice {
            kind: SchurKind::Dense,
            analysed: None,
            first_s: None,
            interval: sla.refactor_every,
            name: "fast (FEM condensed by Cholesky, dense PD system + Sherman-Morrison-Woodbury)",
            why,
            est,
        },
        EngineKind::Sparse => Choice {
            kind: SchurKind::Sparse,
            // the CCM-PD S's bordered form (`fast/base.rs`): K_PP's symbolic analysis and its
            // Cholesky (K_PP does not depend on the FEM part), made here, on the cost model's
            // thread beside the FEM part (the engine takes the LU of S when K_PP turns out not
            // to be symmetric positive definite)
            analysed: match analysed {
                Some(a) => Some(a),
                None => {
                    let b = bordered_analysis(model, k0, probe_dofs)?;
                    timing(
                        "engine: K_PP analysed (nested dissection) and factorised (Cholesky)",
                        t0,
                    );
                    Some(b)
                }
            },
            first_s: symmetric.then_some(pattern),
            interval: est.sparse_interval,
            name: if symmetric {
                "fast, sparse (PD system by sparse Cholesky + Sherman-Morrison-Woodbury)"
            } else {
                "fast, sparse (FEM condensed by Cholesky, PD system by sparse Cholesky of K_PP \
                 bordered by the FEM coupling + Sherman-Morrison-Woodbury)"
            },
            why,
            est,
        },
    })
}

/// The evolving state of a run: the broken bonds (pre-crack included), the groundings, the
/// history, the status and, for an adaptive region, its switches and the keys of what was
/// recorded (`adaptive.rs`).
struct RunState {
    broken: Vec<bool>,
    grounding: Grounding,
    /// (step, node) of every grounding; step 0 = detached by the pre-crack
    detached_nodes: Vec<(usize, usize)>,
    history: Vec<SlaStep>,
    damage_at: Vec<(usize, Vec<f64>)>,
    status: SlaStatus,
    /// the scene's probes, recorded at every step
    probes: Vec<ProbeFunctional>,
    n_checkpoints: usize,
    /// the adaptive region's growths (the result's) and as a checkpoint stores them
    switches: Vec<RegionSwitch>,
    switch_centres: Vec<checkpoint::Switch>,
    /// the records by key, from the first switch on (None: one model, its own numbering)
    keys: Option<Keys>,
    /// the smallest interface distance of a broken bond so far (length; infinite: none)
    closest: f64,
    /// a bond broke within the margin because the region could not grow (warned once)
    margin_violated: bool,
}

/// How far the interface distance of a broken bond is searched (horizons): beyond it the
/// closest approach is reported as "none within".
const INTERFACE_SEARCH: f64 = 10.0;

impl RunState {
    fn new(model: &SpliceModel) -> Self {
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
    fn ground_precrack(&mut self, model: &SpliceModel) -> Vec<Spring> {
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
    fn ground_again(&mut self, model: &SpliceModel) -> Vec<Spring> {
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

    /// Replays the checkpoint's steps on `model` (exactly the updates of the run that wrote it,
    /// in the same order; the recorded numbers come from their stored bits) up to its next
    /// region switch: returns the midpoints of the bonds that grew the region there, or None
    /// when every step is replayed.
    fn replay(
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

    /// Appends a step to the history (its keys too, from the first switch on) and stores the
    /// damage field after it when it is one of `damage_at_steps`.
    fn record(&mut self, model: &SpliceModel, sla: &SlaParams, st: SlaStep) {
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
    fn note_interface(&mut self, model: &SpliceModel, sel: &[usize]) {
        if model.all_pd {
            return;
        }
        // a node farther than the closest so far cannot lower it: search only that far
        let cap = self.closest.min(INTERFACE_SEARCH * model.pd.delta);
        for &b in sel {
            self.closest = self.closest.min(bond_interface_distance(model, b, cap));
        }
    }

    /// Whether the adaptive region must grow before the bonds `sel` break: the midpoints of
    /// those within `pd.adapt_margin` horizons of the interface, when growing around them
    /// changes the region (else they break where they are: the plate's edge or a hole stops
    /// the growth, and the run warns).
    fn growth(&mut self, model: &SpliceModel, sel: &[usize]) -> Option<Vec<[f64; 2]>> {
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

    /// The SLA steps after the replayed ones, up to `max_steps` or until the run ends (separated,
    /// no bond in tension, cancelled, crack length reached) or the adaptive region must grow
    /// (then the midpoints of the bonds that grow it; the step is not taken). `sigma0` is the
    /// reference sigma22 of the intact model.
    fn steps(
        &mut self,
        sla: &SlaParams,
        model: &SpliceModel,
        engine: &mut dyn Engine,
        fp: u64,
        sigma0: f64,
        progress: &(dyn Fn(&SlaProgress) -> bool + Sync),
    ) -> Result<Option<Vec<[f64; 2]>>> {
        let s0 = model.pd.s0;
        let load = model.problem.boundary.plate_load();
        let max_steps = sla.max_steps;
        let mut lam = vec![f64::INFINITY; model.bonds.len()];
        let first_step = self.history.len() + 1;
        let mut crack_len = crack_length(model, &self.broken);
        // a0: the pre-crack's length, where the crack length starts
        let (a0, extent) = crack_extent(model);
        for step in first_step..=max_steps {
            if self.status != SlaStatus::Completed {
                break;
            }
            let st = match engine.state() {
                Ok(s) => s,
                Err(Error::Separated { .. }) => {
                    self.status = SlaStatus::Separated;
                    break;
                }
                Err(e) => return Err(e),
            };
            // under displacement grips a cut load path leaves both parts held by their own grip:
            // the system stays regular but carries no load any more
            if model.response.displacement_driven && st.sigma22.abs() <= 1e-9 * sigma0.abs() {
                self.status = SlaStatus::Separated;
                break;
            }
            let tie_tol = sla.tie_tol;
            let Some((lmin, sel)) =
                critical_bonds(model, &self.broken, engine, s0, tie_tol, &mut lam)
            else {
                self.status = SlaStatus::NoBondInTension;
                break;
            };
            if let Some(centres) = self.growth(model, &sel) {
                return Ok(Some(centres));
            }
            self.note_interface(model, &sel);
            // the load displacement at the reference load (before the break changes u)
            let u0_ref = model
                .response
                .load_displacement(engine.u())
                .unwrap_or(load.u0);
            let first = sel[0];
            let (detached, sep) =
                advance(model, engine, &mut self.broken, &mut self.grounding, &sel)?;
            self.detached_nodes
                .extend(detached.iter().map(|&n| (step, n)));
            // the crack length, updated from this step's bonds (O(bonds) only once a model)
            let cl =
                (sel.iter().filter(|&&b| self.broken[b])).fold(crack_len, |l, &b| l.max(extent(b)));
            crack_len = cl;
            let bf = &model.bonds[first];
            let row = SlaStep {
                step,
                lambda: lmin,
                sigma22: lmin * st.sigma22,
                cmod: lmin * st.cmod,
                u0: lmin * u0_ref,
                bonds: sel,
                nodes: [bf.i as usize, bf.j as usize],
                detached,
                crack_length: cl,
                probes: st_probes(&self.probes, engine.u(), lmin),
            };
            self.record(model, sla, row);
            let every = sla.checkpoint_every;
            if every > 0 && step % every == 0 {
                self.checkpoint(sla, fp)?;
            }
            let go_on = progress(&SlaProgress {
                step,
                max_steps,
                crack_length: cl,
                initial_crack_length: a0,
                stop_crack_length: sla.stop_crack_length,
            });
            if sep {
                self.status = SlaStatus::Separated;
                break;
            }
            if !go_on {
                self.status = SlaStatus::Cancelled;
                self.checkpoint(sla, fp)?;
                break;
            }
            if let Some(l) = sla.stop_crack_length {
                if cl >= l {
                    self.status = SlaStatus::CrackLengthReached;
                    break;
                }
            }
        }
        Ok(None)
    }

    /// Writes the history so far (and the region switches) to `checkpoint_path` when set.
    fn checkpoint(&mut self, sla: &SlaParams, fp: u64) -> Result<()> {
        if let Some(path) = &sla.checkpoint_path {
            checkpoint::write(path, fp, &self.history, &self.switch_centres)?;
            self.n_checkpoints += 1;
        }
        Ok(())
    }
}

/// The keys of a step's records on the model it ran on.
fn step_keys(model: &SpliceModel, st: &SlaStep) -> StepKeys {
    StepKeys {
        bonds: st.bonds.iter().map(|&b| bond_key(model, b)).collect(),
        nodes: st.nodes.map(|n| node_key(model, n)),
        detached: st.detached.iter().map(|&n| node_key(model, n)).collect(),
    }
}

/// The damaged PD nodes of a damage field (order of the model's `pd_nodes`) by key.
fn damage_keys(model: &SpliceModel, d: &[f64]) -> Vec<(NodeKey, f64)> {
    model
        .pd_nodes
        .iter()
        .zip(d)
        .filter(|(_, &v)| v != 0.0)
        .map(|(&n, &v)| (node_key(model, n), v))
        .collect()
}

/// The bonds to break in the engine's last state: lambda_b = s0 / s_b for every intact bond in
/// tension (s0 x the bond's factor under the surface correction,
/// [`crate::pd::surface_correction::critical_stretch_scale`]), lmin = min lambda, and every bond
/// with lambda_b <= lmin (1 + max(tie_tol, 1e-10)) in index order (only the first when
/// tie_tol = 0). None when no bond is in tension. `lam` is scratch of one value per bond. The
/// stretches come from [`Engine::stretches`]: a bond it leaves at an upper bound cannot reach
/// that window, so the selection is the one of the exact stretches.
///
/// Without the surface correction the divisions s0 / s_b are taken only where they can decide:
/// a correctly rounded division is monotone, so min_b s0 / s_b = s0 / max_b s_b exactly, and the
/// tie test is made exactly (the same division as before) on the bonds whose stretch passes a
/// looser bound; one division per bond fewer, the same bonds and lmin bit for bit.
fn critical_bonds(
    model: &SpliceModel,
    broken: &[bool],
    engine: &mut dyn Engine,
    s0: f64,
    tie_tol: f64,
    lam: &mut [f64],
) -> Option<(f64, Vec<usize>)> {
    let tol = tie_tol.max(1e-10);
    let scale = model.surface.as_ref().map(|sf| &sf.s0_scale[..]);
    // lam holds the stretches (-inf for broken bonds), of the bonds `only` when screened
    let mut only = Vec::new();
    let screened = engine.stretches(model, broken, scale, tol, lam, &mut only);
    let n = if screened {
        only.len()
    } else {
        model.bonds.len()
    };
    let id = |i: usize| if screened { only[i] } else { i };
    let (lmin, mut sel) = match scale {
        Some(sc) => {
            let mut lmin = f64::INFINITY;
            for b in (0..n).map(id) {
                let s = lam[b];
                lam[b] = f64::INFINITY;
                if s > 0.0 {
                    // the surface correction keeps each bond's critical energy
                    lam[b] = s0 * sc[b] / s;
                    lmin = lmin.min(lam[b]);
                }
            }
            if !lmin.is_finite() {
                return None;
            }
            let sel: Vec<usize> = (0..n)
                .map(id)
                .filter(|&b| lam[b] <= lmin * (1.0 + tol))
                .collect();
            (lmin, sel)
        }
        None => critical_by_stretch(lam, (0..n).map(id), s0, tol)?,
    };
    if tie_tol == 0.0 {
        sel.truncate(1);
    }
    Some((lmin, sel))
}

/// [`critical_bonds`] without the surface correction, from the stretches `s` (-inf for a broken
/// bond): lmin = s0 / max s (exactly min_b s0 / s_b: a correctly rounded division is monotone) and
/// the bonds with s0 / s_b <= lmin (1 + tol) in index order, the division made only for the bonds
/// whose stretch passes a looser cut.
fn critical_by_stretch(
    s: &[f64],
    bonds: impl Iterator<Item = usize> + Clone,
    s0: f64,
    tol: f64,
) -> Option<(f64, Vec<usize>)> {
    let smax = bonds
        .clone()
        .fold(0.0f64, |m, b| if s[b] > m { s[b] } else { m });
    let lmin = s0 / smax;
    if !(smax > 0.0 && lmin.is_finite()) {
        return None;
    }
    let bound = lmin * (1.0 + tol);
    // s0 / s <= bound needs s >= s0 / bound up to rounding: a looser cut, then the test
    let cut = if bound > 0.0 {
        s0 / bound * (1.0 - 1e-6)
    } else {
        0.0
    };
    let sel = bonds
        .filter(|&b| s[b] > 0.0 && s[b] >= cut && s0 / s[b] <= bound)
        .collect();
    Some((lmin, sel))
}

/// Breaks the bonds `sel` of one step: for each bond in order, the grounding springs its end
/// nodes need once it is gone, then the bond. Returns the detached nodes and whether the body
/// separated (the remaining updates are then skipped). Used by the live run and by the replay of
/// a checkpoint, so both apply exactly the same updates in the same order.
fn advance(
    model: &SpliceModel,
    engine: &mut dyn Engine,
    broken: &mut [bool],
    grounding: &mut Grounding,
    sel: &[usize],
) -> Result<(Vec<usize>, bool)> {
    let mut detached = Vec::new();
    for &b in sel {
        broken[b] = true;
        let bond = &model.bonds[b];
        let mut ups = Vec::new();
        for n in [bond.i as usize, bond.j as usize] {
            for (m, sp) in grounding.springs(model, n, broken) {
                if !detached.contains(&m) {
                    detached.push(m);
                }
                ups.push(Update::Ground(sp));
            }
        }
        ups.push(Update::Break(b));
        for u in ups {
            match engine.apply(u) {
                Ok(()) => {}
                Err(Error::Separated { detail }) => {
                    timing(&detail, Instant::now());
                    return Ok((detached, true));
                }
                Err(e) => return Err(e),
            }
        }
    }
    Ok((detached, false))
}

/// The crack length of the broken bonds: the pre-crack's length, or the farthest projection on
/// its direction of a broken bond's midpoint (pre-crack bonds aside), whichever is larger.
fn crack_length(model: &SpliceModel, broken: &[bool]) -> f64 {
    let (b, extent) = crack_extent(model);
    (0..model.bonds.len())
        .filter(|&i| broken[i])
        .fold(b, |len, i| len.max(extent(i)))
}

/// The pre-crack's length and the crack length a broken bond reaches ([`crack_length`]: the
/// length is the max of both over the broken bonds, so a step updates it from its own bonds).
fn crack_extent(model: &SpliceModel) -> (f64, impl Fn(usize) -> f64 + '_) {
    let pc = &model.precrack;
    let (p0, t, l0) = if pc.len() >= 2 {
        let d = [pc[1][0] - pc[0][0], pc[1][1] - pc[0][1]];
        let l = (d[0] * d[0] + d[1] * d[1]).sqrt();
        let l0: f64 = pc
            .windows(2)
            .map(|s| ((s[1][0] - s[0][0]).powi(2) + (s[1][1] - s[0][1]).powi(2)).sqrt())
            .sum();
        (pc[0], [d[0] / l, d[1] / l], l0)
    } else {
        ([0.0, 0.0], [1.0, 0.0], 0.0)
    };
    let extent = move |b: usize| {
        if model.precrack_broken[b] {
            return f64::NEG_INFINITY;
        }
        let bond = &model.bonds[b];
        let xi = model.grid.xy(bond.i as usize);
        let mid = [xi[0] + 0.5 * bond.xi[0], xi[1] + 0.5 * bond.xi[1]];
        (mid[0] - p0[0]) * t[0] + (mid[1] - p0[1]) * t[1]
    };
    (l0, extent)
}

/// What the driver knows of a run besides its state: the solver, its counters and the timings.
#[derive(Default)]
struct RunInfo {
    solver: String,
    refactor_interval: usize,
    n_refactorisations: usize,
    max_update_rank: usize,
    inverse_columns: usize,
    /// models whose sparse form fell back from the bordered Cholesky to the LU of S (at the
    /// condensation where K_PP was not symmetric positive definite, and from then on)
    lu_fallbacks: usize,
    screened_steps: usize,
    screened_bonds: usize,
    resumed_steps: usize,
    n_checkpoints: usize,
    setup_seconds: f64,
    sla_seconds: f64,
}

/// The result of a run: the model's counts and constants, the reference solution `sol0`, the
/// final displacements, the history, the damage, and a warning when nodes were grounded.
fn results(
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
    let broken = st.broken;
    let nn = model.grid.n_nodes();
    Ok(CcmPdResult {
        method: model.problem.method.name().into(),
        grip: model.problem.boundary.name().into(),
        solver: if info.lu_fallbacks > 0 {
            format!(
                "{}; the LU of S in {} model(s), from the condensation where K_PP was not \
                 symmetric positive definite",
                info.solver, info.lu_fallbacks
            )
        } else {
            info.solver
        },
        u: sol0.u,
        u_final,
        node_xy: (0..nn).map(|n| model.grid.xy(n)).collect(),
        n_nodes: nn,
        n_dofs: model.n_dofs(),
        n_pd_nodes: model.pd_nodes.len(),
        n_bonds: model.bonds.len(),
        n_precrack_bonds: model.precrack_broken.iter().filter(|&&b| b).count(),
        n_removed_elements: model.n_removed_elements,
        bytes_per_bond: BYTES_PER_BOND,
        gamma: model.pd.gamma,
        c: model.pd.c,
        s0: model.pd.s0,
        delta: model.pd.delta,
        sigma22: sol0.sigma22,
        cmod: sol0.cmod,
        out_of_balance: sol0.out_of_balance,
        responses: Default::default(),
        anchor_node: model.anchor,
        anchor_xy: model.grid.xy(model.anchor),
        history: st.history,
        initial_crack_length: model.problem.cracks.first().map_or(0.0, |c| c.a0),
        damage: damage(nn, &model.bonds, &broken, &model.pd_nodes),
        damage_at: st.damage_at,
        pd_node_xy: model.pd_nodes.iter().map(|&n| model.grid.xy(n)).collect(),
        pd_nodes: model.pd_nodes.clone(),
        bond_nodes: model
            .bonds
            .iter()
            .map(|b| [b.i as usize, b.j as usize])
            .collect(),
        broken,
        status: st.status,
        n_refactorisations: info.n_refactorisations,
        max_update_rank: info.max_update_rank,
        inverse_columns: info.inverse_columns,
        screened_steps: info.screened_steps,
        screened_bonds: info.screened_bonds,
        refactor_interval: info.refactor_interval,
        detached_nodes,
        warnings,
        resumed_steps: info.resumed_steps,
        n_checkpoints: info.n_checkpoints,
        setup_seconds: info.setup_seconds,
        sla_seconds: info.sla_seconds,
        peak_memory_bytes: peak_memory_bytes(),
        regions: model.pd_method().regions.clone(),
        switches: st.switches,
        interface_distance_min: st.closest.is_finite().then(|| st.closest / model.pd.delta),
        surface_correction: model.surface.as_ref().map(|s| s.summary),
    })
}

/// The records of a run whose region switched, in the final model's numbering (by key).
fn in_final_numbering(model: &SpliceModel, st: &mut RunState, keys: &Keys) -> Result<()> {
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

/// The probes at the step's load lambda (the engine's u is at the reference load; it holds every
/// probe dof, [`Fast`] keeps them in its ring).
fn st_probes(probes: &[ProbeFunctional], u: &[f64], lambda: f64) -> Vec<[f64; 2]> {
    probes
        .iter()
        .map(|p| p.value(u).map(|v| lambda * v))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::critical_by_stretch;

    /// The reference: lambda_b = s0 / s_b for every bond in tension, lmin = min, the bonds within
    /// the tolerance in index order (the rule as it was written before the one-division form).
    fn reference(s: &[f64], s0: f64, tol: f64) -> Option<(f64, Vec<usize>)> {
        let lam: Vec<f64> = s
            .iter()
            .map(|&v| if v > 0.0 { s0 / v } else { f64::INFINITY })
            .collect();
        let lmin = lam.iter().copied().fold(f64::INFINITY, f64::min);
        if !lmin.is_finite() {
            return None;
        }
        let sel = (0..s.len())
            .filter(|&b| lam[b] <= lmin * (1.0 + tol))
            .collect();
        Some((lmin, sel))
    }

    /// Random stretches (tension, compression, broken, exact and near ties, one-ulp neighbours,
    /// tiny and huge values): the same lmin bit for bit and the same bonds as the reference.
    #[test]
    fn one_division_form_selects_what_the_reference_selects() {
        let mut x: u64 = 0x9E37_79B9_7F4A_7C15;
        let mut rnd = || {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            (x >> 11) as f64 / (1u64 << 53) as f64
        };
        for case in 0..400 {
            let n = 1 + (rnd() * 300.0) as usize;
            let scale = 10f64.powi((rnd() * 40.0) as i32 - 20);
            let mut s: Vec<f64> = (0..n)
                .map(|_| match (rnd() * 10.0) as u32 {
                    0 => f64::NEG_INFINITY,
                    1 => -rnd() * scale,
                    2 => 0.0,
                    _ => rnd() * scale,
                })
                .collect();
            // ties: copies of the largest, its one-ulp neighbours, values just inside and outside
            // the tolerance
            let m = s.iter().copied().fold(0.0f64, f64::max);
            if m > 0.0 && n > 4 {
                s[0] = m;
                s[1] = f64::from_bits(m.to_bits() - 1);
                s[2] = m / (1.0 + 1e-10);
                s[3] = m / (1.0 + 2e-10);
            }
            let s0 = 10f64.powi((rnd() * 8.0) as i32 - 6) * (1.0 + rnd());
            for tol in [1e-10, 1e-6, 1e-2, 0.5] {
                let got = critical_by_stretch(&s, 0..s.len(), s0, tol);
                let want = reference(&s, s0, tol);
                match (&got, &want) {
                    (Some((a, sa)), Some((b, sb))) => {
                        assert_eq!(a.to_bits(), b.to_bits(), "case {case} tol {tol}");
                        assert_eq!(sa, sb, "case {case} tol {tol}");
                    }
                    (None, None) => {}
                    _ => panic!("case {case} tol {tol}: {got:?} against {want:?}"),
                }
            }
        }
        assert!(critical_by_stretch(&[-1.0, f64::NEG_INFINITY, 0.0], 0..3, 1e-3, 1e-10).is_none());
    }
}
