//! XFEM growth of the paper's edge crack (a = 1.1 -> 0.7 W) on NX x NY, timed: at most STATES
//! critical states (0: the whole growth), `cargo run --release --example xfem_growth -- [NX NY
//! [STATES]]`. Prints the time, the number of states, the last state's load factor, K_I and CMOD,
//! and a checksum of the history (for comparing two builds).
use rustfrac_core::problem::value::{Table, Value};
use rustfrac_core::problem::{Method, Problem};
use rustfrac_core::xfem::run;
use std::time::Instant;

fn main() {
    let a: Vec<usize> = std::env::args()
        .skip(1)
        .map(|s| s.parse().expect("NX NY [STATES]"))
        .collect();
    let (nx, ny) = (
        a.first().copied().unwrap_or(44),
        a.get(1).copied().unwrap_or(83),
    );
    let states = a.get(2).copied().unwrap_or(0);
    // the growth options of a parsed scene (the defaults of every option not set here)
    let scene: Table = [
        ("method".to_string(), Value::Str("xfem".into())),
        (
            "xfem".to_string(),
            Value::Table(
                [("growth_steps".to_string(), Value::Int(1))]
                    .into_iter()
                    .collect(),
            ),
        ),
    ]
    .into_iter()
    .collect();
    let Method::Xfem(parsed) = Problem::from_scene(&scene).unwrap().method else {
        unreachable!("an XFEM scene")
    };
    let mut g = parsed.growth.unwrap();
    g.da = None;
    g.a_stop = 0.7 * 11.0;
    g.max_steps = if states == 0 { 100_000 } else { states };
    let mut p = Problem::paper("xfem");
    let x = p.xfem_mut();
    x.grid.nx = nx;
    x.grid.ny = ny;
    x.extra_radii = vec![];
    x.growth = Some(g);
    let t = Instant::now();
    let r = run(&p, &|_, _| true).unwrap();
    let last = r.history.last().unwrap();
    let sum: f64 = r.history.iter().map(|h| h.lambda + h.k_i + h.cmod).sum();
    println!(
        "{nx} x {ny}: {:.3} s, {} states ({}), last lambda {:.12}, K_I {:.12}, CMOD {:.12e}, \
         checksum {sum:.12e}",
        t.elapsed().as_secs_f64(),
        r.history.len() - 1,
        r.status,
        last.lambda,
        last.k_i,
        last.cmod
    );
}
