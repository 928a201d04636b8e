//! The direction rule of XFEM growth (scene key `xfem.kink_rule`): the maximum circumferential
//! stress criterion at the current tip, or a predictor-corrector ([`crate::xfem::kink`] applies
//! it).

use super::schema::KINK_RULES;
use crate::error::{Error, Result};

/// How the growth loop chooses the direction of an extension (scene key `xfem.kink_rule`; see
/// [`crate::xfem::kink`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum KinkRule {
    /// the maximum circumferential stress criterion at the current tip
    #[default]
    Hoop,
    /// a trial extension, the criterion at the trial tip, and the bisector
    PredictorCorrector,
}

impl KinkRule {
    /// The scene name (one of [`KINK_RULES`]).
    pub fn name(&self) -> &'static str {
        match self {
            KinkRule::Hoop => KINK_RULES[0],
            KinkRule::PredictorCorrector => KINK_RULES[1],
        }
    }

    /// The rule of a scene name, or an error naming `xfem.kink_rule`.
    pub fn from_name(s: &str) -> Result<Self> {
        match s {
            _ if s == KINK_RULES[0] => Ok(KinkRule::Hoop),
            _ if s == KINK_RULES[1] => Ok(KinkRule::PredictorCorrector),
            _ => Err(Error::invalid(
                "xfem.kink_rule",
                &super::schema::choice(&KINK_RULES),
                format!("{s:?}"),
            )),
        }
    }

    /// Linear solves per growth step (the critical state, plus the trial of the corrector).
    pub fn solves_per_step(&self) -> usize {
        match self {
            KinkRule::Hoop => 1,
            KinkRule::PredictorCorrector => 2,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_and_bad_names_name_the_key() {
        for r in [KinkRule::Hoop, KinkRule::PredictorCorrector] {
            assert_eq!(KinkRule::from_name(r.name()).unwrap(), r);
        }
        assert_eq!(KinkRule::default(), KinkRule::Hoop);
        let e = KinkRule::from_name("bisector").unwrap_err();
        assert!(e.to_string().contains("xfem.kink_rule"), "{e}");
    }
}
