//! Reading a scene tree into a [`Problem`]: the method, the sections it reads, unknown keys,
//! each key's kind and range ([`schema`]), defaults and the values derived from them (the crack
//! kind of a scene without `[crack]`, tip_nsub = 0 meaning nsub, a_stop = 0 meaning 0.7 W, the
//! PD rectangle from its centre and size). Cross-parameter checks follow in [`super::validate`].

// the negated comparisons are deliberate: they refuse NaN too
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use super::grading::{graded_count, graded_lines};
pub use super::key_value::{crack_name, Section};
use super::pd_region;
use super::schema::{self, Kind, Val};
use super::value::{Table, Value};
use super::{AdaptiveRegion, Elastic, Grip, KinkRule, Plane, PlateLoad, S0Calibration, Side};
use super::{
    Boundary, CrackKind, CrackSpec, Domain, FeGrid, FemMethod, Growth, Hole, HoleVolumes, LoadKind,
    Material, Method, PdMethod, Probe, ProbeKind, Problem, Region, RegionLoad, Shape, SlaParams,
    Support, XfemMethod, XfemOptions,
};
use crate::error::{Error, Result};
use std::collections::BTreeMap;
use std::path::PathBuf;

fn type_error(param: &str, kind: Kind, valid: &str, v: &Value) -> Error {
    let got = match kind {
        Kind::Pair | Kind::IntList | Kind::FloatList | Kind::PairList => v.repr(),
        _ => format!("{} {}", v.type_name(), v.repr()),
    };
    Error::InvalidType {
        param: param.to_string(),
        expected: format!("{} ({valid})", kind.phrase()),
        got,
    }
}

fn numbers(list: &[Value]) -> Option<Vec<f64>> {
    list.iter().map(Value::as_number).collect()
}

/// Checks one value against its spec; `param` is the name errors carry (`crack[2].a0`).
pub fn key_value(spec: &schema::KeySpec, param: &str, v: &Value) -> Result<Val> {
    let bad_type = || type_error(param, spec.kind, &spec.valid(), v);
    let out_of_range = |got: String| Error::InvalidInput {
        param: param.to_string(),
        expected: spec.valid(),
        got,
    };
    // an integer beyond 64 bits is an integer of the right kind, out of every range
    if let Value::Other { type_name, repr } = v {
        if type_name == "int" && matches!(spec.kind, Kind::Float | Kind::Int) {
            return Err(out_of_range(repr.clone()));
        }
        if type_name == "str" && spec.kind == Kind::Str {
            return Err(out_of_range(repr.clone()));
        }
    }
    let val = match (spec.kind, v) {
        (Kind::Float, Value::Float(f)) => Val::Float(*f),
        (Kind::Float, Value::Int(i)) => Val::Float(*i as f64),
        (Kind::Int, Value::Int(i)) => Val::Int(*i),
        (Kind::Str, Value::Str(s)) => Val::Str(s.clone()),
        (Kind::Bool, Value::Bool(b)) => Val::Bool(*b),
        (Kind::Pair, Value::List(l)) if l.len() == 2 => match numbers(l) {
            Some(x) => Val::Pair([x[0], x[1]]),
            None => return Err(bad_type()),
        },
        (Kind::IntList, Value::List(l)) => {
            let ints: Option<Vec<i64>> = l
                .iter()
                .map(|x| match x {
                    Value::Int(i) => Some(*i),
                    _ => None,
                })
                .collect();
            match ints {
                Some(x) => Val::IntList(x),
                None => return Err(bad_type()),
            }
        }
        (Kind::FloatList, Value::List(l)) => match numbers(l) {
            Some(x) => Val::FloatList(x),
            None => return Err(bad_type()),
        },
        (Kind::PairList, Value::List(l)) => {
            let pairs: Option<Vec<[f64; 2]>> = l
                .iter()
                .map(|p| match p {
                    Value::List(q) if q.len() == 2 => numbers(q).map(|x| [x[0], x[1]]),
                    _ => None,
                })
                .collect();
            match pairs {
                Some(x) => Val::PairList(x),
                None => return Err(bad_type()),
            }
        }
        _ => return Err(bad_type()),
    };
    if spec.ok(&val) {
        Ok(val)
    } else {
        Err(out_of_range(val.repr()))
    }
}

