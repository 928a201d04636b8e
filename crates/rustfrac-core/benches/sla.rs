//! SLA benchmark on the paper's grid (dx = 1/15, m = 4, ~105 000 dofs): the fast solver
//! (condensation + Sherman-Morrison-Woodbury) for 500 steps against the refactorise-every-step
//! oracle, in the same run. The oracle runs `SLA_ORACLE_STEPS` steps (default 10; set 500 for the
//! full comparison, which takes long) and its 500-step time is extrapolated linearly from its
//! per-step cost when fewer steps run.
//!
//! `cargo bench -p rustfrac-core --bench sla`

use rustfrac_core::pd::analysis::run;
use rustfrac_core::pd::sla::peak_memory_bytes;
use rustfrac_core::problem::Problem;
use std::time::Instant;

fn main() {
    let steps: usize = std::env::var("SLA_STEPS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(500);
    let oracle_steps: usize = std::env::var("SLA_ORACLE_STEPS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(10);
    let mut p = Problem::paper("ccm_pd");
    p.pd_mut().sla.max_steps = steps;
    let t = Instant::now();
    let fast = run(&p, &|_, _| true).expect("fast run");
    let fast_total = t.elapsed().as_secs_f64();
    let mem_fast = peak_memory_bytes();
    println!(
        "fast: {} steps, status {}, setup {:.3} s, SLA {:.3} s, total {:.3} s ({} dofs, {} PD nodes, {} bonds x {} B = {:.2} MB), peak RSS {:.0} MB",
        fast.history.len(),
        fast.run.status,
        fast.timings.setup_seconds,
        fast.timings.sla_seconds,
        fast_total,
        fast.counts.n_dofs,
        fast.counts.n_pd_nodes,
        fast.counts.n_bonds,
        fast.counts.bytes_per_bond,
        (fast.counts.n_bonds * fast.counts.bytes_per_bond) as f64 / 1e6,
        mem_fast.unwrap_or(0) as f64 / 1e6
    );
    if let (Some(a), Some(b)) = (fast.history.first(), fast.history.last()) {
        println!(
            "  step 1: lambda {:.5}, sigma22 {:.4}, CMOD {:.6}; step {}: lambda {:.5}, sigma22 {:.4}, CMOD {:.6}, crack length {:.4}",
            a.lambda, a.sigma22, a.cmod, b.step, b.lambda, b.sigma22, b.cmod, b.crack_length
        );
    }
    p.pd_mut().sla.max_steps = oracle_steps;
    p.pd_mut().sla.engine = rustfrac_core::problem::SlaEngine::Oracle;
    let t = Instant::now();
    let oracle = run(&p, &|_, _| true).expect("oracle run");
    let oracle_total = t.elapsed().as_secs_f64();
    let per_step = oracle.timings.sla_seconds / oracle_steps.max(1) as f64;
    let oracle_500 = oracle.timings.setup_seconds + per_step * steps as f64;
    let mut worst = 0.0f64;
    for (a, b) in fast.history.iter().zip(&oracle.history) {
        assert_eq!(a.bonds, b.bonds, "different bond at step {}", a.step);
        worst = worst.max((a.lambda - b.lambda).abs() / b.lambda);
    }
    println!(
        "oracle: {} steps, setup {:.3} s, SLA {:.3} s ({:.3} s/step), total {:.3} s; extrapolated {} steps {:.1} s",
        oracle.history.len(),
        oracle.timings.setup_seconds,
        oracle.timings.sla_seconds,
        per_step,
        oracle_total,
        steps,
        oracle_500
    );
    println!(
        "speed-up (total, {} steps): {:.0}x; per SLA step: {:.0}x; max relative lambda difference over the first {} steps: {:.2e}; peak RSS {:.0} MB",
        steps,
        oracle_500 / fast_total,
        per_step / (fast.timings.sla_seconds / fast.history.len().max(1) as f64),
        oracle.history.len(),
        worst,
        peak_memory_bytes().unwrap_or(0) as f64 / 1e6
    );
}
