//! The adaptive CCM-PD region on the paper's case, in one run:
//! * the adaptive run (`pd.region = "adaptive"`, margin and size in horizons) from the tip at
//!   a0 = 1.1 to `--a-stop` (0.7 W = 7.6 by default, the XFEM growth's end) or `--steps`;
//! * the paper's fixed rectangle for its 500 steps (the baseline of Fig. 7): the same bonds
//!   (mirror pairs across the crack line as one) and the load factors along them;
//! * with `--fixed-cover`: a run whose fixed region is the bounding box of the adaptive run's
//!   final region (covering the whole path), compared the same way over the adaptive run's steps.
//!
//! Prints the switches (step, PD nodes, unknowns, seconds), the closest approach of a broken
//! bond to the FEM part, wall and peak memory.
//!
//! `cargo run --release -p rustfrac-core --example adaptive_pd [-- --margin 2 --size 4
//! --a-stop 7.6 --steps 20000 --grading 1 --fixed-cover]`
use rustfrac_core::pd::analysis::run;
use rustfrac_core::pd::sla::CcmPdResult;
use rustfrac_core::problem::pd_region;
use rustfrac_core::problem::{AdaptiveRegion, Problem};
use std::time::Instant;

fn arg(args: &[String], name: &str, default: f64) -> f64 {
    args.iter()
        .position(|a| a == name)
        .and_then(|i| args.get(i + 1))
        .map_or(default, |v| v.parse().expect("a number"))
}

fn compare(name: &str, a: &CcmPdResult, b: &CcmPdResult) {
    let n = a.history.len().min(b.history.len());
    let same = (0..n)
        .take_while(|&k| a.broken_positions(k, Some(10.5)) == b.broken_positions(k, Some(10.5)))
        .count();
    let worst = |m: usize| {
        (0..m)
            .map(|k| (a.history[k].lambda / b.history[k].lambda - 1.0).abs())
            .fold(0.0, f64::max)
    };
    let gap = (same < n).then(|| a.history[same].lambda / b.history[same].lambda - 1.0);
    let peak =
        |r: &CcmPdResult, m: usize| r.history[..m].iter().map(|s| s.sigma22).fold(0.0, f64::max);
    println!(
        "  vs {name}: same bonds for {same} of {n} steps (first divergence: lambda gap {gap:?}); worst lambda difference {:.3e} over them, {:.3e} over all {n}; peak sigma22 over the {n} steps {:.4} / {:.4} ({:+.3} %)",
        worst(same),
        worst(n),
        peak(a, n),
        peak(b, n),
        100.0 * (peak(a, n) / peak(b, n) - 1.0)
    );
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let margin = arg(&args, "--margin", 2.0);
    let size = arg(&args, "--size", 4.0);
    let a_stop = arg(&args, "--a-stop", 7.6);
    let steps = arg(&args, "--steps", 20000.0) as usize;
    let grading = arg(&args, "--grading", 1.0);
    let a = AdaptiveRegion { margin, size };

    let mut p = Problem::paper("ccm_pd");
    {
        let pd = p.pd_mut();
        pd.fem_grading = grading;
        pd.sla.max_steps = steps;
        pd.sla.stop_crack_length = Some(a_stop);
        pd.adaptive = Some(a);
    }
    let (dx, m) = (p.pd().unwrap().dx, p.pd().unwrap().m);
    p.pd_mut().regions = pd_region::initial(&p, dx, m, &a);
    let t = Instant::now();
    let ad = run(&p, &|_, _| true).expect("the adaptive run");
    let wall = t.elapsed().as_secs_f64();
    let last = ad.history.last().expect("steps");
    println!(
        "adaptive (margin {margin}, size {size} horizons, fem_grading {grading}): {} steps ({}), crack {:.3} -> {:.3}, {} switches, {} PD nodes / {} unknowns at the end; set-up {:.2} s, SLA {:.2} s (of which switches {:.2} s), whole run {wall:.2} s; peak memory {:.0} MB; closest approach {:?} horizons",
        ad.history.len(),
        ad.run.status,
        ad.reference.crack_length,
        last.crack_length,
        ad.region.switches.len(),
        ad.counts.n_pd_nodes,
        ad.counts.n_dofs,
        ad.timings.setup_seconds,
        ad.timings.sla_seconds,
        ad.region.switches.iter().map(|s| s.seconds).sum::<f64>(),
        ad.timings.peak_memory_bytes.unwrap_or(0) as f64 / 1e6,
        ad.region.interface_distance_min
    );
    println!("  solver at the end: {}", ad.run.solver.describe());
    for s in &ad.region.switches {
        println!(
            "  switch before step {}: {} rectangles, {} PD nodes, {} unknowns, {:.3} s",
            s.step,
            s.regions.len(),
            s.n_pd_nodes,
            s.n_dofs,
            s.seconds
        );
    }
    // the paper's fixed rectangle, its 500 steps
    let mut q = Problem::paper("ccm_pd");
    q.pd_mut().fem_grading = grading;
    let t = Instant::now();
    let paper = run(&q, &|_, _| true).expect("the paper's run");
    println!(
        "paper's rectangle: {} steps, {:.2} s, closest approach {:?} horizons",
        paper.history.len(),
        t.elapsed().as_secs_f64(),
        paper.region.interface_distance_min
    );
    compare("the paper's rectangle (its 500 steps)", &ad, &paper);
    if args.iter().any(|x| x == "--fixed-cover") {
        let bb = ad.regions_bounding_box().expect("CCM-PD");
        let mut f = Problem::paper("ccm_pd");
        f.pd_mut().fem_grading = grading;
        f.pd_mut().regions = vec![bb];
        f.pd_mut().sla.max_steps = ad.history.len();
        let t = Instant::now();
        let fixed = run(&f, &|_, _| true).expect("the covering run");
        println!(
            "fixed region covering the path {bb:?}: {} PD nodes, {} steps, {:.2} s ({})",
            fixed.counts.n_pd_nodes,
            fixed.history.len(),
            t.elapsed().as_secs_f64(),
            fixed.run.solver.describe()
        );
        compare("the fixed region covering the path", &ad, &fixed);
    }
}