/// A key for messages (TOML keys are strings; a Python dict may hold anything).
fn shown(k: &str) -> String {
    if k.is_empty() {
        "''".into()
    } else {
        k.to_string()
    }
}

/// Checks one section table: unknown keys, then every key (defaults for the missing ones).
/// `name` is the section's scene name (`crack[2]` for the third crack).
pub fn section(section: &str, name: &str, t: &Value) -> Result<Section> {
    let Value::Table(t) = t else {
        return Err(Error::InvalidType {
            param: name.to_string(),
            expected: format!("a table/dict ([{name}])"),
            got: t.type_name().to_string(),
        });
    };
    let allowed: Vec<&str> = schema::section_keys(section).map(|k| k.key).collect();
    let unknown: Vec<&String> = t
        .keys()
        .filter(|k| !allowed.contains(&k.as_str()))
        .collect();
    if let Some(first) = unknown.first() {
        let list: Vec<String> = unknown
            .iter()
            .take(20)
            .map(|k| format!("{name}.{}", shown(k)))
            .collect();
        let more = if unknown.len() > 20 {
            format!(" and {} more", unknown.len() - 20)
        } else {
            String::new()
        };
        return Err(Error::UnknownKey {
            param: format!("{name}.{}", shown(first)),
            message: format!(
                "unknown key(s) {}{more}; allowed in [{name}]: {}",
                list.join(", "),
                allowed.join(", ")
            ),
        });
    }
    let mut out = Section::new();
    for spec in schema::section_keys(section) {
        let param = format!("{name}.{}", spec.key);
        let v = match t.get(spec.key) {
            Some(v) => key_value(spec, &param, v)?,
            None => spec.default.clone(),
        };
        out.insert(spec.key, v);
    }
    required_keys(section, name, &out, |k| t.contains_key(k))?;
    if section == "mesh" {
        grid_line_counts(&mut out);
    }
    section_rules(section, name, &out)?;
    Ok(out)
}

/// Given grid lines set the element counts (`mesh.nx` is the count of `mesh.xs` - 1, `mesh.ny`
/// of `mesh.ys`), so the checked scene reports the grid that runs.
fn grid_line_counts(s: &mut Section) {
    for (lines, count) in [("xs", "nx"), ("ys", "ny")] {
        let n = s[lines].floats().len();
        if n >= 2 {
            s.insert(count, Val::Int(i64::try_from(n - 1).unwrap_or(i64::MAX)));
        }
    }
}

/// Refuses an entry that omits a key the schema requires of it ([`schema::Required`]: always,
/// or for its shape or region), as missing.
fn required_keys(
    section: &str,
    name: &str,
    s: &Section,
    given: impl Fn(&str) -> bool,
) -> Result<()> {
    let value = |k: &str| s.get(k).map(|v| v.s().to_string());
    for spec in schema::section_keys(section) {
        if spec.required_in(&value) && !given(spec.key) {
            let why = match spec.required {
                schema::Required::When { key, .. } => format!(" for {key} '{}'", s[key].s()),
                _ => String::new(),
            };
            return Err(Error::MissingKey {
                param: format!("{name}.{}", spec.key),
                message: format!("missing required key {name}.{}{why}", spec.key),
            });
        }
    }
    Ok(())
}

