//! The PD constitutive model (scene keys `pd.model`, `pd.influence`): bond-based (the paper's)
//! or the linear peridynamic solid, and the LPS influence function ([`crate::pd::lps`]).

use super::schema::{INFLUENCES, PD_MODELS};

/// The PD model (`pd.model`, values [`PD_MODELS`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum PdModel {
    /// bond-based (pairwise) PD, eqs. 46-48 (the paper's): nu = 1/4 in plane strain
    #[default]
    Bond,
    /// the linear peridynamic solid (ordinary state-based, Silling et al. 2007), any nu
    Lps,
}

impl PdModel {
    /// From the scene key's value (one of [`PD_MODELS`]; anything else is `Bond`).
    pub fn from_name(s: &str) -> Option<Self> {
        match s {
            "bond" => Some(Self::Bond),
            "lps" => Some(Self::Lps),
            _ => None,
        }
    }
    /// The scene key's value.
    pub fn name(self) -> &'static str {
        PD_MODELS[self as usize]
    }
}

/// The LPS influence function omega(|xi|) (`pd.influence`, values [`INFLUENCES`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Influence {
    /// omega = 1
    #[default]
    Constant,
    /// omega = 1 - |xi| / delta
    Conical,
}

impl Influence {
    /// From the scene key's value (one of [`INFLUENCES`]; anything else is `Constant`).
    pub fn from_name(s: &str) -> Option<Self> {
        match s {
            "constant" => Some(Self::Constant),
            "conical" => Some(Self::Conical),
            _ => None,
        }
    }
    /// The scene key's value.
    pub fn name(self) -> &'static str {
        INFLUENCES[self as usize]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip() {
        for n in PD_MODELS {
            assert_eq!(PdModel::from_name(n).unwrap().name(), n);
        }
        for n in INFLUENCES {
            assert_eq!(Influence::from_name(n).unwrap().name(), n);
        }
    }
}
