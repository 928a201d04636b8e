//! The general scene's parts beyond the paper's plate: holes and notches of the domain, supports
//! and loads on boundary regions, and probes (named responses). Every value is the reference load:
//! XFEM growth and the SLA scale all of them by one load factor.
//!
//! Each part keeps its scene name (`hole[1]`, `notch[0]`, `support[2]`, `load[0]`, `probe[3]`)
//! so that a refusal made while building a model names the entry to change.

use super::side::Side;
use crate::geometry;

/// A hole's shape; its level set ([`Shape::level_set`]) is negative inside.
#[derive(Debug, Clone, PartialEq)]
pub enum Shape {
    Circle {
        center: [f64; 2],
        radius: f64,
    },
    /// an axis-aligned rectangle [min, max]
    Rect {
        min: [f64; 2],
        max: [f64; 2],
    },
    /// a simple polygon (vertices in order, not closed: the last joins the first)
    Polygon(Vec<[f64; 2]>),
}

impl Shape {
    /// Signed distance to the shape's boundary: negative inside, positive outside.
    pub fn level_set(&self, p: [f64; 2]) -> f64 {
        match self {
            Shape::Circle { center, radius } => (p[0] - center[0]).hypot(p[1] - center[1]) - radius,
            Shape::Rect { min, max } => {
                let dx = (min[0] - p[0]).max(p[0] - max[0]);
                let dy = (min[1] - p[1]).max(p[1] - max[1]);
                if dx <= 0.0 && dy <= 0.0 {
                    dx.max(dy)
                } else {
                    dx.max(0.0).hypot(dy.max(0.0))
                }
            }
            Shape::Polygon(v) => {
                let d = (0..v.len())
                    .map(|i| geometry::point_segment_distance(p, v[i], v[(i + 1) % v.len()]))
                    .fold(f64::INFINITY, f64::min);
                if geometry::point_in_polygon(p, v) {
                    -d
                } else {
                    d
                }
            }
        }
    }

    /// Does the segment a-b pass through the shape's interior (a PD bond through a hole does not
    /// exist)? Circles: its distance to the centre below the radius; rectangles and polygons:
    /// [`geometry::segment_meets_polygon`].
    pub fn cuts_segment(&self, a: [f64; 2], b: [f64; 2]) -> bool {
        match self {
            Shape::Circle { center, radius } => {
                geometry::segment_meets_circle(a, b, *center, *radius)
            }
            Shape::Rect { min, max } => geometry::segment_meets_polygon(
                a,
                b,
                &[*min, [max[0], min[1]], *max, [min[0], max[1]]],
            ),
            Shape::Polygon(v) => geometry::segment_meets_polygon(a, b, v),
        }
    }

    /// The axis-aligned bounding box [x0, y0, x1, y1].
    pub fn bounding_box(&self) -> [f64; 4] {
        match self {
            Shape::Circle { center, radius } => [
                center[0] - radius,
                center[1] - radius,
                center[0] + radius,
                center[1] + radius,
            ],
            Shape::Rect { min, max } => [min[0], min[1], max[0], max[1]],
            Shape::Polygon(v) => v.iter().fold(
                [
                    f64::INFINITY,
                    f64::INFINITY,
                    f64::NEG_INFINITY,
                    f64::NEG_INFINITY,
                ],
                |b, p| {
                    [
                        b[0].min(p[0]),
                        b[1].min(p[1]),
                        b[2].max(p[0]),
                        b[3].max(p[1]),
                    ]
                },
            ),
        }
    }
}

/// A hole or a notch (a slot from an edge, stored as the rectangle it removes).
#[derive(Debug, Clone, PartialEq)]
pub struct Hole {
    /// scene name: `hole[k]` or `notch[k]`
    pub name: String,
    pub shape: Shape,
}

/// Where a support or a load acts.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Region {
    /// a whole side of the plate
    Edge(Side),
    /// the part of a side between two coordinates along it (x1 on bottom/top, x2 on left/right)
    EdgePart { side: Side, from: f64, to: f64 },
    /// the node nearest a point (refused if none lies within half an element)
    Point([f64; 2]),
    /// every node in a box [x0, y0, x1, y1]
    Box([f64; 4]),
}