/// Rules between the keys of one section.
fn section_rules(section: &str, name: &str, s: &Section) -> Result<()> {
    match section {
        "mesh" => {
            if !s["refine"].floats().is_empty() && s["refine_h"].f() == 0.0 {
                return Err(Error::invalid(
                    &format!("{name}.refine_h"),
                    "the element size in the refinement box (a length > 0) when mesh.refine is \
                     set",
                    0.0,
                ));
            }
            let (nx, ny) = (s["nx"].i(), s["ny"].i());
            if nx.saturating_mul(ny) > schema::max_elements() as i64 {
                return Err(Error::invalid(
                    &format!("{name}.nx * {name}.ny"),
                    &format!(
                        "at most {} elements (a documented memory guard)",
                        schema::max_elements()
                    ),
                    format!("{nx} x {ny}"),
                ));
            }
        }
        "xfem" => {
            let (nsub, tip) = (s["nsub"].i(), s["tip_nsub"].i());
            if tip != 0 {
                super::validate::tip_nsub(&format!("{name}.tip_nsub"), nsub, tip)?;
            }
        }
        "pd" if schema::sla_engine(s["fast"].b(), s["engine"].s()).is_none() => {
            return Err(Error::invalid(
                &format!("{name}.engine"),
                &format!(
                    "'auto' or 'oracle' with {name}.fast = false (fast = false is another name \
                     of engine = 'oracle')"
                ),
                format!("'{}'", s["engine"].s()),
            ));
        }
        "hole" if s["shape"].s() == "rect" => {
            let (lo, hi) = (s["min"].pair(), s["max"].pair());
            if !(lo[0] < hi[0] && lo[1] < hi[1]) {
                return Err(Error::invalid(
                    &format!("{name}.max"),
                    &format!("a corner above and right of {name}.min = {lo:?}"),
                    format!("{hi:?}"),
                ));
            }
        }
        "hole" if s["shape"].s() == "circle" && s["radius"].f() == 0.0 => {
            return Err(Error::invalid(
                &format!("{name}.radius"),
                "a radius in [1e-30, 1e30] for shape 'circle'",
                0.0,
            ));
        }
        "notch" if s["width"].f() == 0.0 || s["depth"].f() == 0.0 => {
            let key = if s["width"].f() == 0.0 {
                "width"
            } else {
                "depth"
            };
            return Err(Error::invalid(
                &format!("{name}.{key}"),
                "a length in [1e-30, 1e30]",
                0.0,
            ));
        }
        "region_load"
            if s["region"].s() == "point" && (s["normal"].f() != 0.0 || s["shear"].f() != 0.0) =>
        {
            let key = if s["normal"].f() != 0.0 {
                "normal"
            } else {
                "shear"
            };
            return Err(Error::invalid(
                &format!("{name}.{key}"),
                "0 on a 'point' region (a point carries a force: load.force; a traction needs an \
                 'edge' or 'edge_part' region)",
                s[key].f(),
            ));
        }
        "region_load" if s["region"].s() != "point" && s["force"].pair() != [0.0, 0.0] => {
            return Err(Error::invalid(
                &format!("{name}.force"),
                "[0, 0] on an edge region (an edge carries a traction: normal, shear; a force \
                 needs a 'point' region)",
                format!("{:?}", s["force"].pair()),
            ));
        }
        "support" | "region_load" if s["region"].s() == "edge_part" => {
            let (a, b) = (s["from"].f(), s["to"].f());
            if !(a < b) {
                return Err(Error::invalid(
                    &format!("{name}.to"),
                    &format!("an end after {name}.from = {a}"),
                    b,
                ));
            }
        }
        _ => {}
    }
    Ok(())
}

fn string(t: &Table, key: &str, valid: &str, ok: impl Fn(&str) -> bool) -> Result<Option<String>> {
    match t.get(key) {
        None => Ok(None),
        Some(Value::Str(s)) if ok(s) => Ok(Some(s.clone())),
        Some(Value::Str(s)) => Err(Error::invalid(key, valid, format!("'{s}'"))),
        Some(Value::Other { type_name, repr }) if type_name == "str" => {
            Err(Error::invalid(key, valid, repr))
        }
        Some(v) => Err(Error::InvalidType {
            param: key.into(),
            expected: format!("a string ({valid})"),
            got: format!("{} {}", v.type_name(), v.repr()),
        }),
    }
}

/// The method of a scene tree (required).
pub fn method(t: &Table) -> Result<&'static str> {
    let valid = schema::choice(&schema::METHODS);
    match string(t, "method", &valid, |s| schema::METHODS.contains(&s))? {
        None => Err(Error::MissingKey {
            param: "method".into(),
            message: format!("missing required key 'method' ({valid})"),
        }),
        Some(m) => Ok(schema::METHODS
            .iter()
            .find(|x| **x == m)
            .copied()
            .unwrap_or("fem")),
    }
}

/// The checked sections of a scene tree: `(method, name, sections, cracks)`, each section with
/// every key (missing sections take their defaults), the crack tables in order.
pub struct Checked {
    pub method: &'static str,
    pub name: String,
    pub sections: BTreeMap<&'static str, Section>,
    pub cracks: Vec<Section>,
    /// the general scene's lists ([`schema::LIST_SECTIONS`]) by scene key, each entry checked
    pub lists: BTreeMap<&'static str, Vec<Section>>,
}

