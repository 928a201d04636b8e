//! A singular or separated system is reported (Error::Singular), never solved into wrong
//! numbers; a well-posed system whose unknowns differ wildly in scale is not misreported.

use rustfrac_core::fe::loading::{plate_conditions, PlateEdges};
use rustfrac_core::fe::mesh::Mesh;
use rustfrac_core::fe::{Dirichlet, FemModel, LinearSystem};
use rustfrac_core::la::CscMatrix;
use rustfrac_core::la::{check_condition, Cholesky, COND_SINGULAR, PIVOT_TOL};
use rustfrac_core::problem::Side;
use rustfrac_core::problem::{Elastic, Plane};
use rustfrac_core::problem::{Grip, PlateLoad};
use rustfrac_core::Error;

fn steel() -> Elastic {
    Elastic::new(10000.0, 0.25, Plane::Strain, 1.0).unwrap()
}

fn singular_detail<T>(r: Result<T, Error>) -> String {
    match r {
        Err(Error::Singular { detail }) => detail,
        Err(e) => panic!("wrong error {e}"),
        Ok(_) => panic!("a singular system was accepted"),
    }
}

/// The case: a 60 x 110 plate with u2 prescribed on the top and bottom edges and u1
/// nowhere. The x1 translation is free; elimination leaves a round-off pivot that the pivot test
/// alone may miss. The rigid-mode check names the mode before any factorisation, and the
/// condition check reports the factorised system as numerically singular even without it.
#[test]
fn free_x1_translation_of_a_60_x_110_plate_is_named() {
    let mesh = Mesh::uniform(0.0, 0.0, 11.0, 21.0, 60, 110).unwrap();
    let model = FemModel::new(mesh, steel(), 2).unwrap();
    let mut bc = Dirichlet::default();
    bc.fix(&model.mesh.side_nodes(Side::Top), 1, 0.01);
    bc.fix(&model.mesh.side_nodes(Side::Bottom), 1, -0.01);
    let d = singular_detail(bc.check_rigid_modes(&model.mesh.coords));
    assert!(
        d.contains("1 rigid-body mode(s) free: x1 translation ("),
        "{d}"
    );
    // without the rigid-mode check: the pivot test or the condition check catches it
    let r = LinearSystem::new(model.stiffness(), &bc).and_then(|s| {
        let c = s.condition_estimate()?;
        println!(
            "60 x 110, x1 free: factorised; condition {:.3e} (pivot ratio {:.3e})",
            c.value(),
            c.pivot_ratio
        );
        s.checked_condition("solve", true)?;
        s.checked_condition("solve", false)
    });
    let d = singular_detail(r);
    println!("60 x 110, x1 free: {d}");
    // and the whole Dirichlet set is fine once one u1 is prescribed
    bc.fix(&[model.mesh.side_nodes(Side::Bottom)[0]], 0, 0.0);
    bc.check_rigid_modes(&model.mesh.coords).unwrap();
    let s = LinearSystem::new(model.stiffness(), &bc).unwrap();
    assert!(s.checked_condition("solve", true).unwrap().unwrap().value() < 1e9);
}

/// A seam through the whole width separates the plate: the upper half only has u2 prescribed, so
/// its x1 translation is free although the Dirichlet set as a whole removes every rigid mode.
#[test]
fn plate_cut_through_is_reported_singular() {
    for (nx, ny) in [(11, 21), (60, 110)] {
        let mesh = Mesh::uniform(0.0, 0.0, 11.0, 21.0, nx, ny).unwrap();
        let (mesh, _) = mesh.with_seam(ny / 2, 12.0).unwrap();
        let model = FemModel::new(mesh, steel(), 2).unwrap();
        let edges = PlateEdges::of_mesh(&model.mesh);
        let load = PlateLoad {
            grip: Grip::Free,
            u0: 0.01,
            traction: 0.0,
        };
        let (bc, _, _) = plate_conditions(&edges, &load, model.n_dofs(), 1.0).unwrap();
        bc.check_rigid_modes(&model.mesh.coords).unwrap();
        for estimate in [true, false] {
            let r = LinearSystem::new(model.stiffness(), &bc)
                .and_then(|s| s.checked_condition("solve", estimate));
            let d = singular_detail(r);
            println!("{nx} x {ny} cut through (estimate {estimate}): {d}");
        }
    }
}

