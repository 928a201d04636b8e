//! The SLA driver ([`run`], section 3): build the model and the solver, replay a checkpoint, run
//! the steps, collect the results.
//!
//! Each step solves the current (linear) model once at the reference load, computes the stretch of
//! every intact bond, takes lambda = min s0 / s over the bonds in tension, records (lambda,
//! sigma22, CMOD, u0 = lambda u0_ref) at that load, and breaks the critical bond (or, with
//! `tie_tol > 0`, every bond whose load factor is within that relative tolerance of lambda). Ties
//! closer than 1e-10 (mirror bonds in mode I) are broken deterministically: the lowest bond index
//! goes first, so two solvers that agree to round-off produce the same sequence. Before a bond
//! breaks, its end nodes are grounded where they need it (`grounding.rs`).

use super::checkpoint;
use super::cost::{CostEstimate, EngineKind};
use super::engine::{timing, Engine, Update};
use super::fast::{schur_pattern, Fast, SchurKind, SparseFactor};
use super::grounding::{Grounding, DEBRIS_LIMIT};
use super::memory::{keep_large_blocks_mmapped, peak_memory_bytes};
use super::oracle::Oracle;
use super::result::{CcmPdResult, SlaStatus, SlaStep};
use crate::error::{Error, Result};
use crate::la::{Cholesky, CscMatrix};
use crate::pd::splice::{ProbeFunctional, SpliceModel, Spring, StaticSolution};
use crate::pd::{damage, BYTES_PER_BOND};
use crate::problem::{validate, Problem, SlaEngine, SlaParams};
use crate::warning::{Warning, WarningKind};
use std::path::Path;
use std::time::Instant;

/// Runs a CCM-PD (or pure PD) problem: linear solution at the reference load, then the SLA.
/// `progress(step, max_steps)` is called after every step; returning `false` stops the run
/// (status [`SlaStatus::Cancelled`], a checkpoint is written first when `checkpoint_path` is set).
pub fn run(p: &Problem, progress: &(dyn Fn(usize, usize) -> bool + Sync)) -> Result<CcmPdResult> {
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
    run_from(model, Instant::now(), progress)
}

fn run_from(
    model: &SpliceModel,
    t0: Instant,
    progress: &(dyn Fn(usize, usize) -> bool + Sync),
) -> Result<CcmPdResult> {
    let sla = &model.pd_method().sla;
    let mut st = RunState::new(model);
    let springs0 = st.ground_precrack(model);
    let k0 = model.assemble_with(&st.broken, &springs0);
    st.probes = model.probe_functionals()?;
    let probe_dofs: Vec<usize> = st.probes.iter().flat_map(|p| p.dofs()).collect();
    let (mut engine, solver, refactor_interval) =
        engine_for(model, sla, &k0, (&st.broken, &springs0), &probe_dofs)?;
    timing("engine ready", t0);
    // reference solution before breaking (u from the engine, reactions from the full matrix)
    let u0_full = engine.full_u()?;
    let sol0 = model.postprocess(&k0, u0_full, 0.0);
    drop(k0);
    let responses = model.scene_responses(&sol0.u, &sol0.reactions)?;
    let fp = checkpoint::fingerprint(
        &model.problem,
        &model.precrack,
        model.n_dofs(),
        model.bonds.len(),
    );
    // resume: replay the checkpoint's steps exactly
    let mut resumed_steps = 0;
    if let Some(path) = &sla.resume_from {
        st.replay(sla, model, engine.as_mut(), path, fp)?;
        resumed_steps = st.history.len();
    }
    let setup_seconds = t0.elapsed().as_secs_f64();
    timing("setup done", t0);

    let t1 = Instant::now();
    let n_checkpoints = st.steps(sla, model, engine.as_mut(), fp, sol0.sigma22, progress)?;
    let u_final = if st.status == SlaStatus::Separated {
        Vec::new()
    } else {
        engine.full_u()?
    };
    let sla_seconds = t1.elapsed().as_secs_f64();
    let info = RunInfo {
        solver,
        refactor_interval,
        n_refactorisations: engine.n_refactorisations(),
        max_update_rank: engine.max_update_rank(),
        resumed_steps,
        n_checkpoints,
        setup_seconds,
        sla_seconds,
    };
    let mut r = results(model, st, sol0, u_final, info);
    r.responses = responses;
    Ok(r)
}

