//! Holes that must not hold the body (the fictitious domain, `fe/fictitious.rs`): on a 20 x 10
//! plate with two holes of radius 2 and a self-equilibrated load (normal traction 1 on the top
//! and bottom edges, point supports that only remove the rigid-body modes), the reactions are
//! those of statics, which rustfrac did not compute: zero at every node inside a hole, and a zero
//! resultant and moment at the real supports, at every refinement. With two edge cracks the
//! problem is symmetric under a half turn about the plate's centre, so XFEM's two tips must
//! agree, and K must converge on refinement.

use crate::common;

use common::scene_values::{f, pair, s, scene, tbl};
use rustfrac_core::fem_driver;
use rustfrac_core::problem::value::{Table, Value};
use rustfrac_core::problem::Problem;
use rustfrac_core::xfem;

/// The plate: holes of radius 2 at (3, 7) and (17, 3) (a half turn about (10, 5) swaps them),
/// unit normal traction on the top and bottom edges, supports at (10, 0) (both components) and
/// (10, 10) (u1); with `cracks`, edge cracks of length 1 from the left edge at x2 = 2.85 and
/// from the right edge at x2 = 7.15 (the half turn swaps them too).
fn two_hole_plate(method: &str, nx: i64, ny: i64, cracks: bool) -> Table {
    let hole = |x: f64, y: f64| tbl(&[("center", pair(x, y)), ("radius", f(2.0))]);
    let point = |x: f64, y: f64, fix: &str| {
        tbl(&[
            ("region", s("point")),
            ("point", pair(x, y)),
            ("fix", s(fix)),
        ])
    };
    let edge_load =
        |side: &str| tbl(&[("region", s("edge")), ("side", s(side)), ("normal", f(1.0))]);
    let crack = |side: &str, y: f64| {
        tbl(&[
            ("kind", s("edge")),
            ("side", s(side)),
            ("a0", f(1.0)),
            ("y", f(y)),
        ])
    };
    let crack_list = if cracks {
        vec![crack("left", 2.85), crack("right", 7.15)]
    } else {
        vec![tbl(&[("kind", s("none"))])]
    };
    scene(&[
        ("method", s(method)),
        ("plate", tbl(&[("width", f(20.0)), ("height", f(10.0))])),
        ("material", tbl(&[("E", f(1.0)), ("nu", f(0.3))])),
        (
            "mesh",
            tbl(&[("nx", Value::Int(nx)), ("ny", Value::Int(ny))]),
        ),
        ("hole", Value::List(vec![hole(3.0, 7.0), hole(17.0, 3.0)])),
        (
            "support",
            Value::List(vec![point(10.0, 0.0, "both"), point(10.0, 10.0, "u1")]),
        ),
        (
            "load",
            Value::List(vec![edge_load("top"), edge_load("bottom")]),
        ),
        ("crack", Value::List(crack_list)),
    ])
}

/// (sum of |reaction| over the nodes inside a hole, how many of them carry one above
/// `1e-12`, resultant [R1, R2, M] of the reactions at all the other nodes about (10, 5)),
/// all relative to the load on one edge (20).
fn fem_reactions(nx: i64, ny: i64) -> (f64, usize, [f64; 3]) {
    let p = Problem::from_scene(&two_hole_plate("fem", nx, ny, false)).unwrap();
    let r = fem_driver::run(&p).unwrap();
    let load = 20.0;
    let (mut in_holes, mut count, mut res) = (0.0, 0, [0.0; 3]);
    for (n, xy) in r.coords.iter().enumerate() {
        let rn = [r.reactions[2 * n], r.reactions[2 * n + 1]];
        if p.domain.level_set(*xy) < 0.0 {
            let a = rn[0].hypot(rn[1]) / load;
            in_holes += a;
            count += usize::from(a > 1e-12);
        } else {
            res[0] += rn[0] / load;
            res[1] += rn[1] / load;
            res[2] += ((xy[0] - 10.0) * rn[1] - (xy[1] - 5.0) * rn[0]) / (load * 20.0);
        }
    }
    (in_holes, count, res)
}

