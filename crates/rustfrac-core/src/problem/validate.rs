//! Cross-parameter checks of a [`Problem`], run before anything is built: cracks inside the
//! plate and apart from each other, a load that is not zero, the PD grid fitting the plate, the
//! PD rectangle inside the plate and around the crack tip, a pre-crack between node rows. Each
//! error names the scene key to change. A problem built in Rust rather than read from a scene
//! first meets the [`schema`] ranges of the values it states (plate, material, load, cracks, the
//! FEM grid), the same rules a scene meets.

// the negated comparisons are deliberate: they refuse NaN too
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use super::key_value::crack_name;
use super::schema::{self, Val, PD_NU};
use super::{
    Boundary, CrackKind, CrackSpec, Domain, Method, PdMethod, PdModel, Problem, S0Calibration,
    SlaEngine, SurfaceCorrection, XfemMethod, XfemOptions,
};
use super::{Grip, Plane, Side};
use crate::error::{Error, Result};
use crate::geometry::segment_distance;

/// Every cross-parameter rule of a problem.
pub fn problem(p: &Problem) -> Result<()> {
    super::general::grid_lines(p)?;
    schema_ranges(p)?;
    crack_kinds(p)?;
    let d = &p.domain;
    for (k, c) in p.cracks.iter().enumerate() {
        crack_geometry(c, d, &crack_name(k))?;
        if matches!(p.method, Method::Fem(_)) && c.side != Side::Left {
            return Err(Error::invalid(
                &format!("{}.side", crack_name(k)),
                &format!("'left' (method '{}' starts seams there)", p.method.name()),
                format!("'{}'", c.side.name()),
            ));
        }
    }
    cracks_apart(p)?;
    super::general::check(p)?;
    if matches!(p.method, Method::Fem(_)) {
        if let Some(c) = p.cracks.first() {
            if c.angle != 0.0 {
                return Err(Error::invalid(
                    "crack.angle",
                    &format!(
                        "0 for method '{}' (seams along x1; inclined cracks need method 'xfem', \
                         'pd' or 'ccm_pd')",
                        p.method.name()
                    ),
                    c.angle,
                ));
            }
        }
    }
    match &p.method {
        Method::Xfem(x) => {
            if let Some(g) = &x.growth {
                let a0 = p.cracks.iter().map(|c| c.a0).fold(0.0, f64::max);
                if !(g.a_stop > a0) {
                    return Err(Error::invalid(
                        "xfem.a_stop",
                        &format!(
                            "a stop length beyond the initial crack(s): a_stop > crack.a0 = {a0}"
                        ),
                        g.a_stop,
                    ));
                }
            }
        }
        Method::Pd(pd) | Method::CcmPd(pd) => peridynamics(p, pd)?,
        Method::Fem(_) => {}
    }
    Ok(())
}

/// The schema's range of `section.key` (its `ok` rule and `valid` words) for a value of the
/// problem; `name` is the section's scene name (`crack[1]` for the second crack).
fn in_range(section: &str, name: &str, key: &str, v: Val) -> Result<()> {
    let spec = schema::spec(section, key).expect("a key of the schema");
    if spec.ok(&v) {
        Ok(())
    } else {
        Err(Error::InvalidInput {
            param: format!("{name}.{key}"),
            expected: spec.valid(),
            got: v.repr(),
        })
    }
}

