//! General scenes for PD and CCM-PD (issue 12): pre-cracks at any angle and position, holes,
//! supports and loads on regions, probes; against brute force, Kirsch's hole, the shear of a
//! block, and pure PD against CCM-PD. Run in release (`cargo test --release --test pd_general`).

mod common;

use common::{go_on, pd_plate};
use rustfrac_core::fe::mesh::Side;
use rustfrac_core::pd::cell_fraction;
use rustfrac_core::pd::sla::run;
use rustfrac_core::pd::splice::SpliceModel;
use rustfrac_core::problem::{CrackKind, CrackSpec, Problem, SlaParams};

/// Does the bond p-q cross the crack segment a-b: its ends strictly on both sides of the crack's
/// line, the crack's ends on the closed other side (a crack end on the bond counts: the tip, and
/// the mouth on the plate's edge).
fn crosses(p: [f64; 2], q: [f64; 2], a: [f64; 2], b: [f64; 2]) -> bool {
    let o = |a: [f64; 2], b: [f64; 2], c: [f64; 2]| {
        (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
    };
    o(a, b, p) * o(a, b, q) < 0.0 && o(p, q, a) * o(p, q, b) <= 0.0
}

/// A pure PD 4 x 4 plate (dx = 0.2, m = 3) with one crack.
fn pd_with_crack(c: CrackSpec) -> Problem {
    let mut p = pd_plate("pd", 4.0, 4.0, 0.2, 3);
    p.cracks = vec![c];
    p.pd_mut().sla = SlaParams {
        max_steps: 1,
        ..SlaParams::default()
    };
    p
}

fn edge(side: Side, x: f64, y: f64, a0: f64, angle: f64) -> CrackSpec {
    CrackSpec {
        kind: CrackKind::Edge,
        a0,
        y,
        angle,
        x,
        side,
    }
}

/// The pre-crack breaks exactly the bonds (node pairs whose cells overlap the horizon) that
/// cross it, found by brute force over all node pairs; the SLA's first broken bond lies at one of
/// `tips` (none given: a crack along the grips' pull, which does not open).
fn check_precrack(p: &Problem, tips: &[[f64; 2]]) {
    let model = SpliceModel::new(p).unwrap();
    let line = p.pd_precrack();
    let g = model.grid;
    let m = model.pd.m as f64;
    let mut expected = 0;
    let nn = g.n_nodes();
    for a in 0..nn {
        for b in a + 1..nn {
            let (pa, pb) = (g.xy(a), g.xy(b));
            let (di, dj) = ((pb[0] - pa[0]) / g.dx, (pb[1] - pa[1]) / g.dx);
            if cell_fraction(di, dj, m) <= 0.0 {
                continue;
            }
            if line.windows(2).any(|s| crosses(pa, pb, s[0], s[1])) {
                expected += 1;
            }
        }
    }
    let broken = model.precrack_broken.iter().filter(|&&x| x).count();
    println!("pre-crack {line:?}: {broken} bonds broken (brute force {expected})");
    assert!(broken > 0);
    assert_eq!(broken, expected);
    // the same bonds, one by one
    for (b, bond) in model.bonds.iter().enumerate() {
        let (pa, pb) = (g.xy(bond.i as usize), g.xy(bond.j as usize));
        let x = line.windows(2).any(|s| crosses(pa, pb, s[0], s[1]));
        assert_eq!(model.precrack_broken[b], x, "bond {pa:?}-{pb:?}");
    }
    if tips.is_empty() {
        return;
    }
    let r = run(p, &go_on).unwrap();
    let first = &r.history[0];
    let (a, b) = (g.xy(first.nodes[0]), g.xy(first.nodes[1]));
    let mid = [0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])];
    let d = tips
        .iter()
        .map(|t| (mid[0] - t[0]).hypot(mid[1] - t[1]))
        .fold(f64::INFINITY, f64::min);
    println!("first broken bond {a:?}-{b:?}: {d:.3} from the nearest tip (delta = {})", m * g.dx);
    assert!(d <= m * g.dx, "first bond {d} from the tip");
}

#[test]
fn inclined_edge_precrack_breaks_the_crossing_bonds() {
    let c = edge(Side::Left, 0.0, 2.1, 1.5, 30.0);
    let p = pd_with_crack(c);
    let tip = p.crack_polylines()[0][1];
    check_precrack(&p, &[tip]);
}

#[test]
fn edge_precracks_from_every_side_and_centre_cracks() {
    let p = pd_with_crack(edge(Side::Right, 0.0, 1.9, 1.2, -20.0));
    let tip = p.crack_polylines()[0][1];
    check_precrack(&p, &[tip]);
    // along the grips' pull: the bonds only
    for c in [
        edge(Side::Bottom, 2.1, 0.0, 1.3, 15.0),
        edge(Side::Top, 1.9, 0.0, 1.0, 0.0),
    ] {
        check_precrack(&pd_with_crack(c), &[]);
    }
    let c = CrackSpec {
        kind: CrackKind::Center,
        a0: 0.8,
        y: 2.05,
        angle: 25.0,
        x: 1.95,
        side: Side::Left,
    };
    let p = pd_with_crack(c);
    let line = p.crack_polylines()[0].clone();
    check_precrack(&p, &line);
    // the CMOD is read at the centre: opening > 0 under the grips' tension
    let model = SpliceModel::new(&p).unwrap();
    let s = model.solve(&model.precrack_broken).unwrap();
    assert!(s.cmod > 0.0, "centre opening {}", s.cmod);
}
