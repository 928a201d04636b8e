//! The condensed XFEM growth (one factorisation of the standard block for the whole growth,
//! `rustfrac_core::xfem::condensed`) against the reference path that assembles and factorises
//! the whole system at every step (`xfem::run_reference`): every recorded quantity of every
//! critical state to round-off, on an edge crack, an inclined edge crack (mixed mode, kinked
//! growth), two cracks, a hole, and supports and loads on regions on a graded grid. The condition
//! estimates are compared too (they estimate the same number by a different lower bound).

use crate::common;

use common::scene_values::{edge_shear, f, i, s, tbl};
use common::{paper_growth, quiet, tall_strip, XfemCase};
use rustfrac_core::problem::value::{Table, Value};
use rustfrac_core::problem::{Growth, Hole, Method, Problem, Shape};
use rustfrac_core::xfem::{self, XfemResult};

/// Relative difference of a against the reference b, scaled by `scale` (the quantity's size
/// over the run) so that values crossing zero (K_II) are compared on their own scale.
fn close(a: f64, b: f64, scale: f64, tol: f64, what: &str) -> f64 {
    let d = (a - b).abs() / scale.abs().max(f64::MIN_POSITIVE);
    assert!(
        d <= tol,
        "{what}: {a:e} vs reference {b:e} ({d:.2e} > {tol:.0e})"
    );
    d
}

/// One recorded quantity of a result at a history row.
type Field = dyn Fn(&XfemResult, usize) -> f64;

/// Runs `p` both ways and compares the histories; returns the largest relative difference.
fn compare(name: &str, p: &Problem, min_states: usize) -> f64 {
    let t0 = std::time::Instant::now();
    let new = xfem::run(p, &quiet).unwrap();
    let t1 = std::time::Instant::now();
    let old = xfem::run_reference(p, &quiet).unwrap();
    let t2 = std::time::Instant::now();
    assert_eq!(new.status, old.status, "{name}: status");
    assert_eq!(new.history.len(), old.history.len(), "{name}: states");
    assert!(
        new.history.len() >= min_states,
        "{name}: {} states",
        new.history.len()
    );
    let max_of = |f: &Field| {
        (0..old.history.len())
            .map(|k| f(&old, k).abs())
            .fold(0.0, f64::max)
    };
    let tol = 1e-10;
    let mut worst = 0.0f64;
    // the initial solve (condensed too in a growth run)
    for (what, a, b) in [
        ("initial K_I", new.k_i, old.k_i),
        ("initial CMOD", new.cmod, old.cmod),
        ("initial sigma22", new.sigma22, old.sigma22),
    ] {
        worst = worst.max(close(a, b, b, tol, &format!("{name}: {what}")));
    }
    let fields: [(&str, &Field); 6] = [
        ("lambda", &|r, k| r.history[k].lambda),
        ("sigma22", &|r, k| r.history[k].sigma22),
        ("cmod", &|r, k| r.history[k].cmod),
        ("u0", &|r, k| r.history[k].u0),
        ("k_i", &|r, k| r.history[k].k_i),
        ("kink", &|r, k| r.history[k].kink_angle),
    ];
    for (what, f) in fields {
        // the kink angle in radians (it is round-off in mode I)
        let scale = if what == "kink" { 1.0 } else { max_of(f) };
        for k in 0..old.history.len() {
            let w = format!("{name}: state {k} {what}");
            worst = worst.max(close(f(&new, k), f(&old, k), scale, tol, &w));
        }
    }
    // every tip's SIFs (K_II on the scale of K_I: it is ~0 in mode I)
    let ki_scale = max_of(&|r, k| r.history[k].k_i);
    for (k, (tn, to)) in new.tip_history.iter().zip(&old.tip_history).enumerate() {
        for (t, (a, b)) in tn.iter().zip(to).enumerate() {
            let w = format!("{name}: state {k} tip {t}");
            worst = worst.max(close(a.k_i, b.k_i, ki_scale, tol, &w));
            worst = worst.max(close(a.k_ii, b.k_ii, ki_scale, tol, &w));
            assert_eq!(a.grows, b.grows, "{w}: grows");
            for i in 0..2 {
                worst = worst.max(close(a.pos[i], b.pos[i], 1.0, tol, &w));
            }
        }
    }
    for (k, (a, b)) in new
        .response_history
        .iter()
        .zip(&old.response_history)
        .enumerate()
    {
        let w = format!("{name}: state {k} load displacement");
        let s = old
            .response_history
            .iter()
            .map(|r| r.load_displacement.abs())
            .fold(0.0, f64::max);
        worst = worst.max(close(a.load_displacement, b.load_displacement, s, tol, &w));
        assert_eq!(a.regions.len(), b.regions.len(), "{w}: regions");
        for ((_, ra), (_, rb)) in a.regions.iter().zip(&b.regions) {
            let s = rb.force[0].abs().max(rb.force[1].abs()).max(1e-300);
            for i in 0..2 {
                worst = worst.max(close(ra.force[i], rb.force[i], s, tol, &w));
                worst = worst.max(close(ra.displacement[i], rb.displacement[i], 1.0, tol, &w));
            }
        }
    }
    // the condition estimates: the same quantity (cond_1 of the equilibrated stiffness) by
    // another lower bound
    let ratios: Vec<f64> = new.history[1..]
        .iter()
        .zip(&old.history[1..])
        .filter_map(|(a, b)| Some(a.condition? / b.condition?))
        .collect();
    let (rmin, rmax) = ratios.iter().fold((f64::INFINITY, 0.0f64), |(lo, hi), &r| {
        (lo.min(r), hi.max(r))
    });
    eprintln!(
        "{name}: {} states, status {}, largest relative difference {worst:.2e}; condition \
         estimate new / reference in [{rmin:.3}, {rmax:.3}]; {:.2} s condensed vs {:.2} s reference",
        new.history.len(),
        new.status,
        (t1 - t0).as_secs_f64(),
        (t2 - t1).as_secs_f64()
    );
    if !ratios.is_empty() {
        assert!(
            rmin > 0.3 && rmax < 3.0,
            "{name}: condition ratios {ratios:?}"
        );
    }
    worst
}

