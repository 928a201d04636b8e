//! Stress intensity factors (paper section 2.1.3, eqs. 27-33 and 36): the Williams auxiliary
//! fields, the domain form of the interaction integral (I-integral) and of the J-integral, and the
//! maximum circumferential stress criterion (Erdogan and Sih) used for crack growth.
//!
//! Everything here works in the crack-tip frame (x~1 along the crack, pointing ahead of the tip,
//! x~2 normal to it). The XFEM model ([`crate::xfem`]) supplies, at each quadrature point of the
//! integration domain, the tip-frame position, the tip-frame displacement gradient of the computed
//! field and the tip-frame gradient of the weight function q (eq. 29); [`DomainIntegral`]
//! accumulates
//!
//! I = sum w [sigma_ij u^a_i,1 + sigma^a_ij u_i,1 - sigma^a_mn eps_mn delta_1j] q,j   (eqs. 27-28)
//! J = sum w [sigma_ij u_i,1 - 1/2 sigma_mn eps_mn delta_1j] q,j                     (eq. 33)
//!
//! and returns K_I = I(K^a = (1, 0)) E'/2, K_II = I(K^a = (0, 1)) E'/2 (eq. 31, with E' = E/(1-nu^2)
//! in plane strain and E in plane stress) and J from the SIFs (eq. 32). The auxiliary strain is the
//! exact gradient of the Williams displacement (with kappa of the chosen plane condition) and the
//! auxiliary stress is D times it, so the auxiliary state is exactly compatible and in equilibrium
//! for both plane strain and plane stress.

use crate::material::Elastic;
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

/// Gradient g[i][j] = d u_i / d x_j of the Williams displacement (tip frame).
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

/// SIFs and energy release rates from one integration domain.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DomainSifs {
    /// radius of the q-function domain
    pub radius: f64,
    pub k_i: f64,
    pub k_ii: f64,
    /// J from the SIFs, eq. (32)
    pub j_from_k: f64,
    /// J from its own domain integral, eq. (33)
    pub j_domain: f64,
}

/// Accumulator of the domain integrals over quadrature points (eq. 36).
pub struct DomainIntegral {
    mat: Elastic,
    d: [[f64; 3]; 3],
    i1: f64,
    i2: f64,
    j: f64,
}

#[inline]
fn stress_tensor(d: &[[f64; 3]; 3], g: &[[f64; 2]; 2]) -> [[f64; 2]; 2] {
    let eps = [g[0][0], g[1][1], g[0][1] + g[1][0]];
    let s = crate::fem::stress(d, &eps);
    [[s[0], s[2]], [s[2], s[1]]]
}

impl DomainIntegral {
    pub fn new(mat: &Elastic) -> Self {
        Self {
            mat: *mat,
            d: mat.d_matrix(),
            i1: 0.0,
            i2: 0.0,
            j: 0.0,
        }
    }

    /// The integrands of J and of the two interaction integrals at a point, as the vectors
    /// F_j = W delta_1j - sigma_ij u_i,1 (J, eq. 33) and
    /// F_j = W^int delta_1j - sigma_ij u^a_i,1 - sigma^a_ij u_i,1 (I with K^a = (1, 0) and
    /// (0, 1), eqs. 27-28), W^int = sigma^a_mn eps_mn, all in the tip frame.
    fn fluxes(&self, x: [f64; 2], g: &[[f64; 2]; 2]) -> [[f64; 2]; 3] {
        let s = stress_tensor(&self.d, g);
        let w_real = 0.5 * (s[0][0] * g[0][0] + s[1][1] * g[1][1] + s[0][1] * (g[0][1] + g[1][0]));
        let mut f = [[0.0; 2]; 3];
        for j in 0..2 {
            f[0][j] = -(s[0][j] * g[0][0] + s[1][j] * g[1][0]);
        }
        f[0][0] += w_real;
        for (mode, fm) in f[1..].iter_mut().enumerate() {
            let (k1, k2) = if mode == 0 { (1.0, 0.0) } else { (0.0, 1.0) };
            let ga = williams_gradient(&self.mat, k1, k2, x);
            let sa = stress_tensor(&self.d, &ga);
            // mixed energy sigma^a : eps (= sigma : eps^a)
            let w_int = sa[0][0] * g[0][0] + sa[1][1] * g[1][1] + sa[0][1] * (g[0][1] + g[1][0]);
            for j in 0..2 {
                fm[j] = -(s[0][j] * ga[0][0]
                    + s[1][j] * ga[1][0]
                    + sa[0][j] * g[0][0]
                    + sa[1][j] * g[1][0]);
            }
            fm[0] += w_int;
        }
        f
    }