/// The solver ([`choose`]): the oracle when `fast = false` or `pd.engine = "oracle"`, else the
/// condensation with the form of the condensed system (dense inverse or sparse factor) the scene
/// asks for or, for `"auto"`, the cheaper by the cost model ([`CostEstimate`]). Returns it, its
/// description (the choice and the estimates) and the re-condensation interval (0 for the oracle).
fn engine_for<'a>(
    model: &'a SpliceModel,
    sla: &SlaParams,
    k0: &CscMatrix,
    (broken, springs0): (&[bool], &[Spring]),
    probe_dofs: &[usize],
) -> Result<(Box<dyn Engine + 'a>, String, usize)> {
    if !sla.fast || sla.engine == SlaEngine::Oracle {
        let solver = "oracle (sparse LU refactorised every step)".to_string();
        return Ok((
            Box::new(Oracle::new(model, broken, springs0, k0)?),
            solver,
            0,
        ));
    }
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
        Cholesky::analyze_with(&symmetrised(&pattern), Some(&xy))
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
    let (schur, analysed, interval, name) = match kind {
        EngineKind::Dense => (
            SchurKind::Dense,
            None,
            sla.refactor_every,
            "fast (FEM condensed by Cholesky, dense PD system + Sherman-Morrison-Woodbury)",
        ),
        EngineKind::Sparse => (
            SchurKind::Sparse,
            analysed,
            est.sparse_interval,
            if symmetric {
                "fast, sparse (PD system by sparse Cholesky + Sherman-Morrison-Woodbury)"
            } else {
                "fast, sparse (FEM condensed by Cholesky, PD system by sparse LU + \
                 Sherman-Morrison-Woodbury)"
            },
        ),
    };
    let f = Fast::new(
        model,
        k0,
        (broken, springs0),
        probe_dofs,
        interval,
        (schur, analysed),
    )?;
    let solver = format!("{name}; {why}; {}", est.describe());
    let refactor_interval = f.refactor_every;
    Ok((Box::new(f), solver, refactor_interval))
}

/// The pattern of A + A^T (values 0), for a symmetric analysis of a non-symmetric pattern.
fn symmetrised(a: &CscMatrix) -> CscMatrix {
    let mut trip = Vec::with_capacity(2 * a.nnz());
    for c in 0..a.ncols {
        for &r in &a.row_idx[a.col_ptr[c]..a.col_ptr[c + 1]] {
            trip.push((r, c, 0.0));
            trip.push((c, r, 0.0));
        }
    }
    CscMatrix::from_triplets(a.nrows, a.ncols, &trip).expect("indices of a square matrix")
}

/// The evolving state of a run: the broken bonds (pre-crack included), the groundings, the
/// history and the status.
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
}

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
        }
    }

    /// The springs of the nodes the pre-crack already detaches (recorded as step 0).
    fn ground_precrack(&mut self, model: &SpliceModel) -> Vec<Spring> {
        let mut springs0 = Vec::new();
        // only nodes with a broken bond can be loose (a fragment's nodes all lost a bond)
        let touched: Vec<usize> = model
            .pd_nodes
            .iter()
            .copied()
            .filter(|&n| model.bonds_of(n).iter().any(|&b| self.broken[b as usize]))
            .collect();
        for n in touched {
            for (m, sp) in self.grounding.springs(model, n, &self.broken) {
                if !self.detached_nodes.contains(&(0, m)) {
                    self.detached_nodes.push((0, m));
                }
                springs0.push(sp);
            }
        }
        springs0
    }

    /// Replays the steps of the checkpoint at `path` (at most `max_steps`): exactly the updates of
    /// the run that wrote it, in the same order; the recorded numbers come from their stored bits.
    fn replay(
        &mut self,
        sla: &SlaParams,
        model: &SpliceModel,
        engine: &mut dyn Engine,
        path: &Path,
        fp: u64,
    ) -> Result<()> {
        let sizes = (model.bonds.len(), model.grid.n_nodes(), self.probes.len());
        let steps = checkpoint::read(path, fp, sizes)?;
        for st in steps.into_iter().take(sla.max_steps) {
            if st.bonds.iter().any(|&b| self.broken[b]) {
                return Err(Error::invalid(
                    "pd.resume_from",
                    "a checkpoint breaking every bond once",
                    format!("step {} breaks a bond twice", st.step),
                ));
            }
            let (det, sep) = advance(
                model,
                engine,
                &mut self.broken,
                &mut self.grounding,
                &st.bonds,
            )?;
            self.detached_nodes
                .extend(det.iter().map(|&n| (st.step, n)));
            self.record_damage(sla, model, st.step);
            self.history.push(st);
            if sep {
                self.status = SlaStatus::Separated;
                break;
            }
        }
        Ok(())
    }

    /// The SLA steps after the replayed ones, up to `max_steps` or until the run ends (separated,
    /// no bond in tension, cancelled, crack length reached). `sigma0` is the reference sigma22 of
    /// the intact model. Returns the number of checkpoints written.
    fn steps(
        &mut self,
        sla: &SlaParams,
        model: &SpliceModel,
        engine: &mut dyn Engine,
        fp: u64,
        sigma0: f64,
        progress: &(dyn Fn(usize, usize) -> bool + Sync),
    ) -> Result<usize> {
        let s0 = model.pd.s0;
        let load = model.problem.boundary.plate_load();
        let max_steps = sla.max_steps;
        let mut n_checkpoints = 0;
        let mut lam = vec![f64::INFINITY; model.bonds.len()];
        let first_step = self.history.len() + 1;
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
                critical_bonds(model, &self.broken, engine.u(), s0, tie_tol, &mut lam)
            else {
                self.status = SlaStatus::NoBondInTension;
                break;
            };
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
            let cl = crack_length(model, &self.broken);
            let bf = &model.bonds[first];
            self.history.push(SlaStep {
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
            });
            self.record_damage(sla, model, step);
            let every = sla.checkpoint_every;
            if every > 0 && step % every == 0 {
                self.checkpoint(sla, fp, &mut n_checkpoints)?;
            }
            let go_on = progress(step, max_steps);
            if sep {
                self.status = SlaStatus::Separated;
                break;
            }
            if !go_on {
                self.status = SlaStatus::Cancelled;
                self.checkpoint(sla, fp, &mut n_checkpoints)?;
                break;
            }
            if let Some(l) = sla.stop_crack_length {
                if cl >= l {
                    self.status = SlaStatus::CrackLengthReached;
                    break;
                }
            }
        }
        Ok(n_checkpoints)
    }

    /// Stores the damage field after `step` when it is one of `damage_at_steps`.
    fn record_damage(&mut self, sla: &SlaParams, model: &SpliceModel, step: usize) {
        if sla.damage_at_steps.contains(&step) {
            self.damage_at.push((
                step,
                damage(
                    model.grid.n_nodes(),
                    &model.bonds,
                    &self.broken,
                    &model.pd_nodes,
                ),
            ));
        }
    }

    /// Writes the history so far to `checkpoint_path` (when set) and counts it in `n`.
    fn checkpoint(&self, sla: &SlaParams, fp: u64, n: &mut usize) -> Result<()> {
        if let Some(path) = &sla.checkpoint_path {
            checkpoint::write(path, fp, &self.history)?;
            *n += 1;
        }
        Ok(())
    }
}

