//! A run's record ([`rustfrac_core::output::Record`]) as the dict `rustfrac.Result` stores,
//! knowing no result name: the conversion is the same for every entry, so adding one touches
//! only the core. Also the table of every entry and status for Python (`result_schema`).

use crate::errors::py_error;
use numpy::ndarray::{ArrayD, IxDyn};
use numpy::{IntoPyArray, PyArray1};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyList, PyString};
use rustfrac_core::output::{schema, status, Entries, Group, Record, Value};

/// A record value as a Python object: numbers, strings and None as themselves, arrays as numpy
/// arrays (float64, int64, bool; moved, not copied), lists as lists, tables as dicts.
fn to_py(py: Python<'_>, v: Value) -> PyResult<Bound<'_, PyAny>> {
    fn shaped<T: numpy::Element>(
        py: Python<'_>,
        shape: Vec<usize>,
        data: Vec<T>,
    ) -> PyResult<Bound<'_, PyAny>> {
        let a = ArrayD::from_shape_vec(IxDyn(&shape), data).map_err(|e| {
            py_error(
                py,
                "InternalError",
                format!("a result array of shape {shape:?}: {e}"),
                None,
            )
        })?;
        Ok(a.into_pyarray(py).into_any())
    }
    Ok(match v {
        Value::None => py.None().into_bound(py),
        Value::Bool(b) => PyBool::new(py, b).to_owned().into_any(),
        Value::Int(i) => i.into_pyobject(py)?.into_any(),
        Value::Float(f) => f.into_pyobject(py)?.into_any(),
        Value::Str(s) => PyString::new(py, &s).into_any(),
        Value::Floats { shape, data } => shaped(py, shape, data)?,
        Value::Ints { shape, data } => shaped(py, shape, data)?,
        Value::Bools(b) => PyArray1::from_vec(py, b).into_any(),
        Value::List(l) => {
            let items: PyResult<Vec<_>> = l.into_iter().map(|x| to_py(py, x)).collect();
            PyList::new(py, items?)?.into_any()
        }
        Value::Table(t) => table(py, t)?.into_any(),
    })
}

fn table(py: Python<'_>, t: Entries) -> PyResult<Bound<'_, PyDict>> {
    let d = PyDict::new(py);
    for (k, v) in t {
        d.set_item(k, to_py(py, v)?)?;
    }
    Ok(d)
}

/// The record as `{<headline>..., fields, history, scalars, meta}`, the fields of
/// `rustfrac.Result`.
pub fn to_dict(py: Python<'_>, rec: Record) -> PyResult<Bound<'_, PyDict>> {
    let top = table(py, rec.headline)?;
    for (g, es) in [
        (Group::Fields, rec.fields),
        (Group::History, rec.history),
        (Group::Scalars, rec.scalars),
        (Group::Meta, rec.meta),
    ] {
        top.set_item(g.name(), table(py, es)?)?;
    }
    Ok(top)
}

/// The result schema: `{"entries": [...], "statuses": {method: [...]}}`. Each entry is a dict
/// with methods (list), group ("headline" | "fields" | "history" | "scalars" | "meta"), name
/// (`<region>` / `<name>` parts stand for any region or probe; `table.key` a nested table's
/// key), kind ("float" | "int" | "bool" | "str" | "float array" | "int array" | "bool array" |
/// "float list" | "str list" | "table" | "table list"), shape (e.g. "(n_nodes, 2)", or None),
/// nullable, unit ("length", "stress", "1", ...; "" for text, tables and indices), presence
/// ("always", "when ...", "python: ...") and doc; each status a dict with name and doc.
#[pyfunction]
pub fn result_schema(py: Python<'_>) -> PyResult<Bound<'_, PyDict>> {
    let rows = PyList::empty(py);
    for e in schema::schema() {
        let d = PyDict::new(py);
        d.set_item("methods", e.methods.names())?;
        d.set_item("group", e.group.name())?;
        d.set_item("name", e.name)?;
        d.set_item("kind", e.kind.name())?;
        d.set_item("shape", e.kind.shape_text())?;
        d.set_item("nullable", e.nullable)?;
        d.set_item("unit", e.unit)?;
        d.set_item("presence", e.presence.text())?;
        d.set_item("doc", e.doc)?;
        rows.append(d)?;
    }
    let statuses = PyDict::new(py);
    for m in rustfrac_core::problem::schema::METHODS {
        let l = PyList::empty(py);
        for s in status::statuses(m) {
            let d = PyDict::new(py);
            d.set_item("name", s.name)?;
            d.set_item("doc", s.doc)?;
            l.append(d)?;
        }
        statuses.set_item(m, l)?;
    }
    let out = PyDict::new(py);
    out.set_item("entries", rows)?;
    out.set_item("statuses", statuses)?;
    Ok(out)
}
