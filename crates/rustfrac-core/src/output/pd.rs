//! The record of a PD or CCM-PD run ([`CcmPdResult`]): the SLA history (the unloaded origin
//! first), the grid's fields and damage, the PD constants, and how the SLA ran (status, engine,
//! region growths, counts, timings).

use super::common::{self, Headline};
use super::record::{Entries, Record, Value};
use crate::error::{Error, Result};
use crate::pd::sla::{CcmPdResult, SlaStep};
use crate::problem::schema::PD_REGIONS;
use crate::problem::Problem;

impl CcmPdResult {
    /// The run's record (names: [`super::schema`]); `wall` is the run's wall time. Fails
    /// (an internal error) when the damage snapshots are of unequal lengths.
    pub fn into_record(self, p: &Problem, wall: f64) -> Result<Record> {
        let h = Headline {
            sigma22: self.sigma22,
            cmod: self.cmod,
            n_dofs: self.n_dofs,
            wall_time_s: wall,
        };
        let mut rec = common::start(p, h, &self.warnings);
        let mut r = self;
        history(&mut rec, &r);
        fields(&mut rec, &mut r)?;
        meta(&mut rec, &r, p, wall);
        Ok(rec)
    }
}

fn history(rec: &mut Record, r: &CcmPdResult) {
    let o = r.origin();
    let h: Vec<&SlaStep> = std::iter::once(&o).chain(&r.history).collect();
    let col = |f: fn(&SlaStep) -> f64| -> Vec<f64> { h.iter().map(|x| f(x)).collect() };
    let idx = |f: fn(&SlaStep) -> i64| Value::ints(h.iter().map(|x| f(x)));
    let node = |n: usize| if n == usize::MAX { -1 } else { n as i64 };
    rec.history.set("step", idx(|x| x.step as i64));
    rec.column("load_factor", col(|x| x.lambda));
    rec.column("sigma22", col(|x| x.sigma22));
    rec.column("cmod", col(|x| x.cmod));
    rec.column("u0", col(|x| x.u0));
    rec.column("crack_length", col(|x| x.crack_length));
    let hs = &mut rec.history;
    hs.set("bond", idx(|x| x.bonds.first().map_or(-1, |&b| b as i64)));
    hs.set("n_broken", idx(|x| x.bonds.len() as i64));
    hs.set("node_i", Value::ints(h.iter().map(|x| node(x.nodes[0]))));
    hs.set("node_j", Value::ints(h.iter().map(|x| node(x.nodes[1]))));
    hs.set("n_detached", idx(|x| x.detached.len() as i64));
    // the probes at every step's load (the origin: unloaded, zero)
    for (k, (name, _)) in r.responses.probes.iter().enumerate() {
        for c in 0..2 {
            let v = h
                .iter()
                .map(|x| x.probes.get(k).map_or(0.0, |p| p[c]))
                .collect();
            rec.column(format!("probe:{name}:{}", c + 1), v);
        }
    }
}

/// The grid, the displacements and the damage (the arrays are moved out of the result, whose
/// other parts [`meta`] reads).
fn fields(rec: &mut Record, r: &mut CcmPdResult) -> Result<()> {
    let f = &mut rec.fields;
    let p = r.damage.len();
    f.set(
        "damage_at_steps",
        Value::ints(r.damage_at.iter().map(|(k, _)| *k as i64)),
    );
    let snaps: Vec<f64> = r.damage_at.iter().flat_map(|(_, v)| v.clone()).collect();
    if snaps.len() != r.damage_at.len() * p {
        return Err(Error::Internal {
            detail: "damage_at: snapshots of unequal length".into(),
        });
    }
    f.set("damage_at", Value::table(r.damage_at.len(), p, snaps));
    f.set("node_xy", Value::rows(std::mem::take(&mut r.node_xy)));
    f.set("u", Value::floats(std::mem::take(&mut r.u)));
    f.set("u_final", Value::floats(std::mem::take(&mut r.u_final)));
    f.set("pd_nodes", Value::indices(&r.pd_nodes));
    f.set("pd_node_xy", Value::rows(std::mem::take(&mut r.pd_node_xy)));
    f.set("damage", Value::floats(std::mem::take(&mut r.damage)));
    f.set("broken", Value::Bools(std::mem::take(&mut r.broken)));
    f.set(
        "bond_nodes",
        Value::index_rows(std::mem::take(&mut r.bond_nodes)),
    );
    let detached = r.detached_nodes.iter().map(|&(st, n)| [st, n]);
    f.set("detached_nodes", Value::index_rows(detached));
    Ok(())
}

