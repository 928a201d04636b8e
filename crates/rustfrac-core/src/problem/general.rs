//! The cross checks of the general scene's parts ([`super::regions`]), made before anything is
//! built: holes inside the plate and leaving material, crack tips in material, supports, loads
//! and probes on the plate, a load that is not zero, and which methods read which parts.
//! Checks that need the mesh (a point with no node within half an element, two conditions on
//! one dof, a load on a removed part) are made where the mesh is built
//! ([`crate::fe::regions`]); they name the entry too.

// the negated comparisons are deliberate: they refuse NaN too
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use super::key_value::crack_name;
use super::{Boundary, LoadKind, Method, ProbeKind, Problem, Region, Shape, Side, MAX_ELEMENTS};
use crate::error::{Error, Result};

/// Samples per direction of the test that a domain keeps material.
const MATERIAL_SAMPLES: usize = 64;

fn inside_plate(p: [f64; 2], w: f64, h: f64) -> bool {
    (0.0..=w).contains(&p[0]) && (0.0..=h).contains(&p[1])
}

/// Holes: each overlaps the plate, and together they leave material.
fn holes(p: &Problem) -> Result<()> {
    let d = &p.domain;
    for hole in &d.holes {
        let b = hole.shape.bounding_box();
        if b[2] <= 0.0 || b[0] >= d.width || b[3] <= 0.0 || b[1] >= d.height {
            return Err(Error::invalid(
                &hole.name,
                &format!(
                    "a hole or notch that overlaps the plate [0, {}] x [0, {}]",
                    d.width, d.height
                ),
                format!("bounding box {b:?}"),
            ));
        }
        if let Shape::Polygon(v) = &hole.shape {
            if v.len() < 3 {
                return Err(Error::invalid(
                    &format!("{}.points", hole.name),
                    "at least 3 vertices",
                    v.len(),
                ));
            }
            if let Some((i, j)) = crate::geometry::self_intersection(v) {
                return Err(Error::invalid(
                    &format!("{}.points", hole.name),
                    "a simple polygon (no two edges cross, no repeated vertex)",
                    format!("edges {i} and {j} intersect"),
                ));
            }
        }
    }
    if d.holes.is_empty() {
        return Ok(());
    }
    let n = MATERIAL_SAMPLES;
    let any = (0..n * n).any(|k| {
        let q = [
            d.width * ((k % n) as f64 + 0.5) / n as f64,
            d.height * ((k / n) as f64 + 0.5) / n as f64,
        ];
        d.level_set(q) > 0.0
    });
    if !any {
        return Err(Error::invalid(
            &d.holes[0].name,
            "holes and notches that leave material in the plate",
            "the holes cover the whole plate",
        ));
    }
    // a crack tip in a hole: the crack would end in the void (a centre crack's end in a hole is
    // its mouth, `CrackSpec::tips`, but one of its ends must be a tip)
    for (k, c) in p.cracks.iter().enumerate() {
        let line = c.polyline(d);
        let tips: Vec<[f64; 2]> = match c.kind {
            super::CrackKind::Center => {
                let tips = c.tips(d);
                if tips.is_empty() {
                    let h = d.holes.iter().find(|h| h.shape.level_set(line[0]) <= 0.0);
                    return Err(Error::invalid(
                        &format!("{}.a0", crack_name(k)),
                        "a crack with at least one tip in material (both ends lie in holes)",
                        format!(
                            "ends {:?} and {:?}{}",
                            line[0],
                            line[1],
                            h.map(|h| format!(" in {}", h.name)).unwrap_or_default()
                        ),
                    ));
                }
                tips
            }
            _ => c.tips(d),
        };
        for t in tips {
            if let Some(h) = d.holes.iter().find(|h| h.shape.level_set(t) <= 0.0) {
                return Err(Error::invalid(
                    &format!("{}.a0", crack_name(k)),
                    &format!("a crack whose tip lies in material, not in {}", h.name),
                    format!("tip {t:?} inside {}", h.name),
                ));
            }
        }
    }
    Ok(())
}

