//! The cost model of the SLA's engines ([`crate::pd::sla`]): which form of the condensed PD
//! system (dense LU or sparse factor, `sla/fast/base.rs`) runs the SLA, from estimated times, the
//! re-condensation interval of each form ([`auto_refactor_every`] for the dense one), and the
//! bytes each needs, which the splice model's memory bound reads before the model is built
//! ([`crate::pd::splice`]). Below both, so neither imports the other for it.
//!
//! With n = n_P condensed unknowns, N the re-condensation interval and k <= N stored updates, the
//! SLA costs per step O(k n) for the updates (`sla/fast/smw.rs`: x = v + W y) plus:
//! * dense: one condensation = an LU in place, 2 n^3 / 3 flops at [`DENSE_FLOPS`]; N = n / 2
//!   ([`auto_refactor_every`]); per step [`COLUMNS_PER_STEP`] columns of S^{-1}
//!   (`sla/fast/columns.rs`), 2 n^2 flops each at [`BATCH_SOLVE_FLOPS`].
//! * sparse: one factorisation, about nnz(L)^2 / n flops (exact for a dense band; the supernodal
//!   factor of the 2D grids here measured within a factor 2 of it) at [`SPARSE_FLOPS`], and
//!   per step [`COLUMNS_PER_STEP`] columns of S^{-1} (`sla/fast/columns.rs`), 4 nnz(L) flops each in
//!   multi-column solves at [`BATCH_SOLVE_FLOPS`] (the sparse Cholesky's columns now cost about
//!   half of it, their forward halves running along the elimination-tree paths only: the
//!   estimate is kept, conservative for pure PD, whose choice it does not change). nnz(L) comes
//!   from the symbolic Cholesky analysis of the pattern of S (for the non-symmetric CCM-PD S, of
//!   its symmetrised pattern: LU stores L and U, so twice that; the engine takes the cheaper
//!   bordered Cholesky of K_PP when it can, `sla/fast/base.rs`, so this estimate is an upper bound
//!   there: on the paper's case that form measured no faster than the dense one, whose choice it
//!   keeps). The interval minimising
//!   t_fact / N + t_solve + N n / [`UPDATE_FLOPS`] is N = sqrt(t_fact [`UPDATE_FLOPS`] / n).
//!
//! The estimates are for [`HORIZON_STEPS`] steps whatever the run's `sla_steps`, so a resumed run
//! (checkpoint) picks the same engine as the run that wrote it. The rates are measured on the
//! development machine (2 cores; benches/RESULTS.md, "Large PD regions"); only their ratios
//! matter for the choice.

/// Dense LU rate (flop/s).
pub const DENSE_FLOPS: f64 = 2.0e10;
/// Sparse supernodal factorisation rate (flop/s).
pub const SPARSE_FLOPS: f64 = 8.0e9;
/// Sparse triangular solve rate with a batch of right-hand sides (flop/s): 128 columns of the
/// pure PD paper grid's factor in 3.8 s on the loaded development machine, 1.2e10 (one
/// right-hand side alone: 2e9, memory bound).
pub const BATCH_SOLVE_FLOPS: f64 = 1.2e10;
/// Columns of S^{-1} computed per SLA step, refills after re-factorisations included: measured
/// 1.2 (pure PD paper grid, 500 steps: 600 columns) and 1.5 (coarse CCM-PD, 150 steps).
pub const COLUMNS_PER_STEP: f64 = 1.5;
/// Rate of the O(k n) update work per step (flop/s; memory bound).
pub const UPDATE_FLOPS: f64 = 2.0e9;
/// Unknowns whose x a screened step evaluates (`sla/fast/screening.rs`, from
/// [`SCREEN_MIN_UNKNOWNS`] on): the ends of the 1 000-3 000 bonds near the tip whose
/// bound reaches the tie window. Its O(bonds) passes do not grow with k.
const SCREENED_UNKNOWNS: f64 = 4096.0;
/// Bytes the stored update vectors (n x N) may take when the interval is chosen for a screened
/// step, whose cost hardly grows with N.
const UPDATE_BYTES: f64 = 5.12e8;
/// PD unknowns from which a condensation is screened. Below, the full x = v + W y is cheap and
/// the bonds the bound cannot clear (1 000-3 000 near the tip, each needing rows of W) cost as
/// much: on the paper's case (2 080 unknowns) a version that turned it on at k = 400 made the
/// 500 steps 1.085x slower (10 alternating pairs); on
/// the adaptive run (to 8 748 unknowns) and pure PD (103 583) it is faster (benches/RESULTS.md;
/// `sla/fast/screening.rs`).
pub const SCREEN_MIN_UNKNOWNS: usize = 4096;
/// The automatic re-condensation interval of the fast solver for `n_p` condensed unknowns:
/// max(64, n_p / 2), at most 4096. Re-condensing costs O(n_p^3), a step with k stored updates
/// O(k n_p), so intervals of order n_p balance the two; n_p / 2 keeps the update vectors (k n_p)
/// and the capacitance inverse (k^2) below 3/4 of the condensed inverse (n_p^2), so the solver's
/// memory does not grow with the number of steps. The paper's case (n_p = 2080) never reaches it
/// in 500 steps.
pub fn auto_refactor_every(n_p: usize) -> usize {
    (n_p / 2).clamp(64, 4096)
}