/// The values a problem states within the ranges a scene's keys have (a problem read from a
/// scene meets them already; one built in Rust is checked here).
fn schema_ranges(p: &Problem) -> Result<()> {
    let (d, m) = (&p.domain, &p.material);
    for (section, key, v) in [
        ("plate", "width", d.width),
        ("plate", "height", d.height),
        ("material", "E", m.elastic.e),
        ("material", "nu", m.elastic.nu),
        ("material", "thickness", m.elastic.thickness),
        ("material", "G0", m.g0),
    ] {
        in_range(section, section, key, Val::Float(v))?;
    }
    if let Boundary::Grips(load) = &p.boundary {
        in_range("load", "load", "u0", Val::Float(load.u0))?;
        in_range("load", "load", "traction", Val::Float(load.traction))?;
    }
    for (k, c) in p.cracks.iter().enumerate() {
        // only the keys the crack's kind reads: x for centre cracks and bottom/top edge cracks,
        // y for the others
        let uses_x = c.kind == CrackKind::Center || matches!(c.side, Side::Bottom | Side::Top);
        let uses_y = c.kind != CrackKind::Edge || matches!(c.side, Side::Left | Side::Right);
        for (key, v, used) in [
            ("a0", c.a0, true),
            ("y", c.y, uses_y),
            ("angle", c.angle, true),
            ("x", c.x, uses_x),
        ] {
            if used {
                in_range("crack", &crack_name(k), key, Val::Float(v))?;
            }
        }
    }
    let int = |n: usize| Val::Int(i64::try_from(n).unwrap_or(i64::MAX));
    match &p.method {
        Method::Fem(f) => {
            for (key, n) in [("nx", f.grid.nx), ("ny", f.grid.ny), ("gauss", f.gauss)] {
                in_range("mesh", "mesh", key, int(n))?;
            }
        }
        Method::Xfem(x) => xfem_ranges(x, &int)?,
        Method::Pd(pd) | Method::CcmPd(pd) => pd_ranges(pd, &int)?,
    }
    Ok(())
}

/// The PD and SLA options of a hand-built problem within the scene's ranges (absent options
/// count as the scene's 0; the rectangle as its centre and size).
fn pd_ranges(pd: &PdMethod, int: &dyn Fn(usize) -> Val) -> Result<()> {
    in_range("pd", "pd", "dx", Val::Float(pd.dx))?;
    in_range("pd", "pd", "m", int(pd.m))?;
    for r in &pd.regions {
        let centre = [0.5 * (r[0] + r[2]), 0.5 * (r[1] + r[3])];
        in_range("pd", "pd", "center", Val::Pair(centre))?;
        in_range("pd", "pd", "size", Val::Pair([r[2] - r[0], r[3] - r[1]]))?;
    }
    let sla = &pd.sla;
    for (key, n) in [
        ("sla_steps", sla.max_steps),
        ("refactor_every", sla.refactor_every),
        ("checkpoint_every", sla.checkpoint_every),
    ] {
        in_range("pd", "pd", key, int(n))?;
    }
    in_range("pd", "pd", "tie_tol", Val::Float(sla.tie_tol))?;
    in_range("pd", "pd", "fem_grading", Val::Float(pd.fem_grading))?;
    if let Some(a) = &pd.adaptive {
        in_range("pd", "pd", "adapt_margin", Val::Float(a.margin))?;
        in_range("pd", "pd", "adapt_size", Val::Float(a.size))?;
        // the square around the bond about to break must clear the margin (`pd_region`)
        if a.size < a.margin + 1.0 {
            return Err(Error::invalid(
                "pd.adapt_size",
                &format!(
                    "adapt_size >= adapt_margin + 1 = {} (the square grown around a bond must \
                     hold every node within adapt_margin horizons of its ends)",
                    a.margin + 1.0
                ),
                a.size,
            ));
        }
    }
    in_range("pd", "pd", "fem_coarse", Val::Float(pd.fem_coarse))?;
    let stop = sla.stop_crack_length.unwrap_or(0.0);
    in_range("pd", "pd", "stop_crack_length", Val::Float(stop))?;
    if sla.stop_crack_length == Some(0.0) {
        return Err(Error::invalid(
            "pd.stop_crack_length",
            "a positive length (None: no stop)",
            0.0,
        ));
    }
    let steps: Vec<i64> = sla.damage_at_steps.iter().map(|&k| k as i64).collect();
    in_range("pd", "pd", "damage_at_steps", Val::IntList(steps))
}

