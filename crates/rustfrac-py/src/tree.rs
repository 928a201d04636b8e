//! Python objects as the core's scene tree ([`Value`]) and back, knowing no scene key: the
//! conversion is the same for every parameter, so adding one touches only the core.

use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};
use rustfrac_core::problem::value::{Table, Value};

/// Deepest nesting a scene may have (TOML tables of arrays are two or three levels deep).
pub const MAX_DEPTH: usize = 32;

fn other(ob: &Bound<'_, PyAny>, repr: Option<String>) -> Value {
    let type_name = ob
        .get_type()
        .name()
        .map(|n| n.to_string())
        .unwrap_or_else(|_| "object".into());
    let repr = repr.unwrap_or_else(|| {
        ob.repr()
            .map(|r| r.to_string_lossy().into_owned())
            .unwrap_or_else(|_| format!("<{type_name}>"))
    });
    Value::Other { type_name, repr }
}

/// A key of a Python dict as text (TOML keys are strings; a dict may hold anything).
fn key_text(k: &Bound<'_, PyAny>) -> String {
    match k.cast::<PyString>() {
        Ok(s) => s
            .to_cow()
            .map(|c| c.into_owned())
            .unwrap_or_else(|_| "<a key that is not valid Unicode>".into()),
        Err(_) => other(k, None).repr(),
    }
}

/// The tree of a Python object (dicts, lists, tuples, str, int, float, bool).
pub fn to_value(ob: &Bound<'_, PyAny>, depth: usize) -> Value {
    if depth > MAX_DEPTH {
        return Value::Other {
            type_name: "nested value".into(),
            repr: format!("a value nested deeper than {MAX_DEPTH} levels"),
        };
    }
    if let Ok(b) = ob.cast::<PyBool>() {
        return Value::Bool(b.is_true());
    }
    if ob.is_instance_of::<PyInt>() {
        return match ob.extract::<i64>() {
            Ok(i) => Value::Int(i),
            Err(_) => {
                let bits: u64 = ob
                    .call_method0("bit_length")
                    .and_then(|b| b.extract())
                    .unwrap_or(0);
                Value::Other {
                    type_name: "int".into(),
                    repr: format!("an integer of {bits} bits"),
                }
            }
        };
    }
    if let Ok(f) = ob.cast::<PyFloat>() {
        return Value::Float(f.value());
    }
    if let Ok(s) = ob.cast::<PyString>() {
        return match s.to_cow() {
            Ok(s) => Value::Str(s.into_owned()),
            Err(_) => Value::Other {
                type_name: "str".into(),
                repr: "a string that is not valid Unicode text (lone surrogates)".into(),
            },
        };
    }
    if let Ok(d) = ob.cast::<PyDict>() {
        let mut t = Table::new();
        for (k, v) in d.iter() {
            t.insert(key_text(&k), to_value(&v, depth + 1));
        }
        return Value::Table(t);
    }
    if let Ok(l) = ob.cast::<PyList>() {
        return Value::List(l.iter().map(|v| to_value(&v, depth + 1)).collect());
    }
    if let Ok(l) = ob.cast::<PyTuple>() {
        return Value::List(l.iter().map(|v| to_value(&v, depth + 1)).collect());
    }
    other(ob, None)
}

/// The table of a Python dict (a scene).
pub fn to_table(ob: &Bound<'_, PyAny>) -> Result<Table, rustfrac_core::Error> {
    match to_value(ob, 0) {
        Value::Table(t) => Ok(t),
        v => Err(rustfrac_core::Error::InvalidType {
            param: "scene".into(),
            expected: "a dict".into(),
            got: v.type_name().to_string(),
        }),
    }
}

/// A tree value as a Python object.
pub fn to_py<'py>(py: Python<'py>, v: &Value) -> PyResult<Bound<'py, PyAny>> {
    Ok(match v {
        Value::Bool(b) => PyBool::new(py, *b).to_owned().into_any(),
        Value::Int(i) => i.into_pyobject(py)?.into_any(),
        Value::Float(f) => f.into_pyobject(py)?.into_any(),
        Value::Str(s) => PyString::new(py, s).into_any(),
        Value::List(l) => {
            let items: PyResult<Vec<_>> = l.iter().map(|x| to_py(py, x)).collect();
            PyList::new(py, items?)?.into_any()
        }
        Value::Table(t) => {
            let d = PyDict::new(py);
            for (k, x) in t {
                d.set_item(k, to_py(py, x)?)?;
            }
            d.into_any()
        }
        Value::Other { repr, .. } => PyString::new(py, repr).into_any(),
    })
}
