//! The one shape every result crosses in: `{method, sigma22, cmod, n_dofs, wall_time_s, fields,
//! history, scalars, meta}`, exactly the fields of `rustfrac.Result`.

use crate::arrays::arr1;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use rustfrac_core::problem::Problem;
use rustfrac_core::Warning;

/// A result being shaped for Python.
pub struct Shaped<'py> {
    pub py: Python<'py>,
    pub fields: Bound<'py, PyDict>,
    pub history: Bound<'py, PyDict>,
    pub scalars: Bound<'py, PyDict>,
    pub meta: Bound<'py, PyDict>,
    top: Bound<'py, PyDict>,
}

impl<'py> Shaped<'py> {
    /// The common part: the headline numbers and the meta every method carries (version,
    /// method, grips and their description, warnings with their kinds).
    pub fn new(
        py: Python<'py>,
        p: &Problem,
        headline: (f64, f64, usize, f64),
        warnings: &[Warning],
    ) -> PyResult<Self> {
        let (sigma22, cmod, n_dofs, wall) = headline;
        let top = PyDict::new(py);
        top.set_item("method", p.method.name())?;
        top.set_item("sigma22", sigma22)?;
        top.set_item("cmod", cmod)?;
        top.set_item("n_dofs", n_dofs)?;
        top.set_item("wall_time_s", wall)?;
        let meta = PyDict::new(py);
        meta.set_item("version", env!("CARGO_PKG_VERSION"))?;
        meta.set_item("method", p.method.name())?;
        meta.set_item("bc", p.boundary.plate_load().grip.name())?;
        meta.set_item("bc_description", p.boundary.description())?;
        let kinds: Vec<&str> = warnings.iter().map(|w| w.kind.name()).collect();
        let msgs: Vec<&str> = warnings.iter().map(|w| w.message.as_str()).collect();
        meta.set_item("warnings", msgs)?;
        meta.set_item("warning_kinds", kinds)?;
        Ok(Self {
            py,
            fields: PyDict::new(py),
            history: PyDict::new(py),
            scalars: PyDict::new(py),
            meta,
            top,
        })
    }

    /// A float column of the history.
    pub fn column(&self, name: &str, v: Vec<f64>) -> PyResult<()> {
        self.history.set_item(name, arr1(self.py, v))
    }

    /// The anchor node (None under clamped grips, where no anchor is needed).
    pub fn anchor(&self, p: &Problem, node: usize) -> PyResult<()> {
        let clamped = p.boundary.plate_load().grip == rustfrac_core::fe::loading::Grip::Clamped;
        if clamped {
            self.meta.set_item("anchor_node", self.py.None())
        } else {
            self.meta.set_item("anchor_node", node)
        }
    }

    /// The finished dict.
    pub fn finish(self) -> PyResult<Bound<'py, PyDict>> {
        self.top.set_item("fields", self.fields)?;
        self.top.set_item("history", self.history)?;
        self.top.set_item("scalars", self.scalars)?;
        self.top.set_item("meta", self.meta)?;
        Ok(self.top)
    }
}
