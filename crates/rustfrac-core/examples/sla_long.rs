//! A long SLA run for the memory figures of benches/RESULTS.md: the paper's plate on a coarse grid
//! (dx = 0.2) with a large horizon (m = 12) and a 6 x 6 PD rectangle around the crack, so that
//! enough bonds exist for `SLA_STEPS` (default 100 000) breaks. Prints the resident memory every
//! `SLA_REPORT` steps (default 10 000) and the totals.
//!
//! `cargo run --release -p rustfrac-core --example sla_long`

use rustfrac_core::pd::analysis::run;
use rustfrac_core::pd::sla::peak_memory_bytes;
use rustfrac_core::problem::Problem;
use std::time::Instant;

fn rss() -> u64 {
    std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("VmRSS:"))
                .and_then(|l| l.split_whitespace().nth(1)?.parse::<u64>().ok())
        })
        .unwrap_or(0)
        * 1024
}

fn env(name: &str, default: usize) -> usize {
    std::env::var(name)
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(default)
}

fn main() {
    let steps = env("SLA_STEPS", 100_000);
    let every = env("SLA_REPORT", 10_000);
    let mut p = Problem::paper("ccm_pd");
    p.pd_mut().dx = 0.2;
    p.pd_mut().m = env("SLA_M", 12);
    p.pd_mut().regions = vec![[0.1, 7.5, 6.1, 13.5]];
    p.pd_mut().sla.max_steps = steps;
    let t = Instant::now();
    let report = |s: usize, _: usize| {
        if s % every == 0 {
            println!(
                "step {s}: {:.1} s, RSS {:.1} MB, peak {:.1} MB",
                t.elapsed().as_secs_f64(),
                rss() as f64 / 1e6,
                peak_memory_bytes().unwrap_or(0) as f64 / 1e6
            );
        }
        true
    };
    let r = run(&p, &report).expect("run");
    println!(
        "{} steps, status {}; {} dofs, {} PD nodes, {} bonds ({} B each); setup {:.1} s, SLA {:.1} s; \
         re-condensation every {} updates, {} condensations, at most {} update vectors; {} detached \
         nodes; history {} B/step + bonds; peak RSS {:.1} MB",
        r.history.len(),
        r.run.status,
        r.counts.n_dofs,
        r.counts.n_pd_nodes,
        r.counts.n_bonds,
        r.counts.bytes_per_bond,
        r.timings.setup_seconds,
        r.timings.sla_seconds,
        r.run.solver.refactor_interval,
        r.work.n_refactorisations,
        r.work.max_update_rank,
        r.final_state.detached_nodes.len(),
        std::mem::size_of::<rustfrac_core::pd::sla::SlaStep>(),
        r.timings.peak_memory_bytes.unwrap_or(0) as f64 / 1e6
    );
}
