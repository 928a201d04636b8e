//! Numerical stability at the extremes: the solver's condition estimate against exact
//! dense condition numbers, XFEM crack geometries at the edge of what a mesh resolves (tips on and
//! near nodes and element edges, cracks along mesh lines, sliver cuts, tips next to the boundary,
//! a/W from 0.01 to 0.95) and extreme meshes (one element across the ligament, stretched
//! elements, 1e6 unknowns). Every case either gives a finite, validated number (error against an
//! independent reference printed and asserted) or a clear error.

use crate::common;

use common::{quiet, tada_f, tall_strip};
use nalgebra::DMatrix;
use rustfrac_core::fe::mesh::Mesh;
use rustfrac_core::fe::{Dirichlet, FemModel, LinearSystem};
use rustfrac_core::la::CscMatrix;
use rustfrac_core::la::{Cholesky, ConditionEstimate};
use rustfrac_core::problem::Side;
use rustfrac_core::problem::{Elastic, Plane};
use rustfrac_core::xfem::williams_displacement;
use rustfrac_core::xfem::{branch_functions, XfemModel, XfemOptions};
use std::sync::Arc;

// ------------------------------------------------------------------------------------------------
// condition estimate vs dense exact condition numbers

/// Exact cond_1 and cond_2 of the Jacobi-scaled matrix D^-1/2 A D^-1/2 (dense, nalgebra).
fn exact_scaled_conds(a: &CscMatrix) -> (f64, f64) {
    let n = a.nrows;
    let d = a.to_dense();
    let s: Vec<f64> = (0..n).map(|i| 1.0 / d[i][i].sqrt()).collect();
    let m = DMatrix::from_fn(n, n, |i, j| d[i][j] * s[i] * s[j]);
    let sv = m.clone().singular_values();
    let cond2 = sv.max() / sv.min();
    let inv = m.clone().try_inverse().expect("invertible");
    let norm1 = |x: &DMatrix<f64>| {
        (0..n)
            .map(|j| x.column(j).iter().map(|v| v.abs()).sum::<f64>())
            .fold(0.0, f64::max)
    };
    (norm1(&m) * norm1(&inv), cond2)
}

fn check_estimate(name: &str, a: &CscMatrix) -> ConditionEstimate {
    let c = Cholesky::new(a).unwrap();
    let est = c.condition_estimate(a).unwrap();
    // the full Hager-Higham iteration (LAPACK's 5 steps) may only raise the (lower-bound) estimate
    let full = c.condition_estimate_with(a, 5).unwrap();
    assert!(full.cond1 >= est.cond1 * (1.0 - 1e-12));
    let (c1, c2) = exact_scaled_conds(a);
    println!(
        "{name}: n {} cond1 exact {c1:.4e} est {:.4e} (ratio {:.3}), cond2 exact {c2:.4e}, pivot ratio {:.4e} ({} solves)",
        a.nrows,
        est.cond1,
        est.cond1 / c1,
        est.pivot_ratio,
        est.solves
    );
    println!(
        "  5 Hager steps: {:.4e} (ratio {:.3}, {} solves)",
        full.cond1,
        full.cond1 / c1,
        full.solves
    );
    // Hager-Higham is a lower bound of cond_1, within a factor 3 in practice
    assert!(
        full.cond1 <= c1 * (1.0 + 1e-8),
        "{name}: {} > {c1}",
        full.cond1
    );
    assert!(est.cond1 >= c1 / 3.0, "{name}: {} << {c1}", est.cond1);
    // the pivot ratio is a guaranteed lower bound of cond_2 (and cond_2 <= cond_1)
    assert!(
        est.pivot_ratio <= c2 * (1.0 + 1e-8),
        "{name}: pivot ratio {} > cond2 {c2}",
        est.pivot_ratio
    );
    assert!(est.pivot_ratio >= 1.0 && c2 <= c1 * (1.0 + 1e-8));
    assert!(
        est.value() >= c2 / 3.0,
        "{name}: {} vs cond2 {c2}",
        est.value()
    );
    est
}

fn from_dense(d: &[Vec<f64>]) -> CscMatrix {
    let n = d.len();
    let mut t = Vec::new();
    for (i, row) in d.iter().enumerate() {
        for (j, &v) in row.iter().enumerate() {
            if v != 0.0 {
                t.push((i, j, v));
            }
        }
    }
    CscMatrix::from_triplets(n, n, &t).unwrap()
}

/// A deterministic pseudo-random stream (no rand dependency).
struct Lcg(u64);
impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

fn clamped_plate(nx: usize, ny: usize, e: f64, scale: f64) -> CscMatrix {
    let mesh = Mesh::uniform(0.0, 0.0, scale * 2.0, scale * 1.0, nx, ny).unwrap();
    let mat = Elastic::new(e, 0.3, Plane::Strain, 1.0).unwrap();
    let model = FemModel::new(mesh, mat, 2).unwrap();
    let mut bc = Dirichlet::default();
    let left = model.mesh.side_nodes(Side::Left);
    bc.fix(&left, 0, 0.0);
    bc.fix(&left, 1, 0.0);
    LinearSystem::new(model.stiffness(), &bc)
        .unwrap()
        .reduction
        .reduce(&model.stiffness())
}

