//! The kind of a scene key's value ([`Kind`]) and a value whose kind was checked ([`Val`]):
//! what the schema's table ([`super::schema`]) and the ranges ([`super::range`]) are written in.

use super::value::Value;
use std::collections::BTreeMap;

/// The kind of a key's value.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    Float,
    Int,
    Str,
    Bool,
    /// two floats
    Pair,
    /// a list of integers
    IntList,
    /// a list of numbers
    FloatList,
    /// a list of pairs of numbers
    PairList,
}

impl Kind {
    /// Stable name (the Python side maps it to a type).
    pub fn name(&self) -> &'static str {
        match self {
            Kind::Float => "float",
            Kind::Int => "int",
            Kind::Str => "str",
            Kind::Bool => "bool",
            Kind::Pair => "pair",
            Kind::IntList => "intlist",
            Kind::FloatList => "floatlist",
            Kind::PairList => "pairlist",
        }
    }
    /// How messages say "a value of this kind".
    pub fn phrase(&self) -> &'static str {
        match self {
            Kind::Float => "a number",
            Kind::Int => "an integer",
            Kind::Str => "a string",
            Kind::Bool => "true or false",
            Kind::Pair => "a pair of numbers",
            Kind::IntList => "a list of integers",
            Kind::FloatList => "a list of numbers",
            Kind::PairList => "a list of pairs of numbers",
        }
    }
}

/// A key's value after its kind was checked.
#[derive(Debug, Clone, PartialEq)]
pub enum Val {
    Float(f64),
    Int(i64),
    Str(String),
    Bool(bool),
    Pair([f64; 2]),
    IntList(Vec<i64>),
    FloatList(Vec<f64>),
    PairList(Vec<[f64; 2]>),
}

impl Val {
    /// The kind of the value.
    pub fn kind(&self) -> Kind {
        match self {
            Val::Float(_) => Kind::Float,
            Val::Int(_) => Kind::Int,
            Val::Str(_) => Kind::Str,
            Val::Bool(_) => Kind::Bool,
            Val::Pair(_) => Kind::Pair,
            Val::IntList(_) => Kind::IntList,
            Val::FloatList(_) => Kind::FloatList,
            Val::PairList(_) => Kind::PairList,
        }
    }
    pub fn f(&self) -> f64 {
        match self {
            Val::Float(v) => *v,
            Val::Int(v) => *v as f64,
            _ => f64::NAN,
        }
    }
    pub fn i(&self) -> i64 {
        match self {
            Val::Int(v) => *v,
            _ => 0,
        }
    }
    pub fn s(&self) -> &str {
        match self {
            Val::Str(v) => v,
            _ => "",
        }
    }
    pub fn b(&self) -> bool {
        matches!(self, Val::Bool(true))
    }
    pub fn pair(&self) -> [f64; 2] {
        match self {
            Val::Pair(v) => *v,
            _ => [f64::NAN; 2],
        }
    }
    pub fn ints(&self) -> &[i64] {
        match self {
            Val::IntList(v) => v,
            _ => &[],
        }
    }
    pub fn floats(&self) -> &[f64] {
        match self {
            Val::FloatList(v) => v,
            _ => &[],
        }
    }
    pub fn pairs(&self) -> &[[f64; 2]] {
        match self {
            Val::PairList(v) => v,
            _ => &[],
        }
    }
    /// Back to the tree (defaults and normalised values for Python).
    pub fn to_value(&self) -> Value {
        match self {
            Val::Float(v) => Value::Float(*v),
            Val::Int(v) => Value::Int(*v),
            Val::Str(v) => Value::Str(v.clone()),
            Val::Bool(v) => Value::Bool(*v),
            Val::Pair(v) => Value::List(v.iter().map(|&x| Value::Float(x)).collect()),
            Val::IntList(v) => Value::List(v.iter().map(|&x| Value::Int(x)).collect()),
            Val::FloatList(v) => Value::List(v.iter().map(|&x| Value::Float(x)).collect()),
            Val::PairList(v) => Value::List(
                v.iter()
                    .map(|p| Value::List(p.iter().map(|&x| Value::Float(x)).collect()))
                    .collect(),
            ),
        }
    }
    /// Python-style repr for messages.
    pub fn repr(&self) -> String {
        self.to_value().repr()
    }
}

/// The scene name of crack `k`: "crack" for the first, "crack\[k\]" for the others.
pub fn crack_name(k: usize) -> String {
    if k == 0 {
        "crack".into()
    } else {
        format!("crack[{k}]")
    }
}

/// The checked values of one section, every key present (defaults filled in).
pub type Section = BTreeMap<&'static str, Val>;
