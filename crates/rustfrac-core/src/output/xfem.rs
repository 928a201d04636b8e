//! The record of an XFEM run ([`XfemResult`]): the mesh and enrichment fields, the SIFs of
//! every tip and radius, the growth's history and snapshots, the enrichment counts.

use super::common::{self, Headline};
use super::record::{Entries, Record, Value};
use crate::problem::{Method, Problem};
use crate::xfem::growth_state::node_enrichment;
use crate::xfem::{GrowthStep, TipStep, XfemResult};

impl XfemResult {
    /// The run's record (names: [`super::schema`]); `wall` is the run's wall time.
    pub fn into_record(self, p: &Problem, wall: f64) -> Record {
        let h = Headline {
            sigma22: self.sigma22,
            cmod: self.cmod,
            n_dofs: self.n_dofs,
            wall_time_s: wall,
        };
        let mut rec = common::start(p, h, &self.warnings);
        let (growth, condition, r_i_elements) = match &p.method {
            Method::Xfem(x) => (x.growth.is_some(), x.condition, Some(x.r_i)),
            _ => (false, false, None),
        };
        let mut r = self;
        mesh_fields(&mut rec, &mut r);
        sif_fields(&mut rec, &r);
        growth_fields(&mut rec, &r);
        state_fields(&mut rec, &mut r);
        if growth {
            history(&mut rec, &r, p, condition);
        }
        scalars_and_meta(&mut rec, &r, p, wall, r_i_elements);
        rec
    }
}

/// The mesh, the enrichment and the cut cells (fields; the arrays are moved out of the result,
/// which the other parts do not read).
fn mesh_fields(rec: &mut Record, r: &mut XfemResult) {
    let f = &mut rec.fields;
    let n_nodes = r.coords.len();
    let enrichment = node_enrichment(n_nodes, &r.heaviside_nodes, &r.tip_nodes);
    let mut offsets: Vec<usize> = vec![0];
    for poly in &r.cut.polygons {
        offsets.push(offsets[offsets.len() - 1] + poly.len());
    }
    f.set("coords", Value::rows(std::mem::take(&mut r.coords)));
    f.set(
        "elements",
        Value::index_rows(std::mem::take(&mut r.elements)),
    );
    f.set("u", Value::floats(r.u[..r.n_std].to_vec()));
    f.set("u_enriched", Value::floats(std::mem::take(&mut r.u)));
    f.set("reactions", Value::floats(std::mem::take(&mut r.reactions)));
    f.set("enrichment", Value::floats(enrichment));
    f.set("heaviside_nodes", Value::indices(&r.heaviside_nodes));
    f.set("tip_nodes", Value::indices(&r.tip_nodes));
    f.set("crack", Value::rows(std::mem::take(&mut r.crack)));
    f.set("cut_points", Value::rows(r.cut.polygons.concat()));
    f.set("cut_disp", Value::rows(r.cut.disp.concat()));
    f.set("cut_offsets", Value::indices(&offsets));
    f.set("cut_element", Value::indices(&r.cut.element));
    f.set("cut_stress", Value::rows(std::mem::take(&mut r.cut.stress)));
    f.set(
        "gauss_points",
        Value::rows(std::mem::take(&mut r.gauss_points)),
    );
    f.set(
        "gauss_stress",
        Value::rows(std::mem::take(&mut r.gauss_stress)),
    );
    f.set(
        "deformed_cells",
        Value::quads(std::mem::take(&mut r.deformed.cells)),
    );
    f.set(
        "deformed_disp",
        Value::quads(std::mem::take(&mut r.deformed.disp)),
    );
}

