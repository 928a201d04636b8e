//! Large PD regions, in one run: the new engine (`pd.engine = "auto"`, which picks the sparse
//! form here) against the refactorise-every-step oracle (what these cases ran
//! before: above 6000 free PD dofs the old code fell back to it), per case:
//! * pure PD on the paper's full grid (52 k nodes, 103 583 unknowns): `--steps` (500) steps of
//!   the new engine, set-up included; the oracle's per-step time over `--oracle-steps` (3) steps,
//!   extrapolated to `--steps` (labelled as such; 0: no oracle at all);
//! * CCM-PD with the PD rectangle widened to the ligament (11 x 1.67 at dx = 1/15, 4 316 PD
//!   nodes): per-step time of both over `--ccm-steps` (100) and `--oracle-steps` steps.
//!
//! `cargo run --release -p rustfrac-core --example sla_large_pd [-- --steps 500 --oracle-steps 3
//! --ccm-steps 100 --skip-pure]`
use rustfrac_core::pd::analysis::run;
use rustfrac_core::pd::sla::CcmPdResult;
use rustfrac_core::problem::{Problem, SlaEngine};
use std::time::Instant;

fn arg(args: &[String], name: &str, default: usize) -> usize {
    args.iter()
        .position(|a| a == name)
        .and_then(|i| args.get(i + 1))
        .map_or(default, |v| v.parse().expect("an integer"))
}

fn timed(p: &Problem, engine: SlaEngine, steps: usize) -> (CcmPdResult, f64) {
    let mut p = p.clone();
    p.pd_mut().sla.engine = engine;
    p.pd_mut().sla.max_steps = steps;
    let t = Instant::now();
    let r = run(&p, &|_, _| true).expect("run");
    (r, t.elapsed().as_secs_f64())
}

fn report(case: &str, p: &Problem, steps: usize, oracle_steps: usize) {
    let (new, wall) = timed(p, SlaEngine::Auto, steps);
    let n = new.history.len().max(1) as f64;
    println!(
        "{case}: {} dofs, {} PD nodes",
        new.counts.n_dofs, new.counts.n_pd_nodes
    );
    println!("  new engine: {}", new.run.solver.describe());
    println!(
        "  new engine: {} steps ({}), set-up {:.2} s, SLA {:.2} s ({:.4} s/step), whole run {:.2} s, {} factorisations",
        new.history.len(),
        new.run.status,
        new.timings.setup_seconds,
        new.timings.sla_seconds,
        new.timings.sla_seconds / n,
        wall,
        new.work.n_refactorisations
    );
    if oracle_steps == 0 {
        return; // the oracle's set-up alone is 50 s on the pure PD grid
    }
    let (old, _) = timed(p, SlaEngine::Oracle, oracle_steps);
    let per = old.timings.sla_seconds / old.history.len().max(1) as f64;
    println!(
        "  oracle: {} steps measured, set-up {:.2} s, {:.4} s/step; EXTRAPOLATED to {steps} steps: {:.1} s",
        old.history.len(),
        old.timings.setup_seconds,
        per,
        old.timings.setup_seconds + per * steps as f64
    );
    let same = old
        .history
        .iter()
        .zip(&new.history)
        .all(|(a, b)| a.bonds == b.bonds && ((a.lambda - b.lambda) / b.lambda).abs() < 1e-8);
    println!(
        "  per-step ratio oracle / new: {:.1}; first {} steps agree (bonds, lambda 1e-8): {same}",
        per / (new.timings.sla_seconds / n),
        old.history.len()
    );
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let steps = arg(&args, "--steps", 500);
    let oracle_steps = arg(&args, "--oracle-steps", 3);
    let ccm_steps = arg(&args, "--ccm-steps", 100);
    println!(
        "load average: {}",
        std::fs::read_to_string("/proc/loadavg")
            .unwrap_or_default()
            .trim()
    );
    if !args.iter().any(|a| a == "--skip-pure") {
        report(
            "pure PD, paper grid",
            &Problem::paper("pd"),
            steps,
            oracle_steps,
        );
    }
    let mut wide = Problem::paper("ccm_pd");
    wide.pd_mut().regions = vec![[0.0, 10.5 - 0.835, 11.0, 10.5 + 0.835]];
    report(
        "CCM-PD, PD rectangle 11 x 1.67",
        &wide,
        ccm_steps,
        oracle_steps,
    );
}
