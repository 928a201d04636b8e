//! The engine choice of a run ([`engine_for`]): the oracle, or the fast solver with the form of
//! the condensed system the scene asks for or the cost model (`cost.rs`) estimates cheaper.

use super::engine::{timing, Engine};
use super::fast::{
    bordered_analysis, dense_lead, schur_pattern, Fast, FemPart, SchurKind, SparseFactor,
};
use super::oracle::Oracle;
use super::result::SolverUsed;
use crate::error::{Error, Result};
use crate::la::{Cholesky, CscMatrix};
use crate::pd::cost::{CostEstimate, EngineKind};
use crate::pd::splice::{SpliceModel, Spring};
use crate::problem::{SlaEngine, SlaParams};
use faer::Par;
use std::sync::Arc;
use std::time::Instant;

/// The solver ([`choose`]): the oracle when `fast = false` or `pd.engine = "oracle"`, else the
/// condensation with the form of the condensed system (dense LU or sparse factor) the scene
/// asks for or, for `"auto"`, the cheaper by the cost model ([`CostEstimate`]). Returns it and
/// what it is ([`SolverUsed`]: the form, its description with the choice and the estimates, and
/// the re-condensation interval, 0 for the oracle).
/// The cost model's symbolic analysis (then, for the dense form, the LU of S's PD block; for the
/// sparse CCM-PD form, K_PP's analysis and Cholesky, `fast/base.rs`) and the condensation's FEM part
/// ([`FemPart`]) do not depend on each other: they run at once, the analysis on its own thread
/// while the FEM part's ordering and symbolic phases leave a core idle.
pub(super) fn engine_for<'a>(
    model: &'a SpliceModel,
    sla: &SlaParams,
    k0: &Arc<CscMatrix>,
    (broken, springs0): (&[bool], &[Spring]),
    probe_dofs: &[usize],
) -> Result<(Box<dyn Engine + 'a>, SolverUsed)> {
    // the LPS's break is no rank-1 change: the oracle rebuilds its matrix (`pd::lps`)
    if sla.engine == SlaEngine::Oracle || model.lps.is_some() {
        let solver = SolverUsed {
            engine: SlaEngine::Oracle,
            description: "oracle (sparse LU refactorised every step)".into(),
            refactor_interval: 0,
            lu_fallbacks: 0,
        };
        return Ok((Box::new(Oracle::new(model, broken, springs0, k0)?), solver));
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
    let solver = SolverUsed {
        engine: match c.kind {
            SchurKind::Dense => SlaEngine::Dense,
            SchurKind::Sparse => SlaEngine::Sparse,
        },
        description: format!("{}; {}; {}", c.name, c.why, c.est.describe()),
        refactor_interval: f.refactor_every,
        lu_fallbacks: 0,
    };
    Ok((Box::new(f), solver))
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
