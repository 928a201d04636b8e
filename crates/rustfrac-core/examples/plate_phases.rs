//! Phase timings of the FEM plate pipeline: `cargo run --release --example plate_phases -- NX NY`.
use rustfrac_core::fe::loading::{plate_conditions, PlateEdges};
use rustfrac_core::fe::mesh::Mesh;
use rustfrac_core::fe::FemModel;
use rustfrac_core::la::Cholesky;
use rustfrac_core::la::Reduction;
use rustfrac_core::problem::Problem;
use std::time::Instant;

fn main() {
    let a: Vec<usize> = std::env::args()
        .skip(1)
        .map(|s| s.parse().expect("NX NY"))
        .collect();
    let (nx, ny) = (a[0], a[1]);
    let t = Instant::now();
    let lap = |s: &str, t: &Instant| println!("{s:>12}: {:.3} s", t.elapsed().as_secs_f64());
    // the paper's uncracked plate under free grips, phase by phase as the FEM driver runs it
    let p = Problem::paper("fem");
    let d = &p.domain;
    let mesh = Mesh::uniform(0.0, 0.0, d.width, d.height, nx, ny).unwrap();
    let model = FemModel::new(mesh, p.material.elastic, 2).unwrap();
    lap("pattern", &t);
    let t = Instant::now();
    let k = model.stiffness();
    lap("assemble", &t);
    let m = &model.mesh;
    let edges = PlateEdges::of_mesh(m);
    let load = p.boundary.plate_load();
    let (bc, f, _) = plate_conditions(&edges, &load, model.n_dofs(), 1.0).unwrap();
    let t = Instant::now();
    let (mask, up) = bc.to_mask(k.ncols).unwrap();
    let mut red = Reduction::new(&k, &mask).unwrap();
    let rhs = red.rhs(&k, &f, &up);
    lap("reduce", &t);
    // K_ff as LinearSystem sees it (values gathered into the reduction's pattern, no copy)
    let t = Instant::now();
    let xy: Vec<[f64; 2]> = red.free.iter().map(|&d| m.coords[d / 2]).collect();
    let x = red.with_reduced(&k, |kff| {
        lap("gather", &t);
        let t = Instant::now();
        let mut ch = if std::env::var("AMD").is_ok() {
            Cholesky::analyze(kff).unwrap()
        } else {
            Cholesky::analyze_with(kff, Some(&xy)).unwrap()
        };
        lap("symbolic", &t);
        println!("factor nnz {}", ch.factor_nnz());
        let t = Instant::now();
        ch.factorize(kff).unwrap();
        lap("numeric", &t);
        let t = Instant::now();
        let x = ch.solve(&rhs).unwrap();
        lap("solve", &t);
        x
    });
    let t = Instant::now();
    let _ = model.gauss_stresses(&red.expand(&x, &up));
    let _ = model.nodal_stresses(&red.expand(&x, &up));
    lap("post", &t);
}
