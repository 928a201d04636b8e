//! The LPS influence function and the quadrature weight of a bond (see docs/design.md,
//! "The linear peridynamic solid").
//!
//! A bond with grid offset d = xi / dx has the weight w = omega(|xi|) beta q(d): the influence
//! function, the exact partial volume of its cell ([`crate::pd::partial_volume`]) and the
//! lattice's fourth-moment correction q = 1 + c_4 cos 4 phi (phi the bond's angle). The square
//! lattice's stencil has isotropic second moments by symmetry but not fourth moments
//! (sum w |xi|^2 n1^4 != 3 sum w |xi|^2 n1^2 n2^2: 0.9 % off at m = 4, constant omega), which
//! makes the bulk's deviatoric response cubic rather than isotropic; c_4 ([`lattice_factor`])
//! restores the isotropy of the bulk stencil exactly, so that a uniform strain gives the
//! continuum stress in the bulk to round-off (the patch test). cos 4 phi has the lattice's
//! symmetry, so the second moments stay isotropic.

use crate::error::{Error, Result};
use crate::pd::family_stencil;
use crate::problem::Influence;

/// omega(r / delta): 1 (constant) or 1 - r / delta (conical; 0 beyond delta, for the cells
/// that overlap the disc with their centre outside it).
pub fn omega(influence: Influence, r_over_delta: f64) -> f64 {
    match influence {
        Influence::Constant => 1.0,
        Influence::Conical => (1.0 - r_over_delta).max(0.0),
    }
}

/// cos 4 phi of the grid offset (a, b): (a^4 - 6 a^2 b^2 + b^4) / (a^2 + b^2)^2.
pub fn cos4(a: f64, b: f64) -> f64 {
    let r2 = a * a + b * b;
    (a.powi(4) - 6.0 * a * a * b * b + b.powi(4)) / (r2 * r2)
}

/// The lattice's fourth-moment factor c_4 of the bulk stencil of horizon m: with
/// w0 = omega beta |d|^2 and C = cos 4 phi, the fourth moments of w0 (1 + c_4 C) are isotropic
/// iff sum w0 (1 + c_4 C) C = 0 (n1^4 - 3 n1^2 n2^2 averages over the lattice's symmetry to
/// C / 2), so c_4 = - sum w0 C / sum w0 C^2. Refused when the stencil has no weight (conical
/// omega at m = 1: every cell's centre at |d| >= m) or a weight would not be positive.
pub fn lattice_factor(influence: Influence, m: usize) -> Result<f64> {
    let (mut s1, mut s2) = (0.0, 0.0);
    let st = family_stencil(m);
    for e in &st {
        let (a, b) = (e.di as f64, e.dj as f64);
        let r2 = a * a + b * b;
        let w0 = omega(influence, r2.sqrt() / m as f64) * e.beta * r2;
        let c = cos4(a, b);
        s1 += w0 * c;
        s2 += w0 * c * c;
    }
    let c4 = if s2 > 0.0 { -s1 / s2 } else { f64::NAN };
    if !(c4.is_finite() && c4.abs() < 1.0) {
        return Err(Error::invalid(
            "pd.influence",
            "an influence function with weight on the horizon's stencil (conical needs m >= 2)",
            format!("'{}' with m = {m}", influence.name()),
        ));
    }
    Ok(c4)
}

/// The weight w = omega beta (1 + c_4 cos 4 phi) of a bond with grid offset (a, b) (in units of
/// dx), partial volume `beta`, horizon m.
pub fn weight(influence: Influence, c4: f64, m: usize, a: f64, b: f64, beta: f64) -> f64 {
    let r = (a * a + b * b).sqrt();
    omega(influence, r / m as f64) * beta * (1.0 + c4 * cos4(a, b))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The corrected bulk stencil's fourth moments are isotropic: sum w |d|^2 n1^4 equals
    /// 3 sum w |d|^2 n1^2 n2^2, and the second moments sum w |d|^2 n1^2 = sum w |d|^2 n2^2.
    #[test]
    fn corrected_stencil_is_isotropic() {
        for inf in [Influence::Constant, Influence::Conical] {
            for m in 2..=6 {
                let c4 = lattice_factor(inf, m).unwrap();
                let (mut m4, mut m22, mut m11, mut m2) = (0.0, 0.0, 0.0, 0.0);
                for e in family_stencil(m) {
                    let (a, b) = (e.di as f64, e.dj as f64);
                    let r2 = a * a + b * b;
                    let w = weight(inf, c4, m, a, b, e.beta) * r2;
                    let (n1, n2) = (a * a / r2, b * b / r2);
                    m4 += w * n1 * n1;
                    m22 += w * n1 * n2;
                    m11 += w * n1;
                    m2 += w * n2;
                }
                assert!((m4 - 3.0 * m22).abs() < 1e-12 * m4, "{inf:?} m {m}");
                assert!((m11 - m2).abs() < 1e-12 * m11);
            }
        }
        assert!(lattice_factor(Influence::Conical, 1).is_err());
    }
}
