//! Linear isotropic elasticity in 2D: plane strain or plane stress, with thickness (eq. 14).

use crate::error::{check_positive, Error, Result};
use crate::warning::{Warning, WarningKind};

/// Plane-strain or plane-stress idealisation.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Plane {
    Strain,
    Stress,
}

impl Plane {
    /// Parses "strain" | "stress".
    pub fn parse(s: &str) -> Result<Self> {
        match s {
            "strain" | "plane_strain" => Ok(Plane::Strain),
            "stress" | "plane_stress" => Ok(Plane::Stress),
            _ => Err(Error::invalid("plane", "'strain' or 'stress'", s)),
        }
    }
}

/// Isotropic linear elastic material. Units are consistent (the paper: MPa and mm).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Elastic {
    /// Young's modulus E > 0
    pub e: f64,
    /// Poisson's ratio, -1 < nu < 0.5
    pub nu: f64,
    pub plane: Plane,
    /// out-of-plane thickness h > 0
    pub thickness: f64,
}

/// Plane-strain Poisson's ratio from which [`Elastic::locking_warning`] warns. Measured on a tall
/// edge-cracked strip under traction (a/W = 0.3, 40 and 80 Q4 elements across the width, XFEM K_I
/// and CMOD against Tada, whose K does not depend on nu), the error added by volumetric locking of
/// the fully integrated Q4 over its nu = 0.3 value is, in K_I / CMOD (40 / 80 elements):
///
/// | nu     | K_I           | CMOD          |
/// |--------|---------------|---------------|
/// | 0.45   | 0.6 / 0.2 %   | 1.0 / 0.4 %   |
/// | 0.48   | 1.6 / 0.6 %   | 2.6 / 1.2 %   |
/// | 0.49   | 2.8 / 1.0 %   | 4.8 / 2.3 %   |
/// | 0.499  | 9.8 / 1.4 %   | 26 / 13 %     |
/// | 0.4999 | 20 / 4.4 %    | 63 / 45 %     |
///
/// From 0.49 on the locking error exceeds 1 % even on the finer mesh, and it grows without bound as
/// nu -> 0.5. (Uniform stress states, e.g. the uncracked plate with free grips, are exact at any nu:
/// Q4 passes the patch test; only bending and crack-tip fields lock.) Plane stress does not lock.
pub const NU_LOCKING_WARN: f64 = 0.49;

impl Elastic {
    /// Validated constructor.
    pub fn new(e: f64, nu: f64, plane: Plane, thickness: f64) -> Result<Self> {
        let m = Self {
            e,
            nu,
            plane,
            thickness,
        };
        m.validate()?;
        Ok(m)
    }

    /// Checks the fields (the struct can also be built literally): E finite > 0, -1 < nu < 0.5,
    /// thickness finite > 0.
    pub fn validate(&self) -> Result<()> {
        check_positive("E", self.e)?;
        let nu = self.nu;
        if !(nu.is_finite() && nu > -1.0 && nu < 0.5) {
            return Err(Error::invalid("nu", "-1 < nu < 0.5", nu));
        }
        check_positive("thickness", self.thickness)
    }

    /// A warning when the Q4 elements (full 2 x 2 integration) lock: plane strain with
    /// nu >= [`NU_LOCKING_WARN`]; the measured error is quoted there.
    pub fn locking_warning(&self) -> Option<Warning> {
        (self.plane == Plane::Strain && self.nu >= NU_LOCKING_WARN).then(|| {
            Warning::new(
                WarningKind::Locking,
                format!(
                "plane-strain nu = {} is nearly incompressible: the fully integrated Q4 elements \
                 lock (measured on an edge-cracked strip with 40-80 elements across: extra error \
                 of 1-3 % in K_I and 2-5 % in CMOD at nu = 0.49, 1.4-10 % and 13-26 % at 0.499, \
                 4-20 % and 45-63 % at 0.4999); refine the mesh and check convergence, or use \
                 nu < {NU_LOCKING_WARN}",
                    self.nu
                ),
            )
        })
    }

    /// Shear modulus mu = E / (2 (1 + nu)).
    pub fn mu(&self) -> f64 {
        self.e / (2.0 * (1.0 + self.nu))
    }

    /// Kolosov constant: 3 - 4 nu (plane strain), (3 - nu) / (1 + nu) (plane stress).
    pub fn kappa(&self) -> f64 {
        match self.plane {
            Plane::Strain => 3.0 - 4.0 * self.nu,
            Plane::Stress => (3.0 - self.nu) / (1.0 + self.nu),
        }
    }

    /// Effective modulus E' of eq. (50): E / (1 - nu^2) in plane strain, E in plane stress.
    pub fn e_prime(&self) -> f64 {
        match self.plane {
            Plane::Strain => self.e / (1.0 - self.nu * self.nu),
            Plane::Stress => self.e,
        }
    }

    /// Elasticity matrix D (Voigt: xx, yy, xy with engineering shear), eq. (14) for plane strain.
    pub fn d_matrix(&self) -> [[f64; 3]; 3] {
        let (e, nu) = (self.e, self.nu);
        match self.plane {
            Plane::Strain => {
                let lam = e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
                let mu = self.mu();
                [
                    [lam + 2.0 * mu, lam, 0.0],
                    [lam, lam + 2.0 * mu, 0.0],
                    [0.0, 0.0, mu],
                ]
            }
            Plane::Stress => {
                let c = e / (1.0 - nu * nu);
                [
                    [c, c * nu, 0.0],
                    [c * nu, c, 0.0],
                    [0.0, 0.0, c * (1.0 - nu) / 2.0],
                ]
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plane_strain_uniaxial_strain_modulus() {
        let m = Elastic::new(10000.0, 0.25, Plane::Strain, 1.0).unwrap();
        let d = m.d_matrix();
        // sigma_yy under eps_yy with sigma_xx = 0 (free lateral): E' = D22 - D12^2/D11
        let ep = d[1][1] - d[0][1] * d[0][1] / d[0][0];
        assert!((ep - m.e_prime()).abs() < 1e-9 * ep);
        assert!(Elastic::new(-1.0, 0.25, Plane::Strain, 1.0).is_err());
        assert!(Elastic::new(1.0, 0.5, Plane::Strain, 1.0).is_err());
        assert!(Elastic::new(1.0, f64::NAN, Plane::Strain, 1.0).is_err());
        assert!(m.locking_warning().is_none());
        let soft = Elastic::new(1.0, 0.4999, Plane::Strain, 1.0).unwrap();
        assert!(soft
            .locking_warning()
            .unwrap()
            .message
            .contains("nu = 0.4999"));
        let stress = Elastic::new(1.0, 0.4999, Plane::Stress, 1.0).unwrap();
        assert!(stress.locking_warning().is_none());
    }
}
