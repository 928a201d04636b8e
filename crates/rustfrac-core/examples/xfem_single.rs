//! One XFEM single solve + SIFs on the paper plate (the `xfem` bench's 352 x 664 case), timed:
//! `cargo run --release --example xfem_single -- [NX NY [REPEATS]]`.
use rustfrac_core::problem::Problem;
use rustfrac_core::xfem::run;
use std::time::Instant;

fn main() {
    let a: Vec<usize> = std::env::args()
        .skip(1)
        .map(|s| s.parse().expect("NX NY [REPEATS]"))
        .collect();
    let (nx, ny) = (
        a.first().copied().unwrap_or(352),
        a.get(1).copied().unwrap_or(664),
    );
    let reps = a.get(2).copied().unwrap_or(3);
    let mut p = Problem::paper("xfem");
    let x = p.xfem_mut();
    x.grid.nx = nx;
    x.grid.ny = ny;
    x.extra_radii = vec![];
    for _ in 0..reps {
        let t = Instant::now();
        let r = run(&p, &|_, _| true).unwrap();
        println!(
            "{nx} x {ny}: {:.3} s, K_I {:.12}, sigma22 {:.12}, CMOD {:.12e}",
            t.elapsed().as_secs_f64(),
            r.k_i,
            r.sigma22,
            r.cmod
        );
    }
}