fn hole_nodes_carry_nothing(grids: &[(i64, i64)]) {
    for &(nx, ny) in grids {
        let (in_holes, count, res) = fem_reactions(nx, ny);
        eprintln!(
            "{nx} x {ny}: sum |R| in the holes {in_holes:.3e} ({count} nodes above 1e-12), \
             supports' resultant {:.3e} {:.3e}, moment {:.3e} (relative to the edge load)",
            res[0], res[1], res[2]
        );
        assert!(
            in_holes < 1e-10,
            "{nx} x {ny}: {in_holes:e} on {count} nodes"
        );
        for c in res {
            assert!(c.abs() < 1e-10, "{nx} x {ny}: the supports carry {res:?}");
        }
    }
}

#[test]
fn hole_nodes_carry_no_reaction() {
    hole_nodes_carry_nothing(&[(160, 80), (320, 160)]);
}

#[test]
#[ignore = "slow: 640 x 320 and 1 280 x 640"]
fn hole_nodes_carry_no_reaction_fine() {
    hole_nodes_carry_nothing(&[(640, 320), (1280, 640)]);
}

/// XFEM's (K_I, K_II) of the two tips (left crack, right crack) on `nx` x `ny`.
fn two_crack_sifs(nx: i64, ny: i64) -> [[f64; 2]; 2] {
    let p = Problem::from_scene(&two_hole_plate("xfem", nx, ny, true)).unwrap();
    let r = xfem::run(&p, &common::quiet).unwrap();
    assert_eq!(r.tips.len(), 2);
    let mut tips: Vec<_> = r.tips.iter().collect();
    tips.sort_by(|a, b| a.0[0].total_cmp(&b.0[0]));
    [
        [tips[0].1.k_i, tips[0].1.k_ii],
        [tips[1].1.k_i, tips[1].1.k_ii],
    ]
}

/// The two tips agree (half-turn symmetry) on every grid, and K of the finest grids converges:
/// the change from one grid to the next shrinks for the components `monotone` (0 K_I, 1 K_II);
/// every component's last change stays below `last_rel` of its value.
fn two_crack_plate_converges(
    grids: &[(i64, i64)],
    sym_tol: f64,
    monotone: &[usize],
    last_rel: f64,
) {
    let mut ks = Vec::new();
    for &(nx, ny) in grids {
        let k = two_crack_sifs(nx, ny);
        let sym = [
            (k[0][0] / k[1][0] - 1.0).abs(),
            (k[0][1] / k[1][1] - 1.0).abs(),
        ];
        eprintln!(
            "{nx} x {ny}: left tip K_I {:.6e} K_II {:+.6e}, right tip K_I {:.6e} K_II {:+.6e}; \
             tips differ by {:.2e} / {:.2e}",
            k[0][0], k[0][1], k[1][0], k[1][1], sym[0], sym[1]
        );
        assert!(
            sym[0] < sym_tol && sym[1] < sym_tol,
            "{nx} x {ny}: the tips differ by {sym:?}"
        );
        ks.push(k[0]);
    }
    for w in ks.windows(3) {
        for (c, name) in ["K_I", "K_II"].iter().enumerate() {
            let (d1, d2) = ((w[1][c] - w[0][c]).abs(), (w[2][c] - w[1][c]).abs());
            eprint!("{name}: ");
            eprintln!("component {c}: changes {d1:.3e} then {d2:.3e}");
            assert!(
                d2 < d1 || !monotone.contains(&c),
                "component {c}: {d1:e} then {d2:e} (not converging)"
            );
            assert!(
                d2 < last_rel * w[2][c].abs(),
                "component {c}: the last change {d2:e} is not below {last_rel} of {}",
                w[2][c]
            );
        }
    }
}

#[test]
fn xfem_two_cracks_between_holes_agree_and_converge() {
    two_crack_plate_converges(&[(80, 40), (160, 80), (320, 160)], 1e-9, &[0, 1], 0.02);
}

#[test]
#[ignore = "slow: XFEM up to 1 280 x 640"]
fn xfem_two_cracks_between_holes_agree_and_converge_fine() {
    // measured: K_I changes 9.5e-3 then 2.2e-3 (of 3.80); K_II 2.0e-4 then 1.0e-3 (of -0.523):
    // K_II is converged to 0.2 % but not monotone on these grids (the tips still agree to 2e-11,
    // the hidden-support symptom gone), so only K_I is held to a shrinking change
    two_crack_plate_converges(&[(320, 160), (640, 320), (1280, 640)], 1e-9, &[0], 0.005);
}
