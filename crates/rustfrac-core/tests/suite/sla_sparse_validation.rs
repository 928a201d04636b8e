//! The sparse SLA engine (large PD regions without a speed cliff) against the
//! refactorise-every-step oracle: the same broken bonds and load factors within 1e-8 on CCM-PD and
//! pure PD grids, separation detected at the same step, checkpoints resumed bit for bit, the
//! engine's choice reported; and an ignored paper-scale run (pure PD, 52 k nodes).

use crate::common;
use rustfrac_core::pd::analysis::run;

use common::{coarse, go_on, pd_plate, pd_strip, rel};
use rustfrac_core::pd::sla::{force_lu_form, CcmPdResult};
use rustfrac_core::problem::Grip;
use rustfrac_core::problem::{Problem, SlaEngine};
use std::path::PathBuf;

fn with_engine(mut p: Problem, e: SlaEngine) -> Problem {
    p.pd_mut().sla.engine = e;
    p
}

/// Same bonds at every step, load factors (and sigma22, CMOD) within `tol` relative.
fn agree(a: &CcmPdResult, oracle: &CcmPdResult, tol: f64) {
    assert_eq!(a.history.len(), oracle.history.len());
    assert_eq!(a.run.status, oracle.run.status);
    let mut worst = 0.0f64;
    for (x, y) in a.history.iter().zip(&oracle.history) {
        assert_eq!(x.bonds, y.bonds, "step {}", x.step);
        for (p, q) in [
            (x.lambda, y.lambda),
            (x.sigma22, y.sigma22),
            (x.cmod, y.cmod),
        ] {
            let r = rel(p, q);
            worst = worst.max(r);
            assert!(r < tol, "step {}: {p} vs oracle {q} (rel {r:.2e})", x.step);
        }
    }
    println!(
        "{} steps, same bonds, max rel difference {worst:.2e}",
        a.history.len()
    );
}

/// CCM-PD (the coarse plate, PD rectangle 4.4 x 2.4): the sparse engine (S = K_PP - K_PF Z as
/// the Cholesky of K_PP bordered by the FEM coupling, Woodbury) against the oracle,
/// re-factorising every 40 breaks so the run crosses re-factorisations; the dense engine and the
/// LU form of S (forced) agree too.
#[test]
fn ccm_pd_sparse_matches_oracle() {
    let steps = 150;
    let mut p = coarse(true, steps);
    p.pd_mut().sla.refactor_every = 40;
    let sparse = run(&with_engine(p.clone(), SlaEngine::Sparse), &go_on).unwrap();
    let dense = run(&with_engine(p.clone(), SlaEngine::Dense), &go_on).unwrap();
    let p_lu = p.clone();
    let oracle = run(&with_engine(p, SlaEngine::Oracle), &go_on).unwrap();
    println!(
        "sparse: {}\noracle: {}",
        sparse.run.solver.describe(),
        oracle.run.solver.describe()
    );
    assert!(
        sparse.run.solver.describe().contains("bordered"),
        "{}",
        sparse.run.solver.describe()
    );
    assert!(
        oracle.run.solver.describe().starts_with("oracle"),
        "{}",
        oracle.run.solver.describe()
    );
    assert_eq!(sparse.history.len(), steps);
    assert!(
        sparse.work.n_refactorisations >= 3,
        "{}",
        sparse.work.n_refactorisations
    );
    agree(&sparse, &oracle, 1e-8);
    agree(&dense, &oracle, 1e-8);
    // the LU of S, the form taken when K_PP is not symmetric positive definite
    force_lu_form(true);
    let lu = run(&with_engine(p_lu, SlaEngine::Sparse), &go_on);
    force_lu_form(false);
    let lu = lu.unwrap();
    assert!(
        lu.run
            .solver
            .describe()
            .contains("the LU of S in 1 model(s)"),
        "{}",
        lu.run.solver.describe()
    );
    agree(&lu, &oracle, 1e-8);
}

