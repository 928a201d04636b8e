//! Graded against uniform grids on the paper's XFEM plate (traction grips): the uniform
//! 352 x 664 grid's K_I, and graded grids (fine around the tip, growing by `mesh.grading` to
//! the coarse 44 x 83 spacing) that reach it within 0.1 %: unknowns and wall time of each,
//! measured in the same run (best of 3), with their ratios.
//!
//! `cargo run --release -p rustfrac-core --example graded_grid`

use rustfrac_core::problem::value::{Table, Value};
use rustfrac_core::problem::Problem;
use std::time::Instant;

fn scene(mesh: &[(&str, Value)]) -> Table {
    let t = |kv: &[(&str, Value)]| {
        Value::Table(kv.iter().map(|(k, v)| (k.to_string(), v.clone())).collect())
    };
    [
        ("method", Value::Str("xfem".into())),
        ("load", t(&[("bc", Value::Str("traction".into()))])),
        ("mesh", t(mesh)),
    ]
    .iter()
    .map(|(k, v)| (k.to_string(), v.clone()))
    .collect()
}

fn best_of_3(p: &Problem) -> (f64, usize, f64) {
    let mut best = f64::INFINITY;
    let mut out = (0.0, 0);
    for _ in 0..3 {
        let t0 = Instant::now();
        let r = rustfrac_core::xfem::run(p, &|_, _| true).expect("the run");
        best = best.min(t0.elapsed().as_secs_f64());
        out = (r.k_i, r.n_dofs);
    }
    (out.0, out.1, best)
}

fn main() {
    let i = |n: i64| Value::Int(n);
    let f = Value::Float;
    let uni = Problem::from_scene(&scene(&[("nx", i(352)), ("ny", i(664))])).unwrap();
    let (k_u, n_u, t_u) = best_of_3(&uni);
    println!("uniform 352 x 664: K_I = {k_u:.6}, {n_u} unknowns, {t_u:.3} s");
    for (h_div, grading, half) in [(352.0, 1.15, 0.5), (352.0, 1.25, 0.5), (176.0, 1.15, 0.5)] {
        let h = 11.0 / h_div;
        let b = [1.1 - half, 10.5 - half, 1.1 + half, 10.5 + half];
        let g = Problem::from_scene(&scene(&[
            ("nx", i(44)),
            ("ny", i(83)),
            ("refine", Value::List(b.iter().map(|&x| f(x)).collect())),
            ("refine_h", f(h)),
            ("grading", f(grading)),
        ]))
        .unwrap();
        let (k, n, t) = best_of_3(&g);
        println!(
            "graded (h = W/{h_div}, box {b:?}, grading {grading}): K_I = {k:.6} ({:+.4} % of \
             uniform), {n} unknowns ({:.1}x fewer), {t:.3} s ({:.1}x faster)",
            100.0 * (k / k_u - 1.0),
            n_u as f64 / n as f64,
            t_u / t
        );
    }
}