/// The SIFs of the primary tip at every radius, of every tip, and the final cracks.
fn sif_fields(rec: &mut Record, r: &XfemResult) {
    let f = &mut rec.fields;
    let radii: Vec<f64> = r
        .radii
        .iter()
        .flat_map(|x| {
            let q = x.sifs;
            [q.radius, q.k_i, q.k_ii, q.j_from_k, q.j_domain]
        })
        .collect();
    f.set("radii", Value::table(r.radii.len(), 5, radii));
    let factors: Vec<f64> = r.radii.iter().map(|x| x.factor).collect();
    f.set("radii_factor", Value::floats(factors));
    let tips: Vec<f64> = r
        .tips
        .iter()
        .flat_map(|(p, q)| [p[0], p[1], q.k_i, q.k_ii, q.j_from_k, q.j_domain])
        .collect();
    f.set("tips", Value::table(r.tips.len(), 6, tips));
    f.set("tip_crack", Value::indices(&r.tip_crack));
    let mut offsets: Vec<i64> = vec![0];
    let mut pts: Vec<[f64; 2]> = Vec::new();
    for c in &r.cracks {
        pts.extend_from_slice(c);
        offsets.push(pts.len() as i64);
    }
    f.set("cracks", Value::rows(pts));
    f.set("cracks_offsets", Value::ints(offsets));
}

/// Every tip at every history row, and the snapshots of the growing tip's patch.
fn growth_fields(rec: &mut Record, r: &XfemResult) {
    let f = &mut rec.fields;
    let n_tips = r.tips.len();
    let tip_col = |g: fn(&TipStep) -> f64| {
        let flat: Vec<f64> = r.tip_history.iter().flatten().map(g).collect();
        Value::table(r.tip_history.len(), n_tips, flat)
    };
    f.set("tip_history_x", tip_col(|t| t.pos[0]));
    f.set("tip_history_y", tip_col(|t| t.pos[1]));
    f.set("tip_history_K_I", tip_col(|t| t.k_i));
    f.set("tip_history_K_II", tip_col(|t| t.k_ii));
    f.set("tip_history_kink_angle", tip_col(|t| t.kink_angle));
    f.set("tip_history_r_I", tip_col(|t| t.r_i));
    f.set(
        "tip_history_grows",
        tip_col(|t| f64::from(u8::from(t.grows))),
    );
    let mut offsets: Vec<i64> = vec![0];
    let (mut cells, mut disp) = (Vec::new(), Vec::new());
    for snap in &r.snapshots {
        cells.extend_from_slice(&snap.cells);
        disp.extend_from_slice(&snap.disp);
        offsets.push(cells.len() as i64);
    }
    f.set("snapshot_cells", Value::quads(cells));
    f.set("snapshot_disp", Value::quads(disp));
    f.set("snapshot_offsets", Value::ints(offsets));
}

/// The whole plate at every kept critical state of a growth ([`crate::xfem::GrowthState`]),
/// state after state: the tables of fixed size per state as (n_states, ..) arrays, the cut cells
/// and the cracks concatenated with offsets (empty arrays without growth).
fn state_fields(rec: &mut Record, r: &mut XfemResult) {
    let f = &mut rec.fields;
    let states = std::mem::take(&mut r.states);
    let n = states.len();
    let (n_nodes, n_el) = (rows_of(f, "coords"), rows_of(f, "elements"));
    let (mut u, mut stress, mut enrichment) = (Vec::new(), Vec::new(), Vec::new());
    let (mut cut_offsets, mut point_offsets): (Vec<usize>, Vec<usize>) = (vec![0], vec![0]);
    let (mut points, mut disp, mut element) = (Vec::new(), Vec::new(), Vec::new());
    let mut cut_stress = Vec::new();
    let (mut crack_points, mut crack_offsets): (Vec<[f64; 2]>, Vec<usize>) = (Vec::new(), vec![0]);
    for s in &states {
        u.extend_from_slice(&s.u);
        enrichment.extend_from_slice(&s.enrichment);
        stress.extend(s.stress.iter().flatten());
        for (poly, d) in s.cut.polygons.iter().zip(&s.cut.disp) {
            points.extend_from_slice(poly);
            disp.extend_from_slice(d);
            point_offsets.push(points.len());
        }
        element.extend_from_slice(&s.cut.element);
        cut_stress.extend_from_slice(&s.cut.stress);
        cut_offsets.push(element.len());
        for c in &s.cracks {
            crack_points.extend_from_slice(c);
            crack_offsets.push(crack_points.len());
        }
    }
    let rows: Vec<usize> = states.iter().map(|s| s.row).collect();
    f.set("state_rows", Value::indices(&rows));
    f.set(
        "state_u",
        Value::Floats {
            shape: vec![n, 2 * n_nodes],
            data: u,
        },
    );
    f.set(
        "state_stress",
        Value::Floats {
            shape: vec![n, n_el, 3],
            data: stress,
        },
    );
    f.set(
        "state_enrichment",
        Value::Floats {
            shape: vec![n, n_nodes],
            data: enrichment,
        },
    );
    f.set("state_cut_offsets", Value::indices(&cut_offsets));
    f.set("state_cut_points", Value::rows(points));
    f.set("state_cut_disp", Value::rows(disp));
    f.set("state_cut_point_offsets", Value::indices(&point_offsets));
    f.set("state_cut_element", Value::indices(&element));
    f.set("state_cut_stress", Value::rows(cut_stress));
    f.set("state_cracks", Value::rows(crack_points));
    f.set("state_cracks_offsets", Value::indices(&crack_offsets));
}

