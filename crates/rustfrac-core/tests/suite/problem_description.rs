//! The problem description: a scene tree read into a `Problem` with the paper's defaults, and
//! every refusal naming the scene key (the Python package relies on `Error::param`).

use rustfrac_core::problem::value::{Table, Value};
use rustfrac_core::problem::Grip;
use rustfrac_core::problem::Plane;
use rustfrac_core::problem::Side;
use rustfrac_core::problem::{schema, CrackKind, Method, Problem};
use rustfrac_core::Error;

fn f(v: f64) -> Value {
    Value::Float(v)
}
fn i(v: i64) -> Value {
    Value::Int(v)
}
fn s(v: &str) -> Value {
    Value::Str(v.into())
}

/// A scene tree from (section, key, value) triples; "" as section for top-level keys.
fn scene(method: &str, entries: &[(&str, &str, Value)]) -> Table {
    let mut t = Table::new();
    t.insert("method".into(), s(method));
    for (sec, key, v) in entries {
        if sec.is_empty() {
            t.insert(key.to_string(), v.clone());
            continue;
        }
        let e = t
            .entry(sec.to_string())
            .or_insert_with(|| Value::Table(Table::new()));
        if let Value::Table(inner) = e {
            inner.insert(key.to_string(), v.clone());
        }
    }
    t
}

fn refused(t: &Table) -> Error {
    Problem::from_scene(t).expect_err("the scene must be refused")
}

/// The paper's case (Tuna et al., section 3; docs/design.md, "Units and the paper's conventions")
/// is every default.
#[test]
fn an_empty_scene_is_the_papers_case() {
    for m in schema::METHODS {
        let p = Problem::from_scene(&scene(m, &[])).unwrap();
        assert_eq!((p.domain.width, p.domain.height), (11.0, 21.0));
        let e = p.material.elastic;
        assert_eq!(
            (e.e, e.nu, e.plane, e.thickness),
            (10000.0, 0.25, Plane::Strain, 1.0)
        );
        assert_eq!(p.material.g0, 0.367);
        let l = p.boundary.plate_load();
        assert_eq!((l.grip, l.u0), (Grip::Free, 0.01));
        let c = p.cracks[0];
        let kind = if m == "fem" {
            CrackKind::Seam
        } else {
            CrackKind::Edge
        };
        assert_eq!((c.kind, c.a0, c.y, c.angle), (kind, 1.1, 10.5, 0.0));
        assert_eq!(p.crack_polylines()[0], vec![[0.0, 10.5], [1.1, 10.5]]);
        match &p.method {
            Method::Fem(x) => assert_eq!((x.grid.nx, x.grid.ny, x.gauss), (44, 83, 2)),
            Method::Xfem(x) => {
                assert_eq!((x.grid.nx, x.grid.ny, x.r_i), (44, 83, 2.5));
                assert_eq!((x.options.nsub, x.options.tip_nsub), (4, 4));
                assert!(x.growth.is_none());
            }
            Method::Pd(x) | Method::CcmPd(x) => {
                assert_eq!((x.dx, x.m, x.sla.max_steps), (1.0 / 15.0, 4, 500));
                if m == "ccm_pd" {
                    assert_eq!(x.regions.len(), 1);
                    let r = x.regions[0];
                    let want = [1.70 - 1.365, 10.5 - 0.835, 1.70 + 1.365, 10.5 + 0.835];
                    for (a, b) in r.iter().zip(want) {
                        assert!((a - b).abs() < 1e-12, "{r:?}");
                    }
                } else {
                    assert!(x.regions.is_empty());
                }
            }
        }
    }
}

#[test]
fn derived_values_are_the_cores() {
    // tip_nsub = 0 means nsub; growth: a_stop = 0 means 0.7 W; da = 0 one element length
    let p = Problem::from_scene(&scene(
        "xfem",
        &[("xfem", "nsub", i(6)), ("xfem", "growth_steps", i(1000))],
    ))
    .unwrap();
    let Method::Xfem(x) = &p.method else { panic!() };
    assert_eq!(x.options.tip_nsub, 6);
    let g = x.growth.unwrap();
    assert!((g.a_stop - 7.7).abs() < 1e-12 && g.da.is_none());
    // 44 elements over 11: da = 0.25, (7.7 - 1.1) / 0.25 + 1 = 27 steps
    assert_eq!(p.growth_steps_estimate(), Some(27));
    // traction grips prescribe no displacement
    let t = Problem::from_scene(&scene("xfem", &[("load", "bc", s("traction"))])).unwrap();
    assert_eq!(t.boundary.plate_load().u0, 0.0);
    // a crack on the right side starts at (W, y) and points to -x1
    let r = Problem::from_scene(&scene(
        "xfem",
        &[("crack", "side", s("right")), ("crack", "a0", f(2.0))],
    ))
    .unwrap();
    assert_eq!(r.cracks[0].side, Side::Right);
    assert_eq!(r.crack_polylines()[0], vec![[11.0, 10.5], [9.0, 10.5]]);
}

