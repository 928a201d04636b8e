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
            .is_none_or(|l| l.grip == rustfrac_core::problem::Grip::Clamped);
        if none {
            self.meta.set_item("anchor_node", self.py.None())
        } else {
            self.meta.set_item("anchor_node", node)
        }
    }

    /// `meta["work_conjugate"]`: the pair (a, b) whose product with the history's sigma22 and u0
    /// is twice the load's work ([`rustfrac_core::problem::Boundary::work_conjugate`]), or None.
    pub fn work_conjugate(&self, p: &Problem) -> PyResult<()> {
        let t = p.material.elastic.thickness;
        match p.boundary.work_conjugate(p.domain.width, t) {
            Some(ab) => self.meta.set_item("work_conjugate", ab.to_vec()),
            None => self.meta.set_item("work_conjugate", self.py.None()),
        }
    }

    /// The general scene's responses as flat scalars (present only for the parts a scene has):
    /// `force:<region>:1|2` (the force a support or load region receives from outside),
    /// `mean_stress:<region>` (edge regions), `displacement:<region>:1|2` (its mean),
    /// `probe:<name>:1|2`, and with supports and loads on regions `load_displacement`.
    pub fn responses(&self, p: &Problem, r: &SceneResponses) -> PyResult<()> {
        let sc = &self.scalars;
        for (name, v) in &r.regions {
            for c in 0..2 {
                sc.set_item(format!("force:{name}:{}", c + 1), v.force[c])?;
                sc.set_item(format!("displacement:{name}:{}", c + 1), v.displacement[c])?;
            }
            if let Some(m) = v.mean_stress {
                sc.set_item(format!("mean_stress:{name}"), m)?;
            }
        }
        for (name, v) in &r.probes {
            for (c, x) in v.iter().enumerate() {
                sc.set_item(format!("probe:{name}:{}", c + 1), x)?;
            }
        }
        if p.boundary.grips().is_none() {
            sc.set_item("load_displacement", r.load_displacement)?;
        }
        Ok(())
    }

    /// History columns of the responses along a load path (one entry per history row):
    /// `probe:<name>:1|2`, `force:<region>:1|2`, `mean_stress:<region>` (edge regions), and
    /// with supports and loads on regions `load_displacement`.
    pub fn response_columns(&self, p: &Problem, rows: &[SceneResponses]) -> PyResult<()> {
        let Some(first) = rows.first() else {
            return Ok(());
        };
        if p.boundary.grips().is_none() {
            self.column(
                "load_displacement",
                rows.iter().map(|r| r.load_displacement).collect(),
            )?;
        }
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