fn region_on_plate(name: &str, r: &Region, w: f64, h: f64) -> Result<()> {
    let side_len = |s: Side| {
        if matches!(s, Side::Bottom | Side::Top) {
            w
        } else {
            h
        }
    };
    match *r {
        Region::Edge(_) => Ok(()),
        Region::EdgePart { side, from, to } => {
            let l = side_len(side);
            // a part reaching past the side would be clipped, and its load with it
            let tol = 1e-12 * l;
            let key = if !(from >= -tol) || !(from < to) || from >= l {
                "from"
            } else {
                "to"
            };
            if !(from < to) || !(from >= -tol) || !(to <= l + tol) {
                return Err(Error::invalid(
                    &format!("{name}.{key}"),
                    &format!("a part 0 <= from < to <= {l} of the side (its length)"),
                    format!("[{from}, {to}]"),
                ));
            }
            Ok(())
        }
        Region::Point(q) if !inside_plate(q, w, h) => Err(Error::invalid(
            &format!("{name}.point"),
            &format!("a point on the plate [0, {w}] x [0, {h}]"),
            format!("{q:?}"),
        )),
        Region::Box(b) if b[2] < 0.0 || b[0] > w || b[3] < 0.0 || b[1] > h => Err(Error::invalid(
            &format!("{name}.box"),
            &format!("a box overlapping the plate [0, {w}] x [0, {h}]"),
            format!("{b:?}"),
        )),
        _ => Ok(()),
    }
}

/// Supports and loads: on the plate, a traction only on edges, and some load.
fn boundary(p: &Problem) -> Result<()> {
    let Boundary::Regions { supports, loads } = &p.boundary else {
        return Ok(());
    };
    let (w, h) = (p.domain.width, p.domain.height);
    // a point in a hole would hold (or load) the plate at a fictitious node
    let in_material = |name: &str, r: &Region| match *r {
        Region::Point(q) if p.domain.level_set(q) < 0.0 => Err(Error::invalid(
            &format!("{name}.point"),
            "a point in the material (outside the holes and notches)",
            format!("{q:?}"),
        )),
        _ => Ok(()),
    };
    for s in supports {
        region_on_plate(&s.name, &s.region, w, h)?;
        in_material(&s.name, &s.region)?;
        if s.u1.is_none() && s.u2.is_none() {
            return Err(Error::invalid(
                &format!("{}.fix", s.name),
                "'u1', 'u2' or 'both'",
                "none",
            ));
        }
        for (key, v) in [("u1", s.u1), ("u2", s.u2)] {
            if v.is_some_and(|v| !v.is_finite()) {
                return Err(Error::invalid(
                    &format!("{}.{key}", s.name),
                    "a finite number",
                    v.unwrap_or(0.0),
                ));
            }
        }
    }
    for l in loads {
        region_on_plate(&l.name, &l.region, w, h)?;
        in_material(&l.name, &l.region)?;
        match (l.kind, l.region) {
            (LoadKind::Force(_), Region::Point(_)) => {}
            (LoadKind::Traction { .. }, Region::Edge(_) | Region::EdgePart { .. }) => {}
            (_, r) => {
                return Err(Error::invalid(
                    &format!("{}.region", l.name),
                    "'edge' or 'edge_part' (a traction) or 'point' (a force)",
                    r.name(),
                ))
            }
        }
    }
    let loaded = loads.iter().any(|l| match l.kind {
        LoadKind::Force(f) => f != [0.0, 0.0],
        LoadKind::Traction { normal, shear } => normal != 0.0 || shear != 0.0,
    }) || supports
        .iter()
        .any(|s| s.u1.is_some_and(|v| v != 0.0) || s.u2.is_some_and(|v| v != 0.0));
    if !loaded && !matches!(p.method, Method::Fem(_)) {
        return Err(Error::invalid(
            "load",
            "a reference load: a [[load]] with a non-zero traction or force, or a [[support]] \
             with a non-zero u1 or u2 (growth and the SLA scale it)",
            "every load and prescribed displacement is zero",
        ));
    }
    Ok(())
}

