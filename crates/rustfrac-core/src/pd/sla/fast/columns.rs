//! Columns of S_0^{-1} kept between SMW updates (`base.rs`: solved with its dense LU or sparse
//! factor).
//!
//! A broken bond needs w = S_0^{-1} a, where a has at most four nonzeros (the bond's end dofs),
//! so w is a combination of at most four columns of S_0^{-1}. The bonds an SLA run breaks lie
//! along the crack, so the same few hundred columns serve thousands of breaks. A column not yet
//! kept is computed with every missing column within one horizon of it, in one multi-column solve:
//! the factor is read once for the whole batch (a triangular solve is bound by reading nnz(L)
//! values, the dense LU n_P^2), instead of once per break. The batch is exact (the same factor); only the round-off
//! of w differs from one solve with a (the combination is taken after the solve).
//!
//! The kept columns are bounded by a memory budget; past it they are dropped and refilled.

use super::base::Base;
use crate::error::{Error, Result};
use crate::pd::sla::engine::timing;
use std::time::Instant;

/// Fraction of the memory available at the first batch that kept columns may take.
const BUDGET_FRACTION: f64 = 0.25;
/// Upper bound of the kept columns' memory (bytes).
const BUDGET_MAX_BYTES: f64 = 4.0e9;

/// Kept columns of S_0^{-1}, invalidated at each factorisation.
#[derive(Default)]
pub(in crate::pd::sla) struct Columns {
    /// column of each P unknown, if kept: (batch, place in it)
    col: Vec<Option<(usize, usize)>>,
    /// the batches' columns as solved (column-major, n_P x batch size)
    store: Vec<Vec<f64>>,
    kept: usize,
    /// most columns kept at once (from the memory budget; 0: not set yet)
    max_kept: usize,
    /// batches solved and columns computed (for the run's report)
    pub(in crate::pd::sla) batches: usize,
    pub(in crate::pd::sla) computed: usize,
}

impl Columns {
    /// Drops every kept column (the factor changed).
    pub(in crate::pd::sla) fn clear(&mut self) {
        self.col.clear();
        self.store.clear();
        self.kept = 0;
    }

    /// w = S_0^{-1} a for a sparse a (index, value) on the `xy.len()` P unknowns at `xy`, with the
    /// columns of the unknowns of a, computed in batches of every missing unknown within
    /// `radius` of one of them.
    pub(in crate::pd::sla) fn combine(
        &mut self,
        f: &Base,
        a: &[(usize, f64)],
        xy: &[[f64; 2]],
        radius: f64,
    ) -> Result<Vec<f64>> {
        let n = xy.len();
        if self.col.len() != n {
            self.clear();
            self.col = vec![None; n];
        }
        if self.max_kept == 0 {
            let avail = crate::memory::available_bytes().unwrap_or(8.0e9);
            let budget = (avail * BUDGET_FRACTION).min(BUDGET_MAX_BYTES);
            self.max_kept = ((budget / (8.0 * n.max(1) as f64)) as usize).max(8);
        }
        let missing: Vec<usize> = a
            .iter()
            .map(|&(p, _)| p)
            .filter(|&p| self.col[p].is_none())
            .collect();
        if !missing.is_empty() {
            self.fetch(f, &missing, xy, radius)?;
        }
        let mut w = crate::la::written_zeros(n); // accumulated into
        for &(p, val) in a {
            let (b, j) = self.col[p].ok_or_else(|| Error::Internal {
                detail: format!("column {p} of the condensed inverse not fetched"),
            })?;
            let c = &self.store[b][j * n..(j + 1) * n];
            for (wi, &s) in w.iter_mut().zip(c) {
                *wi += s * val;
            }
        }
        Ok(w)
    }

    /// Solves for the columns of `need` and of every missing unknown within `radius` of them
    /// (as many as the budget allows) in one multi-column solve.
    fn fetch(&mut self, f: &Base, need: &[usize], xy: &[[f64; 2]], radius: f64) -> Result<()> {
        let n = xy.len();
        if self.kept + need.len() > self.max_kept {
            self.clear();
            self.col = vec![None; n];
        }
        let room = self.max_kept - self.kept;
        let mut in_batch = vec![false; n];
        let mut batch: Vec<usize> = Vec::new();
        for &q in need {
            if !in_batch[q] {
                in_batch[q] = true;
                batch.push(q);
            }
        }
        let r2 = radius * radius;
        for (q, p) in xy.iter().enumerate() {
            if batch.len() >= room {
                break;
            }
            if self.col[q].is_some() || in_batch[q] {
                continue;
            }
            let near = need.iter().any(|&c| {
                let (dx, dy) = (p[0] - xy[c][0], p[1] - xy[c][1]);
                dx * dx + dy * dy <= r2
            });
            if near {
                in_batch[q] = true;
                batch.push(q);
            }
        }
        let t0 = Instant::now();
        let k = batch.len();
        let rhs = f.unit_columns(&batch, n)?;
        for (j, &q) in batch.iter().enumerate() {
            self.col[q] = Some((self.store.len(), j));
        }
        self.store.push(rhs);
        self.kept += k;
        self.batches += 1;
        self.computed += k;
        timing(
            &format!(
                "fast: {k} columns of S_0^-1 (batch {}, {} kept)",
                self.batches, self.kept
            ),
            t0,
        );
        Ok(())
    }
}
