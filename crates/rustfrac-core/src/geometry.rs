//! Plane geometry on `[f64; 2]` points, one copy for the whole crate: vector arithmetic, the
//! orientation test, distances between points, segments and polylines, whether a segment crosses
//! another (the PD pre-crack's broken bonds), and clipping: a segment by a box (Liang-Barsky) and
//! a convex polygon by a line (the XFEM small-area rule) or a box, the difference of convex polygons
//! and ear-clipping triangulation (the fictitious domain of holes, [`crate::fe::fictitious`]).
//!
//! Users: the crack level sets, enrichment sets and SIF domains of [`crate::xfem`], the pre-crack
//! of [`crate::pd::splice`] and the cross-parameter checks of [`crate::problem::validate`]. No
//! tolerance is applied unless an argument or the doc says so.

/// a - b
#[inline]
pub(crate) fn sub(a: [f64; 2], b: [f64; 2]) -> [f64; 2] {
    [a[0] - b[0], a[1] - b[1]]
}

/// Scalar product a . b.
#[inline]
pub(crate) fn dot(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[0] + a[1] * b[1]
}

/// 2D cross product a x b = a_1 b_2 - a_2 b_1 (positive when b lies counter-clockwise of a).
#[inline]
pub(crate) fn cross(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[1] - a[1] * b[0]
}

/// Euclidean length |a| (hypot: no overflow).
#[inline]
pub(crate) fn norm(a: [f64; 2]) -> f64 {
    a[0].hypot(a[1])
}

/// a / |a| (not defined for a = 0).
#[inline]
pub(crate) fn unit(a: [f64; 2]) -> [f64; 2] {
    let n = norm(a);
    [a[0] / n, a[1] / n]
}

/// Orientation of `p` against the directed line a -> b: (b - a) x (p - a), positive when p lies
/// on its left, zero on the line (twice the signed area of the triangle a, b, p).
#[inline]
pub(crate) fn orient(a: [f64; 2], b: [f64; 2], p: [f64; 2]) -> f64 {
    cross(sub(b, a), sub(p, a))
}

/// Distance from the point `x` to the segment a-b.
pub fn point_segment_distance(x: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    let d = sub(b, a);
    let t = (dot(sub(x, a), d) / dot(d, d)).clamp(0.0, 1.0);
    norm(sub(x, [a[0] + t * d[0], a[1] + t * d[1]]))
}

/// Smallest distance between the segments a-b and c-d (0 when they cross).
pub fn segment_distance(a: [f64; 2], b: [f64; 2], c: [f64; 2], d: [f64; 2]) -> f64 {
    let (d1, d2) = (orient(a, b, c), orient(a, b, d));
    let (d3, d4) = (orient(c, d, a), orient(c, d, b));
    if d1 * d2 < 0.0 && d3 * d4 < 0.0 {
        return 0.0;
    }
    point_segment_distance(a, c, d)
        .min(point_segment_distance(b, c, d))
        .min(point_segment_distance(c, a, b))
        .min(point_segment_distance(d, a, b))
}

/// Distance from `x` to a polyline.
pub(crate) fn polyline_distance(points: &[[f64; 2]], x: [f64; 2]) -> f64 {
    points
        .windows(2)
        .map(|s| point_segment_distance(x, s[0], s[1]))
        .fold(f64::INFINITY, f64::min)
}

/// Does the bond p-q cross the segment a-b? Its end nodes strictly on opposite sides of a-b
/// (tolerance 1e-9 |a - b|), the crossing point on the closed segment (tolerance 1e-9 |p - q|: a
/// tip on the bond counts). The splice pre-crack calls it in grid units.
pub fn bond_crosses(p: [f64; 2], q: [f64; 2], a: [f64; 2], b: [f64; 2]) -> bool {
    let lab = ((b[0] - a[0]).powi(2) + (b[1] - a[1]).powi(2)).sqrt();
    let lpq = ((q[0] - p[0]).powi(2) + (q[1] - p[1]).powi(2)).sqrt();
    let t1 = 1e-9 * lab;
    let o1 = orient(a, b, p);
    let o2 = orient(a, b, q);
    if !((o1 > t1 && o2 < -t1) || (o1 < -t1 && o2 > t1)) {
        return false;
    }
    let t2 = 1e-9 * lpq;
    let o3 = orient(p, q, a);
    let o4 = orient(p, q, b);
    (o3 <= t2 && o4 >= -t2) || (o3 >= -t2 && o4 <= t2)
}

