//! PD and CCM-PD check the rigid-body modes of their stiffness as FEM and XFEM do: supports
//! that leave a mode free, and a hole that cuts the plate in two with one part unsupported, are
//! refused before the run (statics: such a body has no equilibrium under a general load), naming
//! the free mode and the part.

use common::scene_values::{f, pair, s, scene, tbl};
use rustfrac_core::pd::analysis;
use rustfrac_core::problem::value::{Table, Value};
use rustfrac_core::problem::Problem;
use rustfrac_core::Error;

use crate::common;

/// A 4 x 2 plate of `method` (dx = 0.2, m = 3), no crack, with `support`, `load` and `hole`.
fn plate(method: &str, support: Vec<Value>, load: Vec<Value>, hole: Vec<Value>) -> Table {
    let mut t = scene(&[
        ("method", s(method)),
        ("plate", tbl(&[("width", f(4.0)), ("height", f(2.0))])),
        ("support", Value::List(support)),
        ("load", Value::List(load)),
        ("crack", Value::List(vec![tbl(&[("kind", s("none"))])])),
        (
            "pd",
            tbl(&[
                ("dx", f(0.2)),
                ("m", Value::Int(3)),
                ("sla_steps", Value::Int(5)),
                ("center", pair(2.0, 1.0)),
                ("size", pair(1.6, 1.2)),
            ]),
        ),
    ]);
    if !hole.is_empty() {
        t.insert("hole".into(), Value::List(hole));
    }
    t
}

fn point(x: f64, y: f64, fix: &str) -> Value {
    tbl(&[
        ("region", s("point")),
        ("point", pair(x, y)),
        ("fix", s(fix)),
    ])
}

fn edge(side: &str, key: &str, fix: Option<&str>) -> Value {
    match fix {
        Some(c) => tbl(&[("region", s("edge")), ("side", s(side)), ("fix", s(c))]),
        None => tbl(&[("region", s("edge")), ("side", s(side)), (key, f(1.0))]),
    }
}

/// The run's refusal (a singular-system error) and its message.
fn refused(t: &Table) -> String {
    let p = Problem::from_scene(t).unwrap();
    match analysis::run(&p, &common::go_on) {
        Err(e @ Error::Singular { .. }) => e.to_string(),
        Err(e) => panic!("refused for another reason: {e}"),
        Ok(r) => panic!(
            "ran to {} with |u| up to {:e}",
            r.run.status,
            r.reference.u.iter().fold(0.0f64, |a, v| a.max(v.abs()))
        ),
    }
}

#[test]
fn supports_leaving_a_mode_free_are_refused() {
    for method in ["pd", "ccm_pd"] {
        // two point supports fixing u1 only: the x2 translation is free
        let t = plate(
            method,
            vec![point(2.0, 0.0, "u1"), point(2.0, 2.0, "u1")],
            vec![edge("top", "normal", None), edge("bottom", "normal", None)],
            vec![],
        );
        let e = refused(&t);
        assert!(e.contains("x2 translation"), "{method}: {e}");
        // a shear load with only u2 fixed on the bottom edge: the x1 translation is free
        let t = plate(
            method,
            vec![edge("bottom", "", Some("u2"))],
            vec![edge("top", "shear", None)],
            vec![],
        );
        let e = refused(&t);
        assert!(e.contains("x1 translation"), "{method}: {e}");
    }
}

#[test]
fn a_hole_cutting_the_plate_in_two_is_refused() {
    // a slot across the whole height at x1 = 2: the right half holds no support
    let slot = tbl(&[
        ("shape", s("rect")),
        ("min", pair(1.9, -1.0)),
        ("max", pair(2.1, 3.0)),
    ]);
    let t = plate(
        "pd",
        vec![edge("left", "", Some("both"))],
        vec![edge("right", "normal", None)],
        vec![slot],
    );
    let e = refused(&t);
    assert!(e.contains("a part of the body"), "{e}");
    assert!(
        e.contains("[2.2000, 4.0000]"),
        "the right half is named: {e}"
    );
    // the same plate without the slot runs
    let t = plate(
        "pd",
        vec![edge("left", "", Some("both"))],
        vec![edge("right", "normal", None)],
        vec![],
    );
    analysis::run(&Problem::from_scene(&t).unwrap(), &common::go_on).unwrap();
}
