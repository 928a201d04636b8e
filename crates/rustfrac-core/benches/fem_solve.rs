//! Assemble + factorise + solve the paper's uncracked plate (plane strain, free grips) at about
//! 1e4, 1e5 and 1e6 unknowns, with each phase timed separately. The Python end-to-end comparison
//! against scipy (SuperLU) and CHOLMOD lives in `benches/bench_fem.py` at the repository top.
//!
//! Run: `cargo bench -p rustfrac-core --bench fem_solve`

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use rustfrac_core::fem::{FemModel, LinearSystem};
use rustfrac_core::loading::{plate_conditions, Grip, PlateEdges, PlateLoad};
use rustfrac_core::material::{Elastic, Plane};
use rustfrac_core::mesh::Mesh;
use rustfrac_core::plate::{run, FemPlateParams};
use std::time::Duration;

/// (nx, ny) giving about 1e4, 1e5, 1e6 unknowns with the paper's aspect ratio.
const SIZES: [(usize, usize); 3] = [(50, 98), (160, 310), (510, 980)];

fn model(nx: usize, ny: usize) -> (FemModel, PlateEdges) {
    let mesh = Mesh::uniform(0.0, 0.0, 11.0, 21.0, nx, ny).unwrap();
    let mat = Elastic::new(10000.0, 0.25, Plane::Strain, 1.0).unwrap();
    let model = FemModel::new(mesh, mat, 2).unwrap();
    let m = &model.mesh;
    let edges = PlateEdges::of_mesh(m);
    (model, edges)
}

fn bench(c: &mut Criterion) {
    let mut g = c.benchmark_group("plate");
    g.sample_size(10).measurement_time(Duration::from_secs(8));
    let load = PlateLoad {
        grip: Grip::Free,
        u0: 0.01,
        traction: 0.0,
    };
    for (nx, ny) in SIZES {
        let ndof = 2 * (nx + 1) * (ny + 1);
        let (m, edges) = model(nx, ny);
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
        let p = FemPlateParams {
            width: 11.0,
            height: 21.0,
            nx,
            ny,
            material: m.material,
            load,
            seam: None,
            gauss: 2,
            condition: true,
        };
        g.bench_with_input(BenchmarkId::new("end_to_end", ndof), &p, |b, p| {
            b.iter(|| run(p).unwrap())
        });
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
