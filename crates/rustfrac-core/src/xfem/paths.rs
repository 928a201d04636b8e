//! Comparing grown crack paths (the path-convergence study of `xfem.kink_rule` and its tests):
//! the turning angle at each vertex of a path, and the deviation of two paths from a common
//! start over their common grown length.
//!
//! Deviation: sample each path's grown part (beyond vertex `from`) at `n` equal arc-length steps
//! over the common length L = min(grown length of a, of b) and take every sample's distance to
//! the other path's grown part (the whole of it); the mean is that of all 2 (n + 1) distances,
//! the max is the discrete Hausdorff distance of the two parts restricted to the first L of
//! each.

use crate::geometry::{norm, point_segment_distance, sub};

/// Distances between two grown paths ([`path_deviation`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PathDeviation {
    /// mean distance of the samples to the other path
    pub mean: f64,
    /// largest distance of a sample to the other path (discrete Hausdorff distance)
    pub max: f64,
    /// the common grown length L over which the paths were compared
    pub length: f64,
}

/// Length of the polyline `p`.
pub fn path_length(p: &[[f64; 2]]) -> f64 {
    p.windows(2).map(|w| norm(sub(w[1], w[0]))).sum()
}

/// The point at arc length `s` along `p` (clamped to its ends).
pub fn point_at(p: &[[f64; 2]], s: f64) -> [f64; 2] {
    let mut left = s.max(0.0);
    for w in p.windows(2) {
        let l = norm(sub(w[1], w[0]));
        if left <= l && l > 0.0 {
            let t = left / l;
            return [
                w[0][0] + t * (w[1][0] - w[0][0]),
                w[0][1] + t * (w[1][1] - w[0][1]),
            ];
        }
        left -= l;
    }
    p[p.len() - 1]
}

/// Counter-clockwise turning angle (radians, in (-pi, pi]) at every vertex v of `p` with
/// `first <= v < p.len() - 1` (v >= 1): the angle from segment (v - 1, v) to segment (v, v + 1).
/// For a crack grown from a straight initial crack of vertices 0, 1 (tip), `first = 1` gives the
/// kink at the initial tip, then the kink of every growth step.
pub fn turning_angles(p: &[[f64; 2]], first: usize) -> Vec<f64> {
    (first.max(1)..p.len().saturating_sub(1))
        .map(|v| {
            let (a, b) = (sub(p[v], p[v - 1]), sub(p[v + 1], p[v]));
            (a[0] * b[1] - a[1] * b[0]).atan2(a[0] * b[0] + a[1] * b[1])
        })
        .collect()
}

/// Smallest distance from `x` to the polyline `p` (a single point: the distance to it).
fn distance_to(p: &[[f64; 2]], x: [f64; 2]) -> f64 {
    if p.len() == 1 {
        return norm(sub(x, p[0]));
    }
    p.windows(2)
        .map(|w| point_segment_distance(x, w[0], w[1]))
        .fold(f64::INFINITY, f64::min)
}

/// The deviation of the grown parts (from vertex `from` on) of the paths `a` and `b` over their
/// common grown length, `n` >= 1 steps each (see the module documentation). Both paths must
/// have more than `from` vertices.
pub fn path_deviation(a: &[[f64; 2]], b: &[[f64; 2]], from: usize, n: usize) -> PathDeviation {
    let (ga, gb) = (&a[from..], &b[from..]);
    let length = path_length(ga).min(path_length(gb));
    let n = n.max(1);
    let (mut sum, mut max, mut count) = (0.0, 0.0f64, 0usize);
    for (p, q) in [(ga, gb), (gb, ga)] {
        for k in 0..=n {
            let d = distance_to(q, point_at(p, length * k as f64 / n as f64));
            sum += d;
            max = max.max(d);
            count += 1;
        }
    }
    PathDeviation {
        mean: sum / count as f64,
        max,
        length,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parallel_paths_are_their_offset_apart() {
        let a = [[0.0, 0.0], [1.0, 0.0], [3.0, 0.0]];
        let b = [[0.0, 0.0], [1.0, 0.0], [2.0, 0.5], [3.0, 0.5]];
        let d = path_deviation(&a, &a, 1, 10);
        assert_eq!((d.mean, d.max), (0.0, 0.0));
        let d = path_deviation(&a, &b, 1, 100);
        // b leaves a at 26.6 degrees and runs 0.5 above it; common length 2
        assert!((d.length - 2.0).abs() < 1e-15);
        assert!((d.max - 0.5).abs() < 1e-12, "{d:?}");
        assert!(d.mean > 0.1 && d.mean < 0.5, "{d:?}");
    }

    #[test]
    fn turning_angles_of_a_zig_zag() {
        let p = [[0.0, 0.0], [1.0, 0.0], [2.0, 1.0], [3.0, 1.0]];
        let t = turning_angles(&p, 1);
        assert_eq!(t.len(), 2);
        assert!((t[0] - std::f64::consts::FRAC_PI_4).abs() < 1e-15);
        assert!((t[1] + std::f64::consts::FRAC_PI_4).abs() < 1e-15);
        assert_eq!(point_at(&p, 1.0), [1.0, 0.0]);
        assert_eq!(point_at(&p, 10.0), [3.0, 1.0]);
    }
}
