//! The bond screening of the fast SLA solver (`pd/sla/fast/screening.rs`: the critical bond
//! found from stretch bounds, x evaluated only where a bound reaches the tie window) against the
//! refactorise-every-step oracle, which evaluates every bond: the same broken bonds and load
//! factors within 1e-8 on small cases with the screening forced on (by size it starts at 4 096
//! PD unknowns), across re-condensations, grounding springs, separation, ties, the surface
//! correction, the adaptive region's switches, bonds with an FEM end, and a checkpoint resumed bit
//! for bit.

use crate::common;
use rustfrac_core::pd::analysis::run;

use common::{coarse, go_on, pd_plate, pd_strip, same_sla_history};
use rustfrac_core::pd::sla::{force_screening, CcmPdResult};
use rustfrac_core::problem::Grip;
use rustfrac_core::problem::{Problem, SlaEngine, SurfaceCorrection};

fn with_engine(mut p: Problem, e: SlaEngine) -> Problem {
    p.pd_mut().sla.engine = e;
    p
}

/// The run of `p` with the screening forced on (this thread only).
fn screened(p: &Problem) -> CcmPdResult {
    force_screening(true);
    let r = run(p, &go_on);
    force_screening(false);
    r.unwrap()
}

/// Screened against the oracle over every step; the screening ran at every step and cleared
/// most bonds by their bound (`most`: fraction of the bond-steps left unevaluated).
fn check(name: &str, p: &Problem, most: f64) -> f64 {
    let fast = screened(p);
    let oracle = run(&with_engine(p.clone(), SlaEngine::Oracle), &go_on).unwrap();
    let n = fast.history.len();
    assert!(n > 0, "{name}: no step");
    assert_eq!(fast.run.status, oracle.run.status, "{name}");
    assert_eq!(n, oracle.history.len(), "{name}");
    let worst = same_sla_history(&fast, &oracle, n);
    let bonds = fast.counts.n_bonds as f64;
    let cleared = 1.0 - fast.work.screened_bonds as f64 / (fast.work.screened_steps as f64 * bonds);
    println!(
        "{name}: {n} steps ({}), {} screened, {:.0} bonds evaluated a step of {bonds}, max rel \
         difference to the oracle {worst:.2e}",
        fast.run.status,
        fast.work.screened_steps,
        fast.work.screened_bonds as f64 / fast.work.screened_steps as f64
    );
    assert!(worst < 1e-8, "{name}: {worst:.2e}");
    // every step of the fast solver was screened (a step ending the run is not counted)
    assert!(
        fast.work.screened_steps + 1 >= n,
        "{name}: {}",
        fast.work.screened_steps
    );
    assert!(
        cleared > most,
        "{name}: only {cleared:.3} of the bonds cleared"
    );
    worst
}

/// CCM-PD, coarse plate: dense and sparse condensations, re-condensed every 40 breaks.
#[test]
fn ccm_pd_screened_matches_oracle() {
    for e in [SlaEngine::Dense, SlaEngine::Sparse] {
        let mut p = with_engine(coarse(true, 150), e);
        p.pd_mut().sla.refactor_every = 40;
        check(&format!("coarse CCM-PD {e:?}"), &p, 0.5);
    }
}

/// Pure PD plate under traction (its top-edge bonds change sigma22's functional) with ties
/// allowed (the symmetric lattice breaks bond pairs in one step), re-condensed every 30 breaks.
#[test]
fn pure_pd_screened_matches_oracle_with_ties() {
    let mut p = pd_plate("pd", 2.2, 4.3, 0.1, 3);
    common::set_precrack(&mut p, 0.55, 2.15);
    p.pd_mut().sla.max_steps = 120;
    p.pd_mut().sla.refactor_every = 30;
    p.pd_mut().sla.tie_tol = 1e-6;
    let p = with_engine(p, SlaEngine::Sparse);
    check("pure PD plate, ties", &p, 0.8);
    let r = screened(&p);
    assert!(
        r.history.iter().any(|s| s.bonds.len() > 1),
        "no tie: the tie window is not exercised"
    );
}

/// A pure PD strip cut through (grounding springs for detached nodes, then separation) under
/// both grips, and the surface correction's bond factors in the bounds' ratios.
#[test]
fn separation_and_surface_correction_screened() {
    for grip in [Grip::Free, Grip::Clamped] {
        let r = check(
            &format!("strip {grip:?}"),
            &with_engine(pd_strip(true, grip), SlaEngine::Sparse),
            0.0,
        );
        assert!(r < 1e-8);
    }
    let mut p = pd_strip(true, Grip::Free);
    p.pd_mut().surface_correction = SurfaceCorrection::Energy;
    check("strip, surface correction", &p, 0.0);
    let mut p = coarse(true, 120);
    p.pd_mut().surface_correction = SurfaceCorrection::Energy;
    check("coarse CCM-PD, surface correction", &p, 0.5);
}

/// The adaptive region: every switch builds a new condensation, screened from its start.
#[test]
fn adaptive_region_screened_matches_oracle() {
    let p = common::with_adaptive(coarse(true, 320), 1.5, 2.5);
    let fast = screened(&p);
    assert!(!fast.region.switches.is_empty());
    check("adaptive coarse CCM-PD", &p, 0.5);
}

/// Small cases go without it by size; a checkpoint of a screened run resumes bit for bit.
#[test]
fn size_rule_and_checkpoint_resume() {
    let base = with_engine(coarse(true, 87), SlaEngine::Sparse);
    let plain = run(&base, &go_on).unwrap();
    assert_eq!(
        plain.work.screened_steps, 0,
        "a small case is not screened by size"
    );
    let straight = screened(&base);
    let dir = std::env::temp_dir().join(format!("rustfrac-screen-ckpt-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("run.ckpt");
    let mut p = base.clone();
    p.pd_mut().sla.max_steps = 45;
    p.pd_mut().sla.checkpoint_every = 40;
    p.pd_mut().sla.checkpoint_path = Some(path.clone());
    assert_eq!(screened(&p).run.n_checkpoints, 1);
    let mut q = base.clone();
    q.pd_mut().sla.resume_from = Some(path);
    let resumed = screened(&q);
    assert_eq!(resumed.run.resumed_steps, 40);
    assert_eq!(straight.history, resumed.history);
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&straight.final_state.u), bits(&resumed.final_state.u));
    let _ = std::fs::remove_dir_all(&dir);
}

/// A pre-crack ending a fifth of a horizon from the FEM part: bonds with an FEM end break (their
/// update moves v by beta0 w, so the ring values the screened states read move too).
#[test]
fn bonds_with_an_fem_end_break_screened() {
    let mut p = coarse(true, 40);
    p.pd_mut().regions = vec![[0.0, 9.6, 1.7, 11.4]];
    common::set_precrack(&mut p, 1.5, 10.5);
    p.pd_mut().sla.refactor_every = 50;
    let r = screened(&p);
    assert_eq!(
        r.region.interface_distance_min,
        Some(0.0),
        "no bond with an FEM end broke"
    );
    for e in [SlaEngine::Dense, SlaEngine::Sparse] {
        check(
            &format!("pre-crack at the FEM part {e:?}"),
            &with_engine(p.clone(), e),
            0.3,
        );
    }
}