/// Steps the estimates are made for.
pub const HORIZON_STEPS: usize = 500;
/// Bounds of the sparse re-factorisation interval.
const SPARSE_INTERVAL: (usize, usize) = (16, 4096);

/// The form of the condensed system.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum EngineKind {
    Dense,
    Sparse,
}

/// Estimated seconds of both forms for [`HORIZON_STEPS`] steps, and the interval of each.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CostEstimate {
    pub n_p: usize,
    pub factor_nnz: f64,
    pub dense_seconds: f64,
    pub dense_interval: usize,
    pub sparse_seconds: f64,
    pub sparse_interval: usize,
}

impl CostEstimate {
    /// Estimates for `n_p` unknowns whose sparse factor has `factor_nnz` stored values;
    /// `refactor_every` > 0 fixes both intervals (the scene's `pd.refactor_every`).
    pub fn new(n_p: usize, factor_nnz: f64, refactor_every: usize) -> Self {
        let n = n_p.max(1) as f64;
        let steps = HORIZON_STEPS as f64;
        // the O(k) work per step: x at every unknown, or at those a screened step evaluates
        let screened = n_p >= SCREEN_MIN_UNKNOWNS;
        let per_update = if screened {
            SCREENED_UNKNOWNS.min(n)
        } else {
            n
        } / UPDATE_FLOPS;
        let dense_interval = if refactor_every > 0 {
            refactor_every
        } else {
            auto_refactor_every(n_p)
        };
        let t_cond = 2.0 * n * n * n / 3.0 / DENSE_FLOPS;
        let t_cols = COLUMNS_PER_STEP * 2.0 * n * n / BATCH_SOLVE_FLOPS;
        let dense_seconds = cycle_cost(steps, dense_interval, t_cond, t_cols, per_update);
        let t_fact = factor_nnz * factor_nnz / n / SPARSE_FLOPS;
        let t_solve = COLUMNS_PER_STEP * 4.0 * factor_nnz / BATCH_SOLVE_FLOPS;
        let sparse_interval = if refactor_every > 0 {
            refactor_every
        } else {
            let (lo, hi) = SPARSE_INTERVAL;
            let by_memory = if screened {
                (UPDATE_BYTES / (8.0 * n)) as usize
            } else {
                usize::MAX
            };
            ((t_fact / per_update).sqrt().round() as usize)
                .min(by_memory)
                .clamp(lo, hi)
        };
        let sparse_seconds = cycle_cost(steps, sparse_interval, t_fact, t_solve, per_update);
        Self {
            n_p,
            factor_nnz,
            dense_seconds,
            dense_interval,
            sparse_seconds,
            sparse_interval,
        }
    }

