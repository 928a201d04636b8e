//! Assemble + factorise + solve the paper's uncracked plate (plane strain, free grips) at about
//! 1e4, 1e5 and 1e6 unknowns, with each phase timed separately. The Python end-to-end comparison
//! against scipy (SuperLU) and CHOLMOD lives in `benches/bench_fem.py` at the repository top.
//!
//! Run: `cargo bench -p rustfrac-core --bench fem_solve`

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use rustfrac_core::fe::loading::{plate_conditions, PlateEdges};
use rustfrac_core::fe::mesh::Mesh;
use rustfrac_core::fe::{FemModel, LinearSystem};
use rustfrac_core::fem_driver::run;
use rustfrac_core::problem::{FeGrid, Problem};
use std::time::Duration;

/// (nx, ny) giving about 1e4, 1e5, 1e6 unknowns with the paper's aspect ratio.
const SIZES: [(usize, usize); 3] = [(50, 98), (160, 310), (510, 980)];

/// The paper's uncracked plate under free grips on nx x ny elements.
fn paper_plate(nx: usize, ny: usize) -> Problem {
    let mut p = Problem::paper("fem");
    p.fem_mut().grid = FeGrid::uniform(nx, ny);
    p.cracks.clear();
    p
}

/// The plate's Q4 model (2 x 2 Gauss points) and its edges.
fn model(p: &Problem, nx: usize, ny: usize) -> (FemModel, PlateEdges) {
    let d = &p.domain;
    let mesh = Mesh::uniform(0.0, 0.0, d.width, d.height, nx, ny).unwrap();
    let model = FemModel::new(mesh, p.material.elastic, 2).unwrap();
    let m = &model.mesh;
    let edges = PlateEdges::of_mesh(m);
    (model, edges)
}

fn bench(c: &mut Criterion) {
    let mut g = c.benchmark_group("plate");
    g.sample_size(10).measurement_time(Duration::from_secs(8));
    for (nx, ny) in SIZES {
        let ndof = 2 * (nx + 1) * (ny + 1);
        let p = paper_plate(nx, ny);
        let load = p.boundary.plate_load();
        let (m, edges) = model(&p, nx, ny);
        g.bench_with_input(BenchmarkId::new("assemble", ndof), &m, |b, m| {
            b.iter(|| m.stiffness())
        });
        let k = m.stiffness();
        let (bc, f, _) = plate_conditions(&edges, &load, m.n_dofs(), 1.0).unwrap();
        g.bench_with_input(BenchmarkId::new("factorise", ndof), &k, |b, k| {
            b.iter(|| LinearSystem::new(k.clone(), &bc).unwrap())
        });
        let sys = LinearSystem::new(k, &bc).unwrap();
        g.bench_with_input(BenchmarkId::new("solve", ndof), &sys, |b, s| {
            b.iter(|| s.solve(&f, 1.0).unwrap())
        });
        g.bench_with_input(BenchmarkId::new("end_to_end", ndof), &p, |b, p| {
            b.iter(|| run(p).unwrap())
        });
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
