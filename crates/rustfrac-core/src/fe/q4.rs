//! The Q4 element of plane elasticity (paper section 2.1.1, eqs. 4-14): bilinear shape functions
//! (eq. 6), the isoparametric map and its Jacobian (eqs. 8-11), the B^T D B element stiffness
//! (eq. 12), strains and stresses (eq. 14).
//!
//! The standard dofs of node n are 2n (u1) and 2n + 1 (u2).

use crate::fe::quadrature::QPoint;
use crate::problem::Elastic;

/// Bilinear shape functions N1..N4 at (xi, eta), eq. (6).
#[inline]
pub fn shape(xi: f64, eta: f64) -> [f64; 4] {
    [
        0.25 * (1.0 - xi) * (1.0 - eta),
        0.25 * (1.0 + xi) * (1.0 - eta),
        0.25 * (1.0 + xi) * (1.0 + eta),
        0.25 * (1.0 - xi) * (1.0 + eta),
    ]
}

/// Derivatives of the shape functions w.r.t. (xi, eta): [dN/dxi, dN/deta].
#[inline]
pub fn dshape(xi: f64, eta: f64) -> [[f64; 4]; 2] {
    [
        [
            -0.25 * (1.0 - eta),
            0.25 * (1.0 - eta),
            0.25 * (1.0 + eta),
            -0.25 * (1.0 + eta),
        ],
        [
            -0.25 * (1.0 - xi),
            -0.25 * (1.0 + xi),
            0.25 * (1.0 + xi),
            0.25 * (1.0 - xi),
        ],
    ]
}

/// Physical position, global shape-function gradients [dN/dx1, dN/dx2] and det J at (xi, eta)
/// (eqs. 8-11).
#[inline]
pub fn geometry(xy: &[[f64; 2]; 4], xi: f64, eta: f64) -> ([f64; 2], [[f64; 4]; 2], f64) {
    let n = shape(xi, eta);
    let dn = dshape(xi, eta);
    let mut x = [0.0; 2];
    let mut j = [[0.0; 2]; 2]; // j[a][b] = d x_b / d xi_a
    for k in 0..4 {
        x[0] += n[k] * xy[k][0];
        x[1] += n[k] * xy[k][1];
        for a in 0..2 {
            j[a][0] += dn[a][k] * xy[k][0];
            j[a][1] += dn[a][k] * xy[k][1];
        }
    }
    let det = j[0][0] * j[1][1] - j[0][1] * j[1][0];
    let inv = [
        [j[1][1] / det, -j[0][1] / det],
        [-j[1][0] / det, j[0][0] / det],
    ];
    let mut g = [[0.0; 4]; 2];
    for k in 0..4 {
        g[0][k] = inv[0][0] * dn[0][k] + inv[0][1] * dn[1][k];
        g[1][k] = inv[1][0] * dn[0][k] + inv[1][1] * dn[1][k];
    }
    (x, g, det)
}

/// Adds w * B_a^T D B_b to `k` (row-major na x nb) where the columns of B are given as
/// (d/dx1, d/dx2) pairs of scalar basis functions, one pair per scalar function; each scalar
/// function carries two dofs (u1, u2). Used for standard and enriched blocks alike (eq. 26).
#[inline]
pub fn add_btdb(k: &mut [f64], grads: &[[f64; 2]], d: &[[f64; 3]; 3], w: f64) {
    let nf = grads.len();
    let nd = 2 * nf;
    for (a, ga) in grads.iter().enumerate() {
        // B columns of function a: (ga0, 0, ga1) for u1 and (0, ga1, ga0) for u2
        // D * B_col
        let db1 = [
            d[0][0] * ga[0] + d[0][2] * ga[1],
            d[1][0] * ga[0] + d[1][2] * ga[1],
            d[2][0] * ga[0] + d[2][2] * ga[1],
        ];
        let db2 = [
            d[0][1] * ga[1] + d[0][2] * ga[0],
            d[1][1] * ga[1] + d[1][2] * ga[0],
            d[2][1] * ga[1] + d[2][2] * ga[0],
        ];
        for (b, gb) in grads.iter().enumerate() {
            // B_b^T (D B_a)
            let r1 = [gb[0], 0.0, gb[1]];
            let r2 = [0.0, gb[1], gb[0]];
            let dot = |r: &[f64; 3], c: &[f64; 3]| r[0] * c[0] + r[1] * c[1] + r[2] * c[2];
            k[(2 * b) * nd + 2 * a] += w * dot(&r1, &db1);
            k[(2 * b) * nd + 2 * a + 1] += w * dot(&r1, &db2);
            k[(2 * b + 1) * nd + 2 * a] += w * dot(&r2, &db1);
            k[(2 * b + 1) * nd + 2 * a + 1] += w * dot(&r2, &db2);
        }
    }
}

/// Stiffness of one Q4 element (eq. 12), row-major 8 x 8, integrated with `rule`.
/// For rectangles the 2 x 2 Gauss rule is exact.
pub fn element_stiffness(xy: &[[f64; 2]; 4], mat: &Elastic, rule: &[QPoint], out: &mut Vec<f64>) {
    out.clear();
    out.resize(64, 0.0);
    let d = mat.d_matrix();
    for q in rule {
        let (_, g, det) = geometry(xy, q.xi, q.eta);
        let grads: [[f64; 2]; 4] = std::array::from_fn(|k| [g[0][k], g[1][k]]);
        add_btdb(out, &grads, &d, q.w * det * mat.thickness);
    }
}

/// Strain (xx, yy, 2xy) from global gradients and element displacements (u1, u2 per node).
#[inline]
pub fn strain(g: &[[f64; 4]; 2], ue: &[f64; 8]) -> [f64; 3] {
    let mut e = [0.0; 3];
    for k in 0..4 {
        e[0] += g[0][k] * ue[2 * k];
        e[1] += g[1][k] * ue[2 * k + 1];
        e[2] += g[1][k] * ue[2 * k] + g[0][k] * ue[2 * k + 1];
    }
    e
}

/// sigma = D eps.
#[inline]
pub fn stress(d: &[[f64; 3]; 3], eps: &[f64; 3]) -> [f64; 3] {
    std::array::from_fn(|i| d[i][0] * eps[0] + d[i][1] * eps[1] + d[i][2] * eps[2])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fe::quadrature::subquad_rule;
    use crate::problem::Plane;

    #[test]
    fn rectangle_stiffness_2x2_is_exact() {
        let m = Elastic::new(200.0, 0.3, Plane::Strain, 2.0).unwrap();
        let xy = [[0.0, 0.0], [2.0, 0.0], [2.0, 0.5], [0.0, 0.5]];
        let (mut a, mut b) = (Vec::new(), Vec::new());
        element_stiffness(&xy, &m, &subquad_rule(1, 2), &mut a);
        element_stiffness(&xy, &m, &subquad_rule(1, 5), &mut b);
        for (x, y) in a.iter().zip(&b) {
            assert!((x - y).abs() < 1e-12 * 200.0);
        }
        // rigid translation has zero force, and K is symmetric
        for i in 0..8 {
            let fx: f64 = (0..4).map(|k| a[i * 8 + 2 * k]).sum();
            assert!(fx.abs() < 1e-10);
            for j in 0..8 {
                assert!((a[i * 8 + j] - a[j * 8 + i]).abs() < 1e-12);
            }
        }
    }
}
