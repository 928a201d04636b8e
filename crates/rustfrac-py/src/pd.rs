//! Bond-based peridynamics (PD everywhere) and the splice CCM-PD coupling, solved by the
//! sequentially linear analysis: the run's result for Python.
//!
//! History: one row per SLA step, recorded at the load that breaks the step's bond(s), after the
//! unloaded origin as row 0 (so sigma22 against cmod starts from (0, 0)): step, load_factor,
//! sigma22, cmod, u0, crack_length, bond (the critical bond), n_broken, node_i, node_j,
//! n_detached, and per probe of the scene probe:<name>:1|2 (at the step's load). Fields: node_xy, u, u_final (empty when the body separated), pd_nodes,
//! pd_node_xy, damage, broken, bond_nodes, detached_nodes (d,2) (step, node; step 0 = by the
//! pre-crack), damage_at_steps, damage_at (k,p).

use crate::arrays::{arr1, arr2, ints, pairs_i64, table};
use crate::errors::{detached, py_error};
use crate::progress::Progress;
use crate::shaped::Shaped;
use numpy::PyArray1;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use rustfrac_core::error::Error as CoreError;
use rustfrac_core::pd::sla::{self, CcmPdResult, SlaProgress, SlaStep};
use rustfrac_core::problem::{Method, Problem};
use std::time::Instant;

/// Progress units of a run with a crack-length stop (`pd.stop_crack_length`): the total its
/// reports count the crack's advance in.
const CRACK_UNITS: usize = 1000;

/// Runs the PD or CCM-PD model of `p` with its SLA and shapes the result.
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
        let r = sla::run_reporting(p, &report)?;
        let msg = format!("sla: {} after {} steps", r.status, r.history.len());
        prog.report(total, total, &msg, true);
        Ok(r)
    });
    let wall = t0.elapsed().as_secs_f64();
    prog.deliver(py, r, |r| {
        let s = Shaped::new(py, p, (r.sigma22, r.cmod, r.n_dofs, wall), &r.warnings)?;
        history(&s, &r)?;
        fields(&s, &r)?;
        meta(&s, &r, p, wall)?;
        s.finish()
    })
}

fn history(s: &Shaped<'_>, r: &CcmPdResult) -> PyResult<()> {
    let py = s.py;
    let o = r.origin();
    let h: Vec<&SlaStep> = std::iter::once(&o).chain(&r.history).collect();
    let col = |f: fn(&SlaStep) -> f64| -> Vec<f64> { h.iter().map(|x| f(x)).collect() };
    let idx = |f: fn(&SlaStep) -> i64| {
        PyArray1::from_vec(py, h.iter().map(|x| f(x)).collect()).into_any()
    };
    let node = |n: usize| if n == usize::MAX { -1 } else { n as i64 };
    s.history.set_item("step", idx(|x| x.step as i64))?;
    s.column("load_factor", col(|x| x.lambda))?;
    s.column("sigma22", col(|x| x.sigma22))?;
    s.column("cmod", col(|x| x.cmod))?;
    s.column("u0", col(|x| x.u0))?;
    s.column("crack_length", col(|x| x.crack_length))?;
    s.history
        .set_item("bond", idx(|x| x.bonds.first().map_or(-1, |&b| b as i64)))?;
    s.history
        .set_item("n_broken", idx(|x| x.bonds.len() as i64))?;
    let ni: Vec<i64> = h.iter().map(|x| node(x.nodes[0])).collect();
    let nj: Vec<i64> = h.iter().map(|x| node(x.nodes[1])).collect();
    s.history.set_item("node_i", PyArray1::from_vec(py, ni))?;
    s.history.set_item("node_j", PyArray1::from_vec(py, nj))?;
    s.history
        .set_item("n_detached", idx(|x| x.detached.len() as i64))?;
    // the probes at every step's load (the origin: unloaded, zero)
    for (k, (name, _)) in r.responses.probes.iter().enumerate() {
        for c in 0..2 {
            let v = h
                .iter()
                .map(|x| x.probes.get(k).map_or(0.0, |p| p[c]))
                .collect();
            s.column(&format!("probe:{name}:{}", c + 1), v)?;
        }
    }
    Ok(())
}

fn fields(s: &Shaped<'_>, r: &CcmPdResult) -> PyResult<()> {
    let py = s.py;
    let f = &s.fields;
    let p = r.damage.len();
    f.set_item(
        "damage_at_steps",
        ints(py, r.damage_at.iter().map(|(k, _)| *k)),
    )?;
    let snaps: Vec<f64> = r.damage_at.iter().flat_map(|(_, v)| v.clone()).collect();
    if snaps.len() != r.damage_at.len() * p {
        return Err(py_error(
            py,
            "InternalError",
            "damage_at: snapshots of unequal length".into(),
            None,
        ));
    }
    f.set_item("damage_at", table(py, r.damage_at.len(), p, snaps))?;
    f.set_item("node_xy", arr2(py, r.node_xy.clone()))?;
    f.set_item("u", arr1(py, r.u.clone()))?;
    f.set_item("u_final", arr1(py, r.u_final.clone()))?;
    f.set_item("pd_nodes", ints(py, r.pd_nodes.iter().copied()))?;
    f.set_item("pd_node_xy", arr2(py, r.pd_node_xy.clone()))?;
    f.set_item("damage", arr1(py, r.damage.clone()))?;
    f.set_item("broken", PyArray1::from_vec(py, r.broken.clone()))?;
    f.set_item("bond_nodes", pairs_i64(py, r.bond_nodes.iter().copied()))?;
    f.set_item(
        "detached_nodes",
        pairs_i64(py, r.detached_nodes.iter().map(|&(st, n)| [st, n])),
    )?;
    Ok(())
}

