//! FEM validation against closed forms: patch test, convergence rates on a manufactured solution,
//! the paper's uncracked plate, solver cross-checks and singular systems.

use crate::common;

use common::{grips, solve_fem_plate};
use rustfrac_core::fe::loading::sigma22;
use rustfrac_core::fe::mesh::Mesh;
use rustfrac_core::fe::{Dirichlet, FemModel, LinearSystem};
use rustfrac_core::la::CscMatrix;
use rustfrac_core::la::{Cholesky, Lu};
use rustfrac_core::problem::Grip;
use rustfrac_core::problem::Side;
use rustfrac_core::problem::{Elastic, Plane};
use rustfrac_core::Error;

#[test]
fn patch_test_linear_field_is_exact() {
    // non-uniform spacing
    let xs = vec![0.0, 0.3, 0.45, 1.1, 1.5, 2.0];
    let ys = vec![0.0, 0.2, 0.7, 0.75, 1.3];
    let mesh = Mesh::from_lines(xs, ys).unwrap();
    let mat = Elastic::new(1000.0, 0.3, Plane::Strain, 1.0).unwrap();
    let model = FemModel::new(mesh, mat, 2).unwrap();
    let exact = |x: f64, y: f64| [1e-3 + 2e-3 * x - 1e-3 * y, -2e-3 + 0.5e-3 * x + 3e-3 * y];
    let mut bc = Dirichlet::default();
    let m = &model.mesh;
    let mut boundary = Vec::new();
    for s in [Side::Left, Side::Right, Side::Top, Side::Bottom] {
        boundary.extend(m.side_nodes(s));
    }
    boundary.sort();
    boundary.dedup();
    for &n in &boundary {
        let [x, y] = m.coords[n];
        let u = exact(x, y);
        bc.dofs.push((2 * n, u[0]));
        bc.dofs.push((2 * n + 1, u[1]));
    }
    let sys = LinearSystem::new(model.stiffness(), &bc).unwrap();
    let sol = sys.solve(&vec![0.0; model.n_dofs()], 1.0).unwrap();
    let mut interior = 0;
    for n in 0..m.n_nodes() {
        if boundary.contains(&n) {
            continue;
        }
        interior += 1;
        let [x, y] = m.coords[n];
        let u = exact(x, y);
        for (c, uc) in u.iter().enumerate() {
            let err = (sol.u[2 * n + c] - uc).abs() / uc.abs().max(1e-3);
            assert!(err < 1e-10, "node {n} comp {c}: rel error {err:e}");
        }
    }
    assert!(interior >= 12);
    let d = mat.d_matrix();
    let eps = [2e-3, 3e-3, -1e-3 + 0.5e-3];
    let s_exact: Vec<f64> = (0..3)
        .map(|i| d[i][0] * eps[0] + d[i][1] * eps[1] + d[i][2] * eps[2])
        .collect();
    let (_, sig) = model.gauss_stresses(&sol.u);
    for s in sig {
        for i in 0..3 {
            assert!(
                (s[i] - s_exact[i]).abs() < 1e-10 * s_exact[1].abs(),
                "{s:?} vs {s_exact:?}"
            );
        }
    }
}

/// Least-squares slope of log(err) against log(h).
fn fitted_rate(h: &[f64], e: &[f64]) -> f64 {
    let n = h.len() as f64;
    let lx: Vec<f64> = h.iter().map(|v| v.ln()).collect();
    let ly: Vec<f64> = e.iter().map(|v| v.ln()).collect();
    let mx = lx.iter().sum::<f64>() / n;
    let my = ly.iter().sum::<f64>() / n;
    let num: f64 = lx.iter().zip(&ly).map(|(x, y)| (x - mx) * (y - my)).sum();
    let den: f64 = lx.iter().map(|x| (x - mx).powi(2)).sum();
    num / den
}