impl Checked {
    /// The checked scene as a tree: every section of the method with every key, the cracks as
    /// a list of tables (what the Python layer builds its scene from).
    pub fn to_tree(&self) -> Table {
        let table = |s: &Section| {
            Value::Table(
                s.iter()
                    .map(|(k, v)| (k.to_string(), v.to_value()))
                    .collect(),
            )
        };
        let mut t = Table::new();
        t.insert("method".into(), Value::Str(self.method.into()));
        t.insert("name".into(), Value::Str(self.name.clone()));
        for (k, s) in &self.sections {
            t.insert(k.to_string(), table(s));
        }
        t.insert(
            "crack".into(),
            Value::List(self.cracks.iter().map(table).collect()),
        );
        // `[[load]]` entries go back as "loads" (the tree's "load" is the grips' table)
        for (key, list) in &self.lists {
            let key = if *key == "load" { "loads" } else { key };
            t.insert(key.into(), Value::List(list.iter().map(table).collect()));
        }
        t
    }
}

/// Kinds, ranges, unknown keys and defaults of a whole scene tree.
pub fn check(t: &Table) -> Result<Checked> {
    let method = method(t)?;
    let wanted = schema::method_sections(method);
    let listed = |k: &str| schema::LIST_SECTIONS.iter().any(|(key, _)| *key == k);
    let unknown: Vec<&String> = t
        .keys()
        .filter(|k| {
            !matches!(k.as_str(), "method" | "name") && !wanted.contains(&k.as_str()) && !listed(k)
        })
        .collect();
    if let Some(first) = unknown.first() {
        let other: Vec<&str> = unknown
            .iter()
            .filter(|k| schema::SECTIONS.contains(&k.as_str()))
            .map(|k| k.as_str())
            .collect();
        let hint = if other.is_empty() {
            String::new()
        } else {
            format!(
                " (section(s) {} do not apply to method '{method}')",
                other.join(", ")
            )
        };
        let list: Vec<String> = unknown.iter().take(20).map(|k| shown(k)).collect();
        let mut allowed = vec!["method", "name"];
        allowed.extend_from_slice(wanted);
        allowed.extend(
            schema::LIST_SECTIONS
                .iter()
                .map(|(k, _)| *k)
                .filter(|k| *k != "load"),
        );
        return Err(Error::UnknownKey {
            param: shown(first),
            message: format!(
                "unknown key(s) {}{hint}; allowed: {}",
                list.join(", "),
                allowed.join(", ")
            ),
        });
    }
    let name = string(t, "name", "a string of Unicode text", |_| true)?.unwrap_or_default();
    let mut sections = BTreeMap::new();
    let mut cracks = Vec::new();
    let mut lists = BTreeMap::new();
    for &(key, sec) in &schema::LIST_SECTIONS {
        let entries = match t.get(key) {
            None => Vec::new(),
            // a `[load]` table is the paper's grips, read below
            Some(Value::Table(_)) if key == "load" => Vec::new(),
            Some(Value::List(l)) => l
                .iter()
                .enumerate()
                .map(|(k, e)| section(sec, &format!("{key}[{k}]"), e))
                .collect::<Result<_>>()?,
            Some(v) => {
                return Err(Error::InvalidType {
                    param: key.into(),
                    expected: format!("a list of tables ([[{key}]])"),
                    got: v.type_name().to_string(),
                })
            }
        };
        lists.insert(key, entries);
    }
    for &sec in wanted {
        let v = t.get(sec);
        if sec == "crack" {
            cracks = crack_tables(method, v)?;
            continue;
        }
        // `[[load]]` (a list) are region loads: the grips take their defaults
        let v = v.filter(|v| !(sec == "load" && matches!(v, Value::List(_))));
        let s = match v {
            Some(v) => section(sec, sec, v)?,
            None => section(sec, sec, &Value::Table(Table::new()))?,
        };
        sections.insert(sec, s);
    }
    let c = Checked {
        method,
        name,
        sections,
        cracks,
        lists,
    };
    scene_rules(&c)?;
    let regions = !c.lists["support"].is_empty() || !c.lists["load"].is_empty();
    if regions && matches!(t.get("load"), Some(Value::Table(_))) {
        return Err(Error::invalid(
            "load",
            "either the paper's grips ([load] bc, u0, traction) or supports and loads on \
             regions ([[support]], [[load]] tables), not both",
            "a [load] table beside [[support]] / [[load]] tables",
        ));
    }
    Ok(c)
}

