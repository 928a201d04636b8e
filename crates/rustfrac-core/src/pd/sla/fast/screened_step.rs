//! The engine's screened step ([`super::screening`]): the critical bond from the bounds, x only
//! at the candidates' ends, and the bounds kept up to date as columns are stored and bonds
//! break.

use super::screening::*;
use super::{Fast, CLS_F, CLS_P};
use crate::pd::bonds::Bond;
use crate::pd::cost::SCREEN_MIN_UNKNOWNS;
use rayon::prelude::*;

impl Fast<'_> {
    /// Writes the field of the condensed unknowns `x` into `u` at the P and ring dofs: u_P = x,
    /// u_ring = c y0 - Z_ring x_pc (c = 1 for a state, 0 for an update column). Returns
    /// Z_ring x_pc.
    pub(super) fn spread(&self, x: &[f64], with_y0: bool, u: &mut [f64]) -> Vec<f64> {
        for (&d, &xv) in self.p_dofs.iter().zip(x) {
            u[d] = xv;
        }
        let xpc: Vec<f64> = self.pc.iter().map(|&p| x[p]).collect();
        self.ring_into(&xpc, with_y0, u)
    }

    /// u at the ring from x at `pc`: c y0 - Z_ring x_pc (c = 1 for a state, 0 for a column).
    /// Returns Z_ring x_pc.
    pub(super) fn ring_into(&self, xpc: &[f64], with_y0: bool, u: &mut [f64]) -> Vec<f64> {
        let zx = self.z_ring_times(xpc);
        for (&d, &zx) in self.ring.iter().zip(&zx) {
            u[d] = if with_y0 { self.y0[self.idx[d]] } else { 0.0 } - zx;
        }
        zx
    }

    /// The state's value at ring position `r` (screened states), y0 - rv_r - R_r y, into `u_full`.
    pub(super) fn ring_at(&mut self, r: usize) {
        let s = &self.scr;
        if s.ring_stamp[r] == s.epoch {
            return;
        }
        let d = self.ring[r];
        let zx = if s.y.is_empty() {
            s.rv[r]
        } else {
            s.rv[r] + s.rw.row_dot(r, &s.y)
        };
        self.u_full[d] = self.y0[self.idx[d]] - zx;
        self.scr.ring_stamp[r] = self.scr.epoch;
    }

    /// Starts the screening of a new condensation when it pays (at least
    /// [`SCREEN_MIN_UNKNOWNS`] PD unknowns, or forced by [`force`]): s_b(v) of every bond, no
    /// columns yet.
    pub(super) fn screen_start(&mut self) {
        self.scr.on = self.p_dofs.len() >= SCREEN_MIN_UNKNOWNS || FORCE.with(|f| f.get());
        if !self.scr.on {
            return;
        }
        let model = self.model;
        let nb = model.bonds.len();
        if self.scr.lat.perm.len() != nb {
            match Lattice::new(&model.bonds) {
                Some(l) => self.scr.lat = l,
                None => {
                    self.scr.on = false;
                    return;
                }
            }
        }
        let mut u = self.model.prescribed.clone();
        self.scr.rv = self.spread(&self.v, true, &mut u);
        self.scr.rw.clear();
        self.scr.sv.clear();
        self.scr.sv.extend(self.scr.lat.perm.iter().map(|&b| {
            if self.broken[b as usize] {
                f64::NEG_INFINITY
            } else {
                model.bonds[b as usize].stretch(&u)
            }
        }));
        self.scr.hn2.clear();
        self.scr.hn2.resize(nb, 0.0);
        let nblk = nb.div_ceil(SCREEN_BLOCK);
        self.scr.blk_v.resize(nblk, 0.0);
        block_max(&self.scr.sv, &mut self.scr.blk_v, v_slack);
        self.scr.blk_h2.clear();
        self.scr.blk_h2.resize(nblk, 0.0);
        self.scr.blk_scale = match &model.surface {
            Some(sf) => (self.scr.lat.perm.chunks(SCREEN_BLOCK))
                .map(|c| {
                    c.iter()
                        .fold(f64::INFINITY, |m, &b| m.min(sf.s0_scale[b as usize]))
                })
                .collect(),
            None => vec![1.0; nblk],
        };
        if self.scr.uw.len() != u.len() {
            self.scr.uw = vec![0.0; u.len()];
            self.scr.ux = vec![0.0; u.len() / 2];
            self.scr.uy = vec![0.0; u.len() / 2];
        }
    }

    /// Adds the update column `w` (v grew by `beta0` w; `zw` = Z_ring w_pc, from
    /// `columns.rs`) to the screening: |h_b|^2 += h_b^2 and s_b(v) += beta0 h_b, with h_b the
    /// bond's stretch in the field of w.
    pub(super) fn screen_column(&mut self, w: &[f64], zw: &[f64], beta0: f64) {
        let mut uw = std::mem::take(&mut self.scr.uw);
        for (&d, &xv) in self.p_dofs.iter().zip(w) {
            uw[d] = xv;
        }
        for (&d, &z) in self.ring.iter().zip(zw) {
            uw[d] = -z;
        }
        let s = &mut self.scr;
        if beta0 != 0.0 {
            for (rv, &z) in s.rv.iter_mut().zip(zw) {
                *rv += beta0 * z;
            }
        }
        s.rw.push(zw);
        let nb = s.lat.perm.len();
        if beta0 == 0.0 {
            for ((x, y), u) in s.ux.iter_mut().zip(s.uy.iter_mut()).zip(uw.chunks_exact(2)) {
                (*x, *y) = (u[0], u[1]);
            }
            let (lat, ux, uy) = (&s.lat, &s.ux, &s.uy);
            let items: Vec<_> = s
                .hn2
                .chunks_mut(BOND_CHUNK)
                .zip(s.blk_h2.chunks_mut(BLOCKS_PER_CHUNK))
                .collect();
            chunked(items, nb, |off, (hn2, bh2)| {
                chunk_pass_best(lat, (off / BOND_CHUNK, off), (ux, uy), hn2);
                block_max(hn2, bh2, |v| v);
            });
        } else {
            // v moved: s_b(v) with the bonds' own stretches (its bound has no slack for the
            // kinds' coefficients)
            let (bonds, perm) = (&self.model.bonds, &s.lat.perm);
            let items: Vec<_> = perm
                .chunks(BOND_CHUNK)
                .zip(s.sv.chunks_mut(BOND_CHUNK))
                .zip(s.hn2.chunks_mut(BOND_CHUNK))
                .zip(s.blk_v.chunks_mut(BLOCKS_PER_CHUNK))
                .zip(s.blk_h2.chunks_mut(BLOCKS_PER_CHUNK))
                .collect();
            chunked(items, nb, |_, ((((pc, sv), hn2), bv), bh2)| {
                for ((&b, sv), h2) in pc.iter().zip(sv.iter_mut()).zip(hn2.iter_mut()) {
                    let h = bonds[b as usize].stretch(&uw);
                    *h2 += h * h;
                    *sv += beta0 * h;
                }
                block_max(sv, bv, v_slack);
                block_max(hn2, bh2, |v| v);
            });
        }
        self.scr.uw = uw;
    }

    /// A broken bond leaves the screening (its s_b(v) is -inf; its block's largest s_b(v)
    /// stays an upper bound).
    pub(super) fn screen_broken(&mut self, b: usize) {
        if self.scr.on {
            let p = self.scr.lat.pos[b] as usize;
            self.scr.sv[p] = f64::NEG_INFINITY;
        }
    }

    /// x at the end unknowns of `bond` and u at its ring ends (current for this state), then its
    /// exact stretch.
    fn exact_stretch(&mut self, bond: &Bond) -> f64 {
        let (i, j) = (bond.i as usize, bond.j as usize);
        for d in [2 * i, 2 * i + 1, 2 * j, 2 * j + 1] {
            match self.cls[d] {
                CLS_P => {
                    let p = self.idx[d];
                    if self.scr.stamp[p] != self.scr.epoch {
                        self.u_full[d] = self.x_at(p, &self.scr.y);
                        self.scr.stamp[p] = self.scr.epoch;
                    }
                }
                CLS_F if self.ring_pos[d] != usize::MAX => self.ring_at(self.ring_pos[d]),
                _ => {}
            }
        }
        bond.stretch(&self.u_full)
    }

    /// The bonds whose bound s_b(v) + |h_b| |y| reaches `cut` (its ratio to the bond's `scale`),
    /// in index order. A block is read bond by bond only when its own bound (largest s_b(v),
    /// largest |h_b|, smallest scale) reaches the cut: otherwise none of its bonds can.
    fn candidates(&self, cut: f64, scale: Option<&[f64]>) -> Vec<usize> {
        // the block test takes the block's smallest scale: the smallest threshold cut * scale
        // only while the cut is not negative (it is lmax / (1 + tol) or 0)
        debug_assert!(cut >= 0.0, "a negative cut {cut}");
        let s = &self.scr;
        let yn = s.ynorm * (1.0 + BOUND_SLACK);
        let yn2 = yn * yn;
        let nb = s.sv.len();
        // bound >= t <=> |h| |y| (1 + slack) >= t - v - slack |v| =: d
        let clear = |d: f64, h2: f64| d > 0.0 && h2 * yn2 < d * d;
        let scan = |(c, (sv, hn2)): (usize, (&[f64], &[f64]))| -> Vec<usize> {
            let blocks =
                c * BLOCKS_PER_CHUNK..(c * BLOCKS_PER_CHUNK + sv.len().div_ceil(SCREEN_BLOCK));
            let (bv, bh2, bs) = (
                &s.blk_v[blocks.clone()],
                &s.blk_h2[blocks.clone()],
                &s.blk_scale[blocks],
            );
            let mut out = Vec::new();
            for (k, ((&vmax, &h2max), &smin)) in bv.iter().zip(bh2).zip(bs).enumerate() {
                let t = cut * smin;
                let d = t - vmax;
                if vmax == f64::NEG_INFINITY
                    || clear(d - BLOCK_MARGIN * (t.abs() + vmax.abs()), h2max)
                {
                    continue;
                }
                let lo = k * SCREEN_BLOCK;
                let hi = (lo + SCREEN_BLOCK).min(sv.len());
                for (i, (&v, &h2)) in sv[lo..hi].iter().zip(&hn2[lo..hi]).enumerate() {
                    let b = s.lat.perm[c * BOND_CHUNK + lo + i] as usize;
                    let t = scale.map_or(cut, |sc| cut * sc[b]);
                    if v > f64::NEG_INFINITY && !clear(t - v_slack(v), h2) {
                        out.push(b);
                    }
                }
            }
            out
        };
        let parts: Vec<Vec<usize>> = if nb >= PARALLEL_BONDS {
            (s.sv
                .par_chunks(BOND_CHUNK)
                .zip(s.hn2.par_chunks(BOND_CHUNK)))
            .enumerate()
            .map(scan)
            .collect()
        } else {
            (s.sv.chunks(BOND_CHUNK).zip(s.hn2.chunks(BOND_CHUNK)))
                .enumerate()
                .map(scan)
                .collect()
        };
        let mut out = parts.concat();
        out.sort_unstable();
        out
    }

    /// The bonds to evaluate at this state and their exact stretches in `out` (in index order;
    /// [`crate::pd::sla::engine::Engine::stretches`]): every bond whose bound reaches the cut
    /// below the tie window (ratio to its `scale` within a factor 1 + `tol` of the largest exact
    /// ratio, found from the last step's largest stretches).
    pub(super) fn screened_stretches(
        &mut self,
        scale: Option<&[f64]>,
        tol: f64,
        out: &mut [f64],
        only: &mut Vec<usize>,
    ) {
        let model = self.model;
        let bonds = &model.bonds;
        let ratio = |b: usize, s: f64| scale.map_or(s, |sc| s / sc[b]);
        let mut lmax = f64::NEG_INFINITY;
        let seeds = std::mem::take(&mut self.scr.seeds);
        for &b in &seeds {
            if self.scr.sv[self.scr.lat.pos[b] as usize] > f64::NEG_INFINITY {
                lmax = lmax.max(ratio(b, self.exact_stretch(&bonds[b])));
            }
        }
        if lmax <= 0.0 {
            // no seed in tension: the largest bound's bond
            let yn = self.scr.ynorm;
            let s = &self.scr;
            let top = (0..bonds.len())
                .map(|p| {
                    let b = s.lat.perm[p] as usize;
                    (ratio(b, s.sv[p] + s.hn2[p].sqrt() * yn), b)
                })
                .max_by(|a, b| a.0.total_cmp(&b.0).then(b.1.cmp(&a.1)));
            if let Some((r, b)) = top {
                if r > f64::NEG_INFINITY {
                    lmax = lmax.max(ratio(b, self.exact_stretch(&bonds[b])));
                }
            }
        }
        let cut = if lmax > 0.0 {
            lmax / (1.0 + tol) * (1.0 - CUT_MARGIN)
        } else {
            0.0
        };
        *only = self.candidates(cut, scale);
        let mut top: Vec<(f64, usize)> = Vec::with_capacity(only.len());
        for &b in only.iter() {
            out[b] = self.exact_stretch(&bonds[b]);
            top.push((ratio(b, out[b]), b));
        }
        let ns = SEEDS.min(top.len());
        let mut seeds = seeds;
        seeds.clear();
        if ns > 0 {
            top.select_nth_unstable_by(ns - 1, |a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)));
            seeds.extend(top[..ns].iter().map(|c| c.1));
        }
        self.scr.seeds = seeds;
        self.scr.steps += 1;
        self.scr.evaluated += only.len();
    }
}