#[test]
fn condition_estimate_matches_dense_exact_values() {
    // 1D Laplacian: cond_2 = cot^2(pi / (2 (n + 1)))
    let n: usize = 60;
    let lap: Vec<Vec<f64>> = (0..n)
        .map(|i| {
            (0..n)
                .map(|j| match i.abs_diff(j) {
                    0 => 2.0,
                    1 => -1.0,
                    _ => 0.0,
                })
                .collect()
        })
        .collect();
    let est = check_estimate("1D Laplacian n = 60", &from_dense(&lap));
    // badly scaled copy: D A D with D = 10^U(-3, 3): the equilibrated estimate must not move
    // (not wider: the Cholesky zero-pivot test is relative to the largest diagonal entry)
    let mut rng = Lcg(7);
    let dsc: Vec<f64> = (0..n).map(|_| 10f64.powf(6.0 * rng.next() - 3.0)).collect();
    let scaled: Vec<Vec<f64>> = (0..n)
        .map(|i| (0..n).map(|j| lap[i][j] * dsc[i] * dsc[j]).collect())
        .collect();
    let est_s = check_estimate(
        "1D Laplacian, rows/cols scaled 1e-3..1e3",
        &from_dense(&scaled),
    );
    assert!(
        (est_s.cond1 / est.cond1 - 1.0).abs() < 1e-6,
        "{est_s:?} vs {est:?}"
    );
    // random SPD with eigenvalues spread over 1e9: Q diag Q^T
    let m = 40;
    let mut g = DMatrix::from_fn(m, m, |_, _| rng.next() - 0.5);
    g = g.qr().q();
    let lam = DMatrix::from_diagonal(&nalgebra::DVector::from_fn(m, |i, _| {
        10f64.powf(9.0 * i as f64 / (m - 1) as f64)
    }));
    let a = &g * lam * g.transpose();
    let dense: Vec<Vec<f64>> = (0..m)
        .map(|i| (0..m).map(|j| a[(i, j)]).collect())
        .collect();
    check_estimate("random SPD, spectrum 1..1e9", &from_dense(&dense));
    // plate stiffness: invariant to E and to the plate size (dimensionless)
    let k = clamped_plate(8, 5, 1.0, 1.0);
    let e1 = check_estimate("clamped FEM plate 8 x 5", &k);
    let e2 = check_estimate("same, E = 2e5, plate x 1e3", &clamped_plate(8, 5, 2e5, 1e3));
    assert!((e1.cond1 / e2.cond1 - 1.0).abs() < 1e-6);
    // an XFEM matrix with a sliver (area fraction 1e-5, small-area rule off): ill-conditioned
    let mesh = Arc::new(Mesh::uniform(0.0, 0.0, 1.0, 1.0, 6, 6).unwrap());
    let mat = Elastic::new(1.0, 0.3, Plane::Strain, 1.0).unwrap();
    let y = 0.5 + 1e-5 / 6.0; // just above the grid line y = 0.5
    let opts = XfemOptions {
        area_threshold: 0.0,
        ..XfemOptions::default()
    };
    let model = XfemModel::new(mesh.clone(), mat, vec![[0.0, y], [0.58, y]], opts).unwrap();
    let mut bc = Dirichlet::default();
    let bottom = mesh.side_nodes(Side::Bottom);
    bc.fix(&bottom, 0, 0.0);
    bc.fix(&bottom, 1, 0.0);
    let kx = model.stiffness().unwrap();
    let kff = LinearSystem::new(kx.clone(), &bc)
        .unwrap()
        .reduction
        .reduce(&kx);
    // equilibration removes the sliver function's small diagonal: the scaled condition stays at
    // the level of the plain plate (1.0e4 vs 6.1e3 measured)
    let ex = check_estimate("XFEM 6 x 6, sliver 1e-5, no area rule", &kff);
    assert!(ex.cond1 < 1e2 * e1.cond1, "{ex:?}");
}

// ------------------------------------------------------------------------------------------------
// XFEM crack geometry extremes

use common::{run, XfemCase};
use rustfrac_core::fe::loading::{plate_conditions, PlateEdges};
use rustfrac_core::problem::{Grip, PlateLoad};
use rustfrac_core::xfem::XfemResult;
use rustfrac_core::Error;

/// Relative error of K_I against Tada for a straight edge crack of length a (W = 1, sigma = 1).
fn tada_err(r: &XfemResult, a: f64) -> f64 {
    let k = tada_f(a) * (std::f64::consts::PI * a).sqrt();
    r.k_i / k - 1.0
}

fn assert_sane(name: &str, r: &XfemResult) {
    assert!(
        r.k_i.is_finite() && r.k_ii.is_finite() && r.cmod.is_finite() && r.sigma22.is_finite(),
        "{name}: non-finite result"
    );
    let c = r.condition.unwrap();
    assert!(
        c.cond1.is_finite() && c.value() < 1e12 && r.warnings.is_empty(),
        "{name}: condition {c:?}, warnings {:?}",
        r.warnings
    );
}

// 40 x 160 elements of h = 0.025: the grid line y = 2 is j = 80, x = 0.3 is i = 12
const NX: usize = 40;
const NY: usize = 160;
const H: f64 = 0.025;

