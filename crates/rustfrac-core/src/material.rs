//! Linear isotropic elasticity in 2D: plane strain or plane stress, with thickness (eq. 14).

use crate::error::{check_positive, Error, Result};

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

impl Elastic {
    /// Validated constructor.
    pub fn new(e: f64, nu: f64, plane: Plane, thickness: f64) -> Result<Self> {
        check_positive("E", e)?;
        if !(nu.is_finite() && nu > -1.0 && nu < 0.5) {
            return Err(Error::invalid("nu", "-1 < nu < 0.5", nu));
        }
        check_positive("thickness", thickness)?;
        Ok(Self {
            e,
            nu,
            plane,
            thickness,
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
    }
}