/// Rules between keys of two sections, on the values as written.
fn scene_rules(c: &Checked) -> Result<()> {
    if let (Some(m), Some(plate)) = (c.sections.get("mesh"), c.sections.get("plate")) {
        graded_size(m, plate)?;
    }
    if let (Some(x), Some(plate)) = (c.sections.get("xfem"), c.sections.get("plate")) {
        let (a_stop, w) = (x["a_stop"].f(), plate["width"].f());
        if a_stop != 0.0 && !(a_stop < w) {
            return Err(Error::invalid(
                "xfem.a_stop",
                &format!("0 (0.7 plate.width) or 0 < a_stop < plate.width = {w}"),
                a_stop,
            ));
        }
    }
    Ok(())
}

/// A graded grid's element count, in closed form ([`graded_count`]) before a line is built: at
/// most [`schema::max_elements`], else `mesh.refine_h` is refused.
fn graded_size(m: &Section, plate: &Section) -> Result<()> {
    let (b, h, g) = (m["refine"].floats(), m["refine_h"].f(), m["grading"].f());
    if b.len() != 4 || !(h > 0.0) {
        return Ok(());
    }
    let (w, ht) = (plate["width"].f(), plate["height"].f());
    let (nx, ny) = (m["nx"].i() as f64, m["ny"].i() as f64);
    let count = |given: &[f64], len: f64, lo: f64, hi: f64, n: f64| {
        if given.is_empty() {
            graded_count(len, lo, hi, h, g, len / n)
        } else {
            (given.len() as f64 - 1.0).max(1.0)
        }
    };
    let cx = count(m["xs"].floats(), w, b[0], b[2], nx);
    let cy = count(m["ys"].floats(), ht, b[1], b[3], ny);
    let max = schema::max_elements() as f64;
    if !(cx * cy <= max) {
        return Err(Error::invalid(
            "mesh.refine_h",
            &format!(
                "an element size whose graded grid has at most {} elements (a documented memory \
                 guard)",
                schema::max_elements()
            ),
            format!("{h:e} ({cx:.3e} x {cy:.3e} elements)"),
        ));
    }
    Ok(())
}

/// The `[crack]` table or the `[[crack]]` array (at least one table). A crack without `kind`
/// (or no `[crack]` at all) is the method's default kind ([`schema::default_crack_kind`]).
fn crack_tables(method: &str, v: Option<&Value>) -> Result<Vec<Section>> {
    let one = |k: usize, c: &Value| {
        let mut c = c.clone();
        if let Value::Table(t) = &mut c {
            t.entry("kind".into())
                .or_insert_with(|| Value::Str(schema::default_crack_kind(method).into()));
        }
        section("crack", &crack_name(k), &c)
    };
    match v {
        None => Ok(vec![one(0, &Value::Table(Table::new()))?]),
        Some(Value::List(l)) if l.is_empty() => Err(Error::invalid(
            "crack",
            "at least one [[crack]] table",
            "none",
        )),
        Some(Value::List(l)) => l.iter().enumerate().map(|(k, c)| one(k, c)).collect(),
        Some(v) => Ok(vec![one(0, v)?]),
    }
}

fn side(s: &str) -> Side {
    match s {
        "right" => Side::Right,
        "bottom" => Side::Bottom,
        "top" => Side::Top,
        _ => Side::Left,
    }
}

fn crack(s: &Section) -> Option<CrackSpec> {
    let kind = match s["kind"].s() {
        "seam" => CrackKind::Seam,
        "edge" => CrackKind::Edge,
        "center" => CrackKind::Center,
        _ => return None,
    };
    Some(CrackSpec {
        kind,
        a0: s["a0"].f(),
        y: s["y"].f(),
        angle: s["angle"].f(),
        x: s["x"].f(),
        side: side(s["side"].s()),
    })
}

