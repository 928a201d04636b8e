//! XFEM (Heaviside + branch enrichment, interaction-integral SIFs, LEFM growth): the run's
//! result for Python.
//!
//! Fields: coords (n,2), elements (m,4) int64, u (2n,: the nodal displacements, the standard
//! dofs; the shifted enrichments vanish at the nodes), u_enriched (n_dofs,: standard then
//! enriched dofs), enrichment (n,: 0 standard, 1 Heaviside, 2 tip), heaviside_nodes, tip_nodes
//! (int64), crack (k,2) final polyline, crack_initial, radii (r,5) [radius, K_I, K_II, J_from_K,
//! J_domain], radii_factor (r,), tips (t,6) [x1, x2, K_I, K_II, J_from_K, J_domain], tip_crack
//! (t,), cracks (P,2) with cracks_offsets (C+1,), cut_points / cut_disp (P,2) with cut_offsets
//! (C+1,), cut_element (C,) and cut_stress (C,3) (the enriched elements as polygons on each side
//! of the crack with their own displacements and stresses: files), gauss_points / gauss_stress
//! (4m,2)/(4m,3) (the enriched stresses at the 2 x 2 Gauss points), tip_history_<x|y|K_I|K_II|kink_angle|r_I|grows>
//! (s,t), deformed_cells / deformed_disp (c,4,2), snapshot_cells / snapshot_disp (C,4,2) with
//! snapshot_offsets (s+1,) (snapshot k belongs to history row k + 1). History (growth runs,
//! origin first): load_factor, sigma22, cmod, u0, traction, a, K_I, K_II, kink_angle, tip_x,
//! tip_y, r_I (the q-radius of the SIFs, shrunk where a hole would enter the domain; 0 at the
//! origin), condition (when computed).

use crate::arrays::{arr1, arr2, elements_i64, index_i64, quads, table};
use crate::errors::detached;
use crate::progress::Progress;
use crate::shaped::Shaped;
use numpy::PyArray1;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use rustfrac_core::problem::{Method, Problem};
use rustfrac_core::xfem::{self, GrowthStep, TipStep, XfemResult};
use std::time::Instant;

/// Runs the XFEM plate of `p` and shapes its result.
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
                let msg = format!("xfem: growth step {done} of ~{est} (a_stop {})", g.a_stop);
                prog.report(done.min(est), est, &msg, false)
            }
            _ => true,
        });
        prog.report(total, total, "xfem: done", true);
        r
    });
    let wall = t0.elapsed().as_secs_f64();
    prog.deliver(py, r, |r| {
        let s = Shaped::new(py, p, (r.sigma22, r.cmod, r.n_dofs, wall), &r.warnings)?;
        mesh_fields(&s, &r)?;
        sif_fields(&s, &r)?;
        growth_fields(&s, &r, p)?;
        scalars_and_meta(&s, &r, p, wall)?;
        s.finish()
    })
}

fn mesh_fields(s: &Shaped<'_>, r: &XfemResult) -> PyResult<()> {
    let py = s.py;
    let n_nodes = r.coords.len();
    s.fields.set_item("coords", arr2(py, r.coords.clone()))?;
    s.fields
        .set_item("elements", elements_i64(py, &r.elements))?;
    s.fields.set_item("u", arr1(py, r.u[..r.n_std].to_vec()))?;
    s.fields.set_item("u_enriched", arr1(py, r.u.clone()))?;
    let mut enrichment = vec![0.0; n_nodes];
    for &n in &r.heaviside_nodes {
        enrichment[n] = 1.0;
    }
    for &n in &r.tip_nodes {
        enrichment[n] = 2.0;
    }
    s.fields.set_item("enrichment", arr1(py, enrichment))?;
    s.fields
        .set_item("heaviside_nodes", index_i64(py, &r.heaviside_nodes))?;
    s.fields
        .set_item("tip_nodes", index_i64(py, &r.tip_nodes))?;
    s.fields.set_item("crack", arr2(py, r.crack.clone()))?;
    let mut offsets: Vec<usize> = vec![0];
    for poly in &r.cut.polygons {
        offsets.push(offsets[offsets.len() - 1] + poly.len());
    }
    s.fields
        .set_item("cut_points", arr2(py, r.cut.polygons.concat()))?;
    s.fields
        .set_item("cut_disp", arr2(py, r.cut.disp.concat()))?;
    s.fields.set_item("cut_offsets", index_i64(py, &offsets))?;
    s.fields
        .set_item("cut_element", index_i64(py, &r.cut.element))?;
    s.fields
        .set_item("cut_stress", arr2(py, r.cut.stress.clone()))?;
    s.fields
        .set_item("gauss_points", arr2(py, r.gauss_points.clone()))?;
    s.fields
        .set_item("gauss_stress", arr2(py, r.gauss_stress.clone()))?;
    s.fields
        .set_item("deformed_cells", quads(py, r.deformed.cells.clone()))?;
    s.fields
        .set_item("deformed_disp", quads(py, r.deformed.disp.clone()))?;
    Ok(())
}