/// Is `p` inside the closed polygon `v` (even-odd rule; a point on an edge may go either way)?
pub fn point_in_polygon(p: [f64; 2], v: &[[f64; 2]]) -> bool {
    let n = v.len();
    let mut inside = false;
    for i in 0..n {
        let (a, b) = (v[i], v[(i + 1) % n]);
        if (a[1] > p[1]) != (b[1] > p[1])
            && p[0] < a[0] + (p[1] - a[1]) * (b[0] - a[0]) / (b[1] - a[1])
        {
            inside = !inside;
        }
    }
    inside
}

/// Does the segment a-b pass through the open disc of centre `c` and radius `r` (its distance to
/// the centre below r; a tangent segment does not)?
pub fn segment_meets_circle(a: [f64; 2], b: [f64; 2], c: [f64; 2], r: f64) -> bool {
    point_segment_distance(c, a, b) < r
}

/// Does the segment a-b pass through the interior of the simple polygon `v`: an end or its
/// midpoint strictly inside (farther than 1e-12 of the polygon's size from its edges), or a
/// proper crossing (ends strictly on both sides) with an edge? A segment along an edge or
/// touching a vertex from outside does not (a segment from vertex to vertex through a
/// non-convex polygon's interior is caught by its midpoint only).
pub fn segment_meets_polygon(a: [f64; 2], b: [f64; 2], v: &[[f64; 2]]) -> bool {
    let n = v.len();
    let size = v
        .iter()
        .flat_map(|p| p.iter())
        .fold(0.0f64, |s, &x| s.max(x.abs()))
        .max(f64::MIN_POSITIVE);
    let strictly_inside = |p: [f64; 2]| {
        point_in_polygon(p, v)
            && (0..n).all(|i| point_segment_distance(p, v[i], v[(i + 1) % n]) > 1e-12 * size)
    };
    let mid = [0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])];
    if strictly_inside(a) || strictly_inside(b) || strictly_inside(mid) {
        return true;
    }
    (0..n).any(|i| {
        let (c, d) = (v[i], v[(i + 1) % n]);
        orient(a, b, c) * orient(a, b, d) < 0.0 && orient(c, d, a) * orient(c, d, b) < 0.0
    })
}

/// The first grid node (i, j) of the grid 0..=nx x 0..=ny (grid units: node (i, j) at (i, j))
/// within 1e-9 of the segment a-b (None: the segment passes between the nodes).
pub fn grid_node_on_segment(
    a: [f64; 2],
    b: [f64; 2],
    nx: usize,
    ny: usize,
) -> Option<(usize, usize)> {
    let (i0, i1) = (a[0].min(b[0]).floor() as i64, a[0].max(b[0]).ceil() as i64);
    let (j0, j1) = (a[1].min(b[1]).floor() as i64, a[1].max(b[1]).ceil() as i64);
    let l2 = (b[0] - a[0]).powi(2) + (b[1] - a[1]).powi(2);
    for j in j0.max(0)..=j1.min(ny as i64) {
        for i in i0.max(0)..=i1.min(nx as i64) {
            let p = [i as f64, j as f64];
            let t = (((p[0] - a[0]) * (b[0] - a[0]) + (p[1] - a[1]) * (b[1] - a[1])) / l2)
                .clamp(0.0, 1.0);
            let c = [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])];
            if ((p[0] - c[0]).powi(2) + (p[1] - c[1]).powi(2)).sqrt() < 1e-9 {
                return Some((i as usize, j as usize));
            }
        }
    }
    None
}