/// The number of grid cells of spacing `dx` along a length `len` when they fit it: `len / dx`
/// within 1e-6 of an integer in 1..=1e7 (the grid-fit rule of the PD grid, one copy).
pub fn grid_count(len: f64, dx: f64) -> Option<usize> {
    let r = len / dx;
    let n = r.round();
    ((1.0..=1e7).contains(&n) && (r - n).abs() <= 1e-6 * n.max(1.0)).then_some(n as usize)
}

/// The XFEM options of a hand-built problem within the scene's ranges (the resolved values:
/// `tip_nsub` is at least `nsub`, absent options count as the scene's 0).
fn xfem_ranges(x: &XfemMethod, int: &dyn Fn(usize) -> Val) -> Result<()> {
    for (key, n) in [("nx", x.grid.nx), ("ny", x.grid.ny)] {
        in_range("mesh", "mesh", key, int(n))?;
    }
    xfem_options(&x.options)?;
    in_range("xfem", "xfem", "r_I", Val::Float(x.r_i))?;
    in_range("xfem", "xfem", "tip_tie_tol", Val::Float(x.tip_tie_tol))?;
    for &f in &x.extra_radii {
        in_range("xfem", "xfem", "r_I", Val::Float(f))
            .map_err(|e| Error::invalid("xfem.extra_radii", &schema_valid("xfem", "r_I"), e))?;
    }
    if let Some(g) = &x.growth {
        in_range("xfem", "xfem", "growth_steps", int(g.max_steps))?;
        if g.max_steps == 0 {
            return Err(Error::invalid("xfem.growth_steps", "at least 1 step", 0));
        }
        in_range("xfem", "xfem", "da", Val::Float(g.da.unwrap_or(0.0)))?;
        in_range("xfem", "xfem", "a_stop", Val::Float(g.a_stop))?;
        in_range("xfem", "xfem", "state_every", int(g.state_every))?;
    }
    Ok(())
}

/// The enrichment and integration options within the scene's ranges (resolved values:
/// `tip_nsub` is at least `nsub`; no fixed-area radius counts as the scene's 0).
pub fn xfem_options(o: &XfemOptions) -> Result<()> {
    let int = |n: usize| Val::Int(i64::try_from(n).unwrap_or(i64::MAX));
    in_range("xfem", "xfem", "nsub", int(o.nsub))?;
    in_range("xfem", "xfem", "tip_nsub", int(o.tip_nsub))?;
    tip_nsub("xfem.tip_nsub", o.nsub as i64, o.tip_nsub as i64)?;
    let radius = Val::Float(o.fixed_area_radius.unwrap_or(0.0));
    in_range("xfem", "xfem", "fixed_area_radius", radius)?;
    in_range(
        "xfem",
        "xfem",
        "area_threshold",
        Val::Float(o.area_threshold),
    )
}

/// The valid range of `section.key` in words.
fn schema_valid(section: &str, key: &str) -> String {
    schema::spec(section, key).map_or_else(String::new, schema::KeySpec::valid)
}

/// Tip elements are subdivided at least as finely as the other enriched ones: `tip` (a
/// resolved `xfem.tip_nsub`, not 0) at least `nsub` (its range's upper end: the schema's).
pub fn tip_nsub(param: &str, nsub: i64, tip: i64) -> Result<()> {
    if tip < nsub {
        return Err(Error::invalid(
            param,
            &format!(
                "0 (= nsub) or an integer in [nsub, {}] = [{nsub}, {}]",
                schema::MAX_TIP_NSUB,
                schema::MAX_TIP_NSUB
            ),
            tip,
        ));
    }
    Ok(())
}

/// The crack kinds each method models ([`schema::crack_kinds`]; "none" is no crack), and one
/// crack for the methods other than XFEM.
fn crack_kinds(p: &Problem) -> Result<()> {
    let m = p.method.name();
    let kinds = schema::crack_kinds(m);
    let q: Vec<String> = kinds.iter().map(|x| format!("'{x}'")).collect();
    let expected = format!("for method '{m}' one of {}", q.join(", "));
    if p.cracks.len() > 1 && m != "xfem" {
        return Err(Error::invalid(
            "crack",
            &format!("one crack for method '{m}' (several cracks need method 'xfem')"),
            p.cracks.len(),
        ));
    }
    if p.cracks.is_empty() && !kinds.contains(&"none") {
        return Err(Error::invalid("crack.kind", &expected, "'none'"));
    }
    for (k, c) in p.cracks.iter().enumerate() {
        if !kinds.contains(&c.kind.name()) {
            let param = format!("{}.kind", crack_name(k));
            return Err(Error::invalid(
                &param,
                &expected,
                format!("'{}'", c.kind.name()),
            ));
        }
    }
    Ok(())
}

