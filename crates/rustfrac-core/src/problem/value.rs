//! The generic value tree a scene arrives in (TOML-shaped: tables of keys, arrays, numbers,
//! strings, booleans), before the core reads it into a [`super::Problem`].
//!
//! The bindings turn a Python dict into a [`Value`] without knowing any scene key, so that a new
//! scene parameter touches only the core's description ([`super::schema`]) and its docs. Values
//! the tree cannot hold as such (a Python object of another type, an integer beyond 64 bits, a
//! string that is not valid Unicode) are kept as [`Value::Other`] with a short description, and
//! refused by name when the key that holds them is read.

use std::collections::BTreeMap;

/// One value of a scene tree.
#[derive(Debug, Clone, PartialEq)]
pub enum Value {
    Bool(bool),
    Int(i64),
    Float(f64),
    Str(String),
    List(Vec<Value>),
    Table(Table),
    /// a value of another type: (type name, short repr) for messages
    Other {
        type_name: String,
        repr: String,
    },
}

/// A table: keys in insertion order are not needed (messages sort them), so a sorted map.
pub type Table = BTreeMap<String, Value>;

impl Value {
    /// The type name used in messages (Python's names, as users write scenes in TOML or Python).
    pub fn type_name(&self) -> &str {
        match self {
            Value::Bool(_) => "bool",
            Value::Int(_) => "int",
            Value::Float(_) => "float",
            Value::Str(_) => "str",
            Value::List(_) => "list",
            Value::Table(_) => "dict",
            Value::Other { type_name, .. } => type_name,
        }
    }

    /// A short repr for messages (Python's spelling: `1.0`, `'text'`, `[1, 2]`, `True`), cut
    /// to 120 characters.
    pub fn repr(&self) -> String {
        let r = match self {
            Value::Bool(b) => if *b { "True" } else { "False" }.to_string(),
            Value::Int(i) => i.to_string(),
            Value::Float(f) => float_repr(*f),
            Value::Str(s) => format!("'{s}'"),
            Value::List(v) => {
                let items: Vec<String> = v.iter().take(20).map(Value::repr).collect();
                let more = if v.len() > 20 { ", ..." } else { "" };
                format!("[{}{more}]", items.join(", "))
            }
            Value::Table(t) => {
                let items: Vec<String> = t
                    .iter()
                    .take(10)
                    .map(|(k, v)| format!("'{k}': {}", v.repr()))
                    .collect();
                format!("{{{}}}", items.join(", "))
            }
            Value::Other { repr, .. } => repr.clone(),
        };
        if r.chars().count() <= 120 {
            r
        } else {
            let cut: String = r.chars().take(117).collect();
            cut + "..."
        }
    }

    /// The number held, for a float or an int (a bool is not a number here).
    pub fn as_number(&self) -> Option<f64> {
        match self {
            Value::Float(f) => Some(*f),
            Value::Int(i) => Some(*i as f64),
            _ => None,
        }
    }
}

/// `v` as Python's `repr(float)` writes it (shortest round trip, `1e-05`, `1e+30`, `inf`, `nan`),
/// so that messages read the same whether a scene came from Python or TOML.
pub fn float_repr(v: f64) -> String {
    if v.is_nan() {
        return "nan".into();
    }
    if v.is_infinite() {
        return if v > 0.0 { "inf" } else { "-inf" }.into();
    }
    let s = format!("{v:?}");
    match s.find('e') {
        None => s,
        Some(i) => {
            let (mant, exp) = s.split_at(i);
            let exp = &exp[1..];
            let (sign, digits) = match exp.strip_prefix('-') {
                Some(d) => ('-', d),
                None => ('+', exp),
            };
            let mant = mant.strip_suffix(".0").unwrap_or(mant);
            format!("{mant}e{sign}{digits:0>2}")
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn floats_are_written_as_python_does() {
        assert_eq!(float_repr(-1.0), "-1.0");
        assert_eq!(float_repr(0.1), "0.1");
        assert_eq!(float_repr(1e-5), "1e-05");
        assert_eq!(float_repr(1e30), "1e+30");
        assert_eq!(float_repr(2.5e-300), "2.5e-300");
        assert_eq!(float_repr(f64::INFINITY), "inf");
        assert_eq!(float_repr(123456.0), "123456.0");
    }
}
