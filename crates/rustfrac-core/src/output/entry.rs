//! The kinds of the result schema's entries: an array's dimensions ([`Dim`]), a value's kind
//! ([`Kind`]), the methods an entry belongs to ([`Methods`]), when it is present
//! ([`Presence`]), the entry itself ([`Entry`]) and the table being built (`Table`).

use super::record::Group;

/// A dimension of an array's shape: a fixed size, or a size named for what it counts (the same
/// name means the same size within one record).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Dim {
    Fixed(usize),
    /// `n`
    Var(&'static str),
    /// `2 n` (interleaved components)
    Twice(&'static str),
    /// `n + 1` (offsets into a concatenation of n parts)
    PlusOne(&'static str),
}

impl Dim {
    /// The dimension in words: "2", "n_nodes", "2 n_nodes", "n_cracks + 1".
    pub fn text(&self) -> String {
        match self {
            Dim::Fixed(n) => n.to_string(),
            Dim::Var(v) => (*v).to_string(),
            Dim::Twice(v) => format!("2 {v}"),
            Dim::PlusOne(v) => format!("{v} + 1"),
        }
    }
}

/// The kind of a result value.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    Float,
    Int,
    Bool,
    Str,
    /// a numpy float64 array of this shape
    Floats(&'static [Dim]),
    /// a numpy int64 array of this shape
    Ints(&'static [Dim]),
    /// a numpy bool array of this shape
    Bools(&'static [Dim]),
    /// a plain (nested) list of floats of this shape
    FloatList(&'static [Dim]),
    /// a plain list of strings
    StrList,
    /// a nested table; its entries are named `<table>.<key>`
    Table,
    /// a list of tables; their entries are named `<list>.<key>`
    TableList,
}

impl Kind {
    /// The stable name (Python's `result_schema()`).
    pub fn name(&self) -> &'static str {
        match self {
            Kind::Float => "float",
            Kind::Int => "int",
            Kind::Bool => "bool",
            Kind::Str => "str",
            Kind::Floats(_) => "float array",
            Kind::Ints(_) => "int array",
            Kind::Bools(_) => "bool array",
            Kind::FloatList(_) => "float list",
            Kind::StrList => "str list",
            Kind::Table => "table",
            Kind::TableList => "table list",
        }
    }

    /// The shape of an array or list kind.
    pub fn shape(&self) -> Option<&'static [Dim]> {
        match self {
            Kind::Floats(s) | Kind::Ints(s) | Kind::Bools(s) | Kind::FloatList(s) => Some(s),
            _ => None,
        }
    }

    /// The shape in words, e.g. "(n_nodes, 2)" (None for kinds without a shape).
    pub fn shape_text(&self) -> Option<String> {
        let dims: Vec<String> = self.shape()?.iter().map(Dim::text).collect();
        Some(match dims.len() {
            1 => format!("({},)", dims[0]),
            _ => format!("({})", dims.join(", ")),
        })
    }
}

/// The methods an entry belongs to (a set of [`crate::problem::schema::METHODS`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Methods(u8);

impl Methods {
    pub const FEM: Methods = Methods(1);
    pub const XFEM: Methods = Methods(2);
    pub const PD: Methods = Methods(4);
    pub const CCM_PD: Methods = Methods(8);
    /// both SLA methods (PD and CCM-PD)
    pub const SLA: Methods = Methods(4 | 8);
    /// the mesh methods (FEM and XFEM)
    pub const MESH: Methods = Methods(1 | 2);
    pub const ALL: Methods = Methods(15);

    /// The union of two sets.
    pub const fn or(self, o: Methods) -> Methods {
        Methods(self.0 | o.0)
    }

    /// Whether the set holds the method named `m`.
    pub fn has(self, m: &str) -> bool {
        crate::problem::schema::METHODS
            .iter()
            .position(|x| *x == m)
            .is_some_and(|i| self.0 & (1 << i) != 0)
    }

    /// The names of the methods in the set, in the docs' order.
    pub fn names(self) -> Vec<&'static str> {
        crate::problem::schema::METHODS
            .iter()
            .enumerate()
            .filter(|(i, _)| self.0 & (1 << i) != 0)
            .map(|(_, m)| *m)
            .collect()
    }
}

/// When an entry is present.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Presence {
    /// in every record of its methods
    Always,
    /// only under this condition (in words)
    When(&'static str),
    /// added by Python's `rustfrac.run` after the core's run (in words: what adds it)
    Python(&'static str),
}

impl Presence {
    /// "always", "when ...", "python: ...".
    pub fn text(&self) -> String {
        match self {
            Presence::Always => "always".into(),
            Presence::When(c) => format!("when {c}"),
            Presence::Python(c) => format!("python: {c}"),
        }
    }
}

/// One result entry.
#[derive(Debug, Clone)]
pub struct Entry {
    pub methods: Methods,
    pub group: Group,
    /// the key; `<region>` / `<name>` parts stand for any region or probe name, and
    /// `<table>.<key>` names an entry of a [`Kind::Table`] or [`Kind::TableList`]
    pub name: &'static str,
    pub kind: Kind,
    /// whether the value may be None instead (e.g. "not computed")
    pub nullable: bool,
    pub unit: &'static str,
    pub presence: Presence,
    /// what the entry means
    pub doc: &'static str,
}

impl Entry {
    /// Whether the key `key` is this entry's (a pattern's `<...>` parts match any non-empty
    /// text without a ':').
    pub fn matches(&self, key: &str) -> bool {
        pattern_matches(self.name, key)
    }

    /// The entry's value may be None.
    pub fn or_none(&mut self) -> &mut Self {
        self.nullable = true;
        self
    }

    /// The entry is present only under `condition`.
    pub fn when(&mut self, condition: &'static str) -> &mut Self {
        self.presence = Presence::When(condition);
        self
    }

    /// The entry is added by Python's `rustfrac.run`.
    pub fn python(&mut self, what: &'static str) -> &mut Self {
        self.presence = Presence::Python(what);
        self
    }
}

pub(super) fn pattern_matches(pat: &str, key: &str) -> bool {
    match pat.find('<') {
        None => pat == key,
        Some(i) => {
            let Some(close) = pat[i..].find('>') else {
                return false;
            };
            let (head, tail) = (&pat[..i], &pat[i + close + 1..]);
            let Some(rest) = key.strip_prefix(head) else {
                return false;
            };
            // the variable part: the shortest non-empty text without a separator that lets the
            // rest of the pattern match
            (1..=rest.len())
                .filter(|&n| rest.is_char_boundary(n))
                .take_while(|&n| !rest[..n].contains(':'))
                .any(|n| pattern_matches(tail, &rest[n..]))
        }
    }
}

/// The table being built: entries are added for the current methods and group.
pub(super) struct Table {
    pub(super) v: Vec<Entry>,
    methods: Methods,
    group: Group,
}

impl Table {
    pub(super) fn new() -> Self {
        Self {
            v: Vec::new(),
            methods: Methods::ALL,
            group: Group::Headline,
        }
    }

    pub(super) fn at(&mut self, methods: Methods, group: Group) {
        (self.methods, self.group) = (methods, group);
    }

    pub(super) fn add(
        &mut self,
        name: &'static str,
        kind: Kind,
        unit: &'static str,
        doc: &'static str,
    ) -> &mut Entry {
        self.v.push(Entry {
            methods: self.methods,
            group: self.group,
            name,
            kind,
            nullable: false,
            unit,
            presence: Presence::Always,
            doc,
        });
        self.v.last_mut().expect("just pushed")
    }
}
