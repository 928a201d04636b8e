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
//!
//! A screened run (`screening.rs`) also needs each update column's field at the FEM ring,
//! Z_ring w_pc: it is kept per column too, for a batch one matrix product Z_ring C_pc (read once
//! for the batch) instead of one matrix-vector product of Z_ring per break ([`RingMap`]).

use super::base::Base;
use crate::error::{Error, Result};
use crate::pd::sla::engine::timing;
use faer::linalg::matmul::matmul;
use faer::{Accum, MatMut, MatRef, Par};
use std::time::Instant;

/// Z at the ring (row-major |ring| x |pc|), the P indices `pc` of its columns and |ring| (not
/// derived from Z: with no `pc` Z is empty, the ring not): the ring field of a column c of
/// S_0^{-1} is Z_ring c_pc.
#[derive(Clone, Copy)]
pub(in crate::pd::sla) struct RingMap<'z> {
    pub(in crate::pd::sla) z: &'z [f64],
    pub(in crate::pd::sla) pc: &'z [usize],
    pub(in crate::pd::sla) nring: usize,
}

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
    /// the batches' ring fields (column-major, |ring| x batch size; empty without a [`RingMap`])
    ring: Vec<Vec<f64>>,
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
        self.ring.clear();
        self.kept = 0;
    }

    /// w = S_0^{-1} a for a sparse a (index, value) on the `xy.len()` P unknowns at `xy`, with the
    /// columns of the unknowns of a, computed in batches of every missing unknown within
    /// `radius` of one of them; with `ring`, also w's ring field Z_ring w_pc (the same
    /// combination of the columns' ring fields). `ring` must be the same for every call between
    /// two [`Self::clear`]s.
    pub(in crate::pd::sla) fn combine(
        &mut self,
        f: &Base,
        a: &[(usize, f64)],
        xy: &[[f64; 2]],
        radius: f64,
        ring: Option<RingMap<'_>>,
    ) -> Result<(Vec<f64>, Option<Vec<f64>>)> {
        let n = xy.len();
        if self.col.len() != n {
            self.clear();
            self.col = vec![None; n];
        }
        let nring = ring.map_or(0, |r| r.nring);
        if self.max_kept == 0 {
            let avail = crate::memory::available_bytes().unwrap_or(8.0e9);
            let budget = (avail * BUDGET_FRACTION).min(BUDGET_MAX_BYTES);
            self.max_kept = ((budget / (8.0 * (n + nring).max(1) as f64)) as usize).max(8);
        }
        let missing: Vec<usize> = a
            .iter()
            .map(|&(p, _)| p)
            .filter(|&p| self.col[p].is_none())
            .collect();
        if !missing.is_empty() {
            self.fetch(f, &missing, xy, radius, ring)?;
        }
        let mut w = crate::la::written_zeros(n); // accumulated into
        let mut zw = ring.map(|_| crate::la::written_zeros(nring));
        for &(p, val) in a {
            let (b, j) = self.col[p].ok_or_else(|| Error::Internal {
                detail: format!("column {p} of the condensed inverse not fetched"),
            })?;
            let c = &self.store[b][j * n..(j + 1) * n];
            for (wi, &s) in w.iter_mut().zip(c) {
                *wi += s * val;
            }
            if let Some(zw) = zw.as_mut() {
                let r = self.ring[b]
                    .get(j * nring..(j + 1) * nring)
                    .ok_or_else(|| Error::Internal {
                        detail: format!("ring field of column {p} not computed"),
                    })?;
                for (zi, &s) in zw.iter_mut().zip(r) {
                    *zi += s * val;
                }
            }
        }
        Ok((w, zw))
    }

    /// Solves for the columns of `need` and of every missing unknown within `radius` of them
    /// (as many as the budget allows) in one multi-column solve.
    fn fetch(
        &mut self,
        f: &Base,
        need: &[usize],
        xy: &[[f64; 2]],
        radius: f64,
        ring: Option<RingMap<'_>>,
    ) -> Result<()> {
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
        self.ring
            .push(ring.map_or_else(Vec::new, |r| ring_fields(r, &rhs, n, k)));
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

/// Z_ring C_pc for the `k` columns C (column-major, `n` x k): column-major |ring| x k.
fn ring_fields(r: RingMap<'_>, c: &[f64], n: usize, k: usize) -> Vec<f64> {
    let (nring, npc) = (r.nring, r.pc.len());
    let mut out = vec![0.0; nring * k];
    if nring == 0 || npc == 0 {
        return out;
    }
    let mut cpc = vec![0.0; npc * k];
    for (cj, col) in cpc.chunks_exact_mut(npc).zip(c.chunks_exact(n)) {
        for (v, &p) in cj.iter_mut().zip(r.pc) {
            *v = col[p];
        }
    }
    matmul(
        MatMut::from_column_major_slice_mut(&mut out, nring, k),
        Accum::Replace,
        MatRef::from_row_major_slice(r.z, nring, npc),
        MatRef::from_column_major_slice(&cpc, npc, k),
        1.0,
        Par::Seq,
    );
    out
}
