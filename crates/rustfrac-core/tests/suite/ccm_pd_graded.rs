//! CCM-PD with a graded FEM grid (`pd.fem_grading` > 1, `pd::splice::graded`): the patch test
//! (rigid motions and a uniform strain reproduced to round-off), the SLA history against the
//! uniform grid's on a coarse case, the fast engine against the refactorise-every-step oracle on
//! the graded model, and the refusals.

use crate::common;
use rustfrac_core::pd::analysis::run;
use rustfrac_core::pd::analysis::splice_model;
use rustfrac_core::problem::Calibration;

use common::{coarse, go_on, same_sla_history};
use rustfrac_core::la::{Lu, Reduction};
use rustfrac_core::pd::sla::CcmPdResult;
use rustfrac_core::pd::splice::SpliceModel;
use rustfrac_core::problem::{Domain, Problem};

/// A 6 x 6 uncracked plate, dx = 0.1, PD rectangle [2.0, 3.05] x [1.9, 3.1], FEM grid graded
/// (ratio 1.3, at most 4 dx) beyond the PD rectangle and its band of m + 1 = 5 elements.
fn graded_patch() -> Problem {
    let mut p = Problem::paper("ccm_pd");
    p.domain = Domain::rect(6.0, 6.0);
    p.cracks.clear();
    let pd = p.pd_mut();
    pd.dx = 0.1;
    pd.regions = vec![[2.0, 1.9, 3.05, 3.1]];
    pd.fem_grading = 1.3;
    pd.fem_coarse = 4.0;
    p
}

fn inf(v: &[f64]) -> f64 {
    v.iter().fold(0.0, |a, b| a.max(b.abs()))
}

#[test]
fn graded_grid_keeps_dx_around_the_pd_part_and_grows_beyond() {
    let model = splice_model(&graded_patch()).unwrap();
    let g = &model.grid;
    assert!(!g.is_uniform());
    let h: Vec<f64> = g.xs.windows(2).map(|w| w[1] - w[0]).collect();
    let (hmin, hmax) = h
        .iter()
        .fold((f64::MAX, 0.0f64), |a, &x| (a.0.min(x), a.1.max(x)));
    println!(
        "graded 6 x 6 plate: {} x {} elements (uniform 60 x 60), {} own element matrices, x sizes {hmin:.4} .. {hmax:.4}",
        g.nx,
        g.ny,
        model.own_ke.len()
    );
    assert!(g.nx < 60 && g.ny < 60 && !model.own_ke.is_empty());
    assert!(hmax > 2.0 * 0.1 && hmax <= 4.0 * 0.1 * 1.3);
    // every cell within m + 1 = 5 cells of a PD node has the PD spacing
    for &n in &model.pd_nodes {
        let (i, j) = g.ij(n);
        for k in i.saturating_sub(5)..(i + 5).min(g.nx) {
            assert!((g.xs[k + 1] - g.xs[k] - 0.1).abs() < 1e-12);
        }
        for k in j.saturating_sub(5)..(j + 5).min(g.ny) {
            assert!((g.ys[k + 1] - g.ys[k] - 0.1).abs() < 1e-12);
        }
    }
    // the uniform default: the same grid as before (lines i dx)
    let mut p = graded_patch();
    p.pd_mut().fem_grading = 1.0;
    let u = splice_model(&p).unwrap();
    assert!(u.grid.is_uniform() && u.grid.nx == 60 && u.own_ke.is_empty());
}

/// A displacement field u(x).
type Field = fn([f64; 2]) -> [f64; 2];

#[test]
fn graded_rigid_motions_give_zero_internal_forces() {
    let model = splice_model(&graded_patch()).unwrap();
    let k = model.assemble(&model.precrack_broken);
    let nn = model.grid.n_nodes();
    let fields: [(&str, Field); 3] = [
        ("translation x", |_| [1.0, 0.0]),
        ("translation y", |_| [0.0, 1.0]),
        ("rotation", |p| [-(p[1] - 3.0), p[0] - 3.0]),
    ];
    for (name, field) in fields {
        let mut u = vec![0.0; 2 * nn];
        for n in 0..nn {
            let v = field(model.grid.xy(n));
            u[2 * n] = v[0];
            u[2 * n + 1] = v[1];
        }
        let rel = inf(&k.matvec(&u)) / (inf(&k.val) * inf(&u));
        println!("graded, {name}: max |K u| / (max|K| max|u|) = {rel:.2e}");
        assert!(rel < 1e-12, "{name}: {rel}");
    }
}