/// Smallest (and, inverted, largest) magnitude of the reference load's products with the
/// material and the geometry: far from the subnormal range (2.2e-308), so the solver's own
/// products keep full precision. Smaller loads underflow (a wrong sign, K_I = 0, no bond in
/// tension) and are refused.
pub const LOAD_RANGE: [f64; 2] = [1e-200, 1e200];

/// The preconditions of a run on the reference load: a load that is not zero for the methods
/// that scale a critical state (XFEM, PD, CCM-PD; a zero load has no critical load factor; a
/// scene with a zero load is still a valid description, FEM solves it), and, for every method, a
/// non-zero load whose displacement, strain, stress and edge force lie in [`LOAD_RANGE`].
pub fn reference_load(p: &Problem) -> Result<()> {
    // supports and loads on regions: their values were checked by `general::check`
    let Some(l) = p.boundary.grips() else {
        return Ok(());
    };
    let zero_ok = matches!(p.method, Method::Fem(_));
    let (d, e, t) = (
        &p.domain,
        p.material.elastic.e,
        p.material.elastic.thickness,
    );
    let (key, value, products) = match l.grip {
        Grip::Traction => {
            let strain = l.traction / e;
            (
                "load.traction",
                l.traction,
                [
                    ("the traction", l.traction),
                    ("the strain traction / E", strain),
                    ("the displacement strain L", strain * d.height),
                    ("the edge force traction W t", l.traction * d.width * t),
                ],
            )
        }
        Grip::Free | Grip::Clamped => {
            let strain = l.u0 / d.height;
            (
                "load.u0",
                l.u0,
                [
                    ("the displacement u0", l.u0),
                    ("the strain u0 / L", strain),
                    ("the stress E u0 / L", e * strain),
                    ("the edge force E u0 W t / L", e * strain * d.width * t),
                ],
            )
        }
    };
    let what = if l.grip == Grip::Traction {
        "a non-zero reference traction for bc = 'traction'"
    } else {
        "a non-zero reference displacement for displacement grips"
    };
    if value == 0.0 {
        return if zero_ok {
            Ok(())
        } else {
            Err(Error::invalid(key, what, 0.0))
        };
    }
    let [lo, hi] = LOAD_RANGE;
    for (name, v) in products {
        if !(lo..=hi).contains(&v.abs()) {
            return Err(Error::invalid(
                key,
                &format!(
                    "{what} whose displacement, strain, stress and edge force lie in [{lo:e}, \
                     {hi:e}] in magnitude (solved in floating point: smaller values underflow, \
                     larger ones overflow)"
                ),
                format!("{value:e} ({name} = {v:e})"),
            ));
        }
    }
    Ok(())
}

/// The rule of a PD pre-crack: it passes between the grid nodes (a node on it has no bonds to
/// cut on one side). `units` is the polyline in grid units (node (i, j) at (i, j)) on a grid of
/// `counts` cells, `node_xy` the position of node (i, j); the error names `culprit(segment)`'s
/// key and value (the scene key to change). The one check of the rule: the scene's
/// ([`problem`], on the plate's uniform grid) and the built grid's (`pd::splice::precrack`, on
/// a graded grid too).
pub fn precrack_off_nodes(
    units: &[[f64; 2]],
    counts: [usize; 2],
    node_xy: &dyn Fn(usize, usize) -> [f64; 2],
    culprit: &dyn Fn(usize) -> (String, String),
) -> Result<()> {
    for (k, s) in units.windows(2).enumerate() {
        let Some((i, j)) = crate::geometry::grid_node_on_segment(s[0], s[1], counts[0], counts[1])
        else {
            continue;
        };
        let (key, v) = culprit(k);
        let [x, y] = node_xy(i, j);
        return Err(Error::invalid(
            &key,
            "a pre-crack passing between the PD grid nodes, as the paper's x2 = 10.5 with dx = \
             1/15",
            format!("{v} (the crack passes through the node at ({x:.6}, {y:.6}))"),
        ));
    }
    Ok(())
}

