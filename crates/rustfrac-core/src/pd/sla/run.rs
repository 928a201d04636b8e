//! The SLA run ([`run_calibrated`], section 3): build the model and the solver, replay a checkpoint, run
//! the steps (`steps.rs`), grow an adaptive region between them (`switch.rs`), collect the
//! results (`collect.rs`).

use super::checkpoint;
use super::choice::engine_for;
use super::collect::{results, RunInfo};
use super::engine::{timing, Engine};
use super::memory::keep_large_blocks_mmapped;
use super::oracle::Oracle;
use super::progress::SlaProgress;
use super::result::{CcmPdResult, SlaStatus, SlaStep};
use super::resume::{checkpoint_sizes, Replay};
use super::state::RunState;
use crate::error::Result;
use crate::pd::splice::{SpliceModel, StaticSolution};
use crate::problem::{validate, Calibration, Problem};
use std::sync::Arc;
use std::time::Instant;

/// Runs a CCM-PD (or pure PD) problem whose critical stretch is scaled by `s0` (the calibration
/// of its `pd.s0_calibration`; `crate::pd::analysis::run` makes it): linear solution at the
/// reference load, then the SLA. `progress` reads the whole [`SlaProgress`] after every step;
/// returning `false` stops the run (status [`SlaStatus::Cancelled`], a checkpoint is written
/// first when `checkpoint_path` is set).
pub fn run_calibrated(
    p: &Problem,
    s0: Calibration,
    progress: &(dyn Fn(&SlaProgress) -> bool + Sync),
) -> Result<CcmPdResult> {
    validate::problem(p)?;
    validate::reference_load(p)?;
    keep_large_blocks_mmapped();
    let t0 = Instant::now();
    let model = SpliceModel::new(p, s0)?;
    timing("model built", t0);
    run_from(&model, t0, progress)
}

/// The SLA on a model built by hand ([`SpliceModel::with_precrack`]).
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

/// The rigid-body modes of the model's stiffness, as FEM and XFEM check theirs: every connected
/// part of the material (linked by the intact bonds and the FEM elements; the largest and every
/// one of more than [`DEBRIS_LIMIT`] nodes, smaller fragments are grounded) held by the scene's conditions on its
/// own material nodes ([`crate::fe::Dirichlet::check_rigid_modes_by_part`]: refused naming the
/// free mode and the part, a body cut in two by a hole included).
fn check_rigid_modes(model: &SpliceModel) -> Result<()> {
    let mat = |n: usize| model.material.get(n).is_none_or(|&m| m);
    let bc = crate::fe::Dirichlet {
        dofs: (model.bc.dofs.iter().copied())
            .filter(|&(d, _)| mat(d / 2))
            .collect(),
    };
    let bonds = (model.bonds.iter().zip(&model.precrack_broken))
        .filter(|(_, &pre)| !pre)
        .map(|(b, _)| [b.i as usize, b.j as usize]);
    let edges = model
        .elements
        .iter()
        .flat_map(|e| (0..4).map(move |k| [e[k], e[(k + 1) % 4]]));
    let xy: Vec<[f64; 2]> = (0..model.grid.n_nodes())
        .map(|n| model.grid.xy(n))
        .collect();
    bc.check_rigid_modes_by_part(
        &xy,
        bonds.chain(edges).filter(|&[a, b]| mat(a) && mat(b)),
        super::DEBRIS_LIMIT,
    )
}

fn run_from(
    model0: &SpliceModel,
    t0: Instant,
    progress: &(dyn Fn(&SlaProgress) -> bool + Sync),
) -> Result<CcmPdResult> {
    check_rigid_modes(model0)?;
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
        let (mut engine, solver) = engine_for(model, sla, &k, (&st.broken, &springs), &probe_dofs)?;
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
        info.solver = Some(solver);
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
        let w = &mut info.work;
        w.n_refactorisations += engine.n_refactorisations();
        w.max_update_rank = w.max_update_rank.max(engine.max_update_rank());
        w.inverse_columns += engine.inverse_columns();
        let (ss, sb) = engine.screening();
        w.screened_steps += ss;
        w.screened_bonds += sb;
        info.lu_fallbacks += engine.lu_fallbacks();
        let Some(centres) = grow else {
            break if st.status == SlaStatus::Separated {
                Vec::new()
            } else {
                engine.full_u()?
            };
        };
        drop(engine);
        // the adaptive region grows: the model with the new rectangles, the broken bonds found
        // in it by their end nodes (`switch.rs`)
        let ts = Instant::now();
        switch_start = Some(ts);
        let a = adaptive.expect("only an adaptive region grows");
        owned = Some(st.switch(model, a, centres, ts)?);
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
    r.reference.responses = responses;
    Ok(r)
}

/// The reference solution's displacements on `model` (pre-crack only, no SLA break).
fn reference_field(model: &SpliceModel) -> Result<Vec<f64>> {
    let mut st = RunState::new(model);
    let springs = st.ground_precrack(model);
    let k = model.assemble_with(&st.broken, &springs);
    Oracle::new(model, &st.broken, &springs, &k)?.full_u()
}