/// The patch test (e.g. Zienkiewicz & Taylor, The Finite Element Method, vol. 1, ch. 10): a
/// uniform strain imposed on the outer boundary nodes is the exact discrete solution of Q4 on a
/// rectangular grid of any spacing and of the splice coupling on its uniform part.
#[test]
fn graded_uniform_strain_reproduced_everywhere() {
    let model = splice_model(&graded_patch()).unwrap();
    let (e11, e22, e12) = (1e-3, -4e-4, 2.5e-4);
    let field = |p: [f64; 2]| [e11 * p[0] + e12 * p[1], e12 * p[0] + e22 * p[1]];
    let k = model.assemble(&model.precrack_broken);
    let nn = model.grid.n_nodes();
    let (mut mask, mut up, mut exact) = (vec![false; 2 * nn], vec![0.0; 2 * nn], vec![0.0; 2 * nn]);
    for n in 0..nn {
        let p = model.grid.xy(n);
        let v = field(p);
        exact[2 * n..2 * n + 2].copy_from_slice(&v);
        if p[0].min(6.0 - p[0]).min(p[1]).min(6.0 - p[1]) < 1e-9 {
            mask[2 * n] = true;
            mask[2 * n + 1] = true;
            up[2 * n..2 * n + 2].copy_from_slice(&v);
        }
    }
    let red = Reduction::new(&k, &mask).unwrap();
    let lu = Lu::new(&red.reduce(&k)).unwrap();
    let uf = lu.solve(&red.rhs(&k, &vec![0.0; 2 * nn], &up)).unwrap();
    let u = red.expand(&uf, &up);
    let err: Vec<f64> = u.iter().zip(&exact).map(|(a, b)| a - b).collect();
    let rel = inf(&err) / inf(&exact);
    println!(
        "graded coupled model ({} PD nodes, {} nodes): uniform strain, max relative error {rel:.2e}",
        model.pd_nodes.len(),
        nn
    );
    assert!(rel < 1e-10, "{rel}");
}

/// The coarse paper case (dx = 0.2) with the FEM grid graded at `ratio` (at most 8 dx).
fn graded_coarse(fast: bool, steps: usize, ratio: f64) -> Problem {
    let mut p = coarse(fast, steps);
    p.pd_mut().fem_grading = ratio;
    p.pd_mut().fem_coarse = 8.0;
    p
}

#[test]
fn graded_sla_history_follows_the_uniform_grid() {
    let n = 100;
    let uni = run(&coarse(true, n), &go_on).unwrap();
    let gr = run(&graded_coarse(true, n, 1.2), &go_on).unwrap();
    assert_eq!(gr.counts.n_pd_nodes, uni.counts.n_pd_nodes);
    assert_eq!(gr.counts.n_bonds, uni.counts.n_bonds);
    assert!(
        gr.counts.n_dofs < uni.counts.n_dofs / 2,
        "{} vs {}",
        gr.counts.n_dofs,
        uni.counts.n_dofs
    );
    let same = (0..n)
        .take_while(|&k| gr.broken_positions(k, None) == uni.broken_positions(k, None))
        .count();
    let mut worst = 0.0f64;
    for k in 0..same {
        let (a, b) = (&gr.history[k], &uni.history[k]);
        worst = worst.max((a.lambda / b.lambda - 1.0).abs());
    }
    let peak = |r: &CcmPdResult| r.history.iter().map(|s| s.sigma22).fold(0.0, f64::max);
    println!(
        "coarse case: uniform {} dofs, graded {} dofs; same broken bonds for {same} of {n} steps; worst relative lambda difference {worst:.3e}; sigma22 ref {:.5} / {:.5}, CMOD {:.6e} / {:.6e}; peak sigma22 {:.4} / {:.4}",
        uni.counts.n_dofs, gr.counts.n_dofs, gr.reference.sigma22, uni.reference.sigma22, gr.reference.cmod, uni.reference.cmod, peak(&gr), peak(&uni)
    );
    // measured: the same bonds in the first 84 steps (then two nearly tied bonds swap order),
    // lambda within 5.4e-4, CMOD within 4.8e-4 (the coarser far field); tolerances leave a
    // factor of about 3
    assert!(
        same >= 80,
        "the graded run broke other bonds from step {}",
        same + 1
    );
    assert!(worst < 1.5e-3, "{worst}");
    assert!((gr.reference.cmod / uni.reference.cmod - 1.0).abs() < 1.5e-3);
}

