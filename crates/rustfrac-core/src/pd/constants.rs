//! The constants of the bond-based plane model (paper section 2.2.1, eqs. 46-48, 55-57).
//!
//! * gamma: the correction factor of the discretisation (Ongaro et al. 2021), the ratio of the
//!   continuum integral to its sum over the grid stencil ([`gamma`]); independent of dx.
//! * micromodulus c (eq. 47) and critical stretch s0 (eq. 48), [`PdConstants`].
//! * linearised bond stiffness (eqs. 46, 55, 56), [`PdConstants::bond_alpha`].
//! * which materials bond-based PD represents: plane strain with nu = 1/4 ([`check_material`]).

use super::bonds::Bond;
use super::partial_volume::family_stencil;
use crate::error::{check_positive, Error, Result};
use crate::problem::schema::check_horizon_factor;
use crate::problem::{Elastic, Plane};
use std::f64::consts::PI;

/// gamma = [integral over the disc of xi1^4/|xi|^3 dA] / [sum_j xi1^4/|xi|^3 beta_j dx^2]
/// (Ongaro et al. 2021; docs/design.md, "The bond-based PD model and gamma"), computed on the
/// grid stencil of horizon m dx. It is independent of dx. The continuum integral is pi delta^3 / 4.
pub fn gamma(m: usize) -> Result<f64> {
    check_horizon_factor(m)?;
    let st = family_stencil(m);
    let mut sum = 0.0;
    for e in &st {
        let (a, b) = (e.di as f64, e.dj as f64);
        let r = (a * a + b * b).sqrt();
        sum += a.powi(4) / r.powi(3) * e.beta;
    }
    let md = m as f64;
    Ok(PI * md.powi(3) / 4.0 / sum)
}

/// The PD constants of a bond-based plane model.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PdConstants {
    pub dx: f64,
    pub m: usize,
    /// horizon delta = m dx (eq. 57)
    pub delta: f64,
    /// correction factor from the discretisation
    pub gamma: f64,
    /// micromodulus c = 48 E gamma / (5 pi h delta^3) (eq. 47)
    pub c: f64,
    /// critical stretch s0 = sqrt(5 pi G0 / (12 E delta)) (eq. 48)
    pub s0: f64,
    /// node volume dx^2 h
    pub volume: f64,
}

/// Checks that bond-based PD can represent the material: plane strain needs nu = 1/4 (plane stress
/// would need 1/3, whose constants eqs. 47-48 do not cover: refused too).
pub fn check_material(mat: &Elastic) -> Result<()> {
    mat.validate()?;
    match mat.plane {
        Plane::Strain => {
            if (mat.nu - 0.25).abs() > 1e-12 {
                return Err(Error::invalid(
                    "nu",
                    "nu = 0.25: bond-based (pairwise) peridynamics in plane strain has a fixed \
                     Poisson's ratio of 1/4 (paper section 2.2.1); use XFEM/FEM for other values",
                    mat.nu,
                ));
            }
            Ok(())
        }
        Plane::Stress => Err(Error::invalid(
            "plane",
            "plane strain: bond-based PD in plane stress fixes nu = 1/3 and needs different \
             constants than eqs. 47-48, which are implemented for plane strain only",
            "stress",
        )),
    }
}

impl PdConstants {
    /// Validates the inputs and computes gamma, c, s0.
    pub fn new(mat: &Elastic, g0: f64, dx: f64, m: usize) -> Result<Self> {
        check_material(mat)?;
        check_positive("G0", g0)?;
        check_positive("dx", dx)?;
        check_horizon_factor(m)?;
        let delta = m as f64 * dx;
        let gamma = gamma(m)?;
        let h = mat.thickness;
        let c = 48.0 * mat.e * gamma / (5.0 * PI * h * delta.powi(3));
        let s0 = (5.0 * PI * g0 / (12.0 * mat.e * delta)).sqrt();
        Ok(Self {
            dx,
            m,
            delta,
            gamma,
            c,
            s0,
            volume: dx * dx * h,
        })
    }

    /// Linearised bond stiffness (eqs. 46, 55, 56) with both node volumes (rows scaled by the
    /// node volume: docs/design.md, "The bond-based PD model and gamma"): the force on node i is
    /// alpha n n^T (u_j - u_i) with alpha = c beta V_i V_j / |xi| and n = xi / |xi|. Returns alpha.
    pub fn bond_alpha(&self, bond: &Bond) -> f64 {
        let l = (bond.xi[0] * bond.xi[0] + bond.xi[1] * bond.xi[1]).sqrt();
        self.c * bond.beta * self.volume * self.volume / l
    }
}
