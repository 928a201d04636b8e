//! The scene keys of a [`Problem`]: every section the method reads, with every key of the
//! [`schema`] and the value the problem holds (resolved: `xfem.tip_nsub` as the subdivision
//! used, a graded grid as its lines, `pd.fast = false` as `pd.engine = "oracle"`), the inverse of
//! [`super::parse`]. A problem built in Rust has its keys too, so a rule over keys (the
//! checkpoint fingerprint, `crate::pd::sla::checkpoint`) reads any problem through the table.

use super::key_value::{crack_name, Section};
use super::schema::{self, Val};
use super::value::{Table, Value};
use super::{
    Boundary, CrackKind, FeGrid, LoadKind, Method, PdMethod, Plane, ProbeKind, Problem, Region,
    Shape, Side,
};

/// One section of a problem's scene: its schema section, its scene name (`crack[1]`,
/// `hole[0]`, `load[2]`: the entries of a list are numbered) and every key's value.
#[derive(Debug, Clone, PartialEq)]
pub struct Entry {
    pub section: &'static str,
    pub name: String,
    pub values: Section,
}

/// Every key of `section` at its default.
fn defaults(section: &str) -> Section {
    schema::section_keys(section)
        .map(|k| (k.key, k.default.clone()))
        .collect()
}

fn entry(section: &'static str, name: String, set: &[(&'static str, Val)]) -> Entry {
    let mut values = defaults(section);
    for (k, v) in set {
        debug_assert!(values.contains_key(k), "{section}.{k} is a schema key");
        values.insert(k, v.clone());
    }
    Entry {
        section,
        name,
        values,
    }
}

fn int(n: usize) -> Val {
    Val::Int(i64::try_from(n).unwrap_or(i64::MAX))
}

fn s(v: &str) -> Val {
    Val::Str(v.into())
}

fn grid(g: &FeGrid) -> Vec<(&'static str, Val)> {
    vec![
        ("nx", int(g.nx)),
        ("ny", int(g.ny)),
        ("xs", Val::FloatList(g.xs.clone())),
        ("ys", Val::FloatList(g.ys.clone())),
    ]
}

fn pd(p: &PdMethod) -> Vec<(&'static str, Val)> {
    let sla = &p.sla;
    let mut v = vec![
        ("dx", Val::Float(p.dx)),
        ("m", int(p.m)),
        (
            "region",
            s(if p.adaptive.is_some() {
                "adaptive"
            } else {
                "fixed"
            }),
        ),
        ("fem_grading", Val::Float(p.fem_grading)),
        ("fem_coarse", Val::Float(p.fem_coarse)),
        ("sla_steps", int(sla.max_steps)),
        ("tie_tol", Val::Float(sla.tie_tol)),
        ("refactor_every", int(sla.refactor_every)),
        ("hole_volumes", s(p.hole_volumes.name())),
        ("surface_correction", s(p.surface_correction.name())),
        ("fast", Val::Bool(true)),
        ("engine", s(sla.engine.name())),
        ("s0_calibration", s(p.s0_calibration.name())),
        ("model", s(p.model.name())),
        ("influence", s(p.influence.name())),
        (
            "stop_crack_length",
            Val::Float(sla.stop_crack_length.unwrap_or(0.0)),
        ),
        (
            "damage_at_steps",
            Val::IntList(sla.damage_at_steps.iter().map(|&k| k as i64).collect()),
        ),
        ("checkpoint_every", int(sla.checkpoint_every)),
    ];
    let path = |p: &Option<std::path::PathBuf>| {
        s(&p.as_ref()
            .map(|p| p.display().to_string())
            .unwrap_or_default())
    };
    v.push(("checkpoint_path", path(&sla.checkpoint_path)));
    v.push(("resume_from", path(&sla.resume_from)));
    if let Some(a) = &p.adaptive {
        v.push(("adapt_margin", Val::Float(a.margin)));
        v.push(("adapt_size", Val::Float(a.size)));
    } else if let Some(r) = p.regions.first() {
        let centre = [0.5 * (r[0] + r[2]), 0.5 * (r[1] + r[3])];
        v.push(("center", Val::Pair(centre)));
        v.push(("size", Val::Pair([r[2] - r[0], r[3] - r[1]])));
    }
    v
}

