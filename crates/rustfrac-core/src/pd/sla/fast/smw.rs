//! Sherman-Morrison-Woodbury updates of the condensed system (the fast solver's step).
//!
//! A broken bond or a grounding spring changes S by a rank-1 term, S_k = S_0 - A B^T: the update
//! keeps w = S_0^{-1} a and the row b^T, and the capacitance inverse (I - B^T W)^{-1} grows by
//! bordering (O(k^2) per update). The Schur pivot of the bordering is det(S_k+1) / det(S_k):
//! when it vanishes the body has separated; when it is merely small a fresh condensation decides.

use rayon::prelude::*;

use super::base::Base;
use super::{Fast, CLS_F, CLS_P};
use crate::error::{Error, Result};
use crate::pd::sla::engine::{separated, Update};
use crate::pd::splice::Spring;

/// A Schur pivot of the SMW bordering below this (but above 1e-10) is checked by a fresh
/// condensation: legitimate breaks give pivots of order 1e-2..1 (the paper's 500 steps: none
/// below 1e-3), a mechanism gives round-off (1e-6 after a few hundred updates).
const SUSPICIOUS_PIVOT: f64 = 1e-4;
/// Entries of x updated together by all stored columns (16 kB of x in cache).
const X_CHUNK: usize = 2048;
/// Stored values (k n) above which the update of x runs on all threads.
const PARALLEL_WORK: usize = 1 << 20;

