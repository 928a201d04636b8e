//! The scene description of the core for Python: its schema (every key's kind, default, range
//! and meaning), the checks of one section and of a whole scene, and derived values the Python
//! layer shows (crack polylines). Python keeps the TOML/dict structure and reads every rule here.

use crate::errors::core_err;
use crate::tree::{to_py, to_table, to_value};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use rustfrac_core::problem::value::Value;
use rustfrac_core::problem::{parse, schema, Problem};

/// Every scene key: a list of dicts with section, key, kind ("float" | "int" | "str" | "bool" |
/// "pair" | "intlist" | "floatlist" | "pairlist"), default, valid (the range in words, made from
/// the range the core checks), role ("physics" | "solver" | "output": what the value changes;
/// a checkpoint resumes only the same physics and solver keys), required (None: optional; a
/// dict {key: [values]}: required when each of those keys has one of the values, {} always),
/// required_words (the same in words, "" when optional) and doc.
#[pyfunction]
pub fn scene_schema(py: Python<'_>) -> PyResult<Bound<'_, PyList>> {
    let rows = PyList::empty(py);
    for k in schema::schema() {
        let d = PyDict::new(py);
        d.set_item("section", k.section)?;
        d.set_item("key", k.key)?;
        d.set_item("kind", k.kind.name())?;
        d.set_item("default", to_py(py, &k.default.to_value())?)?;
        d.set_item("valid", k.valid())?;
        d.set_item("role", k.role.name())?;
        let required = match k.required {
            schema::Required::No => None,
            schema::Required::Always => Some(PyDict::new(py)),
            schema::Required::When { key, values } => {
                let r = PyDict::new(py);
                r.set_item(key, values.to_vec())?;
                Some(r)
            }
        };
        d.set_item("required", required)?;
        d.set_item("required_words", k.required_words())?;
        d.set_item("doc", k.doc)?;
        rows.append(d)?;
    }
    Ok(rows)
}

/// The scene's structural constants: methods, grips, sections, the sections and crack kinds of
/// each method, the default crack kind, and the size limits.
#[pyfunction]
pub fn scene_constants(py: Python<'_>) -> PyResult<Bound<'_, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("METHODS", schema::METHODS.to_vec())?;
    d.set_item("BCS", schema::BCS.to_vec())?;
    d.set_item("S0_CALIBRATIONS", schema::S0_CALIBRATIONS.to_vec())?;
    d.set_item("SURFACE_CORRECTIONS", schema::SURFACE_CORRECTIONS.to_vec())?;
    d.set_item("SECTIONS", schema::SECTIONS.to_vec())?;
    let (sections, kinds, default_kind) = (PyDict::new(py), PyDict::new(py), PyDict::new(py));
    for m in schema::METHODS {
        sections.set_item(m, schema::method_sections(m).to_vec())?;
        kinds.set_item(m, schema::crack_kinds(m).to_vec())?;
        default_kind.set_item(m, schema::default_crack_kind(m))?;
    }
    d.set_item("METHOD_SECTIONS", sections)?;
    d.set_item("CRACK_KINDS", kinds)?;
    d.set_item("DEFAULT_CRACK_KIND", default_kind)?;
    d.set_item("MAX_ELEMENTS", schema::max_elements())?;
    d.set_item("MAX_STEPS", schema::MAX_STEPS)?;
    d.set_item("DEFAULT_A_STOP_FRACTION", schema::DEFAULT_A_STOP_FRACTION)?;
    d.set_item("PD_NU", schema::PD_NU)?;
    d.set_item("XFEM_EXTRA_RADII", schema::XFEM_EXTRA_RADII.to_vec())?;
    Ok(d)
}

/// Checks one section's values (kinds, ranges, unknown keys, rules between its keys) and
/// returns them normalised, every key present (defaults filled in). `name` is the section's
/// scene name in messages (e.g. "crack[2]"; default: the section).
#[pyfunction]
#[pyo3(signature = (section, values, name = None))]
pub fn check_section<'py>(
    py: Python<'py>,
    section: &str,
    values: &Bound<'py, PyAny>,
    name: Option<&str>,
) -> PyResult<Bound<'py, PyDict>> {
    let checked = parse::section(section, name.unwrap_or(section), &to_value(values, 0))
        .map_err(|e| core_err(py, e))?;
    let d = PyDict::new(py);
    for (k, v) in checked {
        d.set_item(k, to_py(py, &v.to_value())?)?;
    }
    Ok(d)
}

/// Checks a whole scene dict (every rule of the core, cross-parameter checks included) before
/// anything is built, raising the error of the first refused key; returns the checked scene:
/// method, name, every section the method reads with every key (defaults filled in) and
/// "crack" as a list of crack dicts.
#[pyfunction]
pub fn check_scene<'py>(py: Python<'py>, scene: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
    let t = to_table(scene).map_err(|e| core_err(py, e))?;
    let (_, tree) = Problem::checked(&t).map_err(|e| core_err(py, e))?;
    to_py(py, &Value::Table(tree))
}

/// The polylines [(x1, x2), ...] of a scene's cracks as the method cuts them (a FEM seam on its
/// grid line, to its grid node; empty list for an uncracked scene).
#[pyfunction]
pub fn crack_polylines(py: Python<'_>, scene: &Bound<'_, PyAny>) -> PyResult<Vec<Vec<[f64; 2]>>> {
    let t = to_table(scene).map_err(|e| core_err(py, e))?;
    let p = parse::problem(&t).map_err(|e| core_err(py, e))?;
    // a FEM seam as the grid cuts it (the scene's lines where it cannot be cut: the run refuses)
    Ok(rustfrac_core::fem_driver::cut_polylines(&p).unwrap_or_else(|_| p.crack_polylines()))
}

/// The warnings of a valid scene, said before it runs: `[(message, kind), ...]` (a default
/// sized for another plate, the estimated cost past its budget; the core's
/// `Problem::scene_warnings`). The run's result carries them too.
#[pyfunction]
pub fn scene_warnings(py: Python<'_>, scene: &Bound<'_, PyAny>) -> PyResult<Vec<(String, String)>> {
    let t = to_table(scene).map_err(|e| core_err(py, e))?;
    let p = Problem::from_scene(&t).map_err(|e| core_err(py, e))?;
    Ok(p.scene_warnings()
        .into_iter()
        .map(|w| (w.message, w.kind.name().to_string()))
        .collect())
}

/// The scene tree of a Python dict, for the runners.
pub fn problem_of(py: Python<'_>, scene: &Bound<'_, PyAny>, condition: bool) -> PyResult<Problem> {
    let t = to_table(scene).map_err(|e| core_err(py, e))?;
    let mut p = Problem::from_scene(&t).map_err(|e| core_err(py, e))?;
    rustfrac_core::problem::validate::reference_load(&p).map_err(|e| core_err(py, e))?;
    p.set_condition(condition);
    Ok(p)
}