#[test]
fn tip_on_node_edge_and_within_1e_9_of_them() {
    let a = 0.3;
    let ymid = 2.0 + 0.5 * H; // mid-element row: tip x = a lies on a vertical element edge
    let base = run(&tall_strip(vec![[0.0, ymid], [a, ymid]], NX, NY), &quiet).unwrap();
    assert_sane("tip on an edge", &base);
    println!(
        "tip on a vertical edge: K_I {:.5} (Tada {:+.3} %), cond {:.2e}",
        base.k_i,
        100.0 * tada_err(&base, a),
        base.condition.unwrap().value()
    );
    assert!(tada_err(&base, a).abs() < 0.015);
    let mut worst: f64 = 0.0;
    // within 1e-9 h and 1e-13 h (below the snap) of the edge, both sides
    for d in [-1e-9, 1e-9, -1e-13, 1e-13, 0.5] {
        let r = run(
            &tall_strip(vec![[0.0, ymid], [a + d * H, ymid]], NX, NY),
            &quiet,
        )
        .unwrap();
        assert_sane("tip near an edge", &r);
        let rel = r.k_i / base.k_i - 1.0;
        println!(
            "  tip at edge {d:+.0e} h: K_I {:.5} ({:+.2e} rel), {} tip nodes, cond {:.2e}",
            r.k_i,
            rel,
            r.n_tip_nodes,
            r.condition.unwrap().value()
        );
        if d.abs() < 1e-6 {
            worst = worst.max(rel.abs());
        }
    }
    // a hair's move of the tip changes K by much less than the discretisation error
    assert!(
        worst < 2e-3,
        "K jumps by {worst:.2e} when the tip crosses an element edge"
    );
    // tip on a node: crack along the grid line y = 2, tip at the node (a, 2), then 1e-9 h off in
    // x and in y, both sides
    let node = run(&tall_strip(vec![[0.0, 2.0], [a, 2.0]], NX, NY), &quiet).unwrap();
    assert_sane("tip on a node", &node);
    println!(
        "tip on a node: K_I {:.5} (Tada {:+.3} %), {} tip nodes, {} Heaviside, {} dropped, cond {:.2e}",
        node.k_i,
        100.0 * tada_err(&node, a),
        node.n_tip_nodes,
        node.n_heaviside_nodes,
        node.n_dropped_nodes,
        node.condition.unwrap().value()
    );
    assert!(tada_err(&node, a).abs() < 0.015);
    let mut worst: f64 = 0.0;
    for (dx, dy) in [
        (1e-9, 0.0),
        (-1e-9, 0.0),
        (0.0, 1e-9),
        (0.0, -1e-9),
        (1e-9, 1e-9),
        (-1e-9, -1e-9),
        (1e-13, -1e-13),
    ] {
        let (x, y) = (a + dx * H, 2.0 + dy * H);
        let r = run(&tall_strip(vec![[0.0, y], [x, y]], NX, NY), &quiet).unwrap();
        assert_sane("tip near a node", &r);
        let rel = r.k_i / node.k_i - 1.0;
        println!(
            "  tip at node + ({dx:+.0e}, {dy:+.0e}) h: K_I {:.5} ({rel:+.2e} rel), {} tip / {} Heaviside / {} dropped nodes, cond {:.2e}",
            r.k_i,
            r.n_tip_nodes,
            r.n_heaviside_nodes,
            r.n_dropped_nodes,
            r.condition.unwrap().value()
        );
        worst = worst.max(rel.abs());
    }
    assert!(
        worst < 2e-3,
        "K jumps by {worst:.2e} when the tip moves off a node"
    );
}

#[test]
fn crack_along_a_mesh_line_has_one_side_for_its_nodes() {
    let a = 0.3125; // tip mid-element (12.5 h)
                    // the line y = 2 and copies shifted by round-off and by 1e-9 h
    let mut ks = Vec::new();
    for dy in [0.0, 1e-16, -1e-16, 1e-13, -1e-13, 1e-9, -1e-9] {
        let y = 2.0 + dy * H;
        let r = run(&tall_strip(vec![[0.0, y], [a, y]], NX, NY), &quiet).unwrap();
        assert_sane("crack along a mesh line", &r);
        println!(
            "crack at y = 2 {dy:+.0e} h: K_I {:.5} (Tada {:+.3} %), {} Heaviside / {} dropped nodes, cond {:.2e}",
            r.k_i,
            100.0 * tada_err(&r, a),
            r.n_heaviside_nodes,
            r.n_dropped_nodes,
            r.condition.unwrap().value()
        );
        assert!(
            tada_err(&r, a).abs() < 0.015,
            "dy {dy}: {}",
            tada_err(&r, a)
        );
        // nodes on the line (within the snap) are on the negative side: the Heaviside nodes are
        // the line's own nodes, the same set for every round-off shift
        if dy.abs() < 1e-12 {
            for &n in &r.heaviside_nodes {
                let yn = 2.0 * (n / (NX + 1)) as f64 / NY as f64 * 2.0;
                assert!(
                    (yn - 2.0).abs() < 1e-12,
                    "dy {dy}: Heaviside node {n} at y {yn}"
                );
            }
        }
        ks.push(r.k_i);
    }
    let spread = ks.iter().cloned().fold(f64::MIN, f64::max)
        / ks.iter().cloned().fold(f64::MAX, f64::min)
        - 1.0;
    println!("spread of K_I over the shifts: {spread:.2e}");
    assert!(spread < 2e-3);
    // an inclined crack through nodes (45 degrees on square elements): rounding of the level
    // set at the nodes it passes through must not matter
    let (c, s) = (
        std::f64::consts::FRAC_1_SQRT_2,
        std::f64::consts::FRAC_1_SQRT_2,
    );
    let l = 0.35;
    let on = run(
        &tall_strip(vec![[0.0, 2.0], [l * c, 2.0 + l * s]], NX, NY),
        &quiet,
    )
    .unwrap();
    assert_sane("45 degree crack through nodes", &on);
    let off = run(
        &tall_strip(
            vec![[0.0, 2.0 + 1e-9 * H], [l * c, 2.0 + l * s + 1e-9 * H]],
            NX,
            NY,
        ),
        &quiet,
    )
    .unwrap();
    let (e1, e2) = (on.k_i / off.k_i - 1.0, on.k_ii / off.k_ii - 1.0);
    println!(
        "45 degree crack through nodes: K_I {:.5} K_II {:.5}; shifted 1e-9 h: {e1:+.2e} {e2:+.2e}",
        on.k_i, on.k_ii
    );
    assert!(e1.abs() < 2e-3 && e2.abs() < 5e-3);
}

