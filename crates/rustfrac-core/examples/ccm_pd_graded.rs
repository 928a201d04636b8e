//! CCM-PD on the paper's case with the uniform dx grid and with graded FEM grids
//! (`pd.fem_grading`, at most `pd.fem_coarse` dx; `pd::splice::graded`), in the same run:
//! unknowns, set-up time (model, assembly, condensation), the SLA time of the steps, the
//! reference sigma22 and CMOD, the peak sigma22, and the first step where the broken bonds
//! differ from the uniform run's.
//!
//! `cargo run --release -p rustfrac-core --example ccm_pd_graded -- [STEPS]` (default 500)

use rustfrac_core::pd::analysis::run;
use rustfrac_core::pd::sla::CcmPdResult;
use rustfrac_core::problem::Problem;

fn broken_xy(r: &CcmPdResult, k: usize) -> Vec<[[i64; 2]; 2]> {
    let key = |x: [f64; 2]| [(x[0] * 1e6).round() as i64, (x[1] * 1e6).round() as i64];
    let mut v: Vec<_> = r.history[k]
        .bonds
        .iter()
        .map(|&b| {
            let [i, j] = r.geometry.bond_nodes[b];
            [key(r.geometry.node_xy[i]), key(r.geometry.node_xy[j])]
        })
        .collect();
    v.sort_unstable();
    v
}

fn main() {
    let steps: usize = std::env::args()
        .nth(1)
        .map(|s| s.parse().expect("STEPS"))
        .unwrap_or(500);
    let load = std::fs::read_to_string("/proc/loadavg").unwrap_or_default();
    println!("load average before: {}", load.trim());
    let cases: [(f64, f64); 3] = [(1.0, 8.0), (1.2, 8.0), (1.3, 16.0)];
    let mut uniform: Option<CcmPdResult> = None;
    println!("| grid | unknowns | set-up s | SLA s ({steps} steps) | sigma22 ref | CMOD ref | peak sigma22 | same bonds |");
    println!("|---|---|---|---|---|---|---|---|");
    for (g, c) in cases {
        let mut p = Problem::paper("ccm_pd");
        let pd = p.pd_mut();
        pd.sla.max_steps = steps;
        pd.fem_grading = g;
        pd.fem_coarse = c;
        let r = run(&p, &|_, _| true).expect("the paper's case runs");
        let peak = r.history.iter().map(|s| s.sigma22).fold(0.0, f64::max);
        let (name, vs) = match &uniform {
            None => ("uniform dx".to_string(), String::new()),
            Some(u) => {
                let n = r.history.len().min(u.history.len());
                let same = (0..n)
                    .take_while(|&k| broken_xy(&r, k) == broken_xy(u, k))
                    .count();
                let lam = (0..same)
                    .map(|k| (r.history[k].lambda / u.history[k].lambda - 1.0).abs())
                    .fold(0.0, f64::max);
                (
                    format!("graded {g}, cap {c} dx"),
                    format!(
                        "{same} of {n} steps (lambda within {lam:.1e}); sigma22 ref {:+.4} %, CMOD {:+.4} %, peak {:+.4} %",
                        100.0 * (r.reference.sigma22 / u.reference.sigma22 - 1.0),
                        100.0 * (r.reference.cmod / u.reference.cmod - 1.0),
                        100.0 * (peak / u.history.iter().map(|s| s.sigma22).fold(0.0, f64::max) - 1.0)
                    ),
                )
            }
        };
        println!(
            "| {name} | {} | {:.3} | {:.3} | {:.5} | {:.6e} | {:.4} | {vs} |",
            r.counts.n_dofs,
            r.timings.setup_seconds,
            r.timings.sla_seconds,
            r.reference.sigma22,
            r.reference.cmod,
            peak
        );
        if uniform.is_none() {
            uniform = Some(r);
        }
    }
    let load = std::fs::read_to_string("/proc/loadavg").unwrap_or_default();
    println!("load average after: {}", load.trim());
}
