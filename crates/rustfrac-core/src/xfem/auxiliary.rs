//! The auxiliary fields of the interaction integral (the auxiliary state of eqs. 27-28): the
//! Williams near-tip displacement for given K_I, K_II and its exact gradient, in the crack-tip
//! frame (x~1 along the crack, pointing ahead of the tip, x~2 normal to it), with kappa of the
//! chosen plane condition. The auxiliary strain is this exact gradient and the auxiliary stress D
//! times it ([`crate::xfem::interaction_integral`]), so the auxiliary state is exactly compatible
//! and in equilibrium for both plane strain and plane stress.

use crate::problem::Elastic;
use std::f64::consts::PI;

/// Williams near-tip displacement (tip frame) for given K_I, K_II at tip-frame position `x`.
pub fn williams_displacement(mat: &Elastic, k1: f64, k2: f64, x: [f64; 2]) -> [f64; 2] {
    let (r, t) = polar(x);
    let kap = mat.kappa();
    let a = (r / (2.0 * PI)).sqrt() / (2.0 * mat.mu());
    let (s2, c2) = (0.5 * t).sin_cos();
    let ct = t.cos();
    [
        a * (k1 * c2 * (kap - ct) + k2 * s2 * (kap + 2.0 + ct)),
        a * (k1 * s2 * (kap - ct) - k2 * c2 * (kap - 2.0 + ct)),
    ]
}

/// Gradient `g[i][j]` = d u_i / d x_j of the Williams displacement (tip frame).
pub fn williams_gradient(mat: &Elastic, k1: f64, k2: f64, x: [f64; 2]) -> [[f64; 2]; 2] {
    let (r, t) = polar(x);
    let kap = mat.kappa();
    let a = (r / (2.0 * PI)).sqrt() / (2.0 * mat.mu());
    let (s2, c2) = (0.5 * t).sin_cos();
    let (st, ct) = t.sin_cos();
    // angular parts f(theta) and their derivatives
    let f1 = k1 * c2 * (kap - ct) + k2 * s2 * (kap + 2.0 + ct);
    let df1 =
        k1 * (-0.5 * s2 * (kap - ct) + c2 * st) + k2 * (0.5 * c2 * (kap + 2.0 + ct) - s2 * st);
    let f2 = k1 * s2 * (kap - ct) - k2 * c2 * (kap - 2.0 + ct);
    let df2 =
        k1 * (0.5 * c2 * (kap - ct) + s2 * st) - k2 * (-0.5 * s2 * (kap - 2.0 + ct) - c2 * st);
    let mut g = [[0.0; 2]; 2];
    for (i, (f, df)) in [(f1, df1), (f2, df2)].into_iter().enumerate() {
        // u = a f(theta) with a ~ sqrt(r): du/dr = u / (2 r), du/dtheta = a f'
        let dur = a * f / (2.0 * r);
        let dut = a * df;
        g[i][0] = dur * ct - dut * st / r;
        g[i][1] = dur * st + dut * ct / r;
    }
    g
}

fn polar(x: [f64; 2]) -> (f64, f64) {
    ((x[0] * x[0] + x[1] * x[1]).sqrt(), x[1].atan2(x[0]))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::problem::Plane;

    #[test]
    fn williams_gradient_matches_finite_differences() {
        for plane in [Plane::Strain, Plane::Stress] {
            let m = Elastic::new(200.0, 0.3, plane, 1.0).unwrap();
            for &x in &[[0.3, 0.2], [-0.2, 0.05], [-0.1, -0.4], [0.01, -0.02]] {
                let g = williams_gradient(&m, 1.3, -0.7, x);
                let h = 1e-7;
                for j in 0..2 {
                    let mut xp = x;
                    let mut xm = x;
                    xp[j] += h;
                    xm[j] -= h;
                    let up = williams_displacement(&m, 1.3, -0.7, xp);
                    let um = williams_displacement(&m, 1.3, -0.7, xm);
                    for i in 0..2 {
                        let fd = (up[i] - um[i]) / (2.0 * h);
                        assert!(
                            (fd - g[i][j]).abs() < 1e-5 * (1.0 + fd.abs()),
                            "{fd} {}",
                            g[i][j]
                        );
                    }
                }
            }
        }
    }
}
