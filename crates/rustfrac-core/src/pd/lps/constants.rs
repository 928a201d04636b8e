//! The LPS constants (docs/design.md, "The linear peridynamic solid"): the 2D moduli, the
//! critical stretch calibrated on G0, and the splice model's [`PdConstants`].

use super::influence::lattice_factor;
use crate::error::{check_positive, Result};
use crate::pd::PdConstants;
use crate::problem::schema::check_horizon_factor;
use crate::problem::{Elastic, Influence, Plane};
use std::f64::consts::PI;

/// The constants of an LPS model.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LpsConstants {
    pub influence: Influence,
    pub m: usize,
    pub dx: f64,
    /// horizon delta = m dx
    pub delta: f64,
    /// the 2D bulk modulus kappa' (plane strain lambda + mu, plane stress E / (2 (1 - nu)))
    pub kappa: f64,
    /// the shear modulus mu = E / (2 (1 + nu))
    pub mu: f64,
    /// the lattice's fourth-moment factor ([`super::influence::lattice_factor`])
    pub c4: f64,
    /// the critical stretch s_c = sqrt(G0 m_A / (8 mu I)) ([`critical_stretch`])
    pub s_c: f64,
    /// node volume dx^2 h
    pub volume: f64,
}

/// The continuum integrals of the influence function over the horizon disc: the weighted area
/// m_A = int omega |xi|^2 dA and the crossing moment I = int_{xi2 > 0} xi2 omega |xi|^2 dA
/// (constant: pi delta^4 / 2 and 2 delta^5 / 5; conical: pi delta^4 / 10 and delta^5 / 15).
pub fn moments(influence: Influence, delta: f64) -> (f64, f64) {
    match influence {
        Influence::Constant => (PI * delta.powi(4) / 2.0, 2.0 * delta.powi(5) / 5.0),
        Influence::Conical => (PI * delta.powi(4) / 10.0, delta.powi(5) / 15.0),
    }
}

/// The critical stretch s_c = sqrt(G0 m_A / (8 mu I)): the pairwise energy (8 mu / m) omega
/// |xi|^2 s^2 of the bonds crossing a unit length of a straight crack, at s = s_c, is G0
/// (the derivation: docs/design.md, "The linear peridynamic solid").
pub fn critical_stretch(influence: Influence, mu: f64, g0: f64, delta: f64) -> f64 {
    let (m_a, i) = moments(influence, delta);
    (g0 * m_a / (8.0 * mu * i)).sqrt()
}

impl LpsConstants {
    /// Validates the inputs and computes the moduli, c_4 and s_c.
    pub fn new(mat: &Elastic, g0: f64, dx: f64, m: usize, influence: Influence) -> Result<Self> {
        mat.validate()?;
        check_positive("G0", g0)?;
        check_positive("dx", dx)?;
        check_horizon_factor(m)?;
        let (e, nu) = (mat.e, mat.nu);
        let mu = e / (2.0 * (1.0 + nu));
        let kappa = match mat.plane {
            Plane::Strain => e / (2.0 * (1.0 + nu) * (1.0 - 2.0 * nu)),
            Plane::Stress => e / (2.0 * (1.0 - nu)),
        };
        let delta = m as f64 * dx;
        Ok(Self {
            influence,
            m,
            dx,
            delta,
            kappa,
            mu,
            c4: lattice_factor(influence, m)?,
            s_c: critical_stretch(influence, mu, g0, delta),
            volume: dx * dx * mat.thickness,
        })
    }

    /// The [`PdConstants`] the splice model carries: s0 = s_c (both engines' critical stretch),
    /// gamma = 1 (the LPS needs none: m_i is the discrete sum) and c the pairwise stiffness
    /// 16 mu / m_A of a full bond per unit length (the grounding springs' scale).
    pub fn pd_constants(&self) -> PdConstants {
        let (m_a, _) = moments(self.influence, self.delta);
        let h = self.volume / (self.dx * self.dx);
        PdConstants {
            dx: self.dx,
            m: self.m,
            delta: self.delta,
            gamma: 1.0,
            c: 16.0 * self.mu * self.dx / (m_a * h),
            s0: self.s_c,
            volume: self.volume,
        }
    }
}