/// The sparse engine keeps the columns of S_0^{-1} it computes (in batches around the crack):
/// without a re-factorisation, 150 breaks need far fewer columns than the 4 a break would cost
/// one by one, and the history is still the oracle's.
#[test]
fn sparse_engine_reuses_inverse_columns() {
    let steps = 150;
    let mut p = coarse(true, steps);
    p.pd_mut().sla.refactor_every = 10_000;
    let sparse = run(&with_engine(p.clone(), SlaEngine::Sparse), &go_on).unwrap();
    let oracle = run(&with_engine(p, SlaEngine::Oracle), &go_on).unwrap();
    println!(
        "{} columns for {steps} breaks, {} factorisation(s)",
        sparse.work.inverse_columns, sparse.work.n_refactorisations
    );
    assert_eq!(sparse.work.n_refactorisations, 1);
    assert!(sparse.work.inverse_columns > 0);
    assert!(
        sparse.work.inverse_columns < 2 * steps,
        "{} columns",
        sparse.work.inverse_columns
    );
    assert_eq!(oracle.work.inverse_columns, 0);
    agree(&sparse, &oracle, 1e-8);
}

/// Pure PD (2.2 x 4.3 plate, dx = 0.1, m = 3, 946 nodes, symmetric K: sparse Cholesky) against
/// the oracle, re-factorising every 30 breaks.
#[test]
fn pure_pd_sparse_matches_oracle() {
    let steps = 120;
    let mut p = pd_plate("pd", 2.2, 4.3, 0.1, 3);
    common::set_precrack(&mut p, 0.55, 2.15);
    p.pd_mut().sla.max_steps = steps;
    p.pd_mut().sla.refactor_every = 30;
    let sparse = run(&with_engine(p.clone(), SlaEngine::Sparse), &go_on).unwrap();
    let oracle = run(&with_engine(p, SlaEngine::Oracle), &go_on).unwrap();
    println!("sparse: {}", sparse.run.solver.describe());
    assert!(
        sparse.run.solver.describe().contains("sparse Cholesky"),
        "{}",
        sparse.run.solver.describe()
    );
    assert_eq!(sparse.history.len(), steps);
    assert!(
        sparse.work.n_refactorisations >= 4,
        "{}",
        sparse.work.n_refactorisations
    );
    agree(&sparse, &oracle, 1e-8);
}

/// A pure PD strip cut through: the sparse engine ends with status "separated" at the oracle's
/// step, with the same bonds before.
#[test]
fn sparse_detects_separation_like_the_oracle() {
    for grip in [Grip::Free, Grip::Clamped] {
        let sparse = run(
            &with_engine(pd_strip(true, grip), SlaEngine::Sparse),
            &go_on,
        )
        .unwrap();
        let oracle = run(&pd_strip(false, grip), &go_on).unwrap();
        println!(
            "grip {grip:?}: sparse {} after {} steps, oracle {} after {}",
            sparse.run.status,
            sparse.history.len(),
            oracle.run.status,
            oracle.history.len()
        );
        assert_eq!(sparse.run.status.name(), "separated");
        agree(&sparse, &oracle, 1e-8);
    }
}

/// "auto" reports its choice and the estimates; the paper's CCM-PD case (2 080 PD dofs) stays on
/// the dense engine, the widened PD rectangle of the issue (11 x 1.67, 8 632 PD dofs) goes
/// sparse. Zero steps: only the set-up runs.
#[test]
fn auto_choice_is_reported() {
    let mut p = Problem::paper("ccm_pd");
    p.pd_mut().sla.max_steps = 0;
    let r = run(&p, &go_on).unwrap();
    println!("paper: {}", r.run.solver.describe());
    assert!(
        r.run.solver.describe().starts_with("fast (FEM condensed"),
        "{}",
        r.run.solver.describe()
    );
    assert!(
        r.run.solver.describe().contains("auto") && r.run.solver.describe().contains("estimated")
    );
    p.pd_mut().regions = vec![[0.0, 10.5 - 0.835, 11.0, 10.5 + 0.835]];
    let r = run(&p, &go_on).unwrap();
    println!("widened: {}", r.run.solver.describe());
    assert!(
        r.run.solver.describe().starts_with("fast, sparse"),
        "{}",
        r.run.solver.describe()
    );
}