#[test]
fn corner_cut_with_area_fraction_1e_6_is_dropped_and_k_unchanged() {
    // a 30-degree edge crack whose line passes a distance d below-right of the node (x_i, 2):
    // it cuts a triangle of area d^2 / (2 sin cos) = 1e-6 h^2 off one element's corner
    let th = 30f64.to_radians();
    let (c, s) = (th.cos(), th.sin());
    let (xi, yj) = (6.0 * H, 2.0);
    let crack_for = |d: f64| {
        let y0 = yj - xi * s / c - d / c;
        let l = 0.35;
        vec![[0.0, y0], [l * c, y0 + l * s]]
    };
    let d_cut = (2e-6 * s * c).sqrt() * H;
    let mut out = Vec::new();
    for (name, d) in [
        ("cut 1e-6", d_cut),
        ("cut 1e-2", (2e-2 * s * c).sqrt() * H),
        ("clear of the node", 0.5 * H),
    ] {
        let r = run(&tall_strip(crack_for(d), NX, NY), &quiet).unwrap();
        assert_sane(name, &r);
        println!(
            "{name}: d = {:.2e} h: K_I {:.5} K_II {:.5}, {} Heaviside / {} dropped nodes, cond {:.2e}",
            d / H,
            r.k_i,
            r.k_ii,
            r.n_heaviside_nodes,
            r.n_dropped_nodes,
            r.condition.unwrap().value()
        );
        out.push(r);
    }
    assert!(
        out[0].n_dropped_nodes > 0,
        "the sliver's node must be dropped"
    );
    // moving the crack by < h/2 normal to itself changes K by O(d / a): compare at 1 %
    for r in &out[1..] {
        let e = out[0].k_i / r.k_i - 1.0;
        assert!(e.abs() < 1e-2, "K_I {} vs {}", out[0].k_i, r.k_i);
    }
    // with the area rule off the sliver node stays: the equilibrated condition stays moderate
    // too (the estimate is scale-free), and K must agree
    let mut p = tall_strip(crack_for(d_cut), NX, NY);
    p.area_threshold = 0.0;
    let r = run(&p, &quiet).unwrap();
    println!(
        "cut 1e-6, area rule off: K_I {:.5}, {} Heaviside / {} dropped nodes, cond {:.2e}",
        r.k_i,
        r.n_heaviside_nodes,
        r.n_dropped_nodes,
        r.condition.unwrap().value()
    );
    assert!(r.k_i.is_finite() && (r.k_i / out[0].k_i - 1.0).abs() < 1e-2);
}

#[test]
fn tip_sweep_across_one_element_is_smooth() {
    // 51 tip positions from one vertical element edge to the next (a = 0.3 .. 0.3 + h)
    let ymid = 2.0 + 0.5 * H;
    let n = 50;
    let mut pts = Vec::new();
    for k in 0..=n {
        let a = 0.3 + H * k as f64 / n as f64;
        let r = run(&tall_strip(vec![[0.0, ymid], [a, ymid]], NX, NY), &quiet)
            .unwrap_or_else(|e| panic!("step {k}: {e}"));
        assert_sane("tip sweep", &r);
        pts.push((a, r.k_i, r.condition.unwrap().value()));
    }
    // least-squares quadratic in s = (a - 0.3) / h
    let mut ata = DMatrix::<f64>::zeros(3, 3);
    let mut atb = nalgebra::DVector::<f64>::zeros(3);
    for &(a, k, _) in &pts {
        let s = (a - 0.3) / H;
        let row = [1.0, s, s * s];
        for i in 0..3 {
            for j in 0..3 {
                ata[(i, j)] += row[i] * row[j];
            }
            atb[i] += row[i] * k;
        }
    }
    let c = ata.lu().solve(&atb).unwrap();
    let mut worst: f64 = 0.0;
    for &(a, k, _) in &pts {
        let s = (a - 0.3) / H;
        let fit = c[0] + c[1] * s + c[2] * s * s;
        worst = worst.max((k / fit - 1.0).abs());
    }
    let cmax = pts.iter().map(|p| p.2).fold(0.0, f64::max);
    let tada_worst = pts
        .iter()
        .map(|&(a, k, _)| (k / (tada_f(a) * (std::f64::consts::PI * a).sqrt()) - 1.0).abs())
        .fold(0.0, f64::max);
    println!(
        "tip sweep over one element (51 positions): K_I {:.5} .. {:.5}, largest deviation from a quadratic fit {:.3} %, largest error vs Tada {:.2} %, largest condition {cmax:.2e}",
        pts[0].1,
        pts[n].1,
        100.0 * worst,
        100.0 * tada_worst
    );
    assert!(
        worst < 0.01,
        "K_I deviates {:.3} % from a smooth fit",
        100.0 * worst
    );
    assert!(tada_worst < 0.015);
}

