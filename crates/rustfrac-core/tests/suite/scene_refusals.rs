//! Scene refusals found where the mesh is built (a support box in a hole holds only fictitious
//! nodes), and a support's reaction: only what the support carries, in the components it
//! prescribes (equilibrium, a closed form). The refusals made before anything is built are
//! tested in the core (`problem/refusals_test.rs`).

use rustfrac_core::error::Error;
use rustfrac_core::fem_driver;
use rustfrac_core::problem::value::{Table, Value};
use rustfrac_core::problem::Problem;

use crate::common::scene_values::{f, pair, s, scene, tbl};

/// The key a scene is refused by.
fn refused(t: &Table) -> String {
    match Problem::from_scene(t) {
        Err(Error::InvalidInput { param, .. }) => param,
        Err(e) => panic!("refused with another error: {e}"),
        Ok(_) => panic!("accepted"),
    }
}

/// A 4 x 2 FEM plate pulled by normal tractions on its top and bottom edges (self-equilibrated),
/// held by `supports`.
fn pulled_plate(supports: Vec<Value>) -> Table {
    scene(&[
        ("method", s("fem")),
        ("plate", tbl(&[("width", f(4.0)), ("height", f(2.0))])),
        ("mesh", tbl(&[("nx", Value::Int(8)), ("ny", Value::Int(4))])),
        ("crack", tbl(&[("kind", s("none"))])),
        ("support", Value::List(supports)),
        (
            "load",
            Value::List(vec![
                tbl(&[
                    ("region", s("edge")),
                    ("side", s("top")),
                    ("normal", f(1.0)),
                ]),
                tbl(&[
                    ("region", s("edge")),
                    ("side", s("bottom")),
                    ("normal", f(1.0)),
                ]),
            ]),
        ),
    ])
}

#[test]
fn a_support_in_a_hole_is_refused() {
    let hole = Value::List(vec![tbl(&[
        ("shape", s("circle")),
        ("center", pair(2.0, 1.0)),
        ("radius", f(0.6)),
    ])]);
    let with = |sup: Value| {
        let mut t = pulled_plate(vec![
            tbl(&[("region", s("edge")), ("side", s("left")), ("fix", s("u1"))]),
            sup,
        ]);
        t.insert("hole".into(), hole.clone());
        t
    };
    // a point in the hole: refused by the scene's check
    let t = with(tbl(&[
        ("region", s("point")),
        ("point", pair(2.0, 1.0)),
        ("fix", s("u2")),
    ]));
    assert_eq!(refused(&t), "support[1].point");
    // a box in the hole holds only fictitious nodes: refused where the mesh is built
    let t = with(tbl(&[
        ("region", s("box")),
        ("box", Value::List(vec![f(1.8), f(0.8), f(2.2), f(1.2)])),
        ("fix", s("u2")),
    ]));
    let p = Problem::from_scene(&t).unwrap();
    match fem_driver::run(&p) {
        Err(Error::InvalidInput { param, .. }) => assert_eq!(param, "support[1].box"),
        other => panic!("{other:?}"),
    }
}

/// Under a self-equilibrated load the supports carry nothing (the uniaxial stress state is
/// exact for Q4 elements): a support on a loaded edge that fixes u1 only has no u2 reaction,
/// and every region's force sums to zero.
#[test]
fn a_support_reaction_holds_only_its_prescribed_components() {
    let t = pulled_plate(vec![
        tbl(&[("region", s("edge")), ("side", s("left")), ("fix", s("u1"))]),
        tbl(&[
            ("region", s("point")),
            ("point", pair(0.0, 0.0)),
            ("fix", s("u2")),
        ]),
    ]);
    let p = Problem::from_scene(&t).unwrap();
    let r = fem_driver::run(&p).unwrap();
    let force = |name: &str| {
        r.responses
            .regions
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, x)| x.force)
            .unwrap()
    };
    let applied = 4.0; // traction 1 on the 4-long edge, thickness 1
    let [s0, s1] = [force("support[0]"), force("support[1]")];
    assert_eq!(s0[1], 0.0, "support[0] fixes u1 only: {s0:?}");
    assert_eq!(s1[0], 0.0, "support[1] fixes u2 only: {s1:?}");
    for v in [s0[0], s1[1]] {
        assert!(v.abs() < 1e-10 * applied, "{s0:?} {s1:?}");
    }
    let [top, bottom] = [force("load[0]"), force("load[1]")];
    assert!((top[1] - applied).abs() < 1e-12 && (bottom[1] + applied).abs() < 1e-12);
    let sum: Vec<f64> = (0..2).map(|c| s0[c] + s1[c] + top[c] + bottom[c]).collect();
    assert!(sum.iter().all(|v| v.abs() < 1e-10 * applied), "{sum:?}");
}
