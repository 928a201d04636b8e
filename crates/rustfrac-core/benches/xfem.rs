//! XFEM benchmarks against their targets, each with a plain-FEM baseline on the same mesh in the
//! same run:
//! * growth of the paper's edge crack from a = 1.1 to 0.7 W on 44 x 83 (target < 1 s);
//! * a single solve with SIFs on 352 x 664 (target < 2 s).

use criterion::{criterion_group, criterion_main, Criterion};
use rustfrac_core::fe::loading::{plate_conditions, PlateEdges};
use rustfrac_core::fe::mesh::Mesh;
use rustfrac_core::fe::{FemModel, LinearSystem};
use rustfrac_core::problem::{Grip, PlateLoad};
use rustfrac_core::problem::{Growth, Problem};
use rustfrac_core::xfem::run;
use std::hint::black_box;
use std::time::Duration;

fn fem_uncracked(nx: usize, ny: usize) -> f64 {
    let p = Problem::paper("xfem");
    let mesh = Mesh::uniform(0.0, 0.0, 11.0, 21.0, nx, ny).unwrap();
    let model = FemModel::new(mesh, p.material.elastic, 2).unwrap();
    let edges = PlateEdges::of_mesh(&model.mesh);
    let load = PlateLoad {
        grip: Grip::Free,
        u0: 0.01,
        traction: 0.0,
    };
    let (bc, f, _) = plate_conditions(&edges, &load, model.n_dofs(), 1.0).unwrap();
    let sol = LinearSystem::new(model.stiffness(), &bc)
        .unwrap()
        .solve(&f, 1.0)
        .unwrap();
    sol.energy
}

fn growth_params() -> Problem {
    let mut p = Problem::paper("xfem");
    let x = p.xfem_mut();
    x.extra_radii = vec![];
    x.growth = Some(Growth {
        da: None,
        a_stop: 0.7 * 11.0,
        kink_rule: rustfrac_core::problem::KinkRule::Hoop,
        max_steps: 1000,
        state_every: 0,
    });
    p
}

fn single_params(nx: usize, ny: usize) -> Problem {
    let mut p = Problem::paper("xfem");
    let x = p.xfem_mut();
    x.grid.nx = nx;
    x.grid.ny = ny;
    x.extra_radii = vec![];
    p
}

fn benches(c: &mut Criterion) {
    let mut g = c.benchmark_group("xfem_44x83");
    g.sample_size(10).measurement_time(Duration::from_secs(8));
    g.bench_function("baseline_fem_uncracked_single_solve", |b| {
        b.iter(|| black_box(fem_uncracked(44, 83)))
    });
    g.bench_function("xfem_single_solve_sifs", |b| {
        let p = single_params(44, 83);
        b.iter(|| black_box(run(&p, &|_, _| true).unwrap().k_i))
    });
    g.bench_function("xfem_growth_1.1_to_0.7W", |b| {
        let p = growth_params();
        b.iter(|| black_box(run(&p, &|_, _| true).unwrap().history.len()))
    });
    g.finish();
    let mut g = c.benchmark_group("xfem_352x664");
    g.sample_size(10).measurement_time(Duration::from_secs(20));
    g.bench_function("baseline_fem_uncracked_single_solve", |b| {
        b.iter(|| black_box(fem_uncracked(352, 664)))
    });
    g.bench_function("xfem_single_solve_sifs", |b| {
        let p = single_params(352, 664);
        b.iter(|| black_box(run(&p, &|_, _| true).unwrap().k_i))
    });
    g.finish();
}

criterion_group!(xfem, benches);
criterion_main!(xfem);