/// Every refusal names the scene key to change (no message parsing on the Python side).
#[test]
fn refusals_name_the_scene_key() {
    // (method, scene values, the key named)
    type Case<'a> = (&'a str, Vec<(&'a str, &'a str, Value)>, &'a str);
    let cases: Vec<Case> = vec![
        ("fem", vec![("material", "nu", f(0.5))], "material.nu"),
        ("fem", vec![("material", "E", f(f64::NAN))], "material.E"),
        ("fem", vec![("plate", "width", f(-1.0))], "plate.width"),
        ("fem", vec![("load", "bc", s("glued"))], "load.bc"),
        ("fem", vec![("mesh", "nx", i(0))], "mesh.nx"),
        (
            "fem",
            vec![("mesh", "nx", i(3000)), ("mesh", "ny", i(3000))],
            "mesh.nx * mesh.ny",
        ),
        ("xfem", vec![("xfem", "nsub", i(0))], "xfem.nsub"),
        (
            "xfem",
            vec![("xfem", "nsub", i(4)), ("xfem", "tip_nsub", i(2))],
            "xfem.tip_nsub",
        ),
        ("xfem", vec![("xfem", "a_stop", f(11.0))], "xfem.a_stop"),
        (
            "xfem",
            vec![("xfem", "a_stop", f(1.0)), ("xfem", "growth_steps", i(3))],
            "xfem.a_stop",
        ),
        ("xfem", vec![("crack", "a0", f(11.5))], "crack.a0"),
        ("xfem", vec![("crack", "kind", s("seam"))], "crack.kind"),
        ("fem", vec![("crack", "angle", f(10.0))], "crack.angle"),
        ("pd", vec![("material", "nu", f(0.3))], "material.nu"),
        ("pd", vec![("pd", "m", i(13))], "pd.m"),
        ("pd", vec![("pd", "dx", f(0.07))], "pd.dx"),
        (
            "ccm_pd",
            vec![("pd", "size", Value::List(vec![f(2.73), f(0.5)]))],
            "pd.size",
        ),
        (
            "ccm_pd",
            vec![("pd", "center", Value::List(vec![f(12.0), f(10.5)]))],
            "pd.center",
        ),
        (
            "ccm_pd",
            vec![("pd", "center", Value::List(vec![f(5.0), f(10.5)]))],
            "pd.center",
        ),
        (
            "pd",
            vec![("pd", "checkpoint_every", i(5))],
            "pd.checkpoint_path",
        ),
        // the culprit of a pre-crack along a PD node row is its height, not its length
        ("ccm_pd", vec![("crack", "y", f(10.0))], "crack.y"),
    ];
    for (method, entries, param) in cases {
        let e = refused(&scene(method, &entries));
        assert_eq!(e.param(), Some(param), "{method} {entries:?}: {e}");
        assert!(e.to_string().contains(param), "{e}");
    }
}

#[test]
fn kinds_and_unknown_keys_are_refused_by_name() {
    let e = refused(&scene("fem", &[("plate", "width", s("wide"))]));
    assert!(
        matches!(&e, Error::InvalidType { param, .. } if param == "plate.width"),
        "{e}"
    );
    assert!(e.to_string().contains("must be a number"), "{e}");
    let e = refused(&scene("fem", &[("plate", "widht", f(1.0))]));
    assert!(
        matches!(&e, Error::UnknownKey { param, .. } if param == "plate.widht"),
        "{e}"
    );
    assert!(
        e.to_string().contains("allowed in [plate]: width, height"),
        "{e}"
    );
    let e = refused(&scene("fem", &[("pd", "dx", f(0.1))]));
    assert!(
        e.to_string().contains("do not apply to method 'fem'"),
        "{e}"
    );
    let mut t = scene("fem", &[]);
    t.remove("method");
    assert!(matches!(refused(&t), Error::MissingKey { param, .. } if param == "method"));
    // [[crack]] tables: errors name crack[k]
    let mut t = scene("xfem", &[]);
    let crack = |a0: f64| {
        let mut c = Table::new();
        c.insert("a0".into(), f(a0));
        Value::Table(c)
    };
    t.insert("crack".into(), Value::List(vec![crack(1.1), crack(-1.0)]));
    assert_eq!(refused(&t).param(), Some("crack[1].a0"));
    // an integer beyond 64 bits is out of range, not of the wrong kind
    let big = Value::Other {
        type_name: "int".into(),
        repr: "an integer of 300 bits".into(),
    };
    let e = refused(&scene("fem", &[("mesh", "nx", big)]));
    assert!(
        matches!(&e, Error::InvalidInput { param, .. } if param == "mesh.nx"),
        "{e}"
    );
}

#[test]
fn crossing_cracks_are_refused() {
    let mut t = scene("xfem", &[]);
    let c = |side: &str, a0: f64, y: f64| {
        let mut c = Table::new();
        c.insert("side".into(), s(side));
        c.insert("a0".into(), f(a0));
        c.insert("y".into(), f(y));
        Value::Table(c)
    };
    t.insert(
        "crack".into(),
        Value::List(vec![c("left", 6.0, 10.5), c("right", 6.0, 10.5)]),
    );
    assert_eq!(refused(&t).param(), Some("crack[1]"));
    t.insert(
        "crack".into(),
        Value::List(vec![c("left", 2.0, 10.5), c("right", 2.0, 10.5)]),
    );
    assert_eq!(Problem::from_scene(&t).unwrap().cracks.len(), 2);
}

/// The crack-kind rule is the problem's, not only the scene's: a problem built in Rust with a
/// crack its method does not model is refused by name (it used to run uncracked).
#[test]
fn hand_built_problems_meet_the_crack_kind_rule() {
    let mut p = Problem::paper("fem");
    p.cracks[0].kind = CrackKind::Edge;
    let e = rustfrac_core::problem::validate::problem(&p).unwrap_err();
    assert_eq!(e.param(), Some("crack.kind"), "{e}");
    let mut x = Problem::paper("xfem");
    x.cracks.clear();
    let e = rustfrac_core::problem::validate::problem(&x).unwrap_err();
    assert_eq!(e.param(), Some("crack.kind"), "{e}");
    assert!(rustfrac_core::problem::validate::problem(&Problem::paper("fem")).is_ok());
}
