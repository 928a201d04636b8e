//! The typed record a run's result becomes: five groups of named values (the headline, the
//! fields, the history, the scalars, the meta), each value of a small generic kind
//! ([`Value`]). The bindings convert it to Python without knowing a name, as they convert a
//! scene tree the other way; [`super::schema`] says which names each method's record holds.

/// A value of a result entry.
#[derive(Debug, Clone, PartialEq)]
pub enum Value {
    /// absent ("not computed", "not applicable"): Python's None
    None,
    Bool(bool),
    Int(i64),
    Float(f64),
    Str(String),
    /// a float64 array of the given shape (row-major data)
    Floats {
        shape: Vec<usize>,
        data: Vec<f64>,
    },
    /// an int64 array of the given shape (row-major data)
    Ints {
        shape: Vec<usize>,
        data: Vec<i64>,
    },
    /// a 1-D bool array
    Bools(Vec<bool>),
    /// a plain list (of numbers, strings, lists or tables)
    List(Vec<Value>),
    /// a nested table
    Table(Entries),
}

impl Value {
    /// A 1-D float array.
    pub fn floats(data: Vec<f64>) -> Self {
        Value::Floats {
            shape: vec![data.len()],
            data,
        }
    }

    /// An (n, N) float array of rows.
    pub fn rows<const N: usize>(rows: Vec<[f64; N]>) -> Self {
        Value::Floats {
            shape: vec![rows.len(), N],
            data: rows.into_flattened(),
        }
    }

    /// An (n, 4, 2) float array of quadrilateral cells (corner coordinates or displacements).
    pub fn quads(cells: Vec<[[f64; 2]; 4]>) -> Self {
        Value::Floats {
            shape: vec![cells.len(), 4, 2],
            data: cells.into_iter().flatten().flatten().collect(),
        }
    }

    /// A (rows, cols) float array of row-major values.
    pub fn table(rows: usize, cols: usize, data: Vec<f64>) -> Self {
        debug_assert_eq!(rows * cols, data.len());
        Value::Floats {
            shape: vec![rows, cols],
            data,
        }
    }

    /// A 1-D int64 array.
    pub fn ints(v: impl IntoIterator<Item = i64>) -> Self {
        let data: Vec<i64> = v.into_iter().collect();
        Value::Ints {
            shape: vec![data.len()],
            data,
        }
    }

    /// A 1-D int64 array of indices.
    pub fn indices(v: &[usize]) -> Self {
        Self::ints(v.iter().map(|&i| i as i64))
    }

    /// An (n, N) int64 array of index rows.
    pub fn index_rows<const N: usize>(rows: impl IntoIterator<Item = [usize; N]>) -> Self {
        let data: Vec<i64> = rows.into_iter().flat_map(|r| r.map(|i| i as i64)).collect();
        Value::Ints {
            shape: vec![data.len() / N, N],
            data,
        }
    }

    /// A count.
    pub fn count(n: usize) -> Self {
        Value::Int(n as i64)
    }

    /// A plain list of floats.
    pub fn float_list(v: &[f64]) -> Self {
        Value::List(v.iter().map(|&x| Value::Float(x)).collect())
    }

    /// A plain list of points (lists of two floats).
    pub fn points(v: &[[f64; 2]]) -> Self {
        Value::List(v.iter().map(|p| Value::float_list(p)).collect())
    }

    /// A plain list of rectangles [x0, y0, x1, y1].
    pub fn boxes(v: &[[f64; 4]]) -> Self {
        Value::List(v.iter().map(|p| Value::float_list(p)).collect())
    }

    /// A plain list of strings.
    pub fn strs<S: AsRef<str>>(v: impl IntoIterator<Item = S>) -> Self {
        Value::List(
            v.into_iter()
                .map(|s| Value::Str(s.as_ref().to_string()))
                .collect(),
        )
    }

    /// `Some(x)` as x, None as [`Value::None`].
    pub fn opt<T: Into<Value>>(v: Option<T>) -> Self {
        v.map_or(Value::None, Into::into)
    }
}