fn tmpdir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("rustfrac-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Checkpoint after N steps, stop, resume: the same history, broken bonds and final
/// displacements bit for bit as a straight run of the sparse engine (the replay crosses
/// re-factorisations: every 25 breaks).
#[test]
fn sparse_checkpoint_and_resume_are_bit_for_bit() {
    let dir = tmpdir("sparse-ckpt");
    let (n, total) = (40, 87);
    let mut base = with_engine(coarse(true, total), SlaEngine::Sparse);
    base.pd_mut().sla.refactor_every = 25;
    let straight = run(&base, &go_on).unwrap();
    assert_eq!(straight.history.len(), total);
    let path = dir.join("run.ckpt");
    let mut p = base.clone();
    p.pd_mut().sla.max_steps = n + 5;
    p.pd_mut().sla.checkpoint_every = n;
    p.pd_mut().sla.checkpoint_path = Some(path.clone());
    assert_eq!(run(&p, &go_on).unwrap().run.n_checkpoints, 1);
    let mut q = base.clone();
    q.pd_mut().sla.resume_from = Some(path.clone());
    let resumed = run(&q, &go_on).unwrap();
    assert_eq!(resumed.run.resumed_steps, n);
    assert_eq!(straight.history, resumed.history);
    for (x, y) in straight.history.iter().zip(&resumed.history) {
        assert_eq!(x.lambda.to_bits(), y.lambda.to_bits());
        assert_eq!(x.cmod.to_bits(), y.cmod.to_bits());
    }
    assert_eq!(straight.final_state.broken, resumed.final_state.broken);
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&straight.final_state.u), bits(&resumed.final_state.u));
    // a checkpoint of the sparse engine is refused by the dense one (other solver option)
    let mut d = with_engine(base, SlaEngine::Dense);
    d.pd_mut().sla.resume_from = Some(path);
    assert!(run(&d, &go_on).is_err());
    let _ = std::fs::remove_dir_all(&dir);
}

/// Paper scale: pure PD on the paper's full grid (52 k nodes, 103 583 free unknowns), the sparse
/// engine's first `ORACLE_STEPS` steps against the oracle (170 s a step at load 12, after a
/// 240 s set-up: benches/RESULTS.md), then
/// 300 steps of the sparse engine alone, all finite. `cargo test --release -p rustfrac-core
/// --test suite sla_sparse_validation:: -- --ignored --nocapture` (minutes).
#[test]
#[ignore]
fn paper_grid_pure_pd_sparse_matches_oracle() {
    const ORACLE_STEPS: usize = 3;
    let mut p = Problem::paper("pd");
    p.pd_mut().sla.max_steps = ORACLE_STEPS;
    let sparse = run(&with_engine(p.clone(), SlaEngine::Sparse), &go_on).unwrap();
    let oracle = run(&with_engine(p.clone(), SlaEngine::Oracle), &go_on).unwrap();
    println!(
        "sparse {:.1} s, oracle {:.1} s for {ORACLE_STEPS} steps",
        sparse.timings.sla_seconds, oracle.timings.sla_seconds
    );
    agree(&sparse, &oracle, 1e-8);
    p.pd_mut().sla.max_steps = 300;
    let long = run(&p, &go_on).unwrap();
    println!(
        "auto, 300 steps: {} ({:.1} s)",
        long.run.solver.describe(),
        long.timings.sla_seconds
    );
    assert!(long.run.solver.describe().starts_with("fast, sparse"));
    assert_eq!(long.history.len(), 300);
    assert_eq!(long.history[..ORACLE_STEPS], sparse.history[..]);
    assert!(long.history.iter().all(|s| s.lambda.is_finite()));
}
