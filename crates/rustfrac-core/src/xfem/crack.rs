//! Crack geometry (paper section 2.1, eq. 1): a crack is a polyline `points[0..n]` inside the
//! plate. An end lying on the plate boundary, or on or in a hole or notch of the domain (an edge
//! crack from a notch tip: [`Crack::named_in`]), is a *mouth* (edge crack); an end inside the
//! material is a *tip*, so a crack has one tip (edge crack) or two (interior crack). A crack with
//! both ends on the boundary would cut the plate in two and is refused.
//!
//! The level set phi(x) is the signed distance to the polyline; its sign is (x - x*) . n (eq. 1)
//! with x* the closest point and n the unit normal obtained by turning the segment direction (from
//! `points[0]` towards `points[n]`) by +90 degrees (the mean of the two normals at an interior
//! vertex; beyond an end the end segment's line decides, i.e. the Heaviside function is that of the crack
//! extended straight). H(x) = +1 if phi > snap, else -1 (eq. 1, with snap = [`SNAP_REL`] x the
//! smallest element spacing): a point on the crack, in particular a node of a crack running along
//! a mesh line or through nodes, takes -1 whatever the rounding of its coordinates, so every such
//! node lies on the same side.
//!
//! The cracks of one model must neither cross nor touch (module [`crate::xfem`], "Several
//! cracks"): junctions and coalescence are not modelled.

use crate::error::{Error, Result};
use crate::fe::mesh::Mesh;
use crate::geometry::{cross, dot, norm, segment_distance, sub, unit};
use crate::problem::parse::crack_name;
use crate::problem::Domain;

/// A crack tip: position and unit direction of crack advance (the tip frame's x~1 axis).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tip {
    pub pos: [f64; 2],
    pub dir: [f64; 2],
    /// true if this tip is `points[0]` (the start of the polyline), false if it is the last point
    pub at_start: bool,
}

/// Points closer to the crack than `SNAP_REL` x the smallest element spacing count as lying on it
/// (H = -1); relative, so the rule does not depend on the units of length.
pub const SNAP_REL: f64 = 1e-10;

/// A polyline crack with its tips (see the module documentation).
#[derive(Debug, Clone, PartialEq)]
pub struct Crack {
    pub points: Vec<[f64; 2]>,
    /// distance below which a point lies on the crack (`level_set` returns phi = 0 and `heaviside`
    /// -1): `SNAP_REL` x the mesh's smallest spacing, so the classification does not depend on
    /// the units
    pub snap: f64,
    /// `points[0]` lies on the plate boundary (edge crack mouth)
    pub mouth: bool,
    /// tips: the last point first (if it is a tip), then the first point (if it is a tip)
    pub tips: Vec<Tip>,
}

impl Crack {
    /// Validates the polyline against the plate rectangle of `mesh` and finds mouth and tips.
    pub fn new(points: Vec<[f64; 2]>, mesh: &Mesh) -> Result<Self> {
        Self::named(points, mesh, "crack")
    }

    /// [`Crack::new`] with errors naming the parameter `param` (e.g. "crack\[1\]").
    pub fn named(points: Vec<[f64; 2]>, mesh: &Mesh, param: &str) -> Result<Self> {
        Self::named_in(points, mesh, param, None)
    }