#[test]
fn graded_fast_sla_matches_oracle() {
    let n = 60;
    let fast = run(&graded_coarse(true, n, 1.3), &go_on).unwrap();
    let oracle = run(&graded_coarse(false, n, 1.3), &go_on).unwrap();
    let worst = same_sla_history(&fast, &oracle, n);
    println!(
        "graded coarse case ({} dofs): fast {:.3} s, oracle {:.3} s; worst relative difference {worst:.2e}",
        fast.counts.n_dofs, fast.timings.sla_seconds, oracle.timings.sla_seconds
    );
    assert!(worst < 1e-8, "{worst}");
}

#[test]
fn graded_grid_refusals_name_the_key() {
    // pure PD has no FEM part
    let mut p = Problem::paper("pd");
    p.pd_mut().fem_grading = 1.2;
    let e = splice_model(&p).err().expect("refused").to_string();
    assert!(e.contains("pd.fem_grading"), "{e}");
    // out of range
    let mut p = coarse(true, 0);
    p.pd_mut().fem_grading = 2.5;
    let e = splice_model(&p).err().expect("refused").to_string();
    assert!(e.contains("pd.fem_grading"), "{e}");
    let mut p = coarse(true, 0);
    p.pd_mut().fem_grading = 1.2;
    p.pd_mut().fem_coarse = 0.5;
    let e = splice_model(&p).err().expect("refused").to_string();
    assert!(e.contains("pd.fem_coarse"), "{e}");
    // an inclined pre-crack segment through the graded part
    let p = graded_coarse(true, 0, 1.2);
    let e = SpliceModel::with_precrack(
        &p,
        vec![[0.05, 6.05], [1.1, 10.5]],
        Calibration::continuum(),
    )
    .err()
    .expect("refused")
    .to_string();
    assert!(e.contains("precrack"), "{e}");
    // the same segment on the uniform grid is accepted
    assert!(SpliceModel::with_precrack(
        &coarse(true, 0),
        vec![[0.05, 6.05], [1.1, 10.5]],
        Calibration::continuum()
    )
    .is_ok());
}

/// A 6 x 6 plate with a circular hole (r = 0.5 at (4, 3)) in the FEM part, pulled by u1 = -+0.003
/// on its left and right edges (supports on regions), PD rectangle [0.6, 2.0] x [2.0, 4.0],
/// m = 3, dx = 0.1; graded at `ratio` (at most 3 dx) or uniform (ratio 1).
fn holed_plate(ratio: f64) -> Problem {
    use rustfrac_core::problem::Side;
    use rustfrac_core::problem::{Boundary, Hole, Region, Shape, Support};
    let mut p = Problem::paper("ccm_pd");
    p.domain = Domain::rect(6.0, 6.0);
    p.domain.holes = vec![Hole {
        name: "hole[0]".into(),
        shape: Shape::Circle {
            center: [4.0, 3.0],
            radius: 0.5,
        },
    }];
    p.cracks.clear();
    let support = |k: usize, region, u1, u2| Support {
        name: format!("support[{k}]"),
        region,
        u1,
        u2,
    };
    p.boundary = Boundary::Regions {
        supports: vec![
            support(0, Region::Edge(Side::Left), Some(-0.003), None),
            support(1, Region::Edge(Side::Right), Some(0.003), None),
            support(2, Region::Point([3.0, 0.0]), None, Some(0.0)),
        ],
        loads: Vec::new(),
    };
    let pd = p.pd_mut();
    pd.dx = 0.1;
    pd.m = 3;
    pd.regions = vec![[0.6, 2.0, 2.0, 4.0]];
    pd.fem_grading = ratio;
    pd.fem_coarse = 3.0;
    p
}

