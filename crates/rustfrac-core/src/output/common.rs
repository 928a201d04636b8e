//! The parts of a record every method shares: the headline, the common meta (version, method,
//! boundary condition, warnings), the anchor, the load's work-conjugate pair and the general
//! scene's responses (regions and probes) as scalars and history columns.

use super::record::{Entries, Record, Value};
use crate::fe::regions::SceneResponses;
use crate::problem::Grip;
use crate::problem::Problem;
use crate::warning::Warning;

/// The headline numbers of a run: sigma22 and CMOD at the reference load, the unknowns and the
/// core's wall time.
pub(super) struct Headline {
    pub sigma22: f64,
    pub cmod: f64,
    pub n_dofs: usize,
    pub wall_time_s: f64,
}

/// A record of `p`'s method with the headline and the meta every method carries.
pub(super) fn start(p: &Problem, h: Headline, warnings: &[Warning]) -> Record {
    let method = p.method.name();
    let mut r = Record::new(method);
    let top = &mut r.headline;
    top.set("method", method);
    top.set("sigma22", h.sigma22);
    top.set("cmod", h.cmod);
    top.set("n_dofs", h.n_dofs);
    top.set("wall_time_s", h.wall_time_s);
    // the scene's own warnings (said before the run too: `Problem::scene_warnings`), then the run's
    let warnings: Vec<Warning> = p
        .scene_warnings()
        .into_iter()
        .chain(warnings.iter().cloned())
        .collect();
    let m = &mut r.meta;
    m.set("version", env!("CARGO_PKG_VERSION"));
    m.set("method", method);
    m.set("bc", p.boundary.name());
    m.set("bc_description", p.boundary.description());
    m.set("warnings", Value::strs(warnings.iter().map(|w| &w.message)));
    m.set(
        "warning_kinds",
        Value::strs(warnings.iter().map(|w| w.kind.name())),
    );
    r
}

/// Whether the run has a u1 anchor (none under clamped grips, where none is needed, and with
/// supports on regions, which need none).
pub(super) fn has_anchor(p: &Problem) -> bool {
    p.boundary.grips().is_some_and(|l| l.grip != Grip::Clamped)
}

/// `meta["anchor_node"]`: the anchor node, or None without an anchor.
pub(super) fn anchor(r: &mut Record, p: &Problem, node: usize) {
    let v = if has_anchor(p) {
        Value::count(node)
    } else {
        Value::None
    };
    r.meta.set("anchor_node", v);
}

/// `meta["work_conjugate"]`: the pair (a, b) whose product with the history's sigma22 and u0
/// is twice the load's work ([`crate::problem::Boundary::work_conjugate`]), or None.
pub(super) fn work_conjugate(r: &mut Record, p: &Problem) {
    let t = p.material.elastic.thickness;
    let ab = p.boundary.work_conjugate(p.domain.width, t);
    r.meta.set(
        "work_conjugate",
        ab.map_or(Value::None, |ab| Value::float_list(&ab)),
    );
}

/// `meta["timings"]` with the core's wall time `rust_s` and further parts.
pub(super) fn timings(r: &mut Record, rust_s: f64, parts: &[(&str, f64)]) {
    let mut t = Entries::new();
    t.set("rust_s", rust_s);
    for (k, v) in parts {
        t.set(*k, *v);
    }
    r.meta.set("timings", t);
}

/// The general scene's responses as flat scalars (present only for the parts a scene has):
/// `force:<region>:1|2` (the force a support or load region receives from outside),
/// `displacement:<region>:1|2` (its mean), `mean_stress:<region>` (edge regions),
/// `probe:<name>:1|2`, and with supports and loads on regions `load_displacement`.
pub(super) fn responses(r: &mut Record, p: &Problem, resp: &SceneResponses) {
    let sc = &mut r.scalars;
    for (name, v) in &resp.regions {
        for c in 0..2 {
            sc.set(format!("force:{name}:{}", c + 1), v.force[c]);
            sc.set(format!("displacement:{name}:{}", c + 1), v.displacement[c]);
        }
        if let Some(m) = v.mean_stress {
            sc.set(format!("mean_stress:{name}"), m);
        }
    }
    for (name, v) in &resp.probes {
        for (c, x) in v.iter().enumerate() {
            sc.set(format!("probe:{name}:{}", c + 1), *x);
        }
    }
    if p.boundary.grips().is_none() {
        sc.set("load_displacement", resp.load_displacement);
    }
}

/// History columns of the responses along a load path (one entry per history row):
/// `load_displacement` (supports and loads on regions), `probe:<name>:1|2`,
/// `force:<region>:1|2`, `mean_stress:<region>` (edge regions).
pub(super) fn response_columns(r: &mut Record, p: &Problem, rows: &[SceneResponses]) {
    let Some(first) = rows.first() else {
        return;
    };
    if p.boundary.grips().is_none() {
        r.column(
            "load_displacement",
            rows.iter().map(|x| x.load_displacement).collect(),
        );
    }
    for (k, (name, _)) in first.probes.iter().enumerate() {
        for c in 0..2 {
            let v = rows.iter().map(|x| x.probes[k].1[c]).collect();
            r.column(format!("probe:{name}:{}", c + 1), v);
        }
    }
    for (k, (name, reg)) in first.regions.iter().enumerate() {
        for c in 0..2 {
            let v = rows.iter().map(|x| x.regions[k].1.force[c]).collect();
            r.column(format!("force:{name}:{}", c + 1), v);
        }
        if reg.mean_stress.is_some() {
            let v = rows
                .iter()
                .map(|x| x.regions[k].1.mean_stress.unwrap_or(0.0))
                .collect();
            r.column(format!("mean_stress:{name}"), v);
        }
    }
}
