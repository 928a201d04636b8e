//! Every record a run emits matches the table: runs of each method on small scenes (FEM plain,
//! seam and with regions; XFEM single and growing, with probes; PD with damage snapshots and the
//! surface correction; CCM-PD with probes and an adaptive region), and records changed by hand
//! to show the check fails.

use super::check::check;
use super::record::{Group, Record, Value};
use super::schema::{entries, schema, Kind, Presence};
use super::status::statuses;
use crate::problem::value::{Table, Value as V};
use crate::problem::Problem;
use std::collections::BTreeSet;

fn t(kv: &[(&str, V)]) -> V {
    let mut m = Table::new();
    for (k, v) in kv {
        m.insert((*k).into(), v.clone());
    }
    V::Table(m)
}
fn s(x: &str) -> V {
    V::Str(x.into())
}
fn i(x: i64) -> V {
    V::Int(x)
}
fn f(x: f64) -> V {
    V::Float(x)
}
fn pair(a: f64, b: f64) -> V {
    V::List(vec![f(a), f(b)])
}
fn problem(kv: &[(&str, V)]) -> Problem {
    match t(kv) {
        V::Table(m) => Problem::from_scene(&m).expect("a valid scene"),
        _ => unreachable!(),
    }
}

/// The responses of a general scene: supports and loads on regions, a point probe and, with a
/// crack, an opening probe.
fn regions(crack_y: Option<f64>) -> Vec<(&'static str, V)> {
    let mut probes = vec![t(&[("name", s("corner")), ("point", pair(7.0, 16.0))])];
    if let Some(y) = crack_y {
        probes.push(t(&[
            ("name", s("mouth")),
            ("kind", s("opening")),
            ("point", pair(0.0, y)),
        ]));
    }
    vec![
        (
            "support",
            V::List(vec![
                t(&[("side", s("bottom"))]),
                t(&[
                    ("region", s("edge_part")),
                    ("side", s("left")),
                    ("from", f(4.0)),
                    ("to", f(6.0)),
                    ("fix", s("u1")),
                ]),
            ]),
        ),
        (
            "load",
            V::List(vec![
                t(&[("side", s("top")), ("shear", f(1.0))]),
                t(&[
                    ("region", s("point")),
                    ("point", pair(7.0, 16.0)),
                    ("force", pair(0.0, 0.5)),
                ]),
            ]),
        ),
        ("probe", V::List(probes)),
        ("plate", t(&[("width", f(7.0)), ("height", f(16.0))])),
        ("material", t(&[("E", f(3e7)), ("nu", f(0.25))])),
    ]
}

fn fem_records() -> Vec<(String, Record)> {
    let mesh = ("mesh", t(&[("nx", i(11)), ("ny", i(21))]));
    let seam = problem(&[("method", s("fem")), mesh.clone()]);
    let none = problem(&[
        ("method", s("fem")),
        mesh,
        ("crack", t(&[("kind", s("none"))])),
        ("load", t(&[("bc", s("clamped"))])),
    ]);
    let mut none = none;
    none.set_condition(false);
    let mut general = vec![
        ("method", s("fem")),
        ("mesh", t(&[("nx", i(14)), ("ny", i(32))])),
        ("crack", t(&[("kind", s("none"))])),
    ];
    general.extend(regions(None));
    let general = problem(&general);
    [
        ("fem seam", seam),
        ("fem uncracked", none),
        ("fem regions", general),
    ]
    .into_iter()
    .map(|(n, p)| {
        let r = crate::fem_driver::run(&p).expect("fem runs");
        (n.to_string(), r.into_record(&p))
    })
    .collect()
}

fn xfem_records() -> Vec<(String, Record)> {
    let quiet = |_: usize, _: usize| true;
    let mesh = ("mesh", t(&[("nx", i(22)), ("ny", i(42))]));
    let single = problem(&[("method", s("xfem")), mesh.clone()]);
    let growth = problem(&[
        ("method", s("xfem")),
        mesh.clone(),
        ("xfem", t(&[("growth_steps", i(2))])),
    ]);
    let mut traction = problem(&[
        ("method", s("xfem")),
        mesh,
        ("xfem", t(&[("growth_steps", i(2))])),
        ("load", t(&[("bc", s("traction"))])),
    ]);
    traction.set_condition(false);
    let mut general = vec![
        ("method", s("xfem")),
        ("mesh", t(&[("nx", i(14)), ("ny", i(32))])),
        (
            "crack",
            t(&[("kind", s("edge")), ("a0", f(3.5)), ("y", f(8.0))]),
        ),
        ("xfem", t(&[("growth_steps", i(2))])),
    ];
    general.extend(regions(Some(8.0)));
    let general = problem(&general);
    [
        ("xfem single", single),
        ("xfem growth", growth),
        ("xfem traction growth", traction),
        ("xfem regions growth", general),
    ]
    .into_iter()
    .map(|(n, p)| {
        let r = crate::xfem::run(&p, &quiet).expect("xfem runs");
        (n.to_string(), r.into_record(&p, 0.5))
    })
    .collect()
}

