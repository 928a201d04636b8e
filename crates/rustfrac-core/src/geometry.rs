//! Plane geometry shared by the models: points, segments and their distances.

/// Distance from the point `x` to the segment a-b.
pub fn point_segment_distance(x: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    let d = [b[0] - a[0], b[1] - a[1]];
    let t = (((x[0] - a[0]) * d[0] + (x[1] - a[1]) * d[1]) / (d[0] * d[0] + d[1] * d[1]))
        .clamp(0.0, 1.0);
    (x[0] - a[0] - t * d[0]).hypot(x[1] - a[1] - t * d[1])
}

fn cross3(o: [f64; 2], p: [f64; 2], q: [f64; 2]) -> f64 {
    (p[0] - o[0]) * (q[1] - o[1]) - (p[1] - o[1]) * (q[0] - o[0])
}

/// Smallest distance between the segments a-b and c-d (0 when they cross).
pub fn segment_distance(a: [f64; 2], b: [f64; 2], c: [f64; 2], d: [f64; 2]) -> f64 {
    if cross3(a, b, c) * cross3(a, b, d) < 0.0 && cross3(c, d, a) * cross3(c, d, b) < 0.0 {
        return 0.0;
    }
    point_segment_distance(a, c, d)
        .min(point_segment_distance(b, c, d))
        .min(point_segment_distance(c, a, b))
        .min(point_segment_distance(d, a, b))
}
