//! Holes and notches in the FEM part of CCM-PD (`pd/splice/holes.rs`): the cut elements
//! of the fictitious domain ([`rustfrac_core::fe::fictitious`]) in the splice model, against the
//! pure FEM solution of the same scene and Kirsch's hole; the SLA on a plate with a FEM hole (the
//! fast engine equals the oracle); the refusal of a hole cutting a hybrid element.

use crate::common;
use rustfrac_core::pd::analysis::splice_model;

use common::{coarse, go_on};
use rustfrac_core::fem_driver;
use rustfrac_core::pd::analysis::run;
use rustfrac_core::pd::splice::SpliceModel;
use rustfrac_core::problem::Side;
use rustfrac_core::problem::{Boundary, Domain, Hole, Problem, Region, Shape, Support};

/// Plate size, hole radius and centre (in the FEM part), grid spacing, end displacement.
const W: f64 = 6.0;
const A: f64 = 0.5;
const C: [f64; 2] = [4.0, 3.0];
const DX: f64 = 0.1;
const DU: f64 = 0.003;
/// The PD rectangle, left of the hole (its boundary band is 1.5 from the hole's edge).
const PD_RECT: [f64; 4] = [0.6, 2.0, 2.0, 4.0];

fn support(k: usize, region: Region, u1: Option<f64>, u2: Option<f64>) -> Support {
    Support {
        name: format!("support[{k}]"),
        region,
        u1,
        u2,
    }
}

fn hole() -> Hole {
    Hole {
        name: "hole[0]".into(),
        shape: Shape::Circle {
            center: C,
            radius: A,
        },
    }
}

/// The W x W plate pulled by u1 = -+DU on its left and right edges (a uniform strain without
/// the hole), u2 = 0 at the bottom's midpoint; `method` "ccm_pd" (m = 3, dx = DX) or "fem" (the
/// same grid).
fn plate(method: &str, with_hole: bool) -> Problem {
    let mut p = Problem::paper(method);
    p.domain = Domain::rect(W, W);
    if with_hole {
        p.domain.holes = vec![hole()];
    }
    p.cracks.clear();
    p.boundary = Boundary::Regions {
        supports: vec![
            support(0, Region::Edge(Side::Left), Some(-DU), None),
            support(1, Region::Edge(Side::Right), Some(DU), None),
            support(2, Region::Point([0.5 * W, 0.0]), None, Some(0.0)),
        ],
        loads: Vec::new(),
    };
    if method == "fem" {
        let n = (W / DX).round() as usize;
        p.fem_mut().grid.nx = n;
        p.fem_mut().grid.ny = n;
    } else {
        let pd = p.pd_mut();
        pd.dx = DX;
        pd.m = 3;
        pd.regions = vec![PD_RECT];
    }
    p
}

/// Kirsch (1898): displacements about the centre of a circular hole of radius a in an infinite
/// plate under the remote stress S along x1 (plane strain, kappa = 3 - 4 nu).
fn kirsch(s: f64, g: f64, nu: f64, a: f64, r: f64, t: f64) -> [f64; 2] {
    let k = 3.0 - 4.0 * nu;
    let c = s / (8.0 * g * r);
    let ur = c
        * (r * r * (k - 1.0)
            + 2.0 * a * a
            + 2.0 * (r * r + a * a * (k + 1.0) - a.powi(4) / (r * r)) * (2.0 * t).cos());
    let ut = -c * 2.0 * (r * r + a * a * (k - 1.0) + a.powi(4) / (r * r)) * (2.0 * t).sin();
    [ur * t.cos() - ut * t.sin(), ur * t.sin() + ut * t.cos()]
}

/// The CCM-PD solution (model, u, right support's force) and the FEM one (u, force).
fn solve(with_hole: bool) -> (SpliceModel, Vec<f64>, f64, Vec<f64>, f64) {
    let p = plate("ccm_pd", with_hole);
    let model = splice_model(&p).unwrap();
    let s = model.solve(&model.precrack_broken).unwrap();
    let r = model.scene_responses(&s.u, &s.reactions).unwrap();
    let fem = fem_driver::run(&plate("fem", with_hole)).unwrap();
    assert_eq!(fem.u.len(), s.u.len(), "the same grid");
    let f_cc = r.regions[1].1.force[0];
    let f_fem = fem.responses.regions[1].1.force[0];
    (model, s.u, f_cc, fem.u, f_fem)
}