/// The grid of `[mesh]`: uniform nx x ny, the given lines, or graded around the refinement box
/// (the uniform grid's spacing far from it).
fn grid(s: &Section, d: &Domain) -> FeGrid {
    let (nx, ny) = (s["nx"].i() as usize, s["ny"].i() as usize);
    let (mut xs, mut ys) = (s["xs"].floats().to_vec(), s["ys"].floats().to_vec());
    let (b, h, g) = (s["refine"].floats(), s["refine_h"].f(), s["grading"].f());
    if b.len() == 4 && h > 0.0 {
        if xs.is_empty() {
            xs = graded_lines(d.width, b[0], b[2], h, g, d.width / nx as f64);
        }
        if ys.is_empty() {
            ys = graded_lines(d.height, b[1], b[3], h, g, d.height / ny as f64);
        }
    }
    FeGrid {
        nx: if xs.is_empty() { nx } else { xs.len() - 1 },
        ny: if ys.is_empty() { ny } else { ys.len() - 1 },
        xs,
        ys,
    }
}

/// The holes and notches (a notch is the rectangle it removes, reaching `depth` beyond the edge).
fn holes(c: &Checked, d: &Domain) -> Vec<Hole> {
    let hole = |k: usize, s: &Section| Hole {
        name: format!("hole[{k}]"),
        shape: match s["shape"].s() {
            "rect" => Shape::Rect {
                min: s["min"].pair(),
                max: s["max"].pair(),
            },
            "polygon" => Shape::Polygon(s["points"].pairs().to_vec()),
            _ => Shape::Circle {
                center: s["center"].pair(),
                radius: s["radius"].f(),
            },
        },
    };
    let notch = |k: usize, s: &Section| {
        let (at, w, dp) = (s["at"].f(), s["width"].f() / 2.0, s["depth"].f());
        let (min, max) = match side(s["side"].s()) {
            Side::Bottom => ([at - w, -dp], [at + w, dp]),
            Side::Top => ([at - w, d.height - dp], [at + w, d.height + dp]),
            Side::Left => ([-dp, at - w], [dp, at + w]),
            Side::Right => ([d.width - dp, at - w], [d.width + dp, at + w]),
        };
        Hole {
            name: format!("notch[{k}]"),
            shape: Shape::Rect { min, max },
        }
    };
    let h = c.lists["hole"].iter().enumerate().map(|(k, s)| hole(k, s));
    h.chain(
        c.lists["notch"]
            .iter()
            .enumerate()
            .map(|(k, s)| notch(k, s)),
    )
    .collect()
}

fn region(s: &Section) -> Region {
    let sd = side(s["side"].s());
    match s["region"].s() {
        "edge_part" => Region::EdgePart {
            side: sd,
            from: s["from"].f(),
            to: s["to"].f(),
        },
        "point" => Region::Point(s["point"].pair()),
        "box" => {
            let b = s["box"].floats();
            Region::Box([b[0], b[1], b[2], b[3]])
        }
        _ => Region::Edge(sd),
    }
}

/// The supports and loads on regions, or the paper's grips when there are none.
fn boundary(c: &Checked, load: &Section) -> Result<Boundary> {
    let (sup, loads) = (&c.lists["support"], &c.lists["load"]);
    if sup.is_empty() && loads.is_empty() {
        let grip = Grip::parse(load["bc"].s())?;
        return Ok(Boundary::Grips(PlateLoad {
            grip,
            u0: load["u0"].f(),
            traction: load["traction"].f(),
        }));
    }
    let fix = |s: &Section, comp: &str| {
        matches!(
            (s["fix"].s(), comp),
            ("both", _) | ("u1", "u1") | ("u2", "u2")
        )
        .then(|| s[comp].f())
    };
    Ok(Boundary::Regions {
        supports: sup
            .iter()
            .enumerate()
            .map(|(k, s)| Support {
                name: format!("support[{k}]"),
                region: region(s),
                u1: fix(s, "u1"),
                u2: fix(s, "u2"),
            })
            .collect(),
        loads: loads
            .iter()
            .enumerate()
            .map(|(k, s)| RegionLoad {
                name: format!("load[{k}]"),
                region: region(s),
                kind: if s["region"].s() == "point" {
                    LoadKind::Force(s["force"].pair())
                } else {
                    LoadKind::Traction {
                        normal: s["normal"].f(),
                        shear: s["shear"].f(),
                    }
                },
            })
            .collect(),
    })
}

