//! Scene refusals: what a scene asks that cannot be honoured is refused by name before anything
//! is built (sizes counted in closed form, names that would collide, regions past their edge, a
//! pre-crack that would leave FEM nodes without stiffness). Those found where the mesh is built,
//! and the reactions, are tested with the drivers (`tests/suite/scene_refusals.rs`).

use super::value::{Table, Value};
use super::Problem;
use crate::error::Error;

fn s(v: &str) -> Value {
    Value::Str(v.into())
}
fn f(v: f64) -> Value {
    Value::Float(v)
}
fn pair(a: f64, b: f64) -> Value {
    Value::List(vec![f(a), f(b)])
}
fn tbl(kv: &[(&str, Value)]) -> Value {
    Value::Table(kv.iter().map(|(k, v)| (k.to_string(), v.clone())).collect())
}
fn scene(kv: &[(&str, Value)]) -> Table {
    kv.iter().map(|(k, v)| (k.to_string(), v.clone())).collect()
}

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
fn a_graded_grid_too_fine_is_refused_before_its_lines_are_built() {
    for h in [1e-8, 1e-30] {
        let t = scene(&[
            ("method", s("xfem")),
            (
                "mesh",
                tbl(&[
                    (
                        "refine",
                        Value::List(vec![f(0.5), f(10.0), f(2.5), f(11.0)]),
                    ),
                    ("refine_h", f(h)),
                    ("grading", f(1.0)),
                ]),
            ),
        ]);
        assert_eq!(refused(&t), "mesh.refine_h", "refine_h = {h}");
    }
}

#[test]
fn grid_lines_too_few_are_refused_as_mesh_xs() {
    let t = scene(&[
        ("method", s("fem")),
        ("mesh", tbl(&[("xs", Value::List(vec![f(1.0)]))])),
    ]);
    assert_eq!(refused(&t), "mesh.xs");
}

#[test]
fn two_probes_of_one_name_are_refused() {
    let probe = |name: &str, x: f64| {
        tbl(&[
            ("name", s(name)),
            ("point", pair(x, 5.0)),
            ("kind", s("displacement")),
        ])
    };
    for probes in [
        vec![probe("a", 3.0), probe("a", 4.0)],
        // a name equal to another probe's default name probe[1]
        vec![probe("probe[1]", 3.0), probe("", 4.0)],
    ] {
        let t = scene(&[("method", s("fem")), ("probe", Value::List(probes))]);
        assert_eq!(refused(&t), "probe[1].name");
    }
}

#[test]
fn a_load_past_its_edge_is_refused_not_clipped() {
    let load = |from: f64, to: f64| {
        tbl(&[
            ("region", s("edge_part")),
            ("side", s("top")),
            ("from", f(from)),
            ("to", f(to)),
            ("normal", f(1.0)),
        ])
    };
    let sup = tbl(&[("region", s("edge")), ("side", s("bottom"))]);
    for (from, to, key) in [(-1.0, 2.0, "load[0].from"), (1.0, 5.0, "load[0].to")] {
        let mut t = pulled_plate(vec![sup.clone()]);
        t.insert("load".into(), Value::List(vec![load(from, to)]));
        assert_eq!(refused(&t), key);
    }
    let mut t = pulled_plate(vec![sup]);
    t.insert("load".into(), Value::List(vec![load(0.0, 4.0)]));
    assert!(Problem::from_scene(&t).is_ok());
}

#[test]
fn an_inclined_pre_crack_leaving_the_pd_rectangle_is_refused() {
    let t = scene(&[
        ("method", s("ccm_pd")),
        ("crack", tbl(&[("angle", f(30.0))])),
    ]);
    assert_eq!(refused(&t), "pd.center");
    // the paper's crack along x1 leaves the rectangle too, in a strip of removed elements
    let t = scene(&[("method", s("ccm_pd"))]);
    assert!(Problem::from_scene(&t).is_ok());
}
