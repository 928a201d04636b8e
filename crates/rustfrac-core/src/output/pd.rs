//! The record of a PD or CCM-PD run ([`CcmPdResult`]), read group by group: the SLA history
//! (the unloaded origin first), the grid's fields and damage (geometry, reference and final
//! state), the PD constants, and how the SLA ran (status, solver, region growths, solver work,
//! counts, timings).

use super::common::{self, Headline};
use super::record::{Entries, Record, Value};
use crate::error::{Error, Result};
use crate::pd::sla::{
    CcmPdResult, Constants, FinalState, Geometry, ModelCounts, ReferenceState, RegionRecord,
    SlaStep, SolverWork,
};
use crate::problem::schema::PD_REGIONS;
use crate::problem::{PdMethod, Problem};

impl CcmPdResult {
    /// The run's record (names: [`super::schema`]), group by group; `wall` is the run's wall
    /// time. Fails (an internal error) when the damage snapshots are of unequal lengths.
    pub fn into_record(self, p: &Problem, wall: f64) -> Result<Record> {
        let h = Headline {
            sigma22: self.reference.sigma22,
            cmod: self.reference.cmod,
            n_dofs: self.counts.n_dofs,
            wall_time_s: wall,
        };
        let mut rec = common::start(p, h, &self.warnings);
        history(&mut rec, &self);
        let CcmPdResult {
            run,
            counts,
            constants,
            geometry,
            mut reference,
            history,
            final_state,
            region,
            work,
            timings,
            warnings: _,
        } = self;
        let anchor = (geometry.anchor_node, geometry.anchor_xy);
        let u = std::mem::take(&mut reference.u);
        fields(&mut rec, geometry, u, final_state)?;
        for (k, v) in [
            ("gamma", constants.pd.gamma),
            ("c", constants.pd.c),
            ("s0", constants.pd.s0),
            ("delta", constants.pd.delta),
        ] {
            rec.scalars.set(k, v);
        }
        let Some(pd) = p.pd() else {
            return Ok(rec);
        };
        scene_echo(&mut rec, p, pd, &reference, anchor);
        let m = &mut rec.meta;
        m.set("status", run.status.name());
        m.set("solver", run.solver.describe());
        m.set("sla_steps_done", history.len());
        pd_region(m, pd, &region.regions);
        corrections(m, pd, &constants);
        growth(m, pd, &region);
        m.set("precrack", Value::points(&p.pd_precrack()));
        m.set(
            "out_of_balance",
            Value::float_list(&reference.out_of_balance),
        );
        solver_work(m, &work, run.solver.refactor_interval);
        m.set("resumed_steps", run.resumed_steps);
        m.set("n_checkpoints", run.n_checkpoints);
        let path = |q: &Option<std::path::PathBuf>| q.as_ref().map(|x| x.display().to_string());
        m.set("checkpoint_path", Value::opt(path(&pd.sla.checkpoint_path)));
        m.set("resumed_from", Value::opt(path(&pd.sla.resume_from)));
        m.set("peak_memory_bytes", Value::opt(timings.peak_memory_bytes));
        m.set("counts", count_entries(&counts));
        let switch_s = region.switches.iter().fold(0.0, |a, s| a + s.seconds);
        common::timings(
            &mut rec,
            wall,
            &[
                ("setup_s", timings.setup_seconds),
                ("sla_s", timings.sla_seconds),
                ("region_switch_s", switch_s),
            ],
        );
        Ok(rec)
    }
}

/// The history's columns: one row per step, the unloaded origin first.
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
    for (k, (name, _)) in r.reference.responses.probes.iter().enumerate() {
        for c in 0..2 {
            let v = h
                .iter()
                .map(|x| x.probes.get(k).map_or(0.0, |p| p[c]))
                .collect();
            rec.column(format!("probe:{name}:{}", c + 1), v);
        }
    }
}