fn probes(c: &Checked) -> Vec<Probe> {
    c.lists["probe"]
        .iter()
        .enumerate()
        .map(|(k, s)| Probe {
            name: match s["name"].s() {
                "" => format!("probe[{k}]"),
                n => n.to_string(),
            },
            kind: match s["kind"].s() {
                "opening" => ProbeKind::Opening {
                    point: s["point"].pair(),
                    crack: s["crack"].i() as usize,
                },
                _ => ProbeKind::Displacement(s["point"].pair()),
            },
        })
        .collect()
}

fn positive_or_none(v: f64) -> Option<f64> {
    (v > 0.0).then_some(v)
}

fn path_or_none(s: &str) -> Option<PathBuf> {
    (!s.is_empty()).then(|| PathBuf::from(s))
}

/// The variant of choice key `key` whose value is `v` (`of`: the type's `from_name`), or the
/// error naming the key and its choices (the schema admits only `choices`, so this is reached
/// only where the schema's names and the type's disagree).
fn named<T>(key: &str, choices: &[&str], v: &str, of: impl Fn(&str) -> Option<T>) -> Result<T> {
    of(v).ok_or_else(|| Error::invalid(key, &schema::choice(choices), format!("'{v}'")))
}

fn xfem_method(mesh: &Section, x: &Section, domain: &Domain) -> Result<XfemMethod> {
    let nsub = x["nsub"].i() as usize;
    let tip = x["tip_nsub"].i() as usize;
    let steps = x["growth_steps"].i() as usize;
    let a_stop = x["a_stop"].f();
    let growth = match steps {
        0 => None,
        _ => Some(Growth {
            max_steps: steps,
            da: positive_or_none(x["da"].f()),
            a_stop: if a_stop > 0.0 {
                a_stop
            } else {
                schema::DEFAULT_A_STOP_FRACTION * domain.width
            },
            kink_rule: KinkRule::from_name(x["kink_rule"].s())?,
            state_every: x["state_every"].i() as usize,
        }),
    };
    Ok(XfemMethod {
        grid: grid(mesh, domain),
        options: XfemOptions {
            nsub,
            tip_nsub: if tip == 0 { nsub } else { tip },
            fixed_area_radius: positive_or_none(x["fixed_area_radius"].f()),
            area_threshold: x["area_threshold"].f(),
        },
        r_i: x["r_I"].f(),
        extra_radii: schema::XFEM_EXTRA_RADII.to_vec(),
        growth,
        tip_tie_tol: x["tip_tie_tol"].f(),
        condition: true,
    })
}

fn pd_method(pd: &Section, ccm: bool) -> Result<PdMethod> {
    let [cx, cy] = pd["center"].pair();
    let [sx, sy] = pd["size"].pair();
    let (fast, engine) = (pd["fast"].b(), pd["engine"].s());
    // `pd.fast = false` is `pd.engine = "oracle"` ([`schema::sla_engine`]); `section_rules`
    // refuses a contradiction first
    let engine = schema::sla_engine(fast, engine).ok_or_else(|| {
        Error::invalid(
            "pd.engine",
            "'auto' or 'oracle' with fast = false (fast = false is another name of engine = \
             'oracle')",
            format!("'{engine}'"),
        )
    })?;
    Ok(PdMethod {
        dx: pd["dx"].f(),
        m: pd["m"].i() as usize,
        hole_volumes: named(
            "pd.hole_volumes",
            &schema::HOLE_VOLUMES,
            pd["hole_volumes"].s(),
            HoleVolumes::from_name,
        )?,
        surface_correction: named(
            "pd.surface_correction",
            &schema::SURFACE_CORRECTIONS,
            pd["surface_correction"].s(),
            super::SurfaceCorrection::from_name,
        )?,
        s0_calibration: named(
            "pd.s0_calibration",
            &schema::S0_CALIBRATIONS,
            pd["s0_calibration"].s(),
            S0Calibration::from_name,
        )?,
        model: named(
            "pd.model",
            &schema::PD_MODELS,
            pd["model"].s(),
            super::PdModel::from_name,
        )?,
        influence: named(
            "pd.influence",
            &schema::INFLUENCES,
            pd["influence"].s(),
            super::Influence::from_name,
        )?,
        regions: ccm
            .then_some([cx - sx / 2.0, cy - sy / 2.0, cx + sx / 2.0, cy + sy / 2.0])
            .into_iter()
            .collect(),
        adaptive: (ccm && pd["region"].s() == "adaptive").then(|| AdaptiveRegion {
            margin: pd["adapt_margin"].f(),
            size: pd["adapt_size"].f(),
        }),
        fem_grading: pd["fem_grading"].f(),
        fem_coarse: pd["fem_coarse"].f(),
        sla: SlaParams {
            max_steps: pd["sla_steps"].i() as usize,
            stop_crack_length: positive_or_none(pd["stop_crack_length"].f()),
            tie_tol: pd["tie_tol"].f(),
            refactor_every: pd["refactor_every"].i() as usize,
            engine: named(
                "pd.engine",
                &schema::SLA_ENGINES,
                engine,
                super::SlaEngine::from_name,
            )?,
            damage_at_steps: pd["damage_at_steps"]
                .ints()
                .iter()
                .map(|&k| k as usize)
                .collect(),
            checkpoint_every: pd["checkpoint_every"].i() as usize,
            checkpoint_path: path_or_none(pd["checkpoint_path"].s()),
            resume_from: path_or_none(pd["resume_from"].s()),
        },
    })
}