/// [`precrack_off_nodes`] for a scene's crack on the plate's uniform PD grid: the culprit is the
/// crack's offset across itself (`crack.y` for cracks along x1, `crack.x` along x2), else its
/// angle.
fn precrack_between_nodes(c: &CrackSpec, d: &Domain, counts: [usize; 2]) -> Result<()> {
    let h = d.width / counts[0] as f64;
    let line: Vec<[f64; 2]> = c.polyline(d).iter().map(|q| [q[0] / h, q[1] / h]).collect();
    let culprit = |k: usize| {
        let s = [line[k], line[k + 1]];
        let along_x1 = (s[1][1] - s[0][1]).abs() <= 1e-12 * (s[1][0] - s[0][0]).abs();
        let along_x2 = (s[1][0] - s[0][0]).abs() <= 1e-12 * (s[1][1] - s[0][1]).abs();
        let (key, v) = if along_x1 {
            ("crack.y", c.y)
        } else if along_x2 {
            ("crack.x", c.x)
        } else {
            ("crack.angle", c.angle)
        };
        (key.to_string(), format!("{v} (dx = {h:.6})"))
    };
    let xy = |i: usize, j: usize| [i as f64 * h, j as f64 * h];
    precrack_off_nodes(&line, counts, &xy, &culprit)
}

/// The crack lies inside the plate (tips strictly inside, edge cracks pointing inwards).
fn crack_geometry(c: &CrackSpec, d: &Domain, pre: &str) -> Result<()> {
    let (w, h) = (d.width, d.height);
    // y places seams, centre cracks and left/right edge cracks (bottom/top ones use x)
    let uses_y = c.kind != CrackKind::Edge || matches!(c.side, Side::Left | Side::Right);
    if uses_y && !(c.y < h) {
        return Err(Error::invalid(
            &format!("{pre}.y"),
            &format!("0 < y < plate.height = {h}"),
            c.y,
        ));
    }
    let inside = |q: [f64; 2]| 0.0 < q[0] && q[0] < w && 0.0 < q[1] && q[1] < h;
    match c.kind {
        CrackKind::Seam | CrackKind::Edge => {
            if c.kind == CrackKind::Edge && !(c.angle > -90.0 && c.angle < 90.0) {
                return Err(Error::invalid(
                    &format!("{pre}.angle"),
                    "an edge crack pointing into the plate: -90 < angle < 90",
                    c.angle,
                ));
            }
            if c.kind == CrackKind::Edge && matches!(c.side, Side::Bottom | Side::Top) && !(c.x < w)
            {
                return Err(Error::invalid(
                    &format!("{pre}.x"),
                    &format!("0 < x < plate.width = {w}"),
                    c.x,
                ));
            }
            let tip = c.polyline(d)[1];
            if !inside(tip) {
                let hint = if c.angle == 0.0 && c.side == Side::Left {
                    format!(": 0 < a0 < plate.width = {w}")
                } else {
                    String::new()
                };
                return Err(Error::invalid(
                    &format!("{pre}.a0"),
                    &format!(
                        "a crack tip inside the plate (0, {w}) x (0, {h}){hint} (a crack from \
                         edge to edge would cut the plate in two)"
                    ),
                    format!("{} (tip at ({:.6}, {:.6}))", c.a0, tip[0], tip[1]),
                ));
            }
        }
        CrackKind::Center => {
            if !(c.x < w) {
                return Err(Error::invalid(
                    &format!("{pre}.x"),
                    &format!("0 < x < plate.width = {w}"),
                    c.x,
                ));
            }
            for tip in c.polyline(d) {
                if !inside(tip) {
                    return Err(Error::invalid(
                        &format!("{pre}.a0"),
                        &format!(
                            "both tips of the centre crack inside the plate (0, {w}) x (0, {h})"
                        ),
                        format!(
                            "half-length {} at ({}, {}), angle {}: a tip at ({:.6}, {:.6})",
                            c.a0, c.x, c.y, c.angle, tip[0], tip[1]
                        ),
                    ));
                }
            }
        }
    }
    Ok(())
}