    fn accumulate(&mut self, f: &[[f64; 2]; 3], v: [f64; 2], w: f64) {
        for (acc, fm) in [&mut self.j, &mut self.i1, &mut self.i2].into_iter().zip(f) {
            *acc += w * (fm[0] * v[0] + fm[1] * v[1]);
        }
    }

    /// Adds one area quadrature point: tip-frame position `x`, tip-frame displacement gradient
    /// `g[i][j] = du_i/dx_j`, tip-frame gradient of q, and weight `w` (Gauss weight x det J):
    /// the domain term -F_j q,j of eq. (36).
    pub fn add(&mut self, x: [f64; 2], g: &[[f64; 2]; 2], gq: [f64; 2], w: f64) {
        if gq[0] == 0.0 && gq[1] == 0.0 {
            return;
        }
        let f = self.fluxes(x, g);
        self.accumulate(&f, gq, -w);
    }

    /// Adds one point of the plate boundary inside the q-domain (the domain clipped by the
    /// boundary): the boundary term + F_j m_j q of the divergence theorem, with `m` the outward
    /// unit normal of the plate in the tip frame, `q` the weight function there and `w` the line
    /// quadrature weight. The domain form of eq. (36) assumes q = 0 on the plate boundary; where
    /// the domain reaches it, J = -int_A F_j q,j dA + int_B F_j m_j q ds (the crack faces add
    /// nothing: both fields are traction-free there and m_1 = 0).
    pub fn add_boundary(&mut self, x: [f64; 2], g: &[[f64; 2]; 2], m: [f64; 2], q: f64, w: f64) {
        if q == 0.0 {
            return;
        }
        let f = self.fluxes(x, g);
        self.accumulate(&f, m, w * q);
    }

    /// K_I, K_II (eq. 31), J from K (eq. 32) and the domain J (eq. 33).
    pub fn finish(&self, radius: f64) -> DomainSifs {
        let ep = self.mat.e_prime();
        let k_i = 0.5 * ep * self.i1;
        let k_ii = 0.5 * ep * self.i2;
        DomainSifs {
            radius,
            k_i,
            k_ii,
            j_from_k: (k_i * k_i + k_ii * k_ii) / ep,
            j_domain: self.j,
        }
    }
}

/// Kink angle of the maximum circumferential stress criterion (Erdogan and Sih), in the tip frame:
/// theta_c = 2 atan[(K_I - sqrt(K_I^2 + 8 K_II^2)) / (4 K_II)], written in the cancellation-free
/// form 2 atan[-2 K_II / (K_I + sqrt(K_I^2 + 8 K_II^2))]; 0 when K_II = 0. A positive K_II turns
/// the crack clockwise (negative angle).
pub fn kink_angle(k_i: f64, k_ii: f64) -> f64 {
    if k_ii == 0.0 {
        return 0.0;
    }
    // K_II != 0 makes the root exceed |K_I|, so the denominator is positive
    let s = (k_i * k_i + 8.0 * k_ii * k_ii).sqrt();
    2.0 * (-2.0 * k_ii / (k_i + s)).atan()
}

/// Equivalent mode I SIF in the kink direction:
/// K_eq = cos(theta/2) [K_I cos^2(theta/2) - 3/2 K_II sin(theta)].
pub fn k_equivalent(k_i: f64, k_ii: f64) -> f64 {
    let t = kink_angle(k_i, k_ii);
    let c = (0.5 * t).cos();
    c * (k_i * c * c - 1.5 * k_ii * t.sin())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::Plane;

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

    #[test]
    fn criterion_limits() {
        assert_eq!(kink_angle(1.0, 0.0), 0.0);
        assert!((k_equivalent(2.0, 0.0) - 2.0).abs() < 1e-15);
        // pure mode II: theta = -2 atan(1/sqrt 2) = -70.53 deg
        let t = kink_angle(0.0, 1.0);
        assert!(
            (t.to_degrees() + 70.528_779).abs() < 1e-5,
            "{}",
            t.to_degrees()
        );
        // K_IIc = (sqrt 3 / 2) K_Ic
        assert!((k_equivalent(0.0, 1.0) - 2.0 / 3f64.sqrt()).abs() < 1e-12);
        assert!(kink_angle(1.0, -0.3) > 0.0);
    }
}
