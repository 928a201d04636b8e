//! Times one FEM plate solve: `cargo run --release --example plate_timing -- NX NY`.
use rustfrac_core::loading::{Grip, PlateLoad};
use rustfrac_core::material::{Elastic, Plane};
use rustfrac_core::plate::{run, FemPlateParams};

fn main() {
    let a: Vec<usize> = std::env::args()
        .skip(1)
        .map(|s| s.parse().expect("NX NY"))
        .collect();
    let (nx, ny) = (
        a.first().copied().unwrap_or(44),
        a.get(1).copied().unwrap_or(83),
    );
    let p = FemPlateParams {
        width: 11.0,
        height: 21.0,
        nx,
        ny,
        material: Elastic::new(10000.0, 0.25, Plane::Strain, 1.0).unwrap(),
        load: PlateLoad {
            grip: Grip::Free,
            u0: 0.01,
            traction: 0.0,
        },
        seam: None,
        gauss: 2,
        condition: true,
    };
    let r = run(&p).unwrap();
    println!(
        "ndofs {} sigma22 {:.10} time {:.3} s",
        r.n_dofs, r.sigma22, r.wall_time_s
    );
}