fn refused_as_unresolved(p: &XfemCase) -> String {
    match run(p, &quiet) {
        Err(e @ Error::InvalidInput { .. }) => {
            let m = e.to_string();
            assert!(
                m.contains("cannot resolve") && m.contains("element lengths"),
                "{m}"
            );
            m
        }
        Err(e) => panic!("wrong error {e}"),
        Ok(r) => panic!("accepted: K_I {}", r.k_i),
    }
}

#[test]
fn a_over_w_from_0_01_to_0_95_against_tada() {
    // 80 x 320 elements (h = 1/80): errors measured against Tada's long-strip formula
    let (nx, ny) = (80, 320);
    let h = 1.0 / nx as f64;
    for aw in [0.01, 0.02] {
        let y = 2.0 + 0.5 * h;
        let m = refused_as_unresolved(&tall_strip(vec![[0.0, y], [aw, y]], nx, ny));
        println!(
            "a/W {aw} on {nx} x {ny} (a = {:.1} elements): refused: {m}",
            aw / h
        );
    }
    let mut rows = Vec::new();
    for aw in [
        0.05, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.85, 0.9, 0.95,
    ] {
        let y = 2.0 + 0.5 * h;
        let r = run(&tall_strip(vec![[0.0, y], [aw, y]], nx, ny), &quiet).unwrap();
        assert_sane("a/W sweep", &r);
        let e = tada_err(&r, aw);
        let lig = (1.0 - aw) / h;
        println!(
            "a/W {aw:.2}: F xfem {:.4} Tada {:.4} error {:+.2} % (ligament {lig:.0} elements), cond {:.2e}",
            r.k_i / (std::f64::consts::PI * aw).sqrt(),
            tada_f(aw),
            100.0 * e,
            r.condition.unwrap().value()
        );
        rows.push((aw, e, lig));
    }
    for &(aw, e, lig) in &rows {
        // up to a/W = 0.7 the mesh error is below 1.5 %; deeper cracks lose ~0.3 h / ligament
        let tol = if aw <= 0.7 { 0.015 } else { 0.4 / lig + 0.01 };
        assert!(
            e.abs() < tol,
            "a/W {aw}: error {:+.2} % > {:.1} %",
            100.0 * e,
            100.0 * tol
        );
    }
    // a/W = 0.01 resolved on a finer mesh: 250 x 250 elements (a = 2.5 elements), plate of
    // height = width (the crack is 100 times smaller than both)
    let (nx, ny) = (250, 250);
    let h = 1.0 / nx as f64;
    let mut p = tall_strip(vec![[0.0, 0.5 + 0.5 * h], [0.01, 0.5 + 0.5 * h]], nx, ny);
    p.height = 1.0;
    // r_I = 2.5 h: the q-domain is clipped by the edge the crack starts from
    let r = run(&p, &quiet).unwrap();
    assert_sane("a/W 0.01", &r);
    let e = tada_err(&r, 0.01);
    println!(
        "a/W 0.01 on {nx} x {ny} (a = 2.5 elements, r_I 2.5, clipped by x = 0): error {:+.2} %",
        100.0 * e
    );
    assert!(e.abs() < 0.03, "a/W 0.01: {:+.2} %", 100.0 * e);
}

#[test]
fn single_element_ligament_is_refused_and_two_run() {
    // 20 elements across: a/W = 0.95 leaves one element, 0.9 two
    let h = 1.0 / 20.0;
    let y = 2.0 + 0.5 * h;
    let m = refused_as_unresolved(&tall_strip(vec![[0.0, y], [0.95, y]], 20, 80));
    println!("one element across the ligament: {m}");
    // tip inside the last element, 0.3 elements from the boundary
    let m = refused_as_unresolved(&tall_strip(vec![[0.0, y], [1.0 - 0.3 * h, y]], 20, 80));
    println!("tip 0.3 elements from the boundary: {m}");
    // two elements: accepted (the default r_I = 2.5 elements is clipped by the edge); K is
    // finite, and low by the measured amount
    let r = run(&tall_strip(vec![[0.0, y], [0.9, y]], 20, 80), &quiet).unwrap();
    assert_sane("two-element ligament", &r);
    let e = tada_err(&r, 0.9);
    println!(
        "two elements across the ligament (a/W 0.9, 20 x 80): error {:+.1} %",
        100.0 * e
    );
    assert!(e < 0.0 && e > -0.3, "{e}");
}