/// The first pair of edges (i, j) of a closed polygon that touch or cross other than at a shared
/// vertex of neighbouring edges (None: the polygon is simple). About n log n: a sweep along x1.
pub fn self_intersection(v: &[[f64; 2]]) -> Option<(usize, usize)> {
    let n = v.len();
    let scale = v
        .iter()
        .flat_map(|p| p.iter())
        .fold(0.0f64, |a, &x| a.max(x.abs()))
        .max(1.0);
    // sweep along x1: edge i meets only the edges whose x1 range overlaps its own (grown by
    // the tolerance), so a polygon of n vertices costs about n log n, not n^2
    let tol = 1e-12 * scale;
    let range = |i: usize| {
        let (a, b) = (v[i][0], v[(i + 1) % n][0]);
        (a.min(b) - tol, a.max(b) + tol)
    };
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by(|&i, &j| range(i).0.total_cmp(&range(j).0));
    let mut found: Option<(usize, usize)> = None;
    for (k, &e) in order.iter().enumerate() {
        let hi = range(e).1;
        for &o in order[k + 1..].iter().take_while(|&&o| range(o).0 <= hi) {
            let (i, j) = (e.min(o), e.max(o));
            if pair_meets(v, i, j, scale) && found.is_none_or(|f| (i, j) < f) {
                found = Some((i, j));
            }
        }
    }
    found
}

/// Whether edges i < j of the closed polygon `v` touch (neighbours: fold back onto each other).
fn pair_meets(v: &[[f64; 2]], i: usize, j: usize, scale: f64) -> bool {
    let n = v.len();
    let (a, b) = (v[i], v[(i + 1) % n]);
    let (c, d) = (v[j], v[(j + 1) % n]);
    let neighbours = j == i + 1 || (i == 0 && j == n - 1);
    if neighbours {
        // neighbours share one vertex: they overlap only if collinear and folding back
        let (shared, p, q) = if j == i + 1 { (b, a, d) } else { (a, b, c) };
        let (u, w) = (sub(p, shared), sub(q, shared));
        let cross = u[0] * w[1] - u[1] * w[0];
        let dot = u[0] * w[0] + u[1] * w[1];
        cross.abs() <= 1e-12 * scale * scale && dot > 0.0
    } else {
        segment_distance(a, b, c, d) <= 1e-12 * scale
    }
}

/// Liang-Barsky: parameter interval of segment a-b inside the closed box [lo, hi] grown by `tol`.
pub(crate) fn seg_box(
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

/// Length of the part of segment a-b inside the open box [x0, x1] x [y0, y1] given as
/// `bx = [x0, y0, x1, y1]` (Liang-Barsky; a segment along the box's boundary has length 0).
pub(crate) fn clipped_length(a: [f64; 2], b: [f64; 2], bx: [f64; 4]) -> f64 {
    let d = [b[0] - a[0], b[1] - a[1]];
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    let checks = [
        (-d[0], a[0] - bx[0]),
        (d[0], bx[2] - a[0]),
        (-d[1], a[1] - bx[1]),
        (d[1], bx[3] - a[1]),
    ];
    for (p, q) in checks {
        if p == 0.0 {
            if q <= 0.0 {
                return 0.0;
            }
        } else {
            let r = q / p;
            if p < 0.0 {
                t0 = t0.max(r);
            } else {
                t1 = t1.min(r);
            }
        }
    }
    if t1 > t0 {
        (t1 - t0) * (d[0] * d[0] + d[1] * d[1]).sqrt()
    } else {
        0.0
    }
}

/// Area of the part of a convex polygon with cross(b - a, x - a) > 0 (the polygon clipped by the
/// line through a and b, keeping its left side).
pub(crate) fn positive_area(poly: &[[f64; 2]], a: [f64; 2], b: [f64; 2]) -> f64 {
    polygon_area(&clip_left(poly, a, b)).abs()
}

/// Signed area of a polygon (shoelace; positive counter-clockwise).
pub(crate) fn polygon_area(poly: &[[f64; 2]]) -> f64 {
    let mut area = 0.0;
    for k in 0..poly.len() {
        area += cross(poly[k], poly[(k + 1) % poly.len()]);
    }
    0.5 * area
}

/// The part of a convex polygon strictly left of the directed line a -> b (cross(b - a, x - a)
/// positive; Sutherland-Hodgman against one half-plane; the crossing points are interpolated along
/// the edges). Empty when nothing lies there.
pub(crate) fn clip_left(poly: &[[f64; 2]], a: [f64; 2], b: [f64; 2]) -> Vec<[f64; 2]> {
    clip_half_plane(poly, a, b, false)
}

/// Sutherland-Hodgman against the half-plane left of a -> b: strictly (`closed` false) or with
/// the points on the line (`closed` true).
fn clip_half_plane(poly: &[[f64; 2]], a: [f64; 2], b: [f64; 2], closed: bool) -> Vec<[f64; 2]> {
    let d = sub(b, a);
    let inside = |x: [f64; 2]| {
        let v = cross(d, sub(x, a));
        (v > 0.0 || (closed && v == 0.0), v)
    };
    let mut out: Vec<[f64; 2]> = Vec::with_capacity(poly.len() + 2);
    for k in 0..poly.len() {
        let (p, q) = (poly[k], poly[(k + 1) % poly.len()]);
        let ((ip, fp), (iq, fq)) = (inside(p), inside(q));
        if ip {
            out.push(p);
        }
        if ip != iq && fp != fq {
            let t = fp / (fp - fq);
            out.push([p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])]);
        }
    }
    out
}

