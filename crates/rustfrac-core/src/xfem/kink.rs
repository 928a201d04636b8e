//! The direction rule of XFEM growth (scene key `xfem.kink_rule`): in which direction a critical
//! tip advances by `da`.
//!
//! * `hoop` (the default, [`crate::problem::KinkRule::Hoop`]): the maximum circumferential
//!   stress criterion (Erdogan and Sih, [`crate::xfem::kink_angle`]) at the current tip,
//!   theta_0; one solve per step. On a curving path the SIFs of a tip one `da` past a kink are taken with a straight-
//!   crack auxiliary field over a domain (r_I = 2.5 element lengths) that contains the kink, and
//!   the path zig-zags: the 30-degree edge crack of the paper's plate under tension turns by
//!   -32.1, +7.7, -6.9, +2.7, -2.1 degrees on the 44 x 83 mesh with da = h, and the zig-zag stays
//!   under mesh refinement at fixed da / h (benches/RESULTS.md, "XFEM mixed-mode paths").
//! * `predictor_corrector` ([`crate::problem::KinkRule::PredictorCorrector`]): a trial
//!   extension by `da` at theta_0 (predictor), one more solve of the same plate with the trial cracks, the criterion's
//!   angle theta_1 at the trial tip (relative to the trial segment), and the extension at
//!   theta = theta_0 + theta_1 / 2 (corrector, [`corrected_angle`]): the new segment bisects the
//!   predicted segment and the direction the trial tip would take, the chord of a path whose
//!   tangent turns by theta_1 over the step. Two solves per step. Where the trial cannot be
//!   evaluated (the trial tip leaves the resolvable ligament, meets another crack, or its SIF
//!   domain is refused) the tip keeps theta_0, and the growth loop's own checks stop the run as
//!   with `hoop`.
//!
//! The load factor of a step (the critical state) is that of the current cracks under both
//! rules; only the extension's direction differs.
//!
//! Measured (tests/suite/xfem_paths.rs, benches/RESULTS.md): the 30-degree crack's kinks after the
//! first stay below 1.8 degrees at every h and da tried (`hoop`: up to 10.2), |K_II / K_I| at the
//! grown tips drops 2.7-5.5x (edge crack under shear: 1.6-1.8x), and both rules converge to the
//! same path (mesh h0 / 4, da = h / 2: 0.0026 apart at most, 0.04 h).

use super::criterion::kink_angle;
use super::interaction_integral::MIN_HOLE_FREE_RADIUS;
use super::model::XfemModel;

/// The corrector: the extension's angle (relative to the current tip direction) from the
/// predicted angle `theta_0` and the criterion's angle `theta_1` at the trial tip (relative to
/// the trial segment), theta_0 + theta_1 / 2.
pub fn corrected_angle(theta_0: f64, theta_1: f64) -> f64 {
    theta_0 + 0.5 * theta_1
}

/// The criterion's angle at every growing tip of the `trial` model (the cracks extended by the
/// predictor; the same global tip order as the current model) from its solve `u`, with the
/// q-radius `r_i_factor` element sizes (shrunk clear of holes as in the growth loop); None for
/// the tips that do not grow and for those whose SIF domain cannot be evaluated (another crack
/// enters it, it would have to shrink below [`MIN_HOLE_FREE_RADIUS`], or the domain is
/// refused).
pub fn trial_angles(
    trial: &XfemModel,
    u: &[f64],
    grows: &[bool],
    r_i_factor: f64,
) -> Vec<Option<f64>> {
    (0..trial.tips.len())
        .map(|t| {
            if !grows.get(t).copied().unwrap_or(false) {
                return None;
            }
            let size = trial.tip_element_size(t);
            let r = trial.hole_free_radius(t, r_i_factor * size);
            if r < MIN_HOLE_FREE_RADIUS * size || trial.other_crack_in_domain(t, r).is_some() {
                return None;
            }
            let s = trial.sifs(u, t, r).ok()?;
            Some(kink_angle(s.k_i, s.k_ii))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn corrector_bisects() {
        // a trial tip that wants to turn back by the whole predicted kink halves it
        assert_eq!(corrected_angle(0.4, -0.4), 0.2);
        assert_eq!(corrected_angle(0.3, 0.0), 0.3);
    }
}