#[test]
fn manufactured_solution_converges_at_rates_2_and_1() {
    use std::f64::consts::PI;
    let mat = Elastic::new(100.0, 0.3, Plane::Strain, 1.0).unwrap();
    let d = mat.d_matrix();
    let (lam, mu) = (d[0][1], d[2][2]);
    let exact = |x: f64, y: f64| {
        let s = (PI * x).sin() * (PI * y).sin();
        let gx = PI * (PI * x).cos() * (PI * y).sin();
        let gy = PI * (PI * x).sin() * (PI * y).cos();
        ([s, s], [[gx, gy], [gx, gy]])
    };
    let body = |x: f64, y: f64| {
        let s = (PI * x).sin() * (PI * y).sin();
        let c = (PI * x).cos() * (PI * y).cos();
        let b = PI * PI * ((lam + 3.0 * mu) * s - (lam + mu) * c);
        [b, b]
    };
    let (mut hs, mut l2s, mut ens) = (vec![], vec![], vec![]);
    for n in [4, 8, 16, 32, 64] {
        let mesh = Mesh::uniform(0.0, 0.0, 1.0, 1.0, n, n).unwrap();
        let model = FemModel::new(mesh, mat, 2).unwrap();
        let mut bc = Dirichlet::default();
        for s in [Side::Left, Side::Right, Side::Top, Side::Bottom] {
            let nodes = model.mesh.side_nodes(s);
            bc.fix(&nodes, 0, 0.0);
            bc.fix(&nodes, 1, 0.0);
        }
        let f = model.body_forces(body);
        let sol = LinearSystem::new(model.stiffness(), &bc)
            .unwrap()
            .solve(&f, 1.0)
            .unwrap();
        let (l2, en) = model.error_norms(&sol.u, exact);
        hs.push(1.0 / n as f64);
        l2s.push(l2);
        ens.push(en);
    }
    let (r2, r1) = (fitted_rate(&hs, &l2s), fitted_rate(&hs, &ens));
    println!("L2 errors {l2s:?} rate {r2:.3}; energy errors {ens:?} rate {r1:.3}");
    assert!((r2 - 2.0).abs() < 0.15, "L2 rate {r2}");
    assert!((r1 - 1.0).abs() < 0.15, "energy rate {r1}");
}

fn paper_plate(grip: Grip) -> (f64, Vec<f64>) {
    let mesh = Mesh::uniform(0.0, 0.0, 11.0, 21.0, 22, 42).unwrap();
    let mat = Elastic::new(10000.0, 0.25, Plane::Strain, 1.0).unwrap();
    let model = FemModel::new(mesh, mat, 2).unwrap();
    let (edges, f, sol) = solve_fem_plate(&model, &grips(grip, 0.01));
    (sigma22(&edges, &sol.reactions, &f, 11.0, 1.0), sol.u)
}

#[test]
fn paper_uncracked_plate_sigma22() {
    let (e, nu, u0, l) = (10000.0, 0.25, 0.01, 21.0);
    let exact = e / (1.0 - nu * nu) * 2.0 * u0 / l;
    let (free, _) = paper_plate(Grip::Free);
    assert!(
        (free - exact).abs() < 1e-10 * exact,
        "free grips: {free} vs {exact}"
    );
    let (clamped, _) = paper_plate(Grip::Clamped);
    // clamped grips restrain the lateral contraction near the edges: stiffer, but below the
    // fully restrained uniaxial-strain bound (lambda + 2 mu) eps
    let bound = e * (1.0 - nu) / ((1.0 + nu) * (1.0 - 2.0 * nu)) * 2.0 * u0 / l;
    let excess = clamped / free - 1.0;
    println!(
        "sigma22 free {free:.6}, clamped {clamped:.6} (+{:.3} %), bound {bound:.6}",
        100.0 * excess
    );
    assert!(
        clamped > free * (1.0 + 1e-4) && clamped < bound,
        "clamped {clamped}"
    );
}