/// Cracks must neither cross nor touch (junctions are not modelled).
fn cracks_apart(p: &Problem) -> Result<()> {
    let lines = p.crack_polylines();
    let tol = 1e-9 * p.domain.width.hypot(p.domain.height);
    for j in 1..lines.len() {
        for i in 0..j {
            let (a, b) = (&lines[i], &lines[j]);
            if segment_distance(a[0], a[1], b[0], b[1]) <= tol {
                return Err(Error::invalid(
                    &crack_name(j),
                    "cracks that neither cross nor touch each other (junctions are not modelled)",
                    format!("{} {:?} meets {} {:?}", crack_name(j), b, crack_name(i), a),
                ));
            }
        }
    }
    Ok(())
}

/// The rules of bond-based PD and of the PD grid.
fn peridynamics(p: &Problem, pd: &PdMethod) -> Result<()> {
    let method = p.method.name();
    match (&p.method, pd.regions.first()) {
        (Method::CcmPd(_), None) => {
            return Err(Error::invalid(
                "pd.size",
                "a PD rectangle for method 'ccm_pd' (method 'pd' covers the whole plate)",
                "none",
            ))
        }
        (Method::Pd(_), Some(r)) => {
            return Err(Error::invalid(
                "pd.center",
                "no PD rectangle for method 'pd' (PD covers the whole plate; a rectangle needs \
                 method 'ccm_pd')",
                format!("{r:?}"),
            ))
        }
        _ => {}
    }
    if pd.adaptive.is_some() && matches!(p.method, Method::Pd(_)) {
        return Err(Error::invalid(
            "pd.region",
            "'fixed' for method 'pd' (PD covers the whole plate; an adaptive region needs \
             method 'ccm_pd')",
            "'adaptive'",
        ));
    }
    if pd.fem_grading != 1.0 && matches!(p.method, Method::Pd(_)) {
        return Err(Error::invalid(
            "pd.fem_grading",
            "1 for method 'pd' (pure PD has no FEM part to grade; a graded FEM grid needs \
             method 'ccm_pd')",
            pd.fem_grading,
        ));
    }
    pd_model(p, pd, method)?;
    let d = &p.domain;
    let nodes = (d.width / pd.dx + 1.0) * (d.height / pd.dx + 1.0);
    if nodes > schema::max_elements() as f64 {
        return Err(Error::invalid(
            "pd.dx",
            &format!(
                "a PD grid of at most {} nodes (a documented memory guard)",
                schema::max_elements()
            ),
            format!("{} ({nodes:.3e} nodes)", pd.dx),
        ));
    }
    let mut counts = [0usize; 2];
    for (k, (len, axis)) in [(d.width, "plate.width"), (d.height, "plate.height")]
        .into_iter()
        .enumerate()
    {
        counts[k] = grid_count(len, pd.dx).ok_or_else(|| {
            Error::invalid(
                "pd.dx",
                &format!("a dx that makes the grid fit the plate: {axis} / dx an integer"),
                format!("{} ({axis} {len} / dx = {:.6})", pd.dx, len / pd.dx),
            )
        })?;
    }
    // the grid's spacing is width / nx; it must be the same along x2
    let (hx, hy) = (d.width / counts[0] as f64, d.height / counts[1] as f64);
    if (hy - hx).abs() > 1e-9 * hx {
        return Err(Error::invalid(
            "pd.dx",
            "a dx that fits both plate.width and plate.height with the same spacing (within \
             1e-9)",
            format!("{} (width / nx = {hx}, height / ny = {hy})", pd.dx),
        ));
    }
    if pd.sla.checkpoint_every > 0 && pd.sla.checkpoint_path.is_none() {
        return Err(Error::invalid(
            "pd.checkpoint_path",
            &format!(
                "a checkpoint file path (checkpoint_every = {} > 0 needs a checkpoint file)",
                pd.sla.checkpoint_every
            ),
            "''",
        ));
    }
    let two_h = 2.0 * pd.m as f64 * pd.dx;
    let spans: Vec<[(f64, &str); 2]> = if pd.regions.is_empty() {
        vec![[(d.width, "plate.width"), (d.height, "plate.height")]]
    } else {
        let size = |r: &[f64; 4], i: usize| (r[2 + i] - r[i], "pd.size");
        pd.regions
            .iter()
            .map(|r| [size(r, 0), size(r, 1)])
            .collect()
    };
    for ((s, key), axis) in spans.iter().flat_map(|sp| sp.iter().zip(["x1", "x2"])) {
        if *s < two_h * (1.0 - 1e-9) {
            return Err(Error::invalid(
                key,
                &format!(
                    "a PD region spanning at least two horizons 2 m dx = {two_h:.6} (m = {}, dx \
                     = {:.6}) along {axis}",
                    pd.m, pd.dx
                ),
                format!("{s:.6}"),
            ));
        }
    }
    for r in &pd.regions {
        for (i, axis) in ["x1", "x2"].iter().enumerate() {
            let len = [d.width, d.height][i];
            if r[i] < 0.0 || r[2 + i] > len {
                return Err(Error::invalid(
                    "pd.center",
                    &format!("a PD rectangle inside the plate ([0, {len}] along {axis})"),
                    format!("the range [{:.6}, {:.6}]", r[i], r[2 + i]),
                ));
            }
        }
    }
    if let (Some(c), Some(r)) = (p.cracks.first(), pd.regions.first()) {
        // the tips grow in PD; the rest of the crack may cross the FEM part, where the elements
        // it cuts are removed (`pd::splice::precrack`)
        let tips = c.tips(d);
        let inside = |r: &[f64; 4], q: [f64; 2]| {
            r[0] <= q[0] && q[0] <= r[2] && r[1] <= q[1] && q[1] <= r[3]
        };
        for tip in tips {
            if !pd.regions.iter().any(|r| inside(r, tip)) {
                return Err(Error::invalid(
                    "pd.center",
                    &format!(
                        "a PD rectangle [{:.6}, {:.6}] x [{:.6}, {:.6}] around the crack tip \
                         (move the rectangle, or the tip: crack.a0, crack.y, crack.angle)",
                        r[0], r[2], r[1], r[3]
                    ),
                    format!("the tip at ({:.6}, {:.6})", tip[0], tip[1]),
                ));
            }
        }
    }
    if let Some(c) = p.cracks.first() {
        precrack_in_pd(p, pd, c)?;
        precrack_between_nodes(c, d, counts)?;
    }
    Ok(())
}