    /// The cheaper form (dense on a tie).
    pub fn choice(&self) -> EngineKind {
        if self.sparse_seconds < self.dense_seconds {
            EngineKind::Sparse
        } else {
            EngineKind::Dense
        }
    }

    /// Bytes the solver of form `kind` keeps: the dense form its LU (n x n), N update vectors and
    /// the kept columns of S^{-1} (about `COLUMNS_PER_STEP` N, at most n), the sparse
    /// form its factor (values and indices, 12 bytes a value), N update vectors and the kept
    /// columns of S^{-1} (about `COLUMNS_PER_STEP` N).
    pub fn solver_bytes(&self, kind: EngineKind) -> f64 {
        let n = self.n_p as f64;
        match kind {
            EngineKind::Dense => {
                let nn = self.dense_interval as f64;
                8.0 * n * (n + nn + (COLUMNS_PER_STEP * nn).min(n))
            }
            EngineKind::Sparse => {
                12.0 * self.factor_nnz
                    + 8.0 * n * (1.0 + COLUMNS_PER_STEP) * self.sparse_interval as f64
            }
        }
    }

    /// One line for the result's `solver` string.
    pub fn describe(&self) -> String {
        format!(
            "estimated {HORIZON_STEPS} steps: dense {:.3e} s (re-condense every {}), sparse {:.3e} s \
             (nnz(L) {:.3e}, refactorise every {})",
            self.dense_seconds,
            self.dense_interval,
            self.sparse_seconds,
            self.factor_nnz,
            self.sparse_interval
        )
    }
}

/// Seconds of `steps` steps with a (re)factorisation of `t_fact` every `interval` updates, a
/// solve of `t_solve` per step and `per_update` seconds per stored update per step (k grows
/// from 0 to the interval: on average interval / 2).
fn cycle_cost(steps: f64, interval: usize, t_fact: f64, t_solve: f64, per_update: f64) -> f64 {
    let n_fact = 1.0 + (steps / interval.max(1) as f64).floor();
    n_fact * t_fact + steps * (t_solve + 0.5 * interval as f64 * per_update)
}

/// An estimate of nnz(L) before the model exists (the memory estimate of
/// [`crate::pd::splice`]): nested dissection of the PD grid measured nnz(L) = 0.37 nnz(K_PP)
/// log2(n_P) on the paper's pure PD grid (n_P = 103 583, nnz(K_PP) = 1.40e7, nnz(L) = 8.56e7),
/// with nnz(K_PP) = 4 (2 bonds per node + 1) per node.
pub fn factor_nnz_guess(n_p: usize, n_bonds: f64) -> f64 {
    let n = n_p.max(2) as f64;
    let nnz_k = 4.0 * (2.0 * n_bonds + 0.5 * n);
    0.37 * nnz_k * n.log2()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn small_systems_stay_dense_large_go_sparse() {
        // the paper's CCM-PD (n_P = 2080, nnz(L) 3.53e6 from the symbolic analysis of S with its
        // dense FEM-ring block; measured on the loaded machine: dense 3.1-3.3 s, sparse
        // 3.1-3.4 s a run): dense; its pure PD (n_P = 103 583): sparse
        let small = CostEstimate::new(2080, 3.526e6, 0);
        assert_eq!(small.choice(), EngineKind::Dense, "{small:?}");
        let big = CostEstimate::new(103_583, 8.56e7, 0);
        assert_eq!(big.choice(), EngineKind::Sparse, "{big:?}");
        assert!(big.sparse_interval >= 16 && big.sparse_interval <= 4096);
        // screened (n_P >= 4096): the interval is longer than the O(k n) step's, within the
        // update vectors' memory
        let n = 103_583.0;
        let unscreened = (big.factor_nnz.powi(2) / n / SPARSE_FLOPS * UPDATE_FLOPS / n).sqrt();
        assert!(
            big.sparse_interval as f64 > 1.2 * unscreened,
            "{big:?} vs {unscreened}"
        );
        assert!(
            8.0 * n * big.sparse_interval as f64 <= UPDATE_BYTES,
            "{big:?}"
        );
    }
}