/// Probes on the plate, in material, reading an existing crack, each of its own name.
fn probes(p: &Problem) -> Result<()> {
    let (w, h) = (p.domain.width, p.domain.height);
    for (k, pr) in p.probes.iter().enumerate() {
        let q = pr.point();
        if !inside_plate(q, w, h) || p.domain.level_set(q) < 0.0 {
            return Err(Error::invalid(
                &format!("probe[{k}].point"),
                &format!("a point in the material of the plate [0, {w}] x [0, {h}]"),
                format!("{q:?}"),
            ));
        }
        // a response is read by its name: two probes of one name would keep one value
        if let Some(j) = p.probes[..k].iter().position(|o| o.name == pr.name) {
            return Err(Error::invalid(
                &format!("probe[{k}].name"),
                &format!(
                    "a name no other probe has (probe[{j}] is named '{}'; a probe without a \
                     name is named probe[k])",
                    pr.name
                ),
                format!("'{}'", pr.name),
            ));
        }
        if let ProbeKind::Opening { crack, .. } = pr.kind {
            if crack >= p.cracks.len() {
                return Err(Error::invalid(
                    &format!("probe[{k}].crack"),
                    &format!("the index of a crack of the scene (0..{})", p.cracks.len()),
                    crack,
                ));
            }
        }
    }
    Ok(())
}

/// What each method reads of the general scene: the parts not built for a method yet are
/// refused, naming the first entry. PD and CCM-PD read everything (holes in the FEM part of
/// CCM-PD are a fictitious domain, `pd/splice/holes.rs`, which refuses one cutting a hybrid
/// element where the grid is known).
fn supported(p: &Problem) -> Result<()> {
    let m = p.method.name();
    match &p.method {
        Method::Pd(_) | Method::CcmPd(_) => Ok(()),
        Method::Fem(_) | Method::Xfem(_) => match p.domain.holes.first() {
            Some(h) if FICTITIOUS_DOMAIN_PENDING => Err(Error::invalid(
                &h.name,
                &format!("no holes or notches for method '{m}' (supported by 'pd' and 'ccm_pd')"),
                "a scene with holes or notches",
            )),
            _ => Ok(()),
        },
    }
}

/// Holes for FEM and XFEM arrive with the fictitious-domain integration (cut elements).
const FICTITIOUS_DOMAIN_PENDING: bool = false;

/// Tensor grid lines from 0 to the plate's size, strictly increasing (checked before the
/// grid's element counts, which they define).
pub fn grid_lines(p: &Problem) -> Result<()> {
    let grid = match &p.method {
        Method::Fem(f) => &f.grid,
        Method::Xfem(x) => &x.grid,
        _ => return Ok(()),
    };
    for (key, v, len) in [
        ("mesh.xs", &grid.xs, p.domain.width),
        ("mesh.ys", &grid.ys, p.domain.height),
    ] {
        if v.is_empty() {
            continue;
        }
        let tol = 1e-12 * len;
        let ok = v.len() >= 2
            && v[0].abs() <= tol
            && (v[v.len() - 1] - len).abs() <= tol
            && v.windows(2).all(|w| w[1] > w[0]);
        if !ok {
            return Err(Error::invalid(
                key,
                &format!("at least 2 strictly increasing grid lines from 0 to {len}"),
                format!("{} lines from {} to {}", v.len(), v[0], v[v.len() - 1]),
            ));
        }
    }
    if grid.nx.saturating_mul(grid.ny) > MAX_ELEMENTS {
        return Err(Error::invalid(
            "mesh.xs",
            &format!("at most {} elements", MAX_ELEMENTS),
            format!("{} x {}", grid.nx, grid.ny),
        ));
    }
    Ok(())
}

/// Every cross check of the general scene.
pub fn check(p: &Problem) -> Result<()> {
    holes(p)?;
    boundary(p)?;
    probes(p)?;
    supported(p)
}