#[test]
fn stretched_elements_aspect_ratio_10_both_ways() {
    let a = 0.3;
    for (nx, ny, name) in [(40, 1600, "dx = 10 dy"), (400, 160, "dy = 10 dx")] {
        let (dx, dy) = (1.0 / nx as f64, 4.0 / ny as f64);
        // crack mid-element in y, tip mid-element in x
        let y = 2.0 + 0.5 * dy;
        let r = run(
            &tall_strip(vec![[0.0, y], [a + 0.5 * dx, y]], nx, ny),
            &quiet,
        )
        .unwrap();
        assert_sane(name, &r);
        let e = tada_err(&r, a + 0.5 * dx);
        println!(
            "{name} ({nx} x {ny}, aspect {:.0}): K_I error vs Tada {:+.2} %, r_I {:.4} (tip element size {:.4}), cond {:.2e}",
            (dx / dy).max(dy / dx),
            100.0 * e,
            r.r_i,
            (dx * dy).sqrt(),
            r.condition.unwrap().value()
        );
        assert!(e.abs() < 0.03, "{name}: {:+.2} %", 100.0 * e);
    }
}

/// About 1e6 unknowns: a/W = 0.95 (ligament 18 elements) on 360 x 1440 elements. Slow
/// (about 30 s on 2 cores): run by CI with `--ignored`.
#[test]
#[ignore]
fn a_million_unknowns_deep_crack() {
    let (nx, ny) = (360, 1440);
    let h = 1.0 / nx as f64;
    let y = 2.0 + 0.5 * h;
    let t0 = std::time::Instant::now();
    let r = run(&tall_strip(vec![[0.0, y], [0.95, y]], nx, ny), &quiet).unwrap();
    let t = t0.elapsed().as_secs_f64();
    assert_sane("1e6 unknowns", &r);
    let e = tada_err(&r, 0.95);
    println!(
        "{} unknowns, a/W 0.95 (ligament {:.0} elements): K_I error vs Tada {:+.2} %, cond {:.2e} ({:.0} solves), {t:.1} s",
        r.n_dofs,
        0.05 / h,
        100.0 * e,
        r.condition.unwrap().value(),
        r.condition.unwrap().solves as f64
    );
    assert!(r.n_dofs > 1_000_000);
    assert!(e.abs() < 0.03, "{:+.2} %", 100.0 * e);
}

/// Cost of the condition estimate against the factorisation it reuses, on the paper's plate at
/// 352 x 665 (the finest sweep level). Slow: `--ignored`.
#[test]
#[ignore]
fn condition_estimate_cost_on_the_352_x_665_plate() {
    use rustfrac_core::fe::loading::{plate_conditions, PlateEdges};
    let p = XfemCase::paper(Grip::Free);
    let mesh = Arc::new(Mesh::uniform(0.0, 0.0, p.width, p.height, 352, 665).unwrap());
    let model = XfemModel::new(
        mesh.clone(),
        p.material,
        p.crack.clone(),
        XfemOptions::default(),
    )
    .unwrap();
    let edges = PlateEdges::of_mesh(&mesh);
    let (bc, f, _) = plate_conditions(&edges, &p.load, model.n_dofs, 1.0).unwrap();
    let k = model.stiffness().unwrap();
    let t0 = std::time::Instant::now();
    let sys = LinearSystem::with_positions(k, &bc, Some(&model.dof_positions())).unwrap();
    let t_factor = t0.elapsed().as_secs_f64();
    let t0 = std::time::Instant::now();
    let sol = sys.solve(&f, 1.0).unwrap();
    let t_solve = t0.elapsed().as_secs_f64();
    let t0 = std::time::Instant::now();
    let c = sys.condition_estimate().unwrap();
    let t_cond = t0.elapsed().as_secs_f64();
    let kff = sys.reduction.reduce(&sys.k);
    let xy = model.dof_positions();
    let free_xy: Vec<[f64; 2]> = sys.reduction.free.iter().map(|&d| xy[d]).collect();
    let full = Cholesky::new_with(&kff, Some(&free_xy))
        .unwrap()
        .condition_estimate_with(&kff, 5)
        .unwrap();
    println!(
        "  5 Hager steps: cond1 {:.4e} ({} solves): default / full = {:.4}",
        full.cond1,
        full.solves,
        c.cond1 / full.cond1
    );
    assert!(c.cond1 > full.cond1 / 3.0);
    println!(
        "352 x 665 ({} unknowns): analyse + factorise {t_factor:.2} s, one solve (+ reactions) {t_solve:.3} s, condition estimate {t_cond:.3} s ({} solves, {:.0} % of the factorisation): cond1 {:.3e}, pivot ratio {:.3e}",
        model.n_dofs,
        c.solves,
        100.0 * t_cond / t_factor,
        c.cond1,
        c.pivot_ratio
    );
    assert!(sol.u.iter().all(|v| v.is_finite()) && c.value() < 1e12);
    assert!(
        t_cond < 0.5 * t_factor,
        "estimate {t_cond} s vs factorisation {t_factor} s"
    );
}

