//! Bond-based peridynamics (PD everywhere) and the splice CCM-PD coupling, solved by the
//! sequentially linear analysis: the run, its progress, and its record
//! ([`rustfrac_core::output`]: the SLA history with the unloaded origin first, the grid's
//! fields and damage, the PD constants, the run's meta).

use crate::errors::{core_err, detached};
use crate::progress::Progress;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use rustfrac_core::error::Error as CoreError;
use rustfrac_core::pd::analysis;
use rustfrac_core::pd::sla::SlaProgress;
use rustfrac_core::problem::Problem;
use std::time::Instant;

/// Progress units of a run with a crack-length stop (`pd.stop_crack_length`): the total its
/// reports count the crack's advance in.
const CRACK_UNITS: usize = 1000;

/// Runs the PD or CCM-PD model of `p` with its SLA and returns its record.
pub fn run<'py>(py: Python<'py>, p: &Problem, prog: &Progress) -> PyResult<Bound<'py, PyDict>> {
    let name = p.method.name();
    let sla_params = &p.pd().expect("a PD problem").sla;
    let (max_steps, stop) = (sla_params.max_steps, sla_params.stop_crack_length);
    let t0 = Instant::now();
    let r = detached(py, name, || {
        // with a crack-length stop the run ends at that length, usually long before max_steps:
        // the bar counts the crack's advance then (SlaProgress::fraction), in CRACK_UNITS
        let total = if stop.is_some() {
            CRACK_UNITS
        } else {
            max_steps.max(1)
        };
        if !prog.report(0, total, &format!("{name}: building the model"), true) {
            return Err(CoreError::Internal {
                detail: "cancelled".into(),
            });
        }
        // a raising callback stops the run (status "cancelled", a checkpoint is written when
        // configured); its exception is re-raised below
        let report = |s: &SlaProgress| match s.stop_crack_length {
            None => prog.report(
                s.step,
                total,
                &format!("sla: step {}/{total}", s.step),
                false,
            ),
            Some(stop) => prog.report(
                (s.fraction() * CRACK_UNITS as f64).round() as usize,
                total,
                &format!(
                    "sla: step {}, crack length {:.3} of {stop:.3}",
                    s.step, s.crack_length
                ),
                false,
            ),
        };
        let r = analysis::run_reporting(p, &report)?;
        let msg = format!("sla: {} after {} steps", r.run.status, r.history.len());
        prog.report(total, total, &msg, true);
        Ok(r)
    });
    let wall = t0.elapsed().as_secs_f64();
    prog.deliver(py, r, |r| {
        let rec = r.into_record(p, wall).map_err(|e| core_err(py, e))?;
        crate::record::to_dict(py, rec)
    })
}