/// The rows of the record's array `name` (the mesh's `coords` or `elements`, set before the
/// states).
fn rows_of(f: &Entries, name: &str) -> usize {
    match f.get(name) {
        Some(Value::Floats { shape, .. } | Value::Ints { shape, .. }) => shape[0],
        _ => 0,
    }
}

/// The growth's history (origin first), with the responses and, when computed, the condition.
fn history(rec: &mut Record, r: &XfemResult, p: &Problem, condition: bool) {
    let h = &r.history;
    let col = |f: fn(&GrowthStep) -> f64| -> Vec<f64> { h.iter().map(f).collect() };
    rec.column("load_factor", col(|q| q.lambda));
    rec.column("sigma22", col(|q| q.sigma22));
    rec.column("cmod", col(|q| q.cmod));
    rec.column("u0", col(|q| q.u0));
    rec.column("traction", col(|q| q.traction));
    common::response_columns(rec, p, &r.response_history);
    rec.column("a", col(|q| q.a));
    rec.column("K_I", col(|q| q.k_i));
    rec.column("K_II", col(|q| q.k_ii));
    rec.column("kink_angle", col(|q| q.kink_angle));
    rec.column("tip_x", col(|q| q.tip[0]));
    rec.column("tip_y", col(|q| q.tip[1]));
    rec.column("r_I", col(|q| q.r_i));
    if condition {
        rec.column("condition", col(|q| q.condition.unwrap_or(0.0)));
    }
}

fn scalars_and_meta(
    rec: &mut Record,
    r: &XfemResult,
    p: &Problem,
    wall: f64,
    r_i_elements: Option<f64>,
) {
    common::responses(rec, p, &r.responses);
    let sc = &mut rec.scalars;
    sc.set("K_I", r.k_i);
    sc.set("K_II", r.k_ii);
    sc.set("J", r.j_from_k);
    sc.set("J_domain", r.j_domain);
    sc.set("r_I", r.r_i);
    sc.set("n_std", r.n_std);
    sc.set("n_heaviside_nodes", r.n_heaviside_nodes);
    sc.set("n_tip_nodes", r.n_tip_nodes);
    sc.set("n_dropped_nodes", r.n_dropped_nodes);
    sc.set("condition", Value::opt(r.condition.map(|c| c.value())));
    sc.set(
        "condition_pivot_ratio",
        Value::opt(r.condition.map(|c| c.pivot_ratio)),
    );
    common::anchor(rec, p, r.anchor_node);
    common::work_conjugate(rec, p);
    let m = &mut rec.meta;
    m.set("status", r.status.name());
    let mut e = Entries::new();
    e.set("n_std", r.n_std);
    e.set("n_heaviside_nodes", r.n_heaviside_nodes);
    e.set("n_tip_nodes", r.n_tip_nodes);
    e.set("n_dropped_nodes", r.n_dropped_nodes);
    m.set("enrichment", e);
    m.set("r_I", r.r_i);
    if let Some(x) = r_i_elements {
        m.set("r_I_elements", x);
    }
    let lines = p.crack_polylines();
    rec.fields
        .set("crack_initial", Value::rows(lines[0].clone()));
    m.set("crack_initial", Value::points(&lines[0]));
    m.set(
        "cracks_initial",
        Value::List(lines.iter().map(|l| Value::points(l)).collect()),
    );
    common::timings(rec, wall, &[]);
}