fn sla_records() -> Vec<(String, Record)> {
    let plate = ("plate", t(&[("width", f(4.0)), ("height", f(6.2))]));
    let crack = (
        "crack",
        t(&[("kind", s("edge")), ("a0", f(1.1)), ("y", f(3.1))]),
    );
    let pd = problem(&[
        ("method", s("pd")),
        plate.clone(),
        crack.clone(),
        (
            "pd",
            t(&[
                ("dx", f(0.2)),
                ("m", i(4)),
                ("sla_steps", i(20)),
                ("damage_at_steps", V::List(vec![i(5), i(10)])),
            ]),
        ),
    ]);
    let surface = problem(&[
        ("method", s("pd")),
        plate,
        crack,
        (
            "pd",
            t(&[
                ("dx", f(0.2)),
                ("m", i(3)),
                ("sla_steps", i(5)),
                ("surface_correction", s("energy")),
                ("s0_calibration", s("grid")),
            ]),
        ),
    ]);
    let mut general = vec![
        ("method", s("ccm_pd")),
        (
            "crack",
            t(&[("kind", s("edge")), ("a0", f(3.5)), ("y", f(8.1))]),
        ),
        (
            "pd",
            t(&[
                ("dx", f(0.2)),
                ("center", pair(3.5, 8.1)),
                ("size", pair(3.2, 3.2)),
                ("sla_steps", i(3)),
            ]),
        ),
    ];
    general.extend(regions(Some(8.1)));
    let general = problem(&general);
    let adaptive = problem(&[
        ("method", s("ccm_pd")),
        (
            "pd",
            t(&[
                ("dx", f(0.2)),
                ("sla_steps", i(320)),
                ("region", s("adaptive")),
                ("adapt_margin", f(1.5)),
                ("adapt_size", f(2.5)),
            ]),
        ),
    ]);
    [
        ("pd", pd),
        ("pd surface correction", surface),
        ("ccm_pd regions", general),
        ("ccm_pd adaptive", adaptive),
    ]
    .into_iter()
    .map(|(n, p)| {
        let r = crate::pd::analysis::run(&p, &|_, _| true).expect("the SLA runs");
        (n.to_string(), r.into_record(&p, 0.5).expect("a record"))
    })
    .collect()
}