/// The convex polygon clipped to the closed box [lo, hi] (its four half-planes, points on the
/// box's edges kept).
pub(crate) fn clip_box(poly: &[[f64; 2]], lo: [f64; 2], hi: [f64; 2]) -> Vec<[f64; 2]> {
    let corners = [lo, [hi[0], lo[1]], hi, [lo[0], hi[1]]];
    let mut p = poly.to_vec();
    for k in 0..4 {
        if p.len() < 3 {
            return Vec::new();
        }
        p = clip_keep_closed(&p, corners[k], corners[(k + 1) % 4]);
    }
    p
}

/// [`clip_left`] keeping points on the line too (cross >= 0).
fn clip_keep_closed(poly: &[[f64; 2]], a: [f64; 2], b: [f64; 2]) -> Vec<[f64; 2]> {
    clip_half_plane(poly, a, b, true)
}

/// The convex pieces of `pieces \ hole` for a convex, counter-clockwise `hole`: for each edge
/// a -> b of the hole in turn, the part of what is left that lies right of the edge's line is
/// outside the hole (kept), the rest goes on to the next edge; what is left after the last edge
/// lies inside the hole (dropped). Exact for straight edges; pieces of area below `min_area` are
/// dropped.
pub(crate) fn subtract_convex(
    pieces: Vec<Vec<[f64; 2]>>,
    hole: &[[f64; 2]],
    min_area: f64,
) -> Vec<Vec<[f64; 2]>> {
    let mut out = Vec::with_capacity(pieces.len() + hole.len());
    for piece in pieces {
        let mut rest = piece;
        for k in 0..hole.len() {
            if rest.len() < 3 {
                break;
            }
            let (a, b) = (hole[k], hole[(k + 1) % hole.len()]);
            let outside = clip_left(&rest, b, a);
            if outside.len() >= 3 && polygon_area(&outside).abs() > min_area {
                out.push(outside);
            }
            rest = clip_keep_closed(&rest, a, b);
        }
    }
    out
}