    /// [`Crack::named`] in a domain with holes: when neither end lies on the plate's boundary,
    /// an end on or inside a hole or notch (level set <= 1e-9 x the plate diagonal; the first
    /// such) is the mouth.
    pub fn named_in(
        points: Vec<[f64; 2]>,
        mesh: &Mesh,
        param: &str,
        domain: Option<&Domain>,
    ) -> Result<Self> {
        if points.len() < 2 {
            return Err(Error::invalid(
                param,
                "a polyline of at least 2 points",
                format!("{} point(s)", points.len()),
            ));
        }
        let (x0, y0) = (mesh.xs[0], mesh.ys[0]);
        let (w, h) = mesh.size();
        let tol = 1e-9 * w.hypot(h);
        for (k, p) in points.iter().enumerate() {
            if !(p[0].is_finite() && p[1].is_finite()) {
                return Err(Error::invalid(
                    param,
                    "finite point coordinates",
                    format!("point {k} = {p:?}"),
                ));
            }
            if p[0] < x0 - tol || p[0] > x0 + w + tol || p[1] < y0 - tol || p[1] > y0 + h + tol {
                return Err(Error::invalid(
                    param,
                    &format!(
                        "points inside the plate [{x0}, {}] x [{y0}, {}]",
                        x0 + w,
                        y0 + h
                    ),
                    format!("point {k} = {p:?}"),
                ));
            }
        }
        for (k, s) in points.windows(2).enumerate() {
            if norm(sub(s[1], s[0])) <= 1e-9 * mesh.min_spacing() {
                return Err(Error::invalid(
                    param,
                    "segments of positive length (no repeated points)",
                    format!("segment {k} has length {}", norm(sub(s[1], s[0]))),
                ));
            }
        }
        let on_plate_boundary = |p: [f64; 2]| {
            (p[0] - x0).abs() <= tol
                || (p[0] - x0 - w).abs() <= tol
                || (p[1] - y0).abs() <= tol
                || (p[1] - y0 - h).abs() <= tol
        };
        let on_hole = |p: [f64; 2]| domain.is_some_and(|d| d.on_or_in_hole(p));
        let n = points.len();
        let (mut start_b, mut end_b) = (
            on_plate_boundary(points[0]),
            on_plate_boundary(points[n - 1]),
        );
        // without an end on the plate's boundary, the first end on (or in) a hole is the mouth;
        // an end in a hole facing a mouth is a tip (refused by the driver's tip clearance)
        if !start_b && !end_b {
            start_b = on_hole(points[0]);
            end_b = !start_b && on_hole(points[n - 1]);
        }
        if start_b && end_b {
            return Err(Error::invalid(
                param,
                "at least one end inside the plate (both ends on the boundary cut the plate in two)",
                format!("{:?} .. {:?}", points[0], points[n - 1]),
            ));
        }
        if end_b {
            // orient the polyline so that a mouth is always points[0]
            let mut p = points;
            p.reverse();
            return Self::named_in(p, mesh, param, domain);
        }
        let mut tips = vec![Tip {
            pos: points[n - 1],
            dir: unit(sub(points[n - 1], points[n - 2])),
            at_start: false,
        }];
        if !start_b {
            tips.push(Tip {
                pos: points[0],
                dir: unit(sub(points[0], points[1])),
                at_start: true,
            });
        }
        Ok(Self {
            points,
            snap: SNAP_REL * mesh.min_spacing(),
            mouth: start_b,
            tips,
        })
    }

    /// Total length of the polyline.
    pub fn length(&self) -> f64 {
        self.points.windows(2).map(|s| norm(sub(s[1], s[0]))).sum()
    }

    /// The crack length `a` reported in growth histories: the polyline length for an edge crack,
    /// half of it for an interior crack (the usual "2a" convention).
    pub fn a(&self) -> f64 {
        if self.mouth {
            self.length()
        } else {
            0.5 * self.length()
        }
    }

    /// Signed distance to the polyline (level set phi; sign convention in the module docs).
    pub fn level_set(&self, x: [f64; 2]) -> f64 {
        let p = &self.points;
        let nseg = p.len() - 1;
        let (mut best, mut bk, mut bt) = (f64::INFINITY, 0usize, 0.0f64);
        for k in 0..nseg {
            let d = sub(p[k + 1], p[k]);
            let t = (dot(sub(x, p[k]), d) / dot(d, d)).clamp(0.0, 1.0);
            let c = [p[k][0] + t * d[0], p[k][1] + t * d[1]];
            let d2 = dot(sub(x, c), sub(x, c));
            if d2 < best {
                best = d2;
                bk = k;
                bt = t;
            }
        }
        let seg_n = |k: usize| {
            let t = unit(sub(p[k + 1], p[k]));
            [-t[1], t[0]]
        };
        // s: distance to the line that decides the sign (vertex bisector or segment line), signed
        let s = if bt >= 1.0 && bk + 1 < nseg {
            let (a, b) = (seg_n(bk), seg_n(bk + 1));
            let nv = [a[0] + b[0], a[1] + b[1]];
            dot(sub(x, p[bk + 1]), nv) / norm(nv)
        } else if bt <= 0.0 && bk > 0 {
            let (a, b) = (seg_n(bk - 1), seg_n(bk));
            let nv = [a[0] + b[0], a[1] + b[1]];
            dot(sub(x, p[bk]), nv) / norm(nv)
        } else {
            let d = sub(p[bk + 1], p[bk]);
            cross(d, sub(x, p[bk])) / norm(d)
        };
        if s.abs() <= self.snap {
            0.0
        } else if s > 0.0 {
            best.sqrt()
        } else if s < 0.0 {
            -best.sqrt()
        } else {
            0.0
        }
    }