#[test]
fn condition_warning_above_the_threshold_only() {
    use rustfrac_core::la::{condition_warning, COND_WARN};
    let c = |v: f64| ConditionEstimate {
        cond1: v,
        pivot_ratio: 2.0,
        solves: 5,
    };
    assert!(condition_warning("solve", &c(0.5 * COND_WARN)).is_none());
    let w = condition_warning("growth step 3", &c(3e13)).unwrap();
    assert_eq!(w.kind, rustfrac_core::WarningKind::IllConditioned);
    let w = w.message;
    assert!(
        w.starts_with("growth step 3") && w.contains("3.00e13"),
        "{w}"
    );
}

// ------------------------------------------------------------------------------------------------
// q-domains clipped by the plate boundary

/// The dof vector of the exact Williams field (K_I, K_II) = `k` of a horizontal crack from the
/// left edge of the square [-1, 1]^2 (n x n elements, tip `tip`) with fixed-area tip enrichment
/// of radius `r_enr`: standard dofs = the field at the nodes, every branch dof = the field's
/// coefficient of that branch function (fitted; the Williams field lies in their span), so by the
/// partition of unity the enriched field equals the exact one in every element whose nodes are
/// all branch-enriched. Returns the model and the vector.
fn exact_williams(k: (f64, f64), tip: [f64; 2], n: usize, r_enr: f64) -> (XfemModel, Vec<f64>) {
    let mat = Elastic::new(1000.0, 0.3, Plane::Strain, 1.0).unwrap();
    let mesh = Arc::new(Mesh::uniform(-1.0, -1.0, 2.0, 2.0, n, n).unwrap());
    let opts = XfemOptions {
        fixed_area_radius: Some(r_enr),
        ..XfemOptions::default()
    };
    let model = XfemModel::new(mesh.clone(), mat, vec![[-1.0, tip[1]], tip], opts).unwrap();
    let exact = |x: [f64; 2]| williams_displacement(&mat, k.0, k.1, [x[0] - tip[0], x[1] - tip[1]]);
    // least-squares coefficients of the field in the branch functions, from points around the tip
    let mut ata = DMatrix::<f64>::zeros(4, 4);
    let mut atb = DMatrix::<f64>::zeros(4, 2);
    let pts: Vec<[f64; 2]> = (0..40)
        .map(|i| {
            let (r, t) = (0.01 + 0.002 * i as f64, -3.0 + 0.15 * i as f64);
            [tip[0] + r * t.cos(), tip[1] + r * t.sin()]
        })
        .collect();
    for &x in &pts {
        let (f, _) = branch_functions(&model.tips[0], x);
        let u = exact(x);
        for a in 0..4 {
            for b in 0..4 {
                ata[(a, b)] += f[a] * f[b];
            }
            atb[(a, 0)] += f[a] * u[0];
            atb[(a, 1)] += f[a] * u[1];
        }
    }
    let c = ata.lu().solve(&atb).unwrap();
    for &x in &pts {
        let (f, _) = branch_functions(&model.tips[0], x);
        let u = exact(x);
        for i in 0..2 {
            let fit: f64 = (0..4).map(|a| c[(a, i)] * f[a]).sum();
            assert!(
                (fit - u[i]).abs() < 1e-12 * u[i].abs().max(1e-3),
                "not in the span"
            );
        }
    }
    let mut u = vec![0.0; model.n_dofs];
    for (nd, x) in mesh.coords.iter().enumerate() {
        let v = exact(*x);
        u[2 * nd] = v[0];
        u[2 * nd + 1] = v[1];
    }
    for (_, dofs) in model.branch_dofs(0) {
        for (a, d) in dofs.iter().enumerate() {
            u[d[0]] = c[(a, 0)];
            u[d[1]] = c[(a, 1)];
        }
    }
    (model, u)
}

/// A tip within one element of the plate boundary: the q-domain (r_I = 1.5 .. 3.5 element
/// lengths) is clipped by the boundary, and the boundary term of the interaction integral
/// (xfem::DomainIntegral::add_boundary) keeps K exact. The field is the exact Williams field
/// (K = 1) represented exactly by the enrichment, so any error is the integral's own: the clipped
/// domains give K to 2e-5, like the unclipped ones (without the boundary term: 0.28 .. 0.79).
#[test]
fn clipped_q_domain_gives_the_exact_williams_k() {
    let n = 40;
    let h = 2.0 / n as f64;
    let radii = [1.5, 2.5, 3.5];
    for (mode, k) in [("I", (1.0, 0.0)), ("II", (0.0, 1.0))] {
        for (name, tip) in [
            ("far from the boundary", [0.013, -0.021]),
            ("right edge 0.5 h ahead", [1.0 - 0.5 * h, -0.021]),
            ("right edge 0.01 h ahead", [1.0 - 0.01 * h, -0.021]),
            ("top edge 0.6 h beside", [0.013, 1.0 - 0.6 * h]),
            ("corner 0.3 h, 0.4 h", [1.0 - 0.3 * h, 1.0 - 0.4 * h]),
        ] {
            let (model, u) = exact_williams(k, tip, n, 6.0 * h);
            for f in radii {
                let r = model.sifs(&u, 0, f * h).unwrap();
                let (main, other) = if mode == "I" {
                    (r.k_i, r.k_ii)
                } else {
                    (r.k_ii, r.k_i)
                };
                let jr = r.j_domain / r.j_from_k;
                println!("mode {mode}, {name}, r_I {f} h: K {main:.7}, other {other:+.2e}, J_dom/J_K {jr:.6}");
                assert!(
                    (main - 1.0).abs() < 1e-4,
                    "mode {mode} {name} r {f}: {main}"
                );
                assert!(
                    other.abs() < 1e-4,
                    "mode {mode} {name} r {f}: other {other}"
                );
                assert!((jr - 1.0).abs() < 1e-4, "mode {mode} {name} r {f}: J {jr}");
            }
        }
    }
}