/// Triangles of a simple polygon by ear clipping (O(n^2); either orientation; the triangles are
/// counter-clockwise). Collinear vertices are skipped. A polygon that is not simple returns the
/// triangles found before no ear is left.
pub(crate) fn triangulate(poly: &[[f64; 2]]) -> Vec<[[f64; 2]; 3]> {
    let mut v: Vec<[f64; 2]> = poly.to_vec();
    if polygon_area(&v) < 0.0 {
        v.reverse();
    }
    let mut tris = Vec::with_capacity(v.len().saturating_sub(2));
    while v.len() > 3 {
        let n = v.len();
        let ear = (0..n).find(|&i| {
            let (a, b, c) = (v[(i + n - 1) % n], v[i], v[(i + 1) % n]);
            orient(a, b, c) > 0.0
                && (0..n).all(|k| {
                    let p = v[k];
                    k == i
                        || k == (i + n - 1) % n
                        || k == (i + 1) % n
                        || !(orient(a, b, p) >= 0.0
                            && orient(b, c, p) >= 0.0
                            && orient(c, a, p) >= 0.0)
                })
        });
        match ear {
            Some(i) => {
                let n = v.len();
                tris.push([v[(i + n - 1) % n], v[i], v[(i + 1) % n]]);
                v.remove(i);
            }
            None => {
                // collinear vertex (zero-area ear): drop it, else give up
                match (0..n).find(|&i| orient(v[(i + n - 1) % n], v[i], v[(i + 1) % n]) == 0.0) {
                    Some(i) => {
                        v.remove(i);
                    }
                    None => return tris,
                }
            }
        }
    }
    if v.len() == 3 && orient(v[0], v[1], v[2]) > 0.0 {
        tris.push([v[0], v[1], v[2]]);
    }
    tris
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn simple_and_self_intersecting_polygons() {
        let square = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        assert_eq!(self_intersection(&square), None);
        let bowtie = [[0.0, 0.0], [1.0, 1.0], [1.0, 0.0], [0.0, 1.0]];
        assert_eq!(self_intersection(&bowtie), Some((0, 2)));
        let folded = [[0.0, 0.0], [2.0, 0.0], [1.0, 0.0], [1.0, 1.0]];
        assert!(self_intersection(&folded).is_some());
        let repeated = [[0.0, 0.0], [1.0, 0.0], [0.0, 0.0], [0.0, 1.0]];
        assert!(self_intersection(&repeated).is_some());
    }

    /// The sweep finds the pair the plain O(n^2) search over every pair of edges finds, on
    /// random polygons (simple and not), and a polygon of 20 000 vertices is checked at once.
    #[test]
    fn the_sweep_finds_what_every_pair_finds() {
        let every_pair = |v: &[[f64; 2]]| {
            let n = v.len();
            let scale = v
                .iter()
                .flatten()
                .fold(0.0f64, |a, &x| a.max(x.abs()))
                .max(1.0);
            (0..n)
                .flat_map(|i| (i + 1..n).map(move |j| (i, j)))
                .find(|&(i, j)| pair_meets(v, i, j, scale))
        };
        let mut seed = 12345u64;
        let mut rnd = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        for n in 3..40 {
            for star in [true, false] {
                let v: Vec<[f64; 2]> = (0..n)
                    .map(|k| {
                        if star {
                            let (t, r) = (std::f64::consts::TAU * k as f64 / n as f64, 1.0 + rnd());
                            [r * t.cos(), r * t.sin()]
                        } else {
                            [rnd(), (4.0 * rnd()).round() / 4.0]
                        }
                    })
                    .collect();
                assert_eq!(self_intersection(&v), every_pair(&v), "{v:?}");
                if star {
                    assert_eq!(self_intersection(&v), None);
                }
            }
        }
        let n = 20_000;
        let circle: Vec<[f64; 2]> = (0..n)
            .map(|k| {
                let t = std::f64::consts::TAU * k as f64 / n as f64;
                [5.0 + t.cos(), 5.0 + t.sin()]
            })
            .collect();
        assert_eq!(self_intersection(&circle), None);
    }

    #[test]
    fn orientation_and_distances() {
        let (a, b) = ([0.0, 0.0], [2.0, 0.0]);
        assert!(orient(a, b, [1.0, 1.0]) > 0.0 && orient(a, b, [1.0, -1.0]) < 0.0);
        assert_eq!(orient(a, b, [5.0, 0.0]), 0.0);
        assert_eq!(point_segment_distance([1.0, 3.0], a, b), 3.0);
        assert_eq!(point_segment_distance([5.0, 4.0], a, b), 5.0);
        assert_eq!(segment_distance(a, b, [1.0, -1.0], [1.0, 1.0]), 0.0);
        assert_eq!(segment_distance(a, b, [3.0, 0.0], [3.0, 1.0]), 1.0);
        assert_eq!(polyline_distance(&[a, b, [2.0, 2.0]], [3.0, 1.0]), 1.0);
    }

    #[test]
    fn bonds_crossing_and_clipping() {
        let (a, b) = ([0.0, 0.5], [1.0, 0.5]);
        assert!(bond_crosses([0.5, 0.0], [0.5, 1.0], a, b));
        // the tip counts (closed segment), a node on the crack line does not cross
        assert!(bond_crosses([1.0, 0.0], [1.0, 1.0], a, b));
        assert!(!bond_crosses([1.5, 0.0], [1.5, 1.0], a, b));
        assert!(!bond_crosses([0.5, 0.5], [0.5, 1.0], a, b));
        assert_eq!(
            clipped_length([-1.0, 0.5], [3.0, 0.5], [0.0, 0.0, 2.0, 1.0]),
            2.0
        );
        assert_eq!(
            clipped_length([0.0, 0.0], [2.0, 0.0], [0.0, 0.0, 2.0, 1.0]),
            0.0
        );
        assert_eq!(
            seg_box([-1.0, 0.5], [3.0, 0.5], [0.0, 0.0], [2.0, 1.0], 0.0),
            Some((0.25, 0.75))
        );
        let square = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        assert_eq!(positive_area(&square, [0.0, 0.25], [1.0, 0.25]), 0.75);
        // the unit square less the square [0.25, 0.75]^2: area 0.75 in convex pieces
        let hole = [[0.25, 0.25], [0.75, 0.25], [0.75, 0.75], [0.25, 0.75]];
        let pieces = subtract_convex(vec![square.to_vec()], &hole, 0.0);
        let a: f64 = pieces.iter().map(|p| polygon_area(p)).sum();
        assert!((a - 0.75).abs() < 1e-15, "{a}");
        // a hole covering the square leaves nothing; one outside leaves it whole
        let big = [[-1.0, -1.0], [2.0, -1.0], [2.0, 2.0], [-1.0, 2.0]];
        assert!(subtract_convex(vec![square.to_vec()], &big, 0.0).is_empty());
        let far = [[3.0, 3.0], [4.0, 3.0], [4.0, 4.0]];
        let whole = subtract_convex(vec![square.to_vec()], &far, 1e-15);
        assert_eq!(whole.len(), 1);
        assert!((polygon_area(&whole[0]) - 1.0).abs() < 1e-15);
        assert!((polygon_area(&clip_box(&big, [0.0, 0.0], [1.0, 1.0])) - 1.0).abs() < 1e-15);
        // an L-shaped (non-convex, clockwise) polygon: 4 triangles of total area 3
        let l = [
            [0.0, 0.0],
            [0.0, 2.0],
            [1.0, 2.0],
            [1.0, 1.0],
            [2.0, 1.0],
            [2.0, 0.0],
        ];
        let t = triangulate(&l);
        assert_eq!(t.len(), 4);
        let at: f64 = t.iter().map(|t| polygon_area(t)).sum();
        assert!((at - 3.0).abs() < 1e-15 && t.iter().all(|t| polygon_area(t) > 0.0));
    }

    #[test]
    fn segments_through_holes_and_grid_nodes() {
        let c = [1.0, 1.0];
        assert!(segment_meets_circle([0.0, 1.2], [2.0, 1.2], c, 0.5));
        // tangent: not through the disc
        assert!(!segment_meets_circle([0.0, 1.5], [2.0, 1.5], c, 0.5));
        // the segment ends before the disc
        assert!(!segment_meets_circle([0.0, 1.0], [0.4, 1.0], c, 0.5));
        let sq = [[1.0, 1.0], [2.0, 1.0], [2.0, 2.0], [1.0, 2.0]];
        assert!(segment_meets_polygon([0.0, 1.5], [3.0, 1.5], &sq));
        assert!(segment_meets_polygon([0.0, 0.0], [3.0, 3.0], &sq)); // vertex to vertex
        assert!(!segment_meets_polygon([0.0, 1.0], [3.0, 1.0], &sq)); // along an edge
        assert!(!segment_meets_polygon([0.0, 2.0], [3.0, 2.0], &sq)); // along the other one
        assert!(!segment_meets_polygon([0.0, 2.0], [1.0, 3.0], &sq)); // touches a vertex
        assert!(!segment_meets_polygon([0.0, 0.0], [0.5, 3.0], &sq));
        assert!(point_in_polygon([1.5, 1.5], &sq) && !point_in_polygon([2.5, 1.5], &sq));
        assert_eq!(grid_node_on_segment([0.0, 0.5], [3.0, 0.5], 4, 4), None);
        assert_eq!(
            grid_node_on_segment([0.0, 0.5], [3.0, 2.0], 4, 4),
            Some((1, 1))
        );
    }
}