    /// Heaviside function of eq. (1); points within `snap` of the crack take -1.
    #[inline]
    pub fn heaviside(&self, x: [f64; 2]) -> f64 {
        if self.level_set(x) > self.snap {
            1.0
        } else {
            -1.0
        }
    }
}

/// A tip-frame point behind the tip within `snap` of the tip's line moved onto the H = -1 face
/// (x~2 = -0 for the last polyline point's tip, +0 for a tip at `points[0]`, whose frame is
/// reversed), so that atan2 gives the angle of that face whatever the rounding.
#[inline]
pub(super) fn on_face(tip: &Tip, xl: [f64; 2], snap: f64) -> [f64; 2] {
    if xl[0] < 0.0 && xl[1].abs() <= snap {
        [xl[0], if tip.at_start { 0.0 } else { -0.0 }]
    } else {
        xl
    }
}

/// What a refusal of cracks that meet expects (the growth loop stops on it: `cracks_meet`).
pub(crate) const CRACKS_APART: &str =
    "cracks that neither cross nor touch each other (crack junctions and coalescence are not \
     modelled)";

/// Refuses cracks that cross or touch each other (closer than 1e-9 of the plate diagonal):
/// junctions and coalescence are not modelled (each crack's Heaviside function assumes the crack
/// ends at its own tips or on the boundary).
fn check_cracks_apart(cracks: &[Crack], mesh: &Mesh) -> Result<()> {
    let (w, h) = mesh.size();
    let tol = 1e-9 * w.hypot(h);
    for i in 0..cracks.len() {
        for j in i + 1..cracks.len() {
            for (si, a) in cracks[i].points.windows(2).enumerate() {
                for (sj, b) in cracks[j].points.windows(2).enumerate() {
                    if segment_distance(a[0], a[1], b[0], b[1]) <= tol {
                        return Err(Error::invalid(
                            &crack_name(j),
                            CRACKS_APART,
                            format!(
                                "{} segment {si} {:?}-{:?} meets {} segment {sj} {:?}-{:?}",
                                crack_name(i),
                                a[0],
                                a[1],
                                crack_name(j),
                                b[0],
                                b[1]
                            ),
                        ));
                    }
                }
            }
        }
    }
    Ok(())
}

/// The cracks of a model from their polylines (at least one): each validated against the plate
/// (errors name crack k by its scene key, [`crack_name`]: "crack", "crack[1]", ...; an end on a
/// hole of `domain` is a mouth), then refused if two of them cross or touch (the later one's key).
pub(super) fn build_cracks(
    polylines: Vec<Vec<[f64; 2]>>,
    mesh: &Mesh,
    domain: Option<&Domain>,
) -> Result<Vec<Crack>> {
    if polylines.is_empty() {
        return Err(Error::invalid("crack", "at least one crack", 0));
    }
    let cracks = polylines
        .into_iter()
        .enumerate()
        .map(|(k, p)| Crack::named_in(p, mesh, &crack_name(k), domain))
        .collect::<Result<Vec<Crack>>>()?;
    check_cracks_apart(&cracks, mesh)?;
    Ok(cracks)
}

/// Every tip in global order (the tips of `cracks[0]`, then those of `cracks[1]`, ...) and the
/// crack of each.
pub(super) fn global_tips(cracks: &[Crack]) -> (Vec<Tip>, Vec<usize>) {
    let mut tips = Vec::new();
    let mut tip_crack = Vec::new();
    for (c, crack) in cracks.iter().enumerate() {
        for t in &crack.tips {
            tips.push(*t);
            tip_crack.push(c);
        }
    }
    (tips, tip_crack)
}