fn meta(s: &Shaped<'_>, r: &CcmPdResult, p: &Problem, wall: f64) -> PyResult<()> {
    let py = s.py;
    for (k, v) in [
        ("gamma", r.gamma),
        ("c", r.c),
        ("s0", r.s0),
        ("delta", r.delta),
    ] {
        s.scalars.set_item(k, v)?;
    }
    let m = &s.meta;
    let (Method::Pd(pd) | Method::CcmPd(pd)) = &p.method else {
        return Ok(());
    };
    if pd.regions.is_empty() {
        let d = format!(
            "{}; on volumetric PD boundary layers",
            p.boundary.description()
        );
        m.set_item("bc_description", d)?;
    }
    s.anchor(p, r.anchor_node)?;
    s.work_conjugate(p)?;
    // the general scene's responses of the pre-cracked model before any break (the history's
    // sigma22 and u0 follow every break)
    s.responses(p, &r.responses)?;
    if m.get_item("anchor_node")?.is_some_and(|a| a.is_none()) {
        m.set_item("anchor_xy", py.None())?;
    } else {
        m.set_item("anchor_xy", r.anchor_xy.to_vec())?;
    }
    m.set_item("status", r.status.name())?;
    m.set_item("solver", &r.solver)?;
    m.set_item("sla_steps_done", r.history.len())?;
    match r.regions.is_empty() {
        false => m.set_item("pd_regions", r.regions.clone())?,
        true => m.set_item("pd_regions", "the whole plate")?,
    }
    // the adaptive region: where it started, its growths, and the closest approach of a broken
    // bond to the FEM part (every CCM-PD run)
    // the scene key's own values ("fixed", "adaptive")
    let [fixed, adaptive] = rustfrac_core::problem::schema::PD_REGIONS;
    let region = if pd.adaptive.is_some() {
        adaptive
    } else {
        fixed
    };
    m.set_item("pd_region", region)?;
    // the surface correction (scene key pd.surface_correction) and, with it, its factors
    m.set_item("surface_correction", pd.surface_correction.name())?;
    if let Some(sc) = &r.surface_correction {
        m.set_item("surface_nodes_corrected", sc.n_nodes_corrected)?;
        m.set_item("surface_node_factor_range", sc.node_factor_range.to_vec())?;
        m.set_item("surface_bond_factor_range", sc.bond_factor_range.to_vec())?;
    }
    // the critical stretch's rule: s0 = factor x eq. 48's, G_ref / G0 with eq. 48's s0
    // (memoised in the core: no second strip run)
    let cal = rustfrac_core::pd::calibration::calibration(pd.s0_calibration, pd.m)
        .map_err(|e| crate::errors::core_err(py, e))?;
    let d = PyDict::new(py);
    d.set_item("rule", cal.rule.name())?;
    d.set_item("factor", cal.factor)?;
    d.set_item("G_ref_over_G0", cal.g_ref_over_g0)?;
    m.set_item("s0_calibration", d)?;
    if pd.adaptive.is_some() {
        m.set_item("pd_regions_initial", pd.regions.clone())?;
    }
    let switches = PyList::empty(py);
    for sw in &r.switches {
        let d = PyDict::new(py);
        d.set_item("step", sw.step)?;
        d.set_item("n_regions", sw.regions.len())?;
        d.set_item("n_pd_nodes", sw.n_pd_nodes)?;
        d.set_item("n_dofs", sw.n_dofs)?;
        d.set_item("seconds", sw.seconds)?;
        switches.append(d)?;
    }
    m.set_item("region_switches", switches)?;
    m.set_item("interface_distance_min", r.interface_distance_min)?;
    m.set_item("precrack", p.pd_precrack())?;
    m.set_item("out_of_balance", r.out_of_balance.to_vec())?;
    m.set_item("n_refactorisations", r.n_refactorisations)?;
    m.set_item("max_update_rank", r.max_update_rank)?;
    m.set_item("inverse_columns", r.inverse_columns)?;
    m.set_item("screened_steps", r.screened_steps)?;
    m.set_item("screened_bonds", r.screened_bonds)?;
    m.set_item("refactor_interval", r.refactor_interval)?;
    m.set_item("resumed_steps", r.resumed_steps)?;
    m.set_item("n_checkpoints", r.n_checkpoints)?;
    let path = |q: &Option<std::path::PathBuf>| q.as_ref().map(|x| x.display().to_string());
    m.set_item("checkpoint_path", path(&pd.sla.checkpoint_path))?;
    m.set_item("resumed_from", path(&pd.sla.resume_from))?;
    m.set_item("peak_memory_bytes", r.peak_memory_bytes)?;
    let counts = PyDict::new(py);
    for (k, v) in [
        ("n_nodes", r.n_nodes),
        ("n_dofs", r.n_dofs),
        ("n_pd_nodes", r.n_pd_nodes),
        ("n_bonds", r.n_bonds),
        ("n_precrack_bonds", r.n_precrack_bonds),
        ("n_removed_elements", r.n_removed_elements),
        ("bytes_per_bond", r.bytes_per_bond),
    ] {
        counts.set_item(k, v)?;
    }
    m.set_item("counts", counts)?;
    let t = PyDict::new(py);
    t.set_item("rust_s", wall)?;
    t.set_item("setup_s", r.setup_seconds)?;
    t.set_item("sla_s", r.sla_seconds)?;
    t.set_item(
        "region_switch_s",
        r.switches.iter().fold(0.0, |a, s| a + s.seconds),
    )?;
    m.set_item("timings", t)?;
    Ok(())
}