/// A well-posed FEM system with its unknowns rescaled by factors spanning 1e12 (D K D, D =
/// diag(10^(-6..6))): the pivot test is per unknown, so it factorises, and x = D^-1 x_K to
/// round-off; the equilibrated condition estimate is unchanged (it is Jacobi invariant).
#[test]
fn unknowns_differing_by_1e12_in_scale_solve_correctly() {
    let mesh = Mesh::uniform(0.0, 0.0, 11.0, 21.0, 20, 40).unwrap();
    let model = FemModel::new(mesh, steel(), 2).unwrap();
    let mut bc = Dirichlet::default();
    bc.fix(&model.mesh.side_nodes(Side::Bottom), 0, 0.0);
    bc.fix(&model.mesh.side_nodes(Side::Bottom), 1, 0.0);
    let sys = LinearSystem::new(model.stiffness(), &bc).unwrap();
    let kff = sys.reduction.reduce(&sys.k);
    let n = kff.nrows;
    // factors 10^e, e spread over [-6, 6] in a scrambled order
    let d: Vec<f64> = (0..n)
        .map(|i| 10f64.powf(-6.0 + 12.0 * ((i * 7919) % n) as f64 / (n - 1) as f64))
        .collect();
    let mut scaled = kff.clone();
    for c in 0..n {
        for k in scaled.col_ptr[c]..scaled.col_ptr[c + 1] {
            scaled.val[k] *= d[scaled.row_idx[k]] * d[c];
        }
    }
    let b: Vec<f64> = (0..n).map(|i| ((i * 13) % 7) as f64 - 3.0).collect();
    let ch = Cholesky::new(&kff).unwrap();
    let x = ch.solve(&b).unwrap();
    let cs = Cholesky::new(&scaled).unwrap();
    let bs: Vec<f64> = b.iter().zip(&d).map(|(v, s)| v * s).collect();
    let xs = cs.solve(&bs).unwrap();
    let xmax = x.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    for i in 0..n {
        assert!(
            (xs[i] * d[i] - x[i]).abs() < 1e-10 * xmax,
            "{i}: {} vs {}",
            xs[i] * d[i],
            x[i]
        );
    }
    let (c0, c1) = (
        ch.condition_estimate(&kff).unwrap(),
        cs.condition_estimate(&scaled).unwrap(),
    );
    println!(
        "scale spread 1e12: condition {:.4e} (unscaled {:.4e})",
        c1.value(),
        c0.value()
    );
    assert!((c1.value() / c0.value() - 1.0).abs() < 1e-6);
    check_condition("scaled", c1.value()).unwrap();
}

/// The pivot test is relative to each unknown's own diagonal: a diagonal matrix with entries
/// spanning 1e-200..1e200 factorises; one whose Schur complement loses all but 1e-14 of an
/// entry is singular whatever the other entries' size.
#[test]
fn pivot_test_is_per_unknown() {
    let n = 9;
    let trip: Vec<(usize, usize, f64)> = (0..n)
        .map(|i| (i, i, 10f64.powi(-200 + 50 * i as i32)))
        .collect();
    let a = CscMatrix::from_triplets(n, n, &trip).unwrap();
    let x = Cholesky::new(&a).unwrap().solve(&vec![1.0; n]).unwrap();
    for (i, v) in x.iter().enumerate() {
        assert!((v * trip[i].2 - 1.0).abs() < 1e-14);
    }
    // [[s, s], [s, s (1 + eps)]] x scale: pivot 2 of s eps; tiny next to a huge third unknown
    for (eps, singular) in [(1e-14, true), (1e-11, false)] {
        let s = 1e-150;
        let a = CscMatrix::from_triplets(
            3,
            3,
            &[
                (0, 0, s),
                (0, 1, s),
                (1, 0, s),
                (1, 1, s * (1.0 + eps)),
                (2, 2, 1e150),
            ],
        )
        .unwrap();
        let r = Cholesky::new(&a);
        assert_eq!(
            matches!(r, Err(Error::Singular { .. })),
            singular,
            "eps {eps} vs PIVOT_TOL {PIVOT_TOL}"
        );
    }
}

#[test]
fn condition_above_cond_singular_is_an_error() {
    assert!(check_condition("solve", 0.5 * COND_SINGULAR).is_ok());
    let d = singular_detail(check_condition("growth step 2", 3e15));
    assert!(
        d.starts_with("growth step 2: numerically singular (condition estimate 3.00e15"),
        "{d}"
    );
}

/// A numerically singular system the pivot test cannot see: a free-free chain of n = 1000 unit
/// springs grounded by eps = 1e-15 at every node. Its near-null vector (the rigid translation) is
/// spread over all unknowns, so the last pivot is ~n eps = 1e-12 of its diagonal, above
/// PIVOT_TOL, while cond = 4 / eps = 4e15. The condition estimate reports it "numerically
/// singular"; the free pivot-ratio bound (condition = false) does not (1e12 < COND_SINGULAR).
#[test]
fn spread_near_null_mode_is_caught_by_the_condition_estimate() {
    let (n, eps) = (1000usize, 1e-15);
    let mut trip = Vec::new();
    for i in 0..n {
        let springs = usize::from(i > 0) + usize::from(i + 1 < n);
        trip.push((i, i, springs as f64 + eps));
        if i + 1 < n {
            trip.push((i, i + 1, -1.0));
            trip.push((i + 1, i, -1.0));
        }
    }
    let k = CscMatrix::from_triplets(n, n, &trip).unwrap();
    let sys = LinearSystem::new(k, &Dirichlet::default()).unwrap();
    let c = sys.condition_estimate().unwrap();
    println!(
        "grounded chain: condition {:.3e}, pivot ratio {:.3e}",
        c.value(),
        c.pivot_ratio
    );
    assert!(c.value() > COND_SINGULAR && c.pivot_ratio < COND_SINGULAR);
    let d = singular_detail(sys.checked_condition("solve", true));
    assert!(d.starts_with("solve: numerically singular"), "{d}");
    assert!(sys.checked_condition("solve", false).unwrap().is_none());
}
