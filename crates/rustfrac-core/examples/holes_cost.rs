//! The cost of holes (the fictitious domain, `fe::fictitious`): a square plate [0, 4]^2 with a
//! circular hole (r = 1 at the centre), a triangular hole and a notch from the left edge against
//! the plain plate on the same grid: model build (pattern, and the fictitious-domain data),
//! stiffness assembly, factorisation + solve, best of 3.
//!
//! `cargo run --release -p rustfrac-core --example holes_cost -- [N ...]` (default 128 256 512
//! elements per side).
use rustfrac_core::fe::mesh::Mesh;
use rustfrac_core::fe::{Dirichlet, FemModel, LinearSystem};
use rustfrac_core::problem::Side;
use rustfrac_core::problem::{Domain, Hole, Shape};
use rustfrac_core::problem::{Elastic, Plane};
use std::time::Instant;

/// (build, assemble, factorise + solve) seconds, best of 3, and the free dofs.
fn time(n: usize, domain: &Domain) -> ([f64; 3], usize) {
    let mat = Elastic::new(1.0, 0.3, Plane::Strain, 1.0).unwrap();
    let mut best = [f64::INFINITY; 3];
    let mut free = 0;
    for _ in 0..3 {
        let mesh = Mesh::uniform(0.0, 0.0, 4.0, 4.0, n, n).unwrap();
        let t0 = Instant::now();
        let model = FemModel::with_domain(mesh, mat, 2, domain).unwrap();
        let t1 = Instant::now();
        let k = model.stiffness();
        let t2 = Instant::now();
        let m = &model.mesh;
        let mut bc = Dirichlet::default();
        bc.fix(&m.side_nodes(Side::Bottom), 1, 0.0);
        bc.fix(&m.side_nodes(Side::Top), 1, 1e-3);
        bc.fix(&[m.node(n, 0)], 0, 0.0);
        let mut f = vec![0.0; model.n_dofs()];
        let bc = model.constrain(bc, &mut f).unwrap();
        let sys = LinearSystem::with_positions(k, &bc, Some(&model.dof_positions())).unwrap();
        let sol = sys.solve(&f, 1.0).unwrap();
        let t3 = Instant::now();
        assert!(sol.residual < 1e-8);
        free = sys.reduction.free.len();
        let t = [t1 - t0, t2 - t1, t3 - t2].map(|d| d.as_secs_f64());
        for i in 0..3 {
            best[i] = best[i].min(t[i]);
        }
    }
    (best, free)
}

fn main() {
    let sizes: Vec<usize> = std::env::args()
        .skip(1)
        .map(|s| s.parse().expect("N: elements per side"))
        .collect();
    let sizes = if sizes.is_empty() {
        vec![128, 256, 512]
    } else {
        sizes
    };
    let plain = Domain::rect(4.0, 4.0);
    let mut holes = Domain::rect(4.0, 4.0);
    holes.holes = vec![
        Hole {
            name: "hole[0]".into(),
            shape: Shape::Circle {
                center: [2.0, 2.0],
                radius: 1.0,
            },
        },
        Hole {
            name: "hole[1]".into(),
            shape: Shape::Polygon(vec![[3.1, 0.4], [3.7, 0.5], [3.3, 1.1]]),
        },
        Hole {
            name: "notch[0]".into(),
            shape: Shape::Rect {
                min: [-1.0, 3.2],
                max: [0.8, 3.4],
            },
        },
    ];
    println!("N      free dofs (plain / holes)   build s   assemble s   solve s   (plain | holes | ratio)");
    for n in sizes {
        let (a, fa) = time(n, &plain);
        let (b, fb) = time(n, &holes);
        let total = |t: [f64; 3]| t.iter().sum::<f64>();
        println!(
            "{n:4}  {fa:8} / {fb:8}   build {:.4} | {:.4} | {:.2}   assemble {:.4} | {:.4} | {:.2}   \
             solve {:.3} | {:.3} | {:.2}   total {:.3} | {:.3} | {:.2}",
            a[0],
            b[0],
            b[0] / a[0],
            a[1],
            b[1],
            b[1] / a[1],
            a[2],
            b[2],
            b[2] / a[2],
            total(a),
            total(b),
            total(b) / total(a)
        );
    }
}
