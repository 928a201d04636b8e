//! A record against the table: every key of the record is an entry of its method with the
//! entry's kind and shape (sizes named alike agree within the record), every entry present
//! "always" is there, and the status is one of the method's.

use super::record::{Entries, Group, Record, Value};
use super::schema::{entries, entry, Dim, Entry, Kind, Presence};
use super::status::statuses;
use std::collections::BTreeMap;

/// What is wrong with `rec` against the table (empty: it matches).
pub fn check(rec: &Record) -> Vec<String> {
    let mut c = Checker {
        method: rec.method,
        dims: BTreeMap::new(),
        problems: Vec::new(),
    };
    for g in Group::ALL {
        c.entries(g, "", rec.group(g));
    }
    match rec.meta.get("status") {
        Some(Value::Str(s)) if !statuses(rec.method).iter().any(|st| st.name == s) => {
            c.problems.push(format!(
                "meta.status: {s:?} is not a status of {}",
                rec.method
            ));
        }
        _ => {}
    }
    c.problems
}

struct Checker {
    method: &'static str,
    /// the size each named dimension has in this record, and where it was first seen
    dims: BTreeMap<&'static str, (usize, String)>,
    problems: Vec<String>,
}

impl Checker {
    /// The entries of group `g` under the table `prefix` ("" at the top, "timings." inside).
    fn entries(&mut self, g: Group, prefix: &str, es: &Entries) {
        for (key, v) in es.iter() {
            let name = format!("{prefix}{key}");
            match entry(self.method, g, &name) {
                Some(e) => self.value(e, &format!("{}.{name}", g.name()), v),
                None => self.problems.push(format!(
                    "{}.{name}: not in the result schema of {}",
                    g.name(),
                    self.method
                )),
            }
        }
        let table = prefix.strip_suffix('.').unwrap_or("");
        for e in entries(self.method) {
            let parent = e.name.rsplit_once('.').map_or("", |(p, _)| p);
            if e.group != g || parent != table || e.presence != Presence::Always {
                continue;
            }
            let local = &e.name[prefix.len()..];
            if !es
                .iter()
                .any(|(k, _)| super::entry::pattern_matches(local, k))
            {
                self.problems.push(format!(
                    "{}.{}: missing (an entry of {} present always)",
                    g.name(),
                    e.name,
                    self.method
                ));
            }
        }
    }

    fn value(&mut self, e: &'static Entry, at: &str, v: &Value) {
        let ok = match (e.kind, v) {
            (_, Value::None) => e.nullable,
            (Kind::Float, Value::Float(_))
            | (Kind::Int, Value::Int(_))
            | (Kind::Bool, Value::Bool(_))
            | (Kind::Str, Value::Str(_)) => true,
            (Kind::Floats(s), Value::Floats { shape, data }) => {
                self.shape(s, shape, data.len(), at)
            }
            (Kind::Ints(s), Value::Ints { shape, data }) => self.shape(s, shape, data.len(), at),
            (Kind::Bools(s), Value::Bools(b)) => self.shape(s, &[b.len()], b.len(), at),
            (Kind::FloatList(s), Value::List(_)) => float_list(s, v),
            (Kind::StrList, Value::List(l)) => l.iter().all(|x| matches!(x, Value::Str(_))),
            (Kind::Table, Value::Table(t)) => {
                let g = e.group;
                self.entries(g, &format!("{}.", e.name), t);
                true
            }
            (Kind::TableList, Value::List(l)) => l.iter().all(|x| match x {
                Value::Table(t) => {
                    self.entries(e.group, &format!("{}.", e.name), t);
                    true
                }
                _ => false,
            }),
            _ => false,
        };
        if !ok {
            let shape = e.kind.shape_text().unwrap_or_default();
            let none = if e.nullable { " or None" } else { "" };
            self.problems.push(format!(
                "{at}: expected {} {shape}{none}, got {}",
                e.kind.name(),
                describe(v)
            ));
        }
    }

    /// An array's shape against the entry's: the rank and the fixed sizes, and each named size
    /// the same wherever it occurs in the record.
    fn shape(&mut self, want: &'static [Dim], got: &[usize], len: usize, at: &str) -> bool {
        if want.len() != got.len() || got.iter().product::<usize>() != len {
            return false;
        }
        for (d, &n) in want.iter().zip(got) {
            let (name, size) = match *d {
                Dim::Fixed(k) if k == n => continue,
                Dim::Fixed(_) => return false,
                Dim::Var(v) => (v, n),
                Dim::Twice(v) if n % 2 == 0 => (v, n / 2),
                Dim::PlusOne(v) if n >= 1 => (v, n - 1),
                Dim::Twice(_) | Dim::PlusOne(_) => return false,
            };
            match self.dims.get(name) {
                Some((m, first)) if *m != size => {
                    let msg =
                        format!("{at}: {name} = {size} here but {m} in {first} (shape {got:?})");
                    self.problems.push(msg);
                }
                Some(_) => {}
                None => {
                    self.dims.insert(name, (size, at.to_string()));
                }
            }
        }
        true
    }
}

/// A plain nested list of floats of the shape's depth, with its fixed sizes (named sizes of
/// plain lists may differ between the items: the polylines of several cracks).
fn float_list(want: &[Dim], v: &Value) -> bool {
    match (want.split_first(), v) {
        (None, Value::Float(_)) => true,
        (Some((d, rest)), Value::List(l)) => {
            matches!(d, Dim::Fixed(k) if *k != l.len())
                .then_some(())
                .is_none()
                && l.iter().all(|x| float_list(rest, x))
        }
        _ => false,
    }
}

fn describe(v: &Value) -> String {
    match v {
        Value::None => "None".into(),
        Value::Bool(_) => "bool".into(),
        Value::Int(_) => "int".into(),
        Value::Float(_) => "float".into(),
        Value::Str(_) => "str".into(),
        Value::Floats { shape, .. } => format!("float array {shape:?}"),
        Value::Ints { shape, .. } => format!("int array {shape:?}"),
        Value::Bools(b) => format!("bool array [{}]", b.len()),
        Value::List(l) => format!("a list of {}", l.len()),
        Value::Table(t) => format!("a table of {}", t.len()),
    }
}