fn meta(rec: &mut Record, r: &CcmPdResult, p: &Problem, wall: f64) {
    for (k, v) in [
        ("gamma", r.gamma),
        ("c", r.c),
        ("s0", r.s0),
        ("delta", r.delta),
    ] {
        rec.scalars.set(k, v);
    }
    let Some(pd) = p.pd() else {
        return;
    };
    if pd.regions.is_empty() {
        let d = format!(
            "{}; on volumetric PD boundary layers",
            p.boundary.description()
        );
        rec.meta.set("bc_description", d);
    }
    common::anchor(rec, p, r.anchor_node);
    common::work_conjugate(rec, p);
    // the general scene's responses of the pre-cracked model before any break (the history's
    // sigma22 and u0 follow every break)
    common::responses(rec, p, &r.responses);
    let m = &mut rec.meta;
    let anchor_xy = common::has_anchor(p).then(|| Value::float_list(&r.anchor_xy));
    m.set("anchor_xy", Value::opt(anchor_xy));
    m.set("status", r.status.name());
    m.set("solver", r.solver.as_str());
    m.set("sla_steps_done", r.history.len());
    match r.regions.is_empty() {
        false => m.set("pd_regions", Value::boxes(&r.regions)),
        true => m.set("pd_regions", "the whole plate"),
    }
    // the scene key's own values ("fixed", "adaptive")
    let [fixed, adaptive] = PD_REGIONS;
    m.set(
        "pd_region",
        if pd.adaptive.is_some() {
            adaptive
        } else {
            fixed
        },
    );
    // the surface correction (scene key pd.surface_correction) and, with it, its factors
    m.set("surface_correction", pd.surface_correction.name());
    if let Some(sc) = &r.surface_correction {
        m.set("surface_nodes_corrected", sc.n_nodes_corrected);
        m.set(
            "surface_node_factor_range",
            Value::float_list(&sc.node_factor_range),
        );
        m.set(
            "surface_bond_factor_range",
            Value::float_list(&sc.bond_factor_range),
        );
    }
    // the critical stretch's rule: s0 = factor x eq. 48's, G_ref / G0 with eq. 48's s0
    let cal = &r.s0_calibration;
    let mut d = Entries::new();
    d.set("rule", cal.rule.name());
    d.set("factor", cal.factor);
    d.set("G_ref_over_G0", cal.g_ref_over_g0);
    m.set("s0_calibration", d);
    // the adaptive region: where it started, its growths, and the closest approach of a broken
    // bond to the FEM part (every CCM-PD run)
    if pd.adaptive.is_some() {
        m.set("pd_regions_initial", Value::boxes(&pd.regions));
    }
    let switches = r.switches.iter().map(|sw| {
        let mut d = Entries::new();
        d.set("step", sw.step);
        d.set("n_regions", sw.regions.len());
        d.set("n_pd_nodes", sw.n_pd_nodes);
        d.set("n_dofs", sw.n_dofs);
        d.set("seconds", sw.seconds);
        Value::Table(d)
    });
    m.set("region_switches", Value::List(switches.collect()));
    m.set(
        "interface_distance_min",
        Value::opt(r.interface_distance_min),
    );
    m.set("precrack", Value::points(&p.pd_precrack()));
    m.set("out_of_balance", Value::float_list(&r.out_of_balance));
    m.set("n_refactorisations", r.n_refactorisations);
    m.set("max_update_rank", r.max_update_rank);
    m.set("inverse_columns", r.inverse_columns);
    m.set("screened_steps", r.screened_steps);
    m.set("screened_bonds", r.screened_bonds);
    m.set("refactor_interval", r.refactor_interval);
    m.set("resumed_steps", r.resumed_steps);
    m.set("n_checkpoints", r.n_checkpoints);
    let path = |q: &Option<std::path::PathBuf>| q.as_ref().map(|x| x.display().to_string());
    m.set("checkpoint_path", Value::opt(path(&pd.sla.checkpoint_path)));
    m.set("resumed_from", Value::opt(path(&pd.sla.resume_from)));
    m.set("peak_memory_bytes", Value::opt(r.peak_memory_bytes));
    let mut counts = Entries::new();
    for (k, v) in [
        ("n_nodes", r.n_nodes),
        ("n_dofs", r.n_dofs),
        ("n_pd_nodes", r.n_pd_nodes),
        ("n_bonds", r.n_bonds),
        ("n_precrack_bonds", r.n_precrack_bonds),
        ("n_removed_elements", r.n_removed_elements),
        ("bytes_per_bond", r.bytes_per_bond),
    ] {
        counts.set(k, v);
    }
    m.set("counts", counts);
    let switch_s = r.switches.iter().fold(0.0, |a, s| a + s.seconds);
    common::timings(
        rec,
        wall,
        &[
            ("setup_s", r.setup_seconds),
            ("sla_s", r.sla_seconds),
            ("region_switch_s", switch_s),
        ],
    );
}