fn region(r: &Region) -> Vec<(&'static str, Val)> {
    match *r {
        Region::Edge(side) => vec![("region", s("edge")), ("side", s(side.name()))],
        Region::EdgePart { side, from, to } => vec![
            ("region", s("edge_part")),
            ("side", s(side.name())),
            ("from", Val::Float(from)),
            ("to", Val::Float(to)),
        ],
        Region::Point(q) => vec![("region", s("point")), ("point", Val::Pair(q))],
        Region::Box(b) => vec![("region", s("box")), ("box", Val::FloatList(b.to_vec()))],
    }
}

/// A notch as the scene states it, from the rectangle [`super::parse`] made of it (the
/// rectangle reaches `depth` beyond the edge it is cut from).
fn notch(min: [f64; 2], max: [f64; 2], width: f64, height: f64) -> Vec<(&'static str, Val)> {
    let (side, at, w, depth) = if min[1] < 0.0 {
        (
            Side::Bottom,
            0.5 * (min[0] + max[0]),
            max[0] - min[0],
            max[1],
        )
    } else if max[1] > height {
        (
            Side::Top,
            0.5 * (min[0] + max[0]),
            max[0] - min[0],
            height - min[1],
        )
    } else if min[0] < 0.0 {
        (Side::Left, 0.5 * (min[1] + max[1]), max[1] - min[1], max[0])
    } else {
        (
            Side::Right,
            0.5 * (min[1] + max[1]),
            max[1] - min[1],
            width - min[0],
        )
    };
    vec![
        ("side", s(side.name())),
        ("at", Val::Float(at)),
        ("width", Val::Float(w)),
        ("depth", Val::Float(depth)),
    ]
}