#[test]
fn fem_hole_in_ccm_pd_matches_fem_and_kirsch() {
    let (model, u_cc, f_cc, u_fem, f_fem) = solve(true);
    let (_, u_cc0, f_cc0, u_fem0, f_fem0) = solve(false);
    assert!(!model.own_ke.is_empty(), "elements cut by the hole");
    let removed = model.material.iter().filter(|&&m| !m).count();
    assert!(removed > 0, "nodes inside the hole removed");
    // removed nodes are held at 0
    for (n, _) in model.material.iter().enumerate().filter(|(_, &m)| !m) {
        assert_eq!([u_cc[2 * n], u_cc[2 * n + 1]], [0.0, 0.0]);
    }
    let inf = |v: &[f64]| v.iter().fold(0.0f64, |a, b| a.max(b.abs()));
    let diff = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x - y).collect::<Vec<_>>();
    // the whole field: CCM-PD against FEM, with and without the hole
    let e_hole = inf(&diff(&u_cc, &u_fem)) / inf(&u_fem);
    let e_plain = inf(&diff(&u_cc0, &u_fem0)) / inf(&u_fem0);
    // the hole's effect on the field (the PD rectangle's own error drops out)
    let eff_cc = diff(&u_cc, &u_cc0);
    let eff_fem = diff(&u_fem, &u_fem0);
    let e_effect = inf(&diff(&eff_cc, &eff_fem)) / inf(&eff_fem);
    let (df_cc, df_fem) = (f_cc - f_cc0, f_fem - f_fem0);
    println!(
        "CCM-PD vs FEM: max |du| / max |u| {e_hole:.3e} with the hole, {e_plain:.3e} without; \
         the hole's effect on u {e_effect:.3e}; right force {f_cc:.6e} vs {f_fem:.6e} \
         ({:.3e}), its drop by the hole {df_cc:.4e} vs {df_fem:.4e} ({:.3e}); {} cut elements, \
         {removed} removed nodes",
        (f_cc - f_fem).abs() / f_fem.abs(),
        (df_cc - df_fem).abs() / df_fem.abs(),
        model.own_ke.len()
    );
    // measured: 5.0e-4 with the hole, 3e-13 without (a uniform strain is exact in the PD
    // rectangle too: the patch test), the effect 1.2e-3, its force 1.4e-3 (the PD rectangle
    // feeling the hole's non-uniform field)
    assert!(e_plain < 1e-10, "{e_plain}");
    assert!(e_hole < 2e-3, "{e_hole}");
    assert!(e_effect < 5e-3, "{e_effect}");
    assert!((df_cc - df_fem).abs() < 5e-3 * df_fem.abs());
    // the hole must matter (else the comparison above is empty)
    assert!(df_fem.abs() > 0.05 * f_fem0.abs(), "{df_fem} vs {f_fem0}");

    // Kirsch: displacement differences across the hole, the remote stress from the force
    let e = Problem::paper("pd").material.elastic;
    let g = e.e / (2.0 * (1.0 + e.nu));
    let s = f_cc / (W * e.thickness);
    let node = |x: [f64; 2]| {
        model
            .grid
            .node((x[0] / DX).round() as usize, (x[1] / DX).round() as usize)
    };
    let mut worst: f64 = 0.0;
    for (r, th) in [
        (3.0 * A, 0.0),
        (3.0 * A, 90f64.to_radians()),
        (2.0 * A, 45f64.to_radians()),
    ] {
        let p = [C[0] + r * th.cos(), C[1] + r * th.sin()];
        let q = [C[0] - r * th.cos(), C[1] - r * th.sin()];
        let (np, nq) = (node(p), node(q));
        let d = [
            u_cc[2 * np] - u_cc[2 * nq],
            u_cc[2 * np + 1] - u_cc[2 * nq + 1],
        ];
        let k = kirsch(s, g, e.nu, A, r, th);
        let dk = [2.0 * k[0], 2.0 * k[1]];
        let err = (d[0] - dk[0]).hypot(d[1] - dk[1]) / dk[0].hypot(dk[1]);
        println!(
            "r = {r}, theta = {:.0}: CCM-PD {d:?}, Kirsch {dk:?} ({:.2} %)",
            th.to_degrees(),
            100.0 * err
        );
        worst = worst.max(err);
    }
    // measured 1.3 % (the plate is 12 radii wide, Kirsch's infinite; dx = a / 5)
    assert!(worst < 0.03, "worst {worst}");
}