#[test]
fn cholesky_and_lu_agree() {
    let mesh = Mesh::uniform(0.0, 0.0, 2.0, 1.0, 12, 7).unwrap();
    let mat = Elastic::new(1.0, 0.2, Plane::Stress, 0.5).unwrap();
    let model = FemModel::new(mesh, mat, 2).unwrap();
    let mut bc = Dirichlet::default();
    let left = model.mesh.side_nodes(Side::Left);
    bc.fix(&left, 0, 0.0);
    bc.fix(&left, 1, 0.0);
    let mut f = vec![0.0; model.n_dofs()];
    model.traction_forces(Side::Right, [0.3, -0.1], &mut f);
    let sys = LinearSystem::new(model.stiffness(), &bc).unwrap();
    let kff = sys.reduction.reduce(&sys.k);
    let rhs = sys.reduction.rhs(&sys.k, &f, &sys.prescribed);
    // two right-hand sides at once
    let mut b2 = rhs.clone();
    b2.extend(rhs.iter().map(|v| 2.0 * v));
    let mut x1 = b2.clone();
    Cholesky::new(&kff)
        .unwrap()
        .solve_in_place(&mut x1)
        .unwrap();
    let mut x2 = b2.clone();
    Lu::new(&kff).unwrap().solve_in_place(&mut x2).unwrap();
    let scale = x1.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    for (a, b) in x1.iter().zip(&x2) {
        assert!((a - b).abs() < 1e-10 * scale);
    }
    let n = rhs.len();
    for i in 0..n {
        assert!((x1[n + i] - 2.0 * x1[i]).abs() < 1e-10 * scale);
    }
}

#[test]
fn missing_constraints_are_reported_as_singular() {
    let mesh = Mesh::uniform(0.0, 0.0, 11.0, 21.0, 11, 21).unwrap();
    let mat = Elastic::new(10000.0, 0.25, Plane::Strain, 1.0).unwrap();
    let model = FemModel::new(mesh, mat, 2).unwrap();
    // u2 prescribed on top and bottom, u1 nowhere: rigid translation in x is free
    let mut bc = Dirichlet::default();
    bc.fix(&model.mesh.side_nodes(Side::Top), 1, 0.01);
    bc.fix(&model.mesh.side_nodes(Side::Bottom), 1, -0.01);
    match LinearSystem::new(model.stiffness(), &bc) {
        Err(Error::Singular { detail }) => println!("reported: {detail}"),
        Err(e) => panic!("wrong error {e}"),
        Ok(_) => panic!("a singular system was factorised"),
    }
    // nothing constrained at all
    assert!(matches!(
        LinearSystem::new(model.stiffness(), &Dirichlet::default()),
        Err(Error::Singular { .. })
    ));
}

#[test]
fn zero_pivot_is_reported_in_a_large_supernodal_factor() {
    // 2D Laplacian on a 150 x 150 grid (22 500 unknowns, nested dissection: supernodal factor)
    // with one unknown decoupled and its diagonal zero: exactly one zero pivot
    let (m, hole) = (150usize, 150 * 75 + 75);
    let mut trip = Vec::new();
    for j in 0..m {
        for i in 0..m {
            let v = j * m + i;
            if v == hole {
                trip.push((v, v, 0.0));
                continue;
            }
            trip.push((v, v, 4.0));
            for (di, dj) in [(1i64, 0i64), (-1, 0), (0, 1), (0, -1)] {
                let (a, b) = (i as i64 + di, j as i64 + dj);
                if (0..m as i64).contains(&a) && (0..m as i64).contains(&b) {
                    let w = b as usize * m + a as usize;
                    if w != hole {
                        trip.push((v, w, -1.0));
                    }
                }
            }
        }
    }
    let a = CscMatrix::from_triplets(m * m, m * m, &trip).unwrap();
    let xy: Vec<[f64; 2]> = (0..m * m)
        .map(|v| [(v % m) as f64, (v / m) as f64])
        .collect();
    match Cholesky::new_with(&a, Some(&xy)) {
        Err(Error::Singular { detail }) => assert!(detail.starts_with("1 pivot"), "{detail}"),
        Err(e) => panic!("wrong error {e}"),
        Ok(_) => panic!("a singular matrix was factorised"),
    }
    // the same matrix with the hole's diagonal restored factorises
    let b =
        CscMatrix::from_triplets(m * m, m * m, &[trip, vec![(hole, hole, 1.0)]].concat()).unwrap();
    let ch = Cholesky::new_with(&b, Some(&xy)).unwrap();
    let x = ch.solve(&vec![1.0; m * m]).unwrap();
    assert!((x[hole] - 1.0).abs() < 1e-12);
}