/// The scene of a problem: the method's sections (in [`schema::method_sections`] order, the
/// cracks as `crack`, `crack[1]`, ...; no crack as one of kind "none"), then the entries of the
/// general scene's lists ([`schema::LIST_SECTIONS`] order).
pub fn scene_of(p: &Problem) -> Vec<Entry> {
    let method = p.method.name();
    let (d, m) = (&p.domain, &p.material);
    let mut out = Vec::new();
    for &sec in schema::method_sections(method) {
        let one = |set: &[(&'static str, Val)]| entry(sec, sec.into(), set);
        match sec {
            "plate" => out.push(one(&[
                ("width", Val::Float(d.width)),
                ("height", Val::Float(d.height)),
            ])),
            "material" => out.push(one(&[
                ("E", Val::Float(m.elastic.e)),
                ("nu", Val::Float(m.elastic.nu)),
                (
                    "plane",
                    s(match m.elastic.plane {
                        Plane::Strain => "strain",
                        Plane::Stress => "stress",
                    }),
                ),
                ("thickness", Val::Float(m.elastic.thickness)),
                ("G0", Val::Float(m.g0)),
            ])),
            "load" => out.push(match &p.boundary {
                Boundary::Grips(l) => one(&[
                    ("bc", s(l.grip.name())),
                    ("u0", Val::Float(l.u0)),
                    ("traction", Val::Float(l.traction)),
                ]),
                // the grips keep their defaults beside supports and loads on regions
                Boundary::Regions { .. } => one(&[]),
            }),
            "crack" if p.cracks.is_empty() => out.push(one(&[("kind", s("none"))])),
            "crack" => out.extend(p.cracks.iter().enumerate().map(|(k, c)| {
                let kind = match c.kind {
                    CrackKind::Seam => "seam",
                    CrackKind::Edge => "edge",
                    CrackKind::Center => "center",
                };
                entry(
                    "crack",
                    crack_name(k),
                    &[
                        ("kind", s(kind)),
                        ("a0", Val::Float(c.a0)),
                        ("y", Val::Float(c.y)),
                        ("angle", Val::Float(c.angle)),
                        ("x", Val::Float(c.x)),
                        ("side", s(c.side.name())),
                    ],
                )
            })),
            "mesh" => out.push(match &p.method {
                Method::Fem(f) => {
                    let mut v = grid(&f.grid);
                    v.push(("gauss", int(f.gauss)));
                    one(&v)
                }
                Method::Xfem(x) => one(&grid(&x.grid)),
                _ => one(&[]),
            }),
            "xfem" => {
                let Method::Xfem(x) = &p.method else {
                    continue;
                };
                let o = &x.options;
                let mut v = vec![
                    ("nsub", int(o.nsub)),
                    ("tip_nsub", int(o.tip_nsub)),
                    ("r_I", Val::Float(x.r_i)),
                    (
                        "fixed_area_radius",
                        Val::Float(o.fixed_area_radius.unwrap_or(0.0)),
                    ),
                    ("area_threshold", Val::Float(o.area_threshold)),
                    ("tip_tie_tol", Val::Float(x.tip_tie_tol)),
                ];
                if let Some(g) = &x.growth {
                    v.extend([
                        ("growth_steps", int(g.max_steps)),
                        ("da", Val::Float(g.da.unwrap_or(0.0))),
                        ("kink_rule", s(g.kink_rule.name())),
                        ("a_stop", Val::Float(g.a_stop)),
                        ("state_every", int(g.state_every)),
                    ]);
                }
                out.push(one(&v));
            }
            "pd" => {
                if let Some(pm) = p.pd() {
                    out.push(one(&pd(pm)));
                }
            }
            _ => {}
        }
    }
    let (mut holes, mut notches) = (Vec::new(), Vec::new());
    for h in &d.holes {
        match &h.shape {
            Shape::Rect { min, max } if h.name.starts_with("notch") => {
                notches.push(notch(*min, *max, d.width, d.height));
            }
            Shape::Rect { min, max } => holes.push(vec![
                ("shape", s("rect")),
                ("min", Val::Pair(*min)),
                ("max", Val::Pair(*max)),
            ]),
            Shape::Circle { center, radius } => holes.push(vec![
                ("shape", s("circle")),
                ("center", Val::Pair(*center)),
                ("radius", Val::Float(*radius)),
            ]),
            Shape::Polygon(v) => holes.push(vec![
                ("shape", s("polygon")),
                ("points", Val::PairList(v.clone())),
            ]),
        }
    }
    let (mut supports, mut loads) = (Vec::new(), Vec::new());
    if let Boundary::Regions {
        supports: sup,
        loads: ld,
    } = &p.boundary
    {
        for x in sup {
            let mut v = region(&x.region);
            let fix = match (x.u1, x.u2) {
                (Some(_), None) => "u1",
                (None, Some(_)) => "u2",
                _ => "both",
            };
            v.extend([
                ("fix", s(fix)),
                ("u1", Val::Float(x.u1.unwrap_or(0.0))),
                ("u2", Val::Float(x.u2.unwrap_or(0.0))),
            ]);
            supports.push(v);
        }
        for x in ld {
            let mut v = region(&x.region);
            match x.kind {
                LoadKind::Force(f) => v.push(("force", Val::Pair(f))),
                LoadKind::Traction { normal, shear } => {
                    v.extend([("normal", Val::Float(normal)), ("shear", Val::Float(shear))]);
                }
            }
            loads.push(v);
        }
    }
    let probes = p.probes.iter().map(|x| {
        let mut v = vec![("name", s(&x.name))];
        match x.kind {
            ProbeKind::Displacement(q) => v.push(("point", Val::Pair(q))),
            ProbeKind::Opening { point, crack } => v.extend([
                ("kind", s("opening")),
                ("point", Val::Pair(point)),
                ("crack", int(crack)),
            ]),
        }
        v
    });
    let probes: Vec<_> = probes.collect();
    for &(key, sec) in &schema::LIST_SECTIONS {
        let list = match key {
            "hole" => &holes,
            "notch" => &notches,
            "support" => &supports,
            "load" => &loads,
            _ => &probes,
        };
        for (k, set) in list.iter().enumerate() {
            out.push(entry(sec, format!("{key}[{k}]"), set));
        }
    }
    out
}

/// The scene tree of a problem ([`scene_of`] as the tree [`super::Problem::from_scene`] reads:
/// the cracks as a `[[crack]]` list, the general scene's lists under their scene keys, no
/// `[load]` grips beside supports and loads on regions).
pub fn tree(p: &Problem) -> Table {
    let mut t = Table::new();
    t.insert("method".into(), Value::Str(p.method.name().into()));
    t.insert("name".into(), Value::Str(p.name.clone()));
    let regions = matches!(p.boundary, Boundary::Regions { .. });
    let table = |e: &Entry| {
        Value::Table(
            e.values
                .iter()
                .map(|(k, v)| (k.to_string(), v.to_value()))
                .collect(),
        )
    };
    let mut lists: Vec<(&str, Vec<Value>)> = Vec::new();
    for e in scene_of(p) {
        let listed = schema::LIST_SECTIONS
            .iter()
            .find(|(_, sec)| *sec == e.section)
            .map(|(key, _)| *key);
        let key = match (e.section, listed) {
            ("crack", _) => "crack",
            ("load", None) if regions => continue,
            (_, Some(key)) => key,
            (sec, None) => {
                t.insert(sec.into(), table(&e));
                continue;
            }
        };
        match lists.iter_mut().find(|(k, _)| *k == key) {
            Some((_, l)) => l.push(table(&e)),
            None => lists.push((key, vec![table(&e)])),
        }
    }
    for (k, l) in lists {
        t.insert(k.into(), Value::List(l));
    }
    t
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// A table of every key of `section`, at its default but for `set`.
    fn full(section: &str, set: &[(&str, Value)]) -> Value {
        let mut t: Table = schema::section_keys(section)
            .map(|k| (k.key.to_string(), k.default.to_value()))
            .collect();
        for (k, v) in set {
            assert!(t.contains_key(*k), "{section}.{k}");
            t.insert(k.to_string(), v.clone());
        }
        Value::Table(t)
    }

    fn pair(a: f64, b: f64) -> Value {
        Value::List(vec![Value::Float(a), Value::Float(b)])
    }

    fn str(v: &str) -> Value {
        Value::Str(v.into())
    }

    /// CCM-PD scenes stating every key of every section they read (so that a test can change
    /// any one of them): the paper's grips with holes of each shape, a notch and probes of each
    /// kind, on a fixed and on an adaptive PD region; and supports and loads on regions of each
    /// kind.
    pub(crate) fn scenes() -> Vec<Table> {
        let base = |region: &str| {
            let mut t = Table::new();
            t.insert("method".into(), str("ccm_pd"));
            for sec in ["plate", "material"] {
                t.insert(sec.into(), full(sec, &[]));
            }
            t.insert(
                "crack".into(),
                Value::List(vec![full("crack", &[("kind", str("edge"))])]),
            );
            t.insert("pd".into(), full("pd", &[("region", str(region))]));
            t
        };
        let mut grips = base("fixed");
        grips.insert("load".into(), full("load", &[]));
        let hole = |set: &[(&str, Value)]| full("hole", set);
        grips.insert(
            "hole".into(),
            Value::List(vec![
                hole(&[("center", pair(8.0, 15.0)), ("radius", Value::Float(1.0))]),
                hole(&[
                    ("shape", str("rect")),
                    ("min", pair(7.0, 3.0)),
                    ("max", pair(8.0, 4.0)),
                ]),
                hole(&[
                    ("shape", str("polygon")),
                    (
                        "points",
                        Value::List(vec![pair(9.0, 16.0), pair(10.0, 16.0), pair(9.5, 17.0)]),
                    ),
                ]),
            ]),
        );
        let notch = [("at", Value::Float(8.0)), ("width", Value::Float(0.5))];
        let notch = full(
            "notch",
            &[
                notch[0].clone(),
                notch[1].clone(),
                ("depth", Value::Float(0.5)),
            ],
        );
        grips.insert("notch".into(), Value::List(vec![notch]));
        grips.insert(
            "probe".into(),
            Value::List(vec![
                full("probe", &[("point", pair(1.0, 1.0))]),
                full(
                    "probe",
                    &[
                        ("kind", str("opening")),
                        ("point", pair(1.5, 10.5)),
                        ("name", str("cod")),
                    ],
                ),
            ]),
        );
        let mut adaptive = grips.clone();
        adaptive.insert("pd".into(), full("pd", &[("region", str("adaptive"))]));
        let mut regions = base("fixed");
        let sup = |set: &[(&str, Value)]| full("support", set);
        regions.insert(
            "support".into(),
            Value::List(vec![
                sup(&[]),
                sup(&[
                    ("region", str("edge_part")),
                    ("side", str("left")),
                    ("from", Value::Float(1.0)),
                    ("to", Value::Float(2.0)),
                    ("fix", str("u1")),
                ]),
                sup(&[
                    ("region", str("point")),
                    ("point", pair(11.0, 0.0)),
                    ("fix", str("u2")),
                ]),
                sup(&[
                    ("region", str("box")),
                    (
                        "box",
                        Value::List([0.0, 20.0, 1.0, 21.0].map(Value::Float).to_vec()),
                    ),
                ]),
            ]),
        );
        let load = |set: &[(&str, Value)]| full("region_load", set);
        regions.insert(
            "load".into(),
            Value::List(vec![
                load(&[("normal", Value::Float(1.0))]),
                load(&[
                    ("region", str("edge_part")),
                    ("side", str("right")),
                    ("from", Value::Float(5.0)),
                    ("to", Value::Float(6.0)),
                    ("shear", Value::Float(0.5)),
                ]),
                load(&[
                    ("region", str("point")),
                    ("point", pair(11.0, 21.0)),
                    ("force", pair(0.0, 1.0)),
                ]),
            ]),
        );
        vec![grips, adaptive, regions]
    }

    /// Two values within rounding (a PD rectangle's centre and size computed back from its
    /// corners).
    fn close(a: &Val, b: &Val) -> bool {
        let near = |x: f64, y: f64| (x - y).abs() <= 1e-12 * x.abs().max(y.abs()).max(1.0);
        match (a, b) {
            (Val::Float(x), Val::Float(y)) => near(*x, *y),
            (Val::Pair(x), Val::Pair(y)) => near(x[0], y[0]) && near(x[1], y[1]),
            _ => a == b,
        }
    }

    /// The scene of a problem reads back as the same scene: every method's paper problem and
    /// the test scenes.
    #[test]
    fn scene_of_reads_back() {
        let mut problems: Vec<Problem> =
            schema::METHODS.iter().map(|m| Problem::paper(m)).collect();
        problems.extend(
            scenes()
                .iter()
                .map(|t| super::super::parse::problem(t).expect("a scene")),
        );
        for p in problems {
            let again = super::super::parse::problem(&tree(&p)).expect("the scene of a problem");
            let (a, b) = (scene_of(&p), scene_of(&again));
            assert_eq!(a.len(), b.len());
            for (x, y) in a.iter().zip(&b) {
                assert_eq!((x.section, &x.name), (y.section, &y.name));
                for (k, v) in &x.values {
                    assert!(
                        close(v, &y.values[k]),
                        "{}.{k}: {v:?} vs {:?}",
                        x.name,
                        y.values[k]
                    );
                }
            }
        }
    }
}