/// The bonds to break in the state with displacements `u`: lambda_b = s0 / s_b for every intact
/// bond in tension (`lam`, infinite elsewhere), lmin = min lambda, and every bond with
/// lambda_b <= lmin (1 + max(tie_tol, 1e-10)) in index order (only the first when tie_tol = 0).
/// None when no bond is in tension.
fn critical_bonds(
    model: &SpliceModel,
    broken: &[bool],
    u: &[f64],
    s0: f64,
    tie_tol: f64,
    lam: &mut [f64],
) -> Option<(f64, Vec<usize>)> {
    let mut lmin = f64::INFINITY;
    for (b, bond) in model.bonds.iter().enumerate() {
        lam[b] = f64::INFINITY;
        if broken[b] {
            continue;
        }
        let s = bond.stretch(u);
        if s > 0.0 {
            lam[b] = s0 / s;
            lmin = lmin.min(lam[b]);
        }
    }
    if !lmin.is_finite() {
        return None;
    }
    let tol = tie_tol.max(1e-10);
    let mut sel: Vec<usize> = (0..model.bonds.len())
        .filter(|&b| lam[b] <= lmin * (1.0 + tol))
        .collect();
    if tie_tol == 0.0 {
        sel.truncate(1);
    }
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

fn crack_length(model: &SpliceModel, broken: &[bool]) -> f64 {
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
    let mut len = l0;
    for (b, bond) in model.bonds.iter().enumerate() {
        if broken[b] && !model.precrack_broken[b] {
            let xi = model.grid.xy(bond.i as usize);
            let mid = [xi[0] + 0.5 * bond.xi[0], xi[1] + 0.5 * bond.xi[1]];
            len = len.max((mid[0] - p0[0]) * t[0] + (mid[1] - p0[1]) * t[1]);
        }
    }
    len
}

/// What the driver knows of a run besides its state: the solver, its counters and the timings.
struct RunInfo {
    solver: String,
    refactor_interval: usize,
    n_refactorisations: usize,
    max_update_rank: usize,
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
) -> CcmPdResult {
    let mut warnings = model.warnings.clone();
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
    CcmPdResult {
        method: model.problem.method.name().into(),
        grip: model.problem.boundary.name().into(),
        solver: info.solver,
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
        refactor_interval: info.refactor_interval,
        detached_nodes,
        warnings,
        resumed_steps: info.resumed_steps,
        n_checkpoints: info.n_checkpoints,
        setup_seconds: info.setup_seconds,
        sla_seconds: info.sla_seconds,
        peak_memory_bytes: peak_memory_bytes(),
    }
}

/// The probes at the step's load lambda (the engine's u is at the reference load; it holds every
/// probe dof, [`Fast`] keeps them in its ring).
fn st_probes(probes: &[ProbeFunctional], u: &[f64], lambda: f64) -> Vec<[f64; 2]> {
    probes
        .iter()
        .map(|p| p.value(u).map(|v| lambda * v))
        .collect()
}