/// The rules of `pd.model`: bond-based PD (the paper's) fixes nu = 1/4 in plane strain; the LPS
/// (`crate::pd::lps`) models any nu, for method 'pd' with the oracle engine, the continuum
/// critical stretch and no surface correction (its stiffness is not a sum of bond stiffnesses).
fn pd_model(p: &Problem, pd: &PdMethod, method: &str) -> Result<()> {
    let mat = &p.material.elastic;
    if pd.model == PdModel::Bond {
        if mat.nu != PD_NU {
            return Err(Error::invalid(
                "material.nu",
                &format!(
                    "nu = {PD_NU}: bond-based peridynamics (method '{method}', pd.model = \
                     'bond') fixes it; pd.model = 'lps' (method 'pd') models any nu"
                ),
                mat.nu,
            ));
        }
        if mat.plane != Plane::Strain {
            return Err(Error::invalid(
                "material.plane",
                &format!(
                    "'strain' (method '{method}' with pd.model = 'bond' supports plane strain \
                     only; pd.model = 'lps' (method 'pd') models plane stress)"
                ),
                "'stress'",
            ));
        }
        return Ok(());
    }
    let lps_needs = |key: &str, want: &str, got: String| {
        Err(Error::invalid(
            key,
            &format!("{want} with pd.model = 'lps'"),
            got,
        ))
    };
    if !matches!(p.method, Method::Pd(_)) {
        return lps_needs(
            "pd.model",
            "method 'pd' (pure PD; the CCM-PD splice of the LPS is \
             not implemented: use pd.model = 'bond')",
            format!("'lps' with method '{method}'"),
        );
    }
    if !matches!(pd.sla.engine, SlaEngine::Oracle | SlaEngine::Auto) {
        return lps_needs(
            "pd.engine",
            "'auto' or 'oracle' (the fast engines' rank-1 updates are bond-based)",
            format!("'{}'", pd.sla.engine.name()),
        );
    }
    if pd.surface_correction != SurfaceCorrection::None {
        return lps_needs(
            "pd.surface_correction",
            "'none' (the LPS's weighted volume m of each node is its own correction)",
            format!("'{}'", pd.surface_correction.name()),
        );
    }
    if pd.s0_calibration != S0Calibration::Continuum {
        return lps_needs(
            "pd.s0_calibration",
            "'continuum' (the LPS critical stretch of docs/design.md, 'The linear peridynamic \
             solid')",
            format!("'{}'", pd.s0_calibration.name()),
        );
    }
    Ok(())
}

