//! The fast solver's automatic re-condensation interval ([`auto_refactor_every`]). The SLA
//! options themselves belong to the problem ([`crate::problem::SlaParams`]).

/// The automatic re-condensation interval of the fast solver for `n_p` condensed unknowns:
/// max(64, n_p / 2), at most 4096. Re-condensing costs O(n_p^3), a step with k stored updates
/// O(k n_p), so intervals of order n_p balance the two; n_p / 2 keeps the update vectors (k n_p)
/// and the capacitance inverse (k^2) below 3/4 of the condensed inverse (n_p^2), so the solver's
/// memory does not grow with the number of steps. The paper's case (n_p = 2080) never reaches it
/// in 500 steps.
pub fn auto_refactor_every(n_p: usize) -> usize {
    (n_p / 2).clamp(64, 4096)
}
