//! Plain 2D geometry on `[f64; 2]` points: vector arithmetic, distances between points, segments
//! and polylines, clipping of a segment by a box (Liang-Barsky) and of a convex polygon by a line.
//!
//! One copy for the whole crate (the crack level sets, the enrichment sets and the SIF domains of
//! [`crate::xfem`] use it). No tolerances are applied here unless an argument says so.

/// a - b
#[inline]
pub fn sub(a: [f64; 2], b: [f64; 2]) -> [f64; 2] {
    [a[0] - b[0], a[1] - b[1]]
}

/// Scalar product a . b.
#[inline]
pub fn dot(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[0] + a[1] * b[1]
}

/// 2D cross product a x b = a_1 b_2 - a_2 b_1 (positive when b lies counter-clockwise of a).
#[inline]
pub fn cross(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[1] - a[1] * b[0]
}

/// Euclidean length |a| (hypot, no overflow).
#[inline]
pub fn norm(a: [f64; 2]) -> f64 {
    a[0].hypot(a[1])
}

/// a / |a| (not defined for a = 0).
#[inline]
pub fn unit(a: [f64; 2]) -> [f64; 2] {
    let n = norm(a);
    [a[0] / n, a[1] / n]
}

/// Distance from `x` to the segment a-b.
pub fn point_segment_distance(x: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    let d = sub(b, a);
    let t = (dot(sub(x, a), d) / dot(d, d)).clamp(0.0, 1.0);
    norm(sub(x, [a[0] + t * d[0], a[1] + t * d[1]]))
}

/// Smallest distance between the segments a-b and c-d (0 when they cross).
pub fn segment_distance(a: [f64; 2], b: [f64; 2], c: [f64; 2], d: [f64; 2]) -> f64 {
    let (d1, d2) = (cross(sub(b, a), sub(c, a)), cross(sub(b, a), sub(d, a)));
    let (d3, d4) = (cross(sub(d, c), sub(a, c)), cross(sub(d, c), sub(b, c)));
    if d1 * d2 < 0.0 && d3 * d4 < 0.0 {
        return 0.0;
    }
    point_segment_distance(a, c, d)
        .min(point_segment_distance(b, c, d))
        .min(point_segment_distance(c, a, b))
        .min(point_segment_distance(d, a, b))
}

/// Distance from `x` to a polyline.
pub fn polyline_distance(points: &[[f64; 2]], x: [f64; 2]) -> f64 {
    points
        .windows(2)
        .map(|s| point_segment_distance(x, s[0], s[1]))
        .fold(f64::INFINITY, f64::min)
}

/// Liang-Barsky: parameter interval of segment a-b inside the box [lo, hi] grown by `tol`.
pub fn seg_box(
    a: [f64; 2],
    b: [f64; 2],
    lo: [f64; 2],
    hi: [f64; 2],
    tol: f64,
) -> Option<(f64, f64)> {
    let d = sub(b, a);
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    for ax in 0..2 {
        if d[ax] == 0.0 {
            if a[ax] < lo[ax] - tol || a[ax] > hi[ax] + tol {
                return None;
            }
        } else {
            let ta = (lo[ax] - tol - a[ax]) / d[ax];
            let tb = (hi[ax] + tol - a[ax]) / d[ax];
            t0 = t0.max(ta.min(tb));
            t1 = t1.min(ta.max(tb));
            if t0 > t1 {
                return None;
            }
        }
    }
    Some((t0, t1))
}

/// Area of the part of a convex polygon with cross(b - a, x - a) > 0 (the polygon clipped by the
/// line through a and b, keeping its left side).
pub fn positive_area(poly: &[[f64; 2]], a: [f64; 2], b: [f64; 2]) -> f64 {
    let d = sub(b, a);
    let f = |x: [f64; 2]| cross(d, sub(x, a));
    let mut out: Vec<[f64; 2]> = Vec::with_capacity(poly.len() + 2);
    for k in 0..poly.len() {
        let (p, q) = (poly[k], poly[(k + 1) % poly.len()]);
        let (fp, fq) = (f(p), f(q));
        if fp > 0.0 {
            out.push(p);
        }
        if (fp > 0.0) != (fq > 0.0) && fp != fq {
            let t = fp / (fp - fq);
            out.push([p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])]);
        }
    }
    let mut area = 0.0;
    for k in 0..out.len() {
        area += cross(out[k], out[(k + 1) % out.len()]);
    }
    0.5 * area.abs()
}
