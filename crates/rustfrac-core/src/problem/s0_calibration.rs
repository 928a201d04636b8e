//! The rule of the critical stretch s0 (scene key `pd.s0_calibration`): eq. 48 (the paper's),
//! the grid stencil's fracture energy, or the SLA's release in a reference strip
//! ([`crate::pd::calibration`] computes the factors).

/// The rule of `pd.s0_calibration` (values: [`super::schema::S0_CALIBRATIONS`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum S0Calibration {
    /// eq. 48 (the paper's)
    #[default]
    Continuum,
    /// the grid stencil's discrete fracture energy equals G0
    Grid,
    /// the SLA's release in the reference strip equals G0
    Sla,
}

impl S0Calibration {
    /// From the scene key's value (None: not one of [`super::schema::S0_CALIBRATIONS`]).
    pub fn from_name(s: &str) -> Option<Self> {
        [Self::Continuum, Self::Grid, Self::Sla]
            .into_iter()
            .find(|c| c.name() == s)
    }
    /// The scene key's value.
    pub fn name(self) -> &'static str {
        match self {
            Self::Continuum => "continuum",
            Self::Grid => "grid",
            Self::Sla => "sla",
        }
    }
}

/// What a calibration did (computed by [`crate::pd::calibration`]): s0' = factor s0 with factor = sqrt(G0 / G_ref).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Calibration {
    pub rule: S0Calibration,
    /// s0' / s0 (1 for the continuum rule)
    pub factor: f64,
    /// G_ref / G0 with eq. 48's s0 (1 for the continuum rule)
    pub g_ref_over_g0: f64,
}

impl Calibration {
    /// The continuum rule's calibration: eq. 48's s0, unchanged.
    pub fn continuum() -> Self {
        Self {
            rule: S0Calibration::Continuum,
            factor: 1.0,
            g_ref_over_g0: 1.0,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip() {
        for n in super::super::schema::S0_CALIBRATIONS {
            assert_eq!(S0Calibration::from_name(n).map(|c| c.name()), Some(n));
        }
        assert_eq!(S0Calibration::from_name("exact"), None);
    }
}
