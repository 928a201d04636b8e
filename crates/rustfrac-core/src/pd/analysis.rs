//! A PD or CCM-PD analysis of a problem: the critical stretch's calibration
//! (`pd.s0_calibration`, [`crate::pd::calibration`]), the splice model built with it
//! ([`crate::pd::splice`]) and the sequentially linear analysis on that model
//! ([`crate::pd::sla`]). The calibration is made here, above the SLA, because its `"sla"` rule
//! runs an SLA itself (on a reference strip): the splice model takes the factor it is handed and
//! does not reach up into the calibration.

use crate::error::Result;
use crate::pd::calibration::calibration;
use crate::pd::sla::{self, CcmPdResult, SlaProgress};
use crate::pd::splice::SpliceModel;
use crate::problem::{validate, Calibration, Problem};

/// The calibration `p`'s scene asks for (`pd.s0_calibration` at its `pd.m`; the identity for a
/// problem that is not PD, which the splice model then refuses).
pub fn s0_calibration(p: &Problem) -> Result<Calibration> {
    match p.pd() {
        Some(pm) => calibration(pm.s0_calibration, pm.m),
        None => Ok(Calibration::continuum()),
    }
}

/// The splice model of `p` with its s0 calibration ([`SpliceModel::new`]).
pub fn splice_model(p: &Problem) -> Result<SpliceModel> {
    validate::problem(p)?;
    SpliceModel::new(p, s0_calibration(p)?)
}

/// Runs a CCM-PD (or pure PD) problem: the calibration, then [`sla::run_calibrated`].
/// `progress(step, max_steps)` is called after every step; returning `false` stops the run
/// (status [`sla::SlaStatus::Cancelled`], a checkpoint is written first when `checkpoint_path`
/// is set).
pub fn run(p: &Problem, progress: &(dyn Fn(usize, usize) -> bool + Sync)) -> Result<CcmPdResult> {
    run_reporting(p, &|s: &SlaProgress| progress(s.step, s.max_steps))
}

/// [`run`] with a callback that reads the whole [`SlaProgress`] after every step (the crack's
/// advance towards `pd.stop_crack_length` besides the step).
pub fn run_reporting(
    p: &Problem,
    progress: &(dyn Fn(&SlaProgress) -> bool + Sync),
) -> Result<CcmPdResult> {
    validate::problem(p)?;
    sla::run_calibrated(p, s0_calibration(p)?, progress)
}