/// The fields: the damage snapshots, the grid, the reference and final displacements, the
/// final damage and broken bonds, the groundings.
fn fields(rec: &mut Record, g: Geometry, u: Vec<f64>, fin: FinalState) -> Result<()> {
    let f = &mut rec.fields;
    let p = fin.damage.len();
    f.set(
        "damage_at_steps",
        Value::ints(fin.damage_at.iter().map(|(k, _)| *k as i64)),
    );
    let n_snaps = fin.damage_at.len();
    let snaps: Vec<f64> = fin.damage_at.into_iter().flat_map(|(_, v)| v).collect();
    if snaps.len() != n_snaps * p {
        return Err(Error::Internal {
            detail: "damage_at: snapshots of unequal length".into(),
        });
    }
    f.set("damage_at", Value::table(n_snaps, p, snaps));
    f.set("node_xy", Value::rows(g.node_xy));
    f.set("u", Value::floats(u));
    f.set("u_final", Value::floats(fin.u));
    f.set("pd_nodes", Value::indices(&g.pd_nodes));
    f.set("pd_node_xy", Value::rows(g.pd_node_xy));
    f.set("damage", Value::floats(fin.damage));
    f.set("broken", Value::Bools(fin.broken));
    f.set("bond_nodes", Value::index_rows(g.bond_nodes));
    let detached = fin.detached_nodes.iter().map(|&(st, n)| [st, n]);
    f.set("detached_nodes", Value::index_rows(detached));
    Ok(())
}

/// What the meta echoes of the scene: the conditions, the anchor (its node and position), the
/// load's work-conjugate pair, and the general scene's responses of the pre-cracked model before
/// any break (the history's sigma22 and u0 follow every break).
fn scene_echo(
    rec: &mut Record,
    p: &Problem,
    pd: &PdMethod,
    reference: &ReferenceState,
    (anchor_node, anchor_xy): (usize, [f64; 2]),
) {
    if pd.regions.is_empty() {
        let d = format!(
            "{}; on volumetric PD boundary layers",
            p.boundary.description()
        );
        rec.meta.set("bc_description", d);
    }
    common::anchor(rec, p, anchor_node);
    common::work_conjugate(rec, p);
    common::responses(rec, p, &reference.responses);
    let anchor_xy = common::has_anchor(p).then(|| Value::float_list(&anchor_xy));
    rec.meta.set("anchor_xy", Value::opt(anchor_xy));
}

/// The PD rectangles at the end and the scene key's own value ("fixed", "adaptive").
fn pd_region(m: &mut Entries, pd: &PdMethod, regions: &[[f64; 4]]) {
    match regions.is_empty() {
        false => m.set("pd_regions", Value::boxes(regions)),
        true => m.set("pd_regions", "the whole plate"),
    }
    let [fixed, adaptive] = PD_REGIONS;
    m.set(
        "pd_region",
        if pd.adaptive.is_some() {
            adaptive
        } else {
            fixed
        },
    );
}

/// The surface correction (scene key `pd.surface_correction`) with its factors, and the
/// critical stretch's rule: s0 = factor x eq. 48's, G_ref / G0 with eq. 48's s0.
fn corrections(m: &mut Entries, pd: &PdMethod, c: &Constants) {
    m.set("surface_correction", pd.surface_correction.name());
    if let Some(sc) = &c.surface_correction {
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
    let cal = &c.s0_calibration;
    let mut d = Entries::new();
    d.set("rule", cal.rule.name());
    d.set("factor", cal.factor);
    d.set("G_ref_over_G0", cal.g_ref_over_g0);
    m.set("s0_calibration", d);
}

/// The adaptive region: where it started, its growths, and the closest approach of a broken
/// bond to the FEM part (every CCM-PD run).
fn growth(m: &mut Entries, pd: &PdMethod, region: &RegionRecord) {
    if pd.adaptive.is_some() {
        m.set("pd_regions_initial", Value::boxes(&pd.regions));
    }
    let switches = region.switches.iter().map(|sw| {
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
        Value::opt(region.interface_distance_min),
    );
}

/// The solver's work and its re-condensation interval.
fn solver_work(m: &mut Entries, w: &SolverWork, refactor_interval: usize) {
    m.set("n_refactorisations", w.n_refactorisations);
    m.set("max_update_rank", w.max_update_rank);
    m.set("inverse_columns", w.inverse_columns);
    m.set("screened_steps", w.screened_steps);
    m.set("screened_bonds", w.screened_bonds);
    m.set("refactor_interval", refactor_interval);
}

/// The model's sizes.
fn count_entries(c: &ModelCounts) -> Entries {
    let mut counts = Entries::new();
    for (k, v) in [
        ("n_nodes", c.n_nodes),
        ("n_dofs", c.n_dofs),
        ("n_pd_nodes", c.n_pd_nodes),
        ("n_bonds", c.n_bonds),
        ("n_precrack_bonds", c.n_precrack_bonds),
        ("n_removed_elements", c.n_removed_elements),
        ("bytes_per_bond", c.bytes_per_bond),
    ] {
        counts.set(k, v);
    }
    counts
}