/// CCM-PD: a pre-crack's part in the FEM part removes the elements it cuts
/// (`pd::splice::precrack`); along x1 or x2 they form a strip whose neighbours keep every node,
/// but an inclined part cuts a staircase of elements that leaves nodes without stiffness. So an
/// inclined pre-crack lies in a PD rectangle whole.
fn precrack_in_pd(p: &Problem, pd: &PdMethod, c: &CrackSpec) -> Result<()> {
    if pd.regions.is_empty() {
        return Ok(());
    }
    let line = c.polyline(&p.domain);
    let inside =
        |r: &[f64; 4], q: [f64; 2]| r[0] <= q[0] && q[0] <= r[2] && r[1] <= q[1] && q[1] <= r[3];
    for s in line.windows(2) {
        let (dx, dy) = ((s[1][0] - s[0][0]).abs(), (s[1][1] - s[0][1]).abs());
        let inclined = dy > 1e-12 * dx && dx > 1e-12 * dy;
        // a rectangle is convex: it holds the segment when it holds both ends
        let held = pd
            .regions
            .iter()
            .any(|r| inside(r, s[0]) && inside(r, s[1]));
        if inclined && !held {
            let (lo, hi) = (
                [s[0][0].min(s[1][0]), s[0][1].min(s[1][1])],
                [s[0][0].max(s[1][0]), s[0][1].max(s[1][1])],
            );
            let (key, what) = if pd.adaptive.is_some() {
                (
                    "pd.region",
                    "'fixed' with a PD rectangle (pd.center, pd.size) holding the whole inclined \
                     pre-crack"
                        .to_string(),
                )
            } else {
                (
                    "pd.center",
                    format!(
                        "a PD rectangle (pd.center, pd.size) holding the whole inclined pre-crack \
                         [{:.6}, {:.6}] x [{:.6}, {:.6}] (its part in the FEM part would cut \
                         elements into a staircase that leaves nodes without stiffness), or \
                         crack.angle = 0",
                        lo[0], hi[0], lo[1], hi[1]
                    ),
                )
            };
            let r = pd.regions[0];
            return Err(Error::invalid(
                key,
                &what,
                format!(
                    "the rectangle [{:.6}, {:.6}] x [{:.6}, {:.6}] and the pre-crack from \
                     ({:.6}, {:.6}) to ({:.6}, {:.6})",
                    r[0], r[2], r[1], r[3], s[0][0], s[0][1], s[1][0], s[1][1]
                ),
            ));
        }
    }
    Ok(())
}