fn sif_fields(s: &Shaped<'_>, r: &XfemResult) -> PyResult<()> {
    let py = s.py;
    let radii: Vec<f64> = r
        .radii
        .iter()
        .flat_map(|x| {
            let q = x.sifs;
            [q.radius, q.k_i, q.k_ii, q.j_from_k, q.j_domain]
        })
        .collect();
    s.fields
        .set_item("radii", table(py, r.radii.len(), 5, radii))?;
    let factors: Vec<f64> = r.radii.iter().map(|x| x.factor).collect();
    s.fields.set_item("radii_factor", arr1(py, factors))?;
    let tips: Vec<f64> = r
        .tips
        .iter()
        .flat_map(|(p, q)| [p[0], p[1], q.k_i, q.k_ii, q.j_from_k, q.j_domain])
        .collect();
    s.fields
        .set_item("tips", table(py, r.tips.len(), 6, tips))?;
    s.fields
        .set_item("tip_crack", index_i64(py, &r.tip_crack))?;
    let mut offsets: Vec<i64> = vec![0];
    let mut pts: Vec<[f64; 2]> = Vec::new();
    for c in &r.cracks {
        pts.extend_from_slice(c);
        offsets.push(pts.len() as i64);
    }
    s.fields.set_item("cracks", arr2(py, pts))?;
    s.fields
        .set_item("cracks_offsets", PyArray1::from_vec(py, offsets))?;
    Ok(())
}

fn growth_fields(s: &Shaped<'_>, r: &XfemResult, p: &Problem) -> PyResult<()> {
    let py = s.py;
    let n_tips = r.tips.len();
    let tip_col = |f: fn(&TipStep) -> f64| {
        let flat: Vec<f64> = r.tip_history.iter().flatten().map(f).collect();
        table(py, r.tip_history.len(), n_tips, flat)
    };
    s.fields.set_item("tip_history_x", tip_col(|t| t.pos[0]))?;
    s.fields.set_item("tip_history_y", tip_col(|t| t.pos[1]))?;
    s.fields.set_item("tip_history_K_I", tip_col(|t| t.k_i))?;
    s.fields.set_item("tip_history_K_II", tip_col(|t| t.k_ii))?;
    s.fields
        .set_item("tip_history_kink_angle", tip_col(|t| t.kink_angle))?;
    s.fields.set_item("tip_history_r_I", tip_col(|t| t.r_i))?;
    s.fields.set_item(
        "tip_history_grows",
        tip_col(|t| f64::from(u8::from(t.grows))),
    )?;
    let mut offsets: Vec<i64> = vec![0];
    let (mut cells, mut disp) = (Vec::new(), Vec::new());
    for snap in &r.snapshots {
        cells.extend_from_slice(&snap.cells);
        disp.extend_from_slice(&snap.disp);
        offsets.push(cells.len() as i64);
    }
    s.fields.set_item("snapshot_cells", quads(py, cells))?;
    s.fields.set_item("snapshot_disp", quads(py, disp))?;
    s.fields
        .set_item("snapshot_offsets", PyArray1::from_vec(py, offsets))?;
    let Method::Xfem(x) = &p.method else {
        return Ok(());
    };
    if x.growth.is_none() {
        return Ok(());
    }
    let h = &r.history;
    let col = |f: fn(&GrowthStep) -> f64| -> Vec<f64> { h.iter().map(f).collect() };
    s.column("load_factor", col(|q| q.lambda))?;
    s.column("sigma22", col(|q| q.sigma22))?;
    s.column("cmod", col(|q| q.cmod))?;
    s.column("u0", col(|q| q.u0))?;
    s.column("traction", col(|q| q.traction))?;
    s.response_columns(p, &r.response_history)?;
    s.column("a", col(|q| q.a))?;
    s.column("K_I", col(|q| q.k_i))?;
    s.column("K_II", col(|q| q.k_ii))?;
    s.column("kink_angle", col(|q| q.kink_angle))?;
    s.column("tip_x", col(|q| q.tip[0]))?;
    s.column("tip_y", col(|q| q.tip[1]))?;
    s.column("r_I", col(|q| q.r_i))?;
    if x.condition {
        s.column("condition", col(|q| q.condition.unwrap_or(0.0)))?;
    }
    Ok(())
}

fn scalars_and_meta(s: &Shaped<'_>, r: &XfemResult, p: &Problem, wall: f64) -> PyResult<()> {
    let py = s.py;
    let sc = &s.scalars;
    s.responses(p, &r.responses)?;
    sc.set_item("K_I", r.k_i)?;
    sc.set_item("K_II", r.k_ii)?;
    sc.set_item("J", r.j_from_k)?;
    sc.set_item("J_domain", r.j_domain)?;
    sc.set_item("r_I", r.r_i)?;
    sc.set_item("n_std", r.n_std)?;
    sc.set_item("n_heaviside_nodes", r.n_heaviside_nodes)?;
    sc.set_item("n_tip_nodes", r.n_tip_nodes)?;
    sc.set_item("n_dropped_nodes", r.n_dropped_nodes)?;
    sc.set_item("condition", r.condition.map(|c| c.value()))?;
    sc.set_item("condition_pivot_ratio", r.condition.map(|c| c.pivot_ratio))?;
    let m = &s.meta;
    s.anchor(p, r.anchor_node)?;
    s.work_conjugate(p)?;
    m.set_item("status", r.status.name())?;
    let e = PyDict::new(py);
    e.set_item("n_std", r.n_std)?;
    e.set_item("n_heaviside_nodes", r.n_heaviside_nodes)?;
    e.set_item("n_tip_nodes", r.n_tip_nodes)?;
    e.set_item("n_dropped_nodes", r.n_dropped_nodes)?;
    m.set_item("enrichment", e)?;
    m.set_item("r_I", r.r_i)?;
    if let Method::Xfem(x) = &p.method {
        m.set_item("r_I_elements", x.r_i)?;
    }
    let lines = p.crack_polylines();
    s.fields
        .set_item("crack_initial", arr2(py, lines[0].clone()))?;
    m.set_item("crack_initial", lines[0].clone())?;
    m.set_item("cracks_initial", lines)?;
    let t = PyDict::new(py);
    t.set_item("rust_s", wall)?;
    m.set_item("timings", t)?;
    Ok(())
}