/// K_I (interaction integral at `radii` element lengths) and strain energy at unit traction of the
/// tall strip (W = 1, H = 4) with an edge crack of length `a` on `nx` x `ny` elements, through the
/// model API (the plate driver refuses tips this close to the boundary as unresolved).
fn strip_model(a: f64, nx: usize, ny: usize, radii: &[f64], r_enr: Option<f64>) -> (Vec<f64>, f64) {
    let mat = Elastic::new(1000.0, 0.3, Plane::Strain, 1.0).unwrap();
    let mesh = Arc::new(Mesh::uniform(0.0, 0.0, 1.0, 4.0, nx, ny).unwrap());
    let y = 2.0 + 0.5 * 4.0 / ny as f64;
    let opts = XfemOptions {
        fixed_area_radius: r_enr,
        ..XfemOptions::default()
    };
    let model = XfemModel::new(mesh.clone(), mat, vec![[0.0, y], [a, y]], opts).unwrap();
    let load = PlateLoad {
        grip: Grip::Traction,
        u0: 0.0,
        traction: 1.0,
    };
    let edges = PlateEdges::of_mesh(&mesh);
    let (bc, f, _) = plate_conditions(&edges, &load, model.n_dofs, 1.0).unwrap();
    let sys = LinearSystem::new(model.stiffness().unwrap(), &bc).unwrap();
    let sol = sys.solve(&f, 1.0).unwrap();
    let h = model.tip_element_size(0);
    let ks = radii
        .iter()
        .map(|&r| model.sifs(&sol.u, 0, r * h).unwrap().k_i)
        .collect();
    (ks, sol.energy)
}

/// A real crack close to the free edge it grows towards (tall strip on 40 x 160 elements, tip 4,
/// 2 and 0.5 element lengths from the edge): K_I from q-domains clipped by the edge (r_I above the
/// clearance) against unclipped ones (r_I below it, where they exist), and against the discrete
/// energy release rate of the same model (G = dU/da at fixed traction, central difference over
/// +-0.02 h, K = sqrt(G E'): an independent, global measure). Fixed-area enrichment (radius 6 h)
/// keeps blending elements out of every domain. Measured: clipped and unclipped domains agree
/// within 0.7 % and with the energy within 1.7 %; with the tip 0.5 element from the edge the
/// clipped domains agree with each other within 0.3 % and with the energy within 3.8 %, but the
/// mesh does not resolve the ligament (K_I 49 % below Tada), which is why the plate driver
/// refuses such tips (MIN_TIP_CLEARANCE).
#[test]
fn clipped_q_domain_agrees_with_unclipped_ones_and_the_energy_release_rate() {
    let (nx, ny) = (40, 160);
    let h = 1.0 / nx as f64;
    let e_prime = 1000.0 / (1.0 - 0.09);
    let radii = [1.5, 2.5, 3.5, 5.0];
    let r_enr = Some(6.0 * h);
    for clear in [4.0, 2.0, 0.5] {
        let a = 1.0 - clear * h;
        let (ks, _) = strip_model(a, nx, ny, &radii, r_enr);
        let d = 0.02 * h;
        let (_, up) = strip_model(a + d, nx, ny, &[], r_enr);
        let (_, um) = strip_model(a - d, nx, ny, &[], r_enr);
        let k_g = ((up - um) / (2.0 * d) * e_prime).sqrt();
        let k_tada = tada_f(a) * (std::f64::consts::PI * a).sqrt();
        for (r, k) in radii.iter().zip(&ks) {
            println!(
                "tip {clear} h from the edge, r_I {r} h ({}): K_I {k:.4} vs energy {k_g:.4} ({:+.2} %), Tada {k_tada:.4} ({:+.1} %)",
                if *r > clear { "clipped" } else { "inside" },
                100.0 * (k / k_g - 1.0),
                100.0 * (k / k_tada - 1.0)
            );
        }
        let (lo, hi) = ks
            .iter()
            .fold((f64::MAX, f64::MIN), |(a, b), &v| (a.min(v), b.max(v)));
        assert!(
            (hi - lo) / hi < 1e-2,
            "clearance {clear} h: K spread {:.3} %",
            100.0 * (hi - lo) / hi
        );
        if clear >= 2.0 {
            for k in &ks {
                assert!(
                    (k / k_g - 1.0).abs() < 0.02,
                    "clearance {clear} h: {k} vs {k_g}"
                );
            }
        }
    }
}
