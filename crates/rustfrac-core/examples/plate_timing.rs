//! Times one FEM plate solve: `cargo run --release --example plate_timing -- NX NY`.
use rustfrac_core::fem_driver::run;
use rustfrac_core::problem::{FeGrid, Problem};

fn main() {
    let a: Vec<usize> = std::env::args()
        .skip(1)
        .map(|s| s.parse().expect("NX NY"))
        .collect();
    let (nx, ny) = (
        a.first().copied().unwrap_or(44),
        a.get(1).copied().unwrap_or(83),
    );
    // the paper's uncracked plate under free grips
    let mut p = Problem::paper("fem");
    p.fem_mut().grid = FeGrid::uniform(nx, ny);
    p.cracks.clear();
    let r = run(&p).unwrap();
    println!(
        "ndofs {} sigma22 {:.10} time {:.3} s",
        r.n_dofs, r.sigma22, r.wall_time_s
    );
}