/// The keys a record holds, as "group.name" with nested tables' keys as "group.table.key",
/// each matched to its table entry's name.
fn emitted(rec: &Record, out: &mut BTreeSet<(String, Group, &'static str)>) {
    fn walk(
        rec: &Record,
        g: Group,
        prefix: &str,
        es: &super::record::Entries,
        out: &mut BTreeSet<(String, Group, &'static str)>,
    ) {
        for (k, v) in es.iter() {
            let name = format!("{prefix}{k}");
            if let Some(e) = super::schema::entry(rec.method, g, &name) {
                out.insert((rec.method.to_string(), g, e.name));
                let nested = match v {
                    Value::Table(t) => vec![t],
                    Value::List(l) => l
                        .iter()
                        .filter_map(|x| match x {
                            Value::Table(t) => Some(t),
                            _ => None,
                        })
                        .collect(),
                    _ => vec![],
                };
                for t in nested {
                    walk(rec, g, &format!("{}.", e.name), t, out);
                }
            }
        }
    }
    for g in Group::ALL {
        walk(rec, g, "", rec.group(g), out);
    }
}

#[test]
fn every_record_matches_the_table_and_every_entry_is_emitted() {
    let mut runs = fem_records();
    runs.extend(xfem_records());
    runs.extend(sla_records());
    let mut seen = BTreeSet::new();
    let mut methods = BTreeSet::new();
    for (name, rec) in &runs {
        let problems = check(rec);
        assert!(problems.is_empty(), "{name}: {problems:#?}");
        emitted(rec, &mut seen);
        methods.insert(rec.method);
    }
    assert_eq!(methods.len(), 4, "every method ran");
    // every entry the core emits is emitted by one of these runs (of one of its methods): the
    // table holds no name that no run produces (the Python-added ones aside)
    let missed: Vec<String> = schema()
        .iter()
        .filter(|e| !matches!(e.presence, Presence::Python(_)))
        .filter(|e| {
            let names = e.methods.names();
            !names
                .iter()
                .any(|m| seen.contains(&(m.to_string(), e.group, e.name)))
        })
        .map(|e| format!("{:?}: {}.{}", e.methods.names(), e.group.name(), e.name))
        .collect();
    assert!(missed.is_empty(), "entries no run emitted: {missed:#?}");
}

/// A small record of each method, for the mutations.
fn small() -> Vec<Record> {
    let mut v: Vec<Record> = fem_records().into_iter().take(1).map(|x| x.1).collect();
    v.extend(xfem_records().into_iter().skip(1).take(1).map(|x| x.1));
    v.extend(sla_records().into_iter().take(1).map(|x| x.1));
    v
}

#[test]
fn the_check_fails_on_a_renamed_missing_misshaped_or_mistyped_entry() {
    for rec in small() {
        assert!(check(&rec).is_empty(), "{}: {:?}", rec.method, check(&rec));
        // a renamed key: unknown, and its entry missing
        let mut r = rec.clone();
        let (k, v) = r
            .fields
            .iter()
            .next()
            .map(|(k, v)| (k.to_string(), v.clone()))
            .unwrap();
        r.fields.remove(&k);
        r.fields.set(format!("{k}_renamed"), v);
        let p = check(&r);
        assert!(
            p.iter().any(|x| x.contains("not in the result schema")),
            "{p:?}"
        );
        assert!(p.iter().any(|x| x.contains("missing")), "{p:?}");
        // a wrong shape: a 2-D array flattened
        let mut r = rec.clone();
        let key = r
            .fields
            .iter()
            .find(|(_, v)| matches!(v, Value::Floats { shape, .. } if shape.len() == 2))
            .map(|(k, _)| k.to_string())
            .unwrap();
        if let Some(Value::Floats { data, .. }) = r.fields.get(&key).cloned() {
            r.fields.set(key.clone(), Value::floats(data));
        }
        assert!(check(&r).iter().any(|x| x.contains(&key)), "{key}: shape");
        // a wrong kind: an int where a float belongs, None where it may not be
        let mut r = rec.clone();
        r.headline.set("sigma22", Value::Int(1));
        r.meta.set("method", Value::None);
        let p = check(&r);
        assert!(p.iter().any(|x| x.starts_with("headline.sigma22")), "{p:?}");
        assert!(p.iter().any(|x| x.starts_with("meta.method")), "{p:?}");
        // a size named alike that disagrees: one more node's displacement
        let mut r = rec.clone();
        if let Some(Value::Floats { mut data, .. }) = r.fields.get("u").cloned() {
            data.extend([0.0, 0.0]);
            r.fields.set("u", Value::floats(data));
        }
        assert!(
            check(&r).iter().any(|x| x.contains("n_nodes")),
            "{:?}",
            check(&r)
        );
        // a nested table's key, and an unknown status
        let mut r = rec.clone();
        if let Some(Value::Table(mut tm)) = r.meta.get("timings").cloned() {
            tm.set("python_s", 1.0);
            r.meta.set("timings", tm);
        }
        if r.meta.get("status").is_some() {
            r.meta.set("status", "finished");
            assert!(check(&r).iter().any(|x| x.contains("not a status")));
        }
        assert!(check(&r)
            .iter()
            .any(|x| x.contains("meta.timings.python_s")));
    }
}

#[test]
fn the_table_is_well_formed() {
    for m in crate::problem::schema::METHODS {
        let es: Vec<_> = entries(m).collect();
        for (k, a) in es.iter().enumerate() {
            // no two entries of a method and group name the same key
            for b in &es[k + 1..] {
                assert!(
                    a.group != b.group || a.name != b.name,
                    "{m}: {}.{} twice",
                    a.group.name(),
                    a.name
                );
            }
            // a nested entry's table exists and is a table
            if let Some((parent, _)) = a.name.rsplit_once('.') {
                let p = es.iter().find(|e| e.group == a.group && e.name == parent);
                assert!(
                    p.is_some_and(|p| matches!(p.kind, Kind::Table | Kind::TableList)),
                    "{m}: {} has no table {parent}",
                    a.name
                );
            }
            // history columns are 1-D arrays of the rows
            if a.group == Group::History {
                assert!(matches!(
                    a.kind.shape(),
                    Some([super::schema::Dim::Var("n_rows")])
                ));
            }
            assert!(!a.doc.is_empty(), "{m}: {} has no meaning", a.name);
        }
    }
    // statuses: unique names, each with a meaning
    for m in ["xfem", "pd", "ccm_pd"] {
        let st = statuses(m);
        let names: BTreeSet<_> = st.iter().map(|x| x.name).collect();
        assert!(!st.is_empty() && names.len() == st.len());
        assert!(st.iter().all(|x| !x.doc.is_empty()));
    }
    assert!(statuses("fem").is_empty());
}