impl Fast<'_> {
    /// The condensed solution of the current state: x = v + W C^{-1} (B^T v), with v = S_0^{-1} g_k
    /// and C^{-1} the capacitance inverse.
    pub(super) fn x(&self) -> Vec<f64> {
        let k = self.w.len();
        let z: Vec<f64> = self
            .bt
            .iter()
            .map(|b| b.iter().map(|&(p, val)| val * self.v[p]).sum())
            .collect();
        let mut y = vec![0.0; k];
        for (i, yi) in y.iter_mut().enumerate() {
            let row = &self.cinv[i * self.cs..i * self.cs + k];
            *yi = row.iter().zip(&z).map(|(a, b)| a * b).sum();
        }
        let mut x = self.v.clone();
        // x += W y, in chunks of x that stay in cache while every stored column passes (W is
        // read once: the step is bound by reading it); each x_i sums its terms in column order,
        // so the result does not depend on the chunking or the threads
        let add = |(c, xc): (usize, &mut [f64])| {
            let (off, len) = (c * X_CHUNK, xc.len());
            for (wc, &yc) in self.w.iter().zip(&y) {
                for (xi, &wi) in xc.iter_mut().zip(&wc[off..off + len]) {
                    *xi += wi * yc;
                }
            }
        };
        if k * x.len() >= PARALLEL_WORK {
            x.par_chunks_mut(X_CHUNK).enumerate().for_each(add);
        } else {
            x.chunks_mut(X_CHUNK).enumerate().for_each(add);
        }
        x
    }

    /// Rank-1 data of removing bond `b`: S changes by -a bt^T on the free PD rows, g by a beta0.
    #[allow(clippy::type_complexity)]
    pub(super) fn bond_update(
        &mut self,
        b: usize,
    ) -> Result<(Vec<(usize, f64)>, Vec<(usize, f64)>, f64)> {
        let model = self.model;
        let bond = &model.bonds[b];
        let (alpha, nv) = model.bond_alpha_n(b);
        let (i, j) = (bond.i as usize, bond.j as usize);
        let dofs = [2 * i, 2 * i + 1, 2 * j, 2 * j + 1];
        let bv = [nv[0], nv[1], -nv[0], -nv[1]];
        let np = self.p_dofs.len();
        let npc = self.pc.len();
        // PD rows of the loaded top edge (pure PD layers): sigma22 loses this bond's force
        let mut c_top = 0.0;
        for t in 0..4 {
            let d = dofs[t];
            let r = self.resp_coef[d];
            if r != 0.0 && model.is_pd[d / 2] && (t < 2 || model.is_pd[j]) {
                c_top += alpha * bv[t] * r / self.wh;
            }
        }
        if c_top != 0.0 {
            self.sig_bonds.push((c_top, dofs, bv));
        }
        // a on free PD rows
        let mut a: Vec<(usize, f64)> = Vec::new();
        for t in 0..4 {
            let d = dofs[t];
            if self.cls[d] == CLS_P && model.is_pd[d / 2] {
                a.push((self.idx[d], alpha * bv[t]));
            }
        }
        // condensed b and beta0
        let mut bt_dense = vec![0.0; np];
        let mut beta0 = 0.0;
        for t in 0..4 {
            let d = dofs[t];
            match self.cls[d] {
                CLS_P => bt_dense[self.idx[d]] += bv[t],
                CLS_F => {
                    beta0 += bv[t] * self.y0[self.idx[d]];
                    let rp = self.ring_pos[d];
                    if rp == usize::MAX {
                        return Err(Error::Internal {
                            detail: "bond end outside the coupling ring".into(),
                        });
                    }
                    let zrow = &self.z_ring[rp * npc..(rp + 1) * npc];
                    for (tt, &z) in zrow.iter().enumerate() {
                        bt_dense[self.pc[tt]] -= bv[t] * z;
                    }
                }
                _ => beta0 += bv[t] * model.prescribed[d],
            }
        }
        let bt: Vec<(usize, f64)> = bt_dense
            .iter()
            .enumerate()
            .filter(|(_, v)| **v != 0.0)
            .map(|(p, &v)| (p, v))
            .collect();
        Ok((a, bt, beta0))
    }

    /// Rank-1 data of a grounding spring k p p^T at a PD node: S changes by +k p p^T on its free
    /// dofs (a = -k p, bt = p), g does not change (its dofs carry no prescribed value).
    #[allow(clippy::type_complexity)]
    pub(super) fn spring_update(
        &mut self,
        sp: Spring,
    ) -> (Vec<(usize, f64)>, Vec<(usize, f64)>, f64) {
        let ks = self.model.spring_stiffness();
        let n = sp.node;
        let mut a = Vec::new();
        let mut bt = Vec::new();
        let mut c_top = 0.0;
        for t in 0..2 {
            let d = 2 * n + t;
            if self.cls[d] == CLS_P && sp.p[t] != 0.0 {
                a.push((self.idx[d], -ks * sp.p[t]));
                bt.push((self.idx[d], sp.p[t]));
                let r = self.resp_coef[d];
                if r != 0.0 {
                    c_top -= ks * sp.p[t] * r / self.wh;
                }
            }
        }
        if c_top != 0.0 {
            let dofs = [2 * n, 2 * n + 1, 2 * n, 2 * n + 1];
            self.sig_bonds
                .push((c_top, dofs, [sp.p[0], sp.p[1], 0.0, 0.0]));
        }
        (a, bt, 0.0)
    }

    /// Sherman-Morrison-Woodbury with S_k = S_0 - A B^T: appends the column a (as w = S_0^{-1} a)
    /// and the row bt, and grows the capacitance inverse by bordering (O(k^2)). The Schur pivot of
    /// the bordering is det(S_k+1) / det(S_k): when it vanishes the body has separated.
    pub(super) fn smw_append(
        &mut self,
        a: Vec<(usize, f64)>,
        bt: Vec<(usize, f64)>,
        beta0: f64,
        upd: Update,
    ) -> Result<()> {
        let np = self.p_dofs.len();
        // w = S0^{-1} a (sparse base: from kept columns, `columns.rs`)
        let w = match &self.base {
            Base::Sparse(f) => self
                .columns
                .combine(f, &a, &self.p_xy, self.model.pd.delta)?,
            base => base.solve_sparse(&a, np)?,
        };
        // bordering of the capacitance C = I - B^T W
        let k = self.w.len();
        let col: Vec<f64> = self
            .bt
            .iter()
            .map(|bl| -bl.iter().map(|&(p, v)| v * w[p]).sum::<f64>())
            .collect();
        let row: Vec<f64> = self
            .w
            .iter()
            .map(|wm| -bt.iter().map(|&(p, v)| v * wm[p]).sum::<f64>())
            .collect();
        let d = 1.0 - bt.iter().map(|&(p, v)| v * w[p]).sum::<f64>();
        let (e, cs) = (&self.cinv, self.cs);
        let ec: Vec<f64> = (0..k)
            .map(|r| (0..k).map(|c| e[r * cs + c] * col[c]).sum())
            .collect();
        let re: Vec<f64> = (0..k)
            .map(|c| (0..k).map(|r| row[r] * e[r * cs + c]).sum())
            .collect();
        let s = d - row.iter().zip(&ec).map(|(a, b)| a * b).sum::<f64>();
        if s.is_nan() || s.abs() <= 1e-10 {
            return Err(separated(format!(
                "{upd:?} makes the system singular (Schur pivot {s:.3e})"
            )));
        }
        if s.abs() < SUSPICIOUS_PIVOT {
            // nearly singular: a mechanism (a part held by a hinge) shows up here with a pivot of
            // the size of the accumulated round-off, not zero. Decide on a fresh condensation of
            // the new state, which also discards the round-off of the updates so far.
            let mut broken = self.broken.clone();
            let mut springs = self.springs.clone();
            match upd {
                Update::Break(b) => broken[b] = true,
                Update::Ground(sp) => springs.push(sp),
            }
            let k = self.model.assemble_with(&broken, &springs);
            self.condense(&k).map_err(|e| {
                separated(format!(
                    "{upd:?}: Schur pivot {s:.3e}, and the re-condensed system is singular \
                     (a part of the body came loose or hangs on a hinge): {e}"
                ))
            })?;
            return Ok(());
        }
        if k + 1 > self.cs {
            let ncs = (2 * self.cs).max(64).max(k + 1);
            let mut grown = vec![0.0; ncs * ncs];
            for r in 0..k {
                grown[r * ncs..r * ncs + k].copy_from_slice(&self.cinv[r * cs..r * cs + k]);
            }
            self.cinv = grown;
            self.cs = ncs;
        }
        let (e, cs) = (&mut self.cinv, self.cs);
        for r in 0..k {
            for c in 0..k {
                e[r * cs + c] += ec[r] * re[c] / s;
            }
            e[r * cs + k] = -ec[r] / s;
        }
        for c in 0..k {
            e[k * cs + c] = -re[c] / s;
        }
        e[k * cs + k] = 1.0 / s;
        for (vi, &wi) in self.v.iter_mut().zip(&w) {
            *vi += wi * beta0;
        }
        self.w.push(w);
        self.bt.push(bt);
        self.max_rank = self.max_rank.max(self.w.len());
        Ok(())
    }
}