impl From<f64> for Value {
    fn from(x: f64) -> Self {
        Value::Float(x)
    }
}
impl From<usize> for Value {
    fn from(n: usize) -> Self {
        Value::count(n)
    }
}
impl From<u64> for Value {
    fn from(n: u64) -> Self {
        Value::Int(i64::try_from(n).unwrap_or(i64::MAX))
    }
}
impl From<bool> for Value {
    fn from(b: bool) -> Self {
        Value::Bool(b)
    }
}
impl From<&str> for Value {
    fn from(s: &str) -> Self {
        Value::Str(s.to_string())
    }
}
impl From<String> for Value {
    fn from(s: String) -> Self {
        Value::Str(s)
    }
}
impl From<Entries> for Value {
    fn from(t: Entries) -> Self {
        Value::Table(t)
    }
}

/// Named values in the order they were set (the order Python's dicts keep).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Entries(Vec<(String, Value)>);

impl Entries {
    pub fn new() -> Self {
        Self::default()
    }

    /// Sets `name` to `v`: a new name goes last, a name already set keeps its place.
    pub fn set(&mut self, name: impl Into<String>, v: impl Into<Value>) {
        let (name, v) = (name.into(), v.into());
        match self.0.iter_mut().find(|(k, _)| *k == name) {
            Some(slot) => slot.1 = v,
            None => self.0.push((name, v)),
        }
    }

    /// The value of `name`.
    pub fn get(&self, name: &str) -> Option<&Value> {
        self.0.iter().find(|(k, _)| k == name).map(|(_, v)| v)
    }

    /// Removes `name` (tests: a record with an entry missing).
    pub fn remove(&mut self, name: &str) -> Option<Value> {
        let i = self.0.iter().position(|(k, _)| k == name)?;
        Some(self.0.remove(i).1)
    }

    pub fn iter(&self) -> impl Iterator<Item = (&str, &Value)> {
        self.0.iter().map(|(k, v)| (k.as_str(), v))
    }

    pub fn len(&self) -> usize {
        self.0.len()
    }

    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }
}

impl IntoIterator for Entries {
    type Item = (String, Value);
    type IntoIter = std::vec::IntoIter<(String, Value)>;
    fn into_iter(self) -> Self::IntoIter {
        self.0.into_iter()
    }
}

/// The groups of a record ([`Record`]'s fields, in the order the bindings emit them).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Group {
    /// the top-level numbers every result has (`method`, `sigma22`, `cmod`, `n_dofs`,
    /// `wall_time_s`)
    Headline,
    /// arrays on the mesh or grid
    Fields,
    /// equal-length columns, one row per state of a load path (growth and SLA runs)
    History,
    /// single numbers
    Scalars,
    /// what the run was and how it went (status, counts, timings, the scene's echoes)
    Meta,
}

impl Group {
    pub const ALL: [Group; 5] = [
        Group::Headline,
        Group::Fields,
        Group::History,
        Group::Scalars,
        Group::Meta,
    ];

    /// The stable name (Python's `Result` attribute of the group; "headline" for the top level).
    pub fn name(self) -> &'static str {
        match self {
            Group::Headline => "headline",
            Group::Fields => "fields",
            Group::History => "history",
            Group::Scalars => "scalars",
            Group::Meta => "meta",
        }
    }
}

/// One run's result as named values in groups.
#[derive(Debug, Clone, PartialEq)]
pub struct Record {
    /// the method's name ([`crate::problem::schema::METHODS`])
    pub method: &'static str,
    pub headline: Entries,
    pub fields: Entries,
    pub history: Entries,
    pub scalars: Entries,
    pub meta: Entries,
}

impl Record {
    /// An empty record of `method`.
    pub fn new(method: &'static str) -> Self {
        Self {
            method,
            headline: Entries::new(),
            fields: Entries::new(),
            history: Entries::new(),
            scalars: Entries::new(),
            meta: Entries::new(),
        }
    }

    /// The entries of group `g`.
    pub fn group(&self, g: Group) -> &Entries {
        match g {
            Group::Headline => &self.headline,
            Group::Fields => &self.fields,
            Group::History => &self.history,
            Group::Scalars => &self.scalars,
            Group::Meta => &self.meta,
        }
    }

    /// The entries of group `g`, to change.
    pub fn group_mut(&mut self, g: Group) -> &mut Entries {
        match g {
            Group::Headline => &mut self.headline,
            Group::Fields => &mut self.fields,
            Group::History => &mut self.history,
            Group::Scalars => &mut self.scalars,
            Group::Meta => &mut self.meta,
        }
    }

    /// A float column of the history.
    pub fn column(&mut self, name: impl Into<String>, v: Vec<f64>) {
        self.history.set(name, Value::floats(v));
    }
}
