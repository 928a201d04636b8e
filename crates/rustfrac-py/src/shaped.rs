//! The one shape every result crosses in: `{method, sigma22, cmod, n_dofs, wall_time_s, fields,
//! history, scalars, meta}`, exactly the fields of `rustfrac.Result`.

use crate::arrays::arr1;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use rustfrac_core::fe::regions::SceneResponses;
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
        meta.set_item("bc", p.boundary.name())?;
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

    /// The anchor node (None under clamped grips, where no anchor is needed, and with supports
    /// on regions, which need none).
    pub fn anchor(&self, p: &Problem, node: usize) -> PyResult<()> {
        let none = p
            .boundary
            .grips()
            .is_none_or(|l| l.grip == rustfrac_core::fe::loading::Grip::Clamped);
        if none {
            self.meta.set_item("anchor_node", self.py.None())
        } else {
            self.meta.set_item("anchor_node", node)
        }
    }

    /// The general scene's responses: `scalars["regions"]` = {name: {force, mean_stress,
    /// displacement}}, `scalars["probes"]` = {name: [a, b]}, `scalars["load_displacement"]`;
    /// with a history, the columns `probe:<name>` (two components each) scaled per state.
    pub fn responses(&self, r: &SceneResponses) -> PyResult<()> {
        let regions = PyDict::new(self.py);
        for (name, v) in &r.regions {
            let d = PyDict::new(self.py);
            d.set_item("force", v.force.to_vec())?;
            d.set_item("mean_stress", v.mean_stress)?;
            d.set_item("displacement", v.displacement.to_vec())?;
            regions.set_item(name, d)?;
        }
        let probes = PyDict::new(self.py);
        for (name, v) in &r.probes {
            probes.set_item(name, v.to_vec())?;
        }
        self.scalars.set_item("regions", regions)?;
        self.scalars.set_item("probes", probes)?;
        self.scalars
            .set_item("load_displacement", r.load_displacement)
    }

    /// History columns of the responses along a load path (one entry per history row):
    /// `load_displacement`, `probe:<name>:1|2`, `force:<region>:1|2`, `mean_stress:<region>`
    /// (edge regions).
    pub fn response_columns(&self, rows: &[SceneResponses]) -> PyResult<()> {
        let Some(first) = rows.first() else {
            return Ok(());
        };
        self.column(
            "load_displacement",
            rows.iter().map(|r| r.load_displacement).collect(),
        )?;
        for (k, (name, _)) in first.probes.iter().enumerate() {
            for c in 0..2 {
                let v = rows.iter().map(|r| r.probes[k].1[c]).collect();
                self.column(&format!("probe:{name}:{}", c + 1), v)?;
            }
        }
        for (k, (name, reg)) in first.regions.iter().enumerate() {
            for c in 0..2 {
                let v = rows.iter().map(|r| r.regions[k].1.force[c]).collect();
                self.column(&format!("force:{name}:{}", c + 1), v)?;
            }
            if reg.mean_stress.is_some() {
                let v = rows
                    .iter()
                    .map(|r| r.regions[k].1.mean_stress.unwrap_or(0.0))
                    .collect();
                self.column(&format!("mean_stress:{name}"), v)?;
            }
        }
        Ok(())
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