/// The [`Problem`] of a checked scene.
pub fn from_checked(c: &Checked) -> Result<Problem> {
    let s = &c.sections;
    let (plate, mat, load) = (&s["plate"], &s["material"], &s["load"]);
    let mut domain = Domain::rect(plate["width"].f(), plate["height"].f());
    domain.holes = holes(c, &domain);
    let elastic = Elastic {
        e: mat["E"].f(),
        nu: mat["nu"].f(),
        plane: if mat["plane"].s() == "stress" {
            Plane::Stress
        } else {
            Plane::Strain
        },
        thickness: mat["thickness"].f(),
    };
    let method = match c.method {
        "fem" => Method::Fem(FemMethod {
            grid: grid(&s["mesh"], &domain),
            gauss: s["mesh"]["gauss"].i() as usize,
            condition: true,
        }),
        "xfem" => Method::Xfem(xfem_method(&s["mesh"], &s["xfem"], &domain)?),
        "pd" => Method::Pd(pd_method(&s["pd"], false)?),
        _ => Method::CcmPd(pd_method(&s["pd"], true)?),
    };
    let mut p = Problem {
        name: c.name.clone(),
        domain,
        material: Material {
            elastic,
            g0: mat["G0"].f(),
        },
        boundary: boundary(c, load)?,
        cracks: c.cracks.iter().filter_map(crack).collect(),
        probes: probes(c),
        method,
    };
    // the adaptive region starts around the crack tips (its rule: `pd_region`)
    if let Method::CcmPd(pm) = &p.method {
        if let Some(a) = pm.adaptive {
            let regions = pd_region::initial(&p, pm.dx, pm.m, &a);
            p.pd_mut().regions = regions;
        }
    }
    Ok(p)
}

/// Kinds, ranges and defaults of a scene tree, read into a [`Problem`] (not yet
/// cross-validated: [`Problem::from_scene`] does both).
pub fn problem(t: &Table) -> Result<Problem> {
    from_checked(&check(t)?)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::problem::{SlaEngine, SurfaceCorrection};

    /// Every choice key's names round-trip through its type's `from_name`, and an unknown name
    /// is an error naming the key and its choices (no silent default).
    #[test]
    fn choice_names_round_trip_and_unknown_ones_are_refused() {
        for n in schema::HOLE_VOLUMES {
            assert_eq!(HoleVolumes::from_name(n).map(|h| h.name()), Some(n));
        }
        for n in schema::SURFACE_CORRECTIONS {
            assert_eq!(SurfaceCorrection::from_name(n).map(|c| c.name()), Some(n));
        }
        for n in schema::SLA_ENGINES {
            assert_eq!(SlaEngine::from_name(n).map(|e| e.name()), Some(n));
        }
        assert_eq!(HoleVolumes::from_name("centroid"), None);
        assert_eq!(SurfaceCorrection::from_name("Energy"), None);
        let e = named(
            "pd.hole_volumes",
            &schema::HOLE_VOLUMES,
            "centroid",
            HoleVolumes::from_name,
        )
        .unwrap_err()
        .to_string();
        assert!(
            e.contains("pd.hole_volumes") && e.contains("'exact'"),
            "{e}"
        );
    }
}