impl Region {
    /// The scene's spelling (`region`).
    pub fn name(&self) -> &'static str {
        match self {
            Region::Edge(_) => "edge",
            Region::EdgePart { .. } => "edge_part",
            Region::Point(_) => "point",
            Region::Box(_) => "box",
        }
    }
}

/// Prescribed displacements on a region (reference values; None: that component is free).
#[derive(Debug, Clone, PartialEq)]
pub struct Support {
    /// scene name `support[k]`
    pub name: String,
    pub region: Region,
    pub u1: Option<f64>,
    pub u2: Option<f64>,
}

/// What a load applies.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum LoadKind {
    /// a uniform traction on an edge region (stress): `normal` along the outward normal
    /// (tension positive), `shear` along +x1 on the bottom and top sides and along +x2 on the
    /// left and right sides
    Traction { normal: f64, shear: f64 },
    /// a force (total over the thickness) at a point
    Force([f64; 2]),
}

/// A load on a region (reference value).
#[derive(Debug, Clone, PartialEq)]
pub struct RegionLoad {
    /// scene name `load[k]`
    pub name: String,
    pub region: Region,
    pub kind: LoadKind,
}

/// A named response.
#[derive(Debug, Clone, PartialEq)]
pub enum ProbeKind {
    /// the displacement at a point
    Displacement([f64; 2]),
    /// the opening (jump of u) across crack `crack` at the crack point nearest `point`
    Opening { point: [f64; 2], crack: usize },
}

/// A named response point.
#[derive(Debug, Clone, PartialEq)]
pub struct Probe {
    /// the user's name (results carry it); scene name `probe[k]` in errors
    pub name: String,
    pub kind: ProbeKind,
}

impl Probe {
    /// The point it reads.
    pub fn point(&self) -> [f64; 2] {
        match &self.kind {
            ProbeKind::Displacement(p) | ProbeKind::Opening { point: p, .. } => *p,
        }
    }
}

/// The outward unit normal of a side.
pub fn outward_normal(side: Side) -> [f64; 2] {
    match side {
        Side::Left => [-1.0, 0.0],
        Side::Right => [1.0, 0.0],
        Side::Bottom => [0.0, -1.0],
        Side::Top => [0.0, 1.0],
    }
}

/// The traction vector of (normal, shear) on a side ([`LoadKind::Traction`]).
pub fn traction_vector(side: Side, normal: f64, shear: f64) -> [f64; 2] {
    let n = outward_normal(side);
    let s = match side {
        Side::Bottom | Side::Top => [1.0, 0.0],
        Side::Left | Side::Right => [0.0, 1.0],
    };
    [normal * n[0] + shear * s[0], normal * n[1] + shear * s[1]]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn level_sets_are_signed_distances() {
        let c = Shape::Circle {
            center: [1.0, 1.0],
            radius: 0.5,
        };
        assert!((c.level_set([1.0, 1.0]) + 0.5).abs() < 1e-15);
        assert!((c.level_set([2.0, 1.0]) - 0.5).abs() < 1e-15);
        let r = Shape::Rect {
            min: [0.0, 0.0],
            max: [2.0, 1.0],
        };
        assert!((r.level_set([1.0, 0.5]) + 0.5).abs() < 1e-15);
        assert!((r.level_set([3.0, 2.0]) - 2f64.sqrt()).abs() < 1e-15);
        let p = Shape::Polygon(vec![[0.0, 0.0], [2.0, 0.0], [2.0, 1.0], [0.0, 1.0]]);
        for q in [[1.0, 0.5], [3.0, 2.0], [0.1, 0.9], [-0.5, 0.5]] {
            assert!((p.level_set(q) - r.level_set(q)).abs() < 1e-14, "{q:?}");
        }
    }

    #[test]
    fn traction_components() {
        assert_eq!(traction_vector(Side::Top, 2.0, 1.0), [1.0, 2.0]);
        assert_eq!(traction_vector(Side::Bottom, 2.0, 1.0), [1.0, -2.0]);
        assert_eq!(traction_vector(Side::Left, 2.0, 1.0), [-2.0, 1.0]);
    }
}
