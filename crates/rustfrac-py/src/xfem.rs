//! XFEM (Heaviside + branch enrichment, interaction-integral SIFs, LEFM growth): the run, its
//! progress, and its record ([`rustfrac_core::output`]: the names, shapes and units of its
//! fields, history, scalars and meta).

use crate::errors::detached;
use crate::progress::Progress;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use rustfrac_core::problem::number::short;
use rustfrac_core::problem::{Method, Problem};
use rustfrac_core::xfem;
use std::time::Instant;

/// Runs the XFEM plate of `p` and returns its record.
pub fn run<'py>(py: Python<'py>, p: &Problem, prog: &Progress) -> PyResult<Bound<'py, PyDict>> {
    let growth = match &p.method {
        Method::Xfem(x) => x.growth,
        _ => None,
    };
    let est = p.growth_steps_estimate();
    let total = est.unwrap_or(1);
    let t0 = Instant::now();
    let r = detached(py, "xfem plate", || {
        prog.report(0, total, "xfem: enrich + assemble + solve", true);
        let r = xfem::run(p, &|done, _| match (est, &growth) {
            (Some(est), Some(g)) => {
                let msg = format!(
                    "xfem: growth step {done} of ~{est} (a_stop {})",
                    short(g.a_stop)
                );
                prog.report(done.min(est), est, &msg, false)
            }
            _ => true,
        });
        prog.report(total, total, "xfem: done", true);
        r
    });
    let wall = t0.elapsed().as_secs_f64();
    prog.deliver(py, r, |r| {
        crate::record::to_dict(py, r.into_record(p, wall))
    })
}