fn problem(case: &XfemCase) -> Problem {
    case.problem()
}

/// Growth options with `max_steps` and `a_stop`, the rest the scene defaults (taken from a
/// parsed scene, so that options added later keep their defaults).
fn growth(max_steps: usize, a_stop: f64) -> Growth {
    let scene: Table = [
        ("method".to_string(), s("xfem")),
        ("xfem".to_string(), tbl(&[("growth_steps", i(1))])),
    ]
    .into_iter()
    .collect();
    let Method::Xfem(x) = Problem::from_scene(&scene).unwrap().method else {
        panic!("an XFEM scene")
    };
    let mut g = x.growth.unwrap();
    g.max_steps = max_steps;
    g.a_stop = a_stop;
    g.da = None;
    g
}

#[test]
fn paper_edge_crack_growth_matches_the_reference() {
    let mut p = Problem::paper("xfem");
    let x = p.xfem_mut();
    x.extra_radii = vec![];
    x.growth = Some(growth(1000, 0.7 * 11.0));
    compare("paper 44 x 83", &p, 20);
}

/// The paper plate at 2x the paper's mesh in each direction (30 k unknowns): a supernodal factor
/// (44 x 83 is simplicial), so the condensed solves' backward half is faer's blocked L^T solve.
#[test]
fn paper_growth_on_a_supernodal_factor_matches_the_reference() {
    let mut p = Problem::paper("xfem");
    let x = p.xfem_mut();
    x.extra_radii = vec![];
    x.grid = rustfrac_core::problem::FeGrid::uniform(88, 166);
    x.growth = Some(growth(6, 0.7 * 11.0));
    compare("paper 88 x 166", &p, 6);
}

#[test]
fn inclined_edge_crack_growth_matches_the_reference() {
    // a 30 degree edge crack in the tall strip under traction: mixed mode, the crack kinks
    let mut c = tall_strip(vec![[0.0, 2.0], [0.3 * 0.866, 2.0 + 0.3 * 0.5]], 30, 121);
    c.growth = Some(paper_growth(0.6, 8));
    compare("inclined edge crack", &problem(&c), 8);
}

#[test]
fn predictor_corrector_growth_matches_the_reference() {
    // the corrector's trial solve goes through the same condensed solver (xfem.kink_rule)
    let mut c = tall_strip(vec![[0.0, 2.0], [0.3 * 0.866, 2.0 + 0.3 * 0.5]], 30, 121);
    c.growth = Some(paper_growth(0.6, 8));
    let mut p = problem(&c);
    if let Method::Xfem(x) = &mut p.method {
        x.growth.as_mut().unwrap().kink_rule = rustfrac_core::problem::KinkRule::PredictorCorrector;
    }
    compare("inclined edge crack, predictor-corrector", &p, 8);
}

#[test]
fn two_crack_growth_matches_the_reference() {
    // a longer and a shorter edge crack: the longer one grows first, then both
    let mut c = tall_strip(vec![[0.0, 2.0], [0.15, 2.0]], 30, 121);
    c.extra_cracks = vec![vec![[1.0, 2.0], [0.9, 2.0]]];
    c.growth = Some(paper_growth(0.35, 12));
    compare("two cracks", &problem(&c), 8);
}

#[test]
fn growth_towards_a_hole_matches_the_reference() {
    let mut p = Problem::paper("xfem");
    p.domain.holes.push(Hole {
        name: "hole[0]".into(),
        shape: Shape::Circle {
            center: [3.9, 10.5],
            radius: 0.75,
        },
    });
    if let Method::Xfem(x) = &mut p.method {
        x.extra_radii = vec![];
        x.growth = Some(growth(40, 8.0));
    }
    compare("hole", &p, 3);
}

/// The edge crack under shear (Moes et al. 1999) on a grid graded towards the crack, supports
/// and loads on regions: the crack kinks.
#[test]
fn graded_regions_growth_matches_the_reference() {
    let mut scene = edge_shear(14, 32);
    scene.insert(
        "mesh".into(),
        tbl(&[
            ("nx", i(14)),
            ("ny", i(32)),
            ("refine", Value::List(vec![f(2.5), f(6.5), f(5.5), f(9.5)])),
            ("refine_h", f(0.125)),
            ("grading", f(1.2)),
        ]),
    );
    scene.insert("xfem".into(), tbl(&[("growth_steps", i(6))]));
    let p = Problem::from_scene(&scene).unwrap();
    compare("graded, regions, shear", &p, 5);
}