/// Holes in the FEM part and supports on regions on a graded grid: a cap of 1 dx (the graded
/// code path on lines that are all dx) reproduces the uniform model to round-off; cap 2 dx
/// differs by the coarser discretisation around the hole (measured: response 6.3e-4, cap 1.5:
/// 2.4e-4, cap 3: 1.35e-3; displacements 3.5e-3 of max |u|).
#[test]
fn graded_grid_with_a_fem_hole_and_supports_on_regions() {
    let um = splice_model(&holed_plate(1.0)).unwrap();
    let us = um.solve(&um.precrack_broken).unwrap();
    for (cap, tol_response, tol_u) in [(1.0, 1e-10, 1e-10), (2.0, 1.5e-3, 7e-3)] {
        let mut gp = holed_plate(1.2);
        gp.pd_mut().fem_coarse = cap;
        let gm = splice_model(&gp).unwrap();
        let gs = gm.solve(&gm.precrack_broken).unwrap();
        // the graded field (bilinear in its cell) against the uniform grid's nodal values at
        // points near the hole, in the PD rectangle and far away (nodes of the uniform grid)
        let interp = |m: &SpliceModel, u: &[f64], q: [f64; 2]| -> [f64; 2] {
            let g = &m.grid;
            let cell =
                |l: &[f64], x: f64| (l.partition_point(|&v| v <= x).clamp(1, l.len() - 1)) - 1;
            let (i, j) = (cell(&g.xs, q[0]), cell(&g.ys, q[1]));
            let [hx, hy] = g.cell_size(i, j);
            let (s, t) = ((q[0] - g.xs[i]) / hx, (q[1] - g.ys[j]) / hy);
            let n = [
                g.node(i, j),
                g.node(i + 1, j),
                g.node(i + 1, j + 1),
                g.node(i, j + 1),
            ];
            assert!(
                n.iter().all(|&k| m.material[k]),
                "{q:?} in a cell with removed nodes"
            );
            let w = [(1.0 - s) * (1.0 - t), s * (1.0 - t), s * t, (1.0 - s) * t];
            let mut out = [0.0; 2];
            for (k, wk) in n.iter().zip(w) {
                out[0] += wk * u[2 * k];
                out[1] += wk * u[2 * k + 1];
            }
            out
        };
        let umax = inf(&us.u);
        let mut worst = 0.0f64;
        for q in [
            [4.0, 3.8],
            [4.8, 3.0],
            [3.2, 3.0],
            [1.3, 3.0],
            [5.5, 5.5],
            [3.0, 1.0],
        ] {
            let (a, b) = (interp(&gm, &gs.u, q), interp(&um, &us.u, q));
            worst = worst.max((a[0] - b[0]).abs().max((a[1] - b[1]).abs()) / umax);
        }
        println!(
        "holed plate, cap {cap} dx: graded {} / uniform {} dofs, {} / {} own element matrices; response {:.6} / {:.6}; worst displacement difference {worst:.2e} of max |u|",
        gm.n_dofs(),
        um.n_dofs(),
        gm.own_ke.len(),
        um.own_ke.len(),
        gs.sigma22,
        us.sigma22
    );
        assert!(gs.residual < 1e-10 && gs.sigma22.is_finite());
        assert!(
            (gs.sigma22 / us.sigma22 - 1.0).abs() < tol_response,
            "cap {cap}"
        );
        assert!(worst < tol_u, "cap {cap}: {worst}");
        if cap > 1.0 {
            assert!(gm.n_dofs() < um.n_dofs() * 3 / 5);
        }
    }
}