#[test]
fn notch_on_the_gripped_edge_holds_its_removed_nodes() {
    // the paper's coarse plate under its grips, a notch from the top edge in the FEM part: the
    // grip's nodes in the notch are removed and held at 0, the rest of the grip stays
    let mut p = coarse(true, 1);
    p.domain.holes = vec![Hole {
        name: "notch[0]".into(),
        shape: Shape::Rect {
            min: [7.5, 19.5],
            max: [8.5, 22.0],
        },
    }];
    let m = splice_model(&p).unwrap();
    let s = m.solve(&m.precrack_broken).unwrap();
    let top_removed: Vec<usize> = m
        .edges
        .top
        .iter()
        .copied()
        .filter(|&n| !m.material[n])
        .collect();
    assert!(!top_removed.is_empty());
    for &n in &top_removed {
        assert_eq!(s.u[2 * n + 1], 0.0);
    }
    let p0 = coarse(true, 1);
    let m0 = splice_model(&p0).unwrap();
    let s0 = m0.solve(&m0.precrack_broken).unwrap();
    println!(
        "sigma22 with the notch {:.6e}, without {:.6e}; residual {:.1e}",
        s.sigma22, s0.sigma22, s.residual
    );
    assert!(s.residual < 1e-10 && s.sigma22.is_finite());
    // a notch of 1/11 of the width on the gripped edge softens the plate: less force at the
    // same displacement, but not less than the ligament's share
    assert!(s.sigma22 < s0.sigma22 && s.sigma22 > 0.8 * s0.sigma22);
}

#[test]
fn sla_with_a_fem_hole_runs_and_fast_equals_oracle() {
    let n = 8;
    let with_hole = |fast: bool| {
        let mut p = coarse(fast, n);
        p.domain.holes = vec![Hole {
            name: "hole[0]".into(),
            shape: Shape::Circle {
                center: [8.0, 5.0],
                radius: 1.0,
            },
        }];
        run(&p, &go_on).unwrap()
    };
    let fast = with_hole(true);
    let oracle = with_hole(false);
    let plain = run(&coarse(true, n), &go_on).unwrap();
    assert_eq!(fast.history.len(), n);
    assert_eq!(oracle.history.len(), n);
    let mut worst: f64 = 0.0;
    for (a, b) in fast.history.iter().zip(&oracle.history) {
        assert_eq!(a.bonds, b.bonds, "step {}", a.step);
        worst = worst.max((a.lambda - b.lambda).abs() / b.lambda.abs());
        assert!(a.lambda.is_finite() && a.lambda > 0.0);
    }
    let (l, l0) = (fast.history[0].lambda, plain.history[0].lambda);
    println!(
        "SLA with a FEM hole: fast vs oracle worst lambda {worst:.2e}; first lambda {l:.6e}, \
         without the hole {l0:.6e}"
    );
    assert!(worst < 1e-8, "{worst}");
    // the hole far from the crack changes the load factor a little
    assert!(l != l0 && (l - l0).abs() < 0.1 * l0, "{l} vs {l0}");
}

#[test]
fn hole_cutting_a_hybrid_element_is_refused() {
    let mut p = plate("ccm_pd", false);
    // across the PD rectangle's right edge x1 = 2.0
    p.domain.holes = vec![Hole {
        name: "hole[0]".into(),
        shape: Shape::Circle {
            center: [2.05, 3.0],
            radius: 0.2,
        },
    }];
    let e = splice_model(&p).err().expect("refused");
    assert_eq!(e.param(), Some("hole[0]"), "{e}");
    assert!(e.to_string().contains("hybrid element"), "{e}");
}
