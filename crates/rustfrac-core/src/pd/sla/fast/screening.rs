//! Bond screening: the SLA step's critical bond found without the whole x = v + W y.
//!
//! The stretch of a bond is affine in the condensed unknowns, s_b(x) = s_b(v) + h_b . y with
//! h_b[j] = the stretch of bond b in the field of the update column w_j (its ring values
//! -Z_ring w_pc, fixed dofs zero). The screening keeps s_b(v) and |h_b|^2 for every bond, updated
//! once per stored column (O(bonds)), so each step has the bound (Cauchy-Schwarz)
//! s_b <= s_b(v) + |h_b| |y| at O(1) a bond. Only the bonds whose bound reaches the tie window of
//! the largest exact stretch need x, at their end unknowns (one row of W each): the step costs
//! O(bonds + candidates k) instead of O(n k). The other bonds can be neither critical nor tie
//! with the critical one, so the driver's selection is the one of the exact stretches.
//!
//! The screening keeps its bonds in the order of their lattice vector, then first node
//! ([`Lattice`]): a column's pass then reads runs of parallel bonds between consecutive nodes,
//! whose end values are contiguous slices (vectorised, no gathers). The step's pass goes by
//! blocks of [`SCREEN_BLOCK`] bonds of that order (a run of parallel bonds along a grid row):
//! each block keeps the largest s_b(v) and |h_b|^2 of its bonds (and the smallest
//! critical-stretch scale), so a block whose bound stays below the cut is cleared at O(1), and
//! only the blocks near the tip are read bond by bond.
//!
//! The FEM ring's values follow the same way: x = v + W y gives u_ring = y0 - Z_ring v_pc -
//! R y, with R's columns Z_ring w_pc kept beside W (computed per batch of columns of S_0^{-1},
//! `columns.rs`), so a state reads a ring dof at O(k), only where it needs one (the load
//! displacement's and the probes' dofs, the FEM ends of the bonds evaluated), instead of the
//! whole Z_ring x_pc (|ring| |pc|) at every state and every column.
//!
//! Small condensations go without it ([`SCREEN_MIN_UNKNOWNS`]): x in full.

use rayon::prelude::*;

use super::{Fast, CLS_F, CLS_P};
use crate::pd::bonds::Bond;
use crate::pd::cost::SCREEN_MIN_UNKNOWNS;

/// Bonds above which the screening's passes over them run on all threads.
const PARALLEL_BONDS: usize = 1 << 15;
/// Bonds a thread takes at once in those passes (fixed: the result does not depend on threads).
const BOND_CHUNK: usize = 4096;
/// Bonds of a block of the step's pass (a divisor of [`BOND_CHUNK`]).
const SCREEN_BLOCK: usize = 256;
const BLOCKS_PER_CHUNK: usize = BOND_CHUNK / SCREEN_BLOCK;
/// Relative margin of a block's test over its bonds' own tests (which it must never clear a
/// candidate of): covers the rounding of the two forms of the same inequality.
const BLOCK_MARGIN: f64 = 1e-12;
/// Relative slack of each bound's terms, above the round-off of the exact stretches and of the
/// bounds' own accumulation (near 1e-14 of the terms; the kinds' coefficients of the column
/// passes, whose two terms may cancel, are bounded apart: [`COEF_ROUNDING`]).
const BOUND_SLACK: f64 = 1e-9;
/// Relative margin of the cut below the tie window, for the round-off of the window's ends.
const CUT_MARGIN: f64 = 1e-8;
/// Bonds of the largest exact stretches kept as the next step's seeds.
const SEEDS: usize = 8;

thread_local! {
    /// Screens every condensation made on this thread, whatever its size (tests: the small
    /// cases then check the screening against the oracle).
    static FORCE: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
}

/// Screens (`on`) or not (the size rule) every condensation the fast solver makes on this thread
/// from now on: for tests, which check the screening on small cases against the oracle.
#[doc(hidden)]
pub fn force_screening(on: bool) {
    FORCE.with(|f| f.set(on));
}

/// The screening's state: s_b(v) and |h_b|^2 per bond, and the last state's coefficients y.
#[derive(Default)]
pub(super) struct Screening {
    /// on for the current condensation (else x in full)
    pub(super) on: bool,
    /// the screening's order of the bonds and its runs ([`Lattice`]); the per-bond arrays below
    /// are in that order
    lat: Lattice,
    /// stretch of each bond in the field of v (with the constant parts: y0 at the ring,
    /// prescribed values); -inf once broken
    sv: Vec<f64>,
    /// a bound of |h_b|^2: the sum over the stored columns of the square of a bound of the
    /// bond's |stretch| in each column's field ([`add_run`])
    hn2: Vec<f64>,
    /// per block of [`SCREEN_BLOCK`] bonds: the largest s_b(v) (1 + slack) (an upper bound
    /// once a bond broke), the largest |h_b|^2 and the smallest critical-stretch scale (1
    /// without the surface correction)
    blk_v: Vec<f64>,
    blk_h2: Vec<f64>,
    blk_scale: Vec<f64>,
    /// scratch: a column's field at every dof (zero except at P and ring dofs), and its two
    /// components by node
    uw: Vec<f64>,
    /// Z_ring w_pc of each stored update column (its ring field, negated), and Z_ring v_pc: a
    /// state's ring value is y0 - rv - R y, read at O(k) a ring dof where it is needed
    /// ([`Fast::ring_at`]) instead of the whole Z_ring x_pc (|ring| |pc|) every state
    pub(super) rw: super::smw::UpdateColumns,
    pub(super) rv: Vec<f64>,
    /// the ring value at ring position r is current when `ring_stamp[r] == epoch`
    pub(super) ring_stamp: Vec<u32>,
    ux: Vec<f64>,
    uy: Vec<f64>,
    /// the coefficients y of the last state and |y|
    pub(super) y: Vec<f64>,
    pub(super) ynorm: f64,
    /// x is current at P unknown p when `stamp[p] == epoch` (one epoch per state)
    pub(super) stamp: Vec<u32>,
    pub(super) epoch: u32,
    /// the bonds of the largest exact stretches at the last step
    seeds: Vec<usize>,
    /// steps screened and bonds evaluated exactly in them (for the run's report)
    pub(super) steps: usize,
    pub(super) evaluated: usize,
}

/// The screening's order of the bonds: by kind (the lattice vector, with the offset of the
/// second node from the first in the grid's numbering), then first node, cut into runs of one
/// kind over consecutive first nodes (and at every [`BOND_CHUNK`]). A grid has a few dozen
/// kinds, so a run is a row of parallel bonds, whose first and second ends are two contiguous
/// ranges of nodes.
#[derive(Default)]
struct Lattice {
    /// position -> bond, bond -> position
    perm: Vec<u32>,
    pos: Vec<u32>,
    runs: Vec<Run>,
    /// the runs of chunk c (positions c BOND_CHUNK..): `chunk_runs[c]..chunk_runs[c + 1]`
    chunk_runs: Vec<usize>,
    kinds: Vec<Kind>,
}

/// Bonds of one kind at positions `start..start + len` from the consecutive nodes
/// `first..first + len` to `first + offset..`.
#[derive(Clone, Copy)]
struct Run {
    start: usize,
    first: usize,
    len: usize,
    kind: usize,
}

/// A lattice vector of bonds: the offset of the second node and the stretch coefficients
/// xi / |xi|^2.
#[derive(Clone, Copy)]
struct Kind {
    offset: i64,
    coef: [f64; 2],
}

impl Lattice {
    /// The order and runs of `bonds`; None beyond 65 536 kinds (not a grid's bonds).
    fn new(bonds: &[Bond]) -> Option<Self> {
        let mut index = std::collections::HashMap::new();
        let mut kinds = Vec::new();
        let mut kind_of = Vec::with_capacity(bonds.len());
        for b in bonds {
            let offset = i64::from(b.j) - i64::from(b.i);
            let key = (offset, b.xi[0].to_bits(), b.xi[1].to_bits());
            let k = *index.entry(key).or_insert_with(|| {
                let l2 = b.xi[0] * b.xi[0] + b.xi[1] * b.xi[1];
                kinds.push(Kind {
                    offset,
                    coef: [b.xi[0] / l2, b.xi[1] / l2],
                });
                kinds.len() - 1
            });
            kind_of.push(u16::try_from(k).ok()?);
        }
        // by kind (counting sort, stable), then first node (bonds come node by node: sorted
        // already, else sorted here)
        let mut start = vec![0usize; kinds.len() + 1];
        for &k in &kind_of {
            start[usize::from(k) + 1] += 1;
        }
        for k in 0..kinds.len() {
            start[k + 1] += start[k];
        }
        let bounds = start.clone();
        let mut perm = vec![0u32; bonds.len()];
        for (b, &k) in kind_of.iter().enumerate() {
            perm[start[usize::from(k)]] = b as u32;
            start[usize::from(k)] += 1;
        }
        for w in bounds.windows(2) {
            let part = &mut perm[w[0]..w[1]];
            if !part
                .windows(2)
                .all(|p| bonds[p[0] as usize].i <= bonds[p[1] as usize].i)
            {
                part.sort_unstable_by_key(|&b| (bonds[b as usize].i, b));
            }
        }
        let mut pos = vec![0u32; bonds.len()];
        for (p, &b) in perm.iter().enumerate() {
            pos[b as usize] = p as u32;
        }
        let mut runs: Vec<Run> = Vec::new();
        let mut chunk_runs = vec![0];
        for (p, &b) in perm.iter().enumerate() {
            let (first, kind) = (
                bonds[b as usize].i as usize,
                usize::from(kind_of[b as usize]),
            );
            if p > 0 && p % BOND_CHUNK == 0 {
                chunk_runs.push(runs.len());
            }
            match runs.last_mut() {
                Some(r)
                    if r.kind == kind
                        && r.first + r.len == first
                        && r.start + r.len == p
                        && p % BOND_CHUNK != 0 =>
                {
                    r.len += 1
                }
                _ => runs.push(Run {
                    start: p,
                    first,
                    len: 1,
                    kind,
                }),
            }
        }
        chunk_runs.push(runs.len());
        Some(Self {
            perm,
            pos,
            runs,
            chunk_runs,
            kinds,
        })
    }
}

/// f(chunk offset, chunk) over fixed chunks of `n` items, on all threads for many items.
fn chunked<T: Send, F: Fn(usize, T) + Sync>(items: Vec<T>, n: usize, f: F) {
    if n >= PARALLEL_BONDS {
        items
            .into_par_iter()
            .enumerate()
            .for_each(|(c, t)| f(c * BOND_CHUNK, t));
    } else {
        items
            .into_iter()
            .enumerate()
            .for_each(|(c, t)| f(c * BOND_CHUNK, t));
    }
}

/// Bound of the difference between the stretch from a kind's coefficients, c . du, and the
/// bond's own (xi . du) / |xi|^2 ([`Bond::stretch`]), relative to |c0 du0| + |c1 du1|: each form
/// rounds within 3 units of 2^-53 of it (2^-50).
const COEF_ROUNDING: f64 = 8.881_784_197_001_252e-16;

/// |h|^2 += (a bound of |h|)^2 for the bonds of a run, h = c0 (x_j - x_i) + c1 (y_j - y_i) their
/// stretches in a column's field from the kind's coefficients `c`, with their rounding (the
/// bound holds even when the two terms cancel): contiguous slices, vectorised.
#[inline(always)]
fn add_run(c: [f64; 2], (xi, xj): (&[f64], &[f64]), (yi, yj): (&[f64], &[f64]), hn2: &mut [f64]) {
    for ((((h2, &a), &b), &p), &q) in hn2.iter_mut().zip(xi).zip(xj).zip(yi).zip(yj) {
        let t0 = c[0] * (b - a);
        let t1 = c[1] * (q - p);
        let h = (t0 + t1).abs() + COEF_ROUNDING * (t0.abs() + t1.abs());
        *h2 += h * h;
    }
}

/// [`add_run`] over the runs of chunk `c` (positions `off..`, |h_b|^2 in `hn2`) in the column
/// field (`ux`, `uy`).
#[inline(always)]
fn chunk_pass(
    lat: &Lattice,
    (c, off): (usize, usize),
    (ux, uy): (&[f64], &[f64]),
    hn2: &mut [f64],
) {
    for r in &lat.runs[lat.chunk_runs[c]..lat.chunk_runs[c + 1]] {
        let k = lat.kinds[r.kind];
        let (i, j, n) = (r.first, (r.first as i64 + k.offset) as usize, r.len);
        let h = &mut hn2[r.start - off..r.start - off + n];
        add_run(
            k.coef,
            (&ux[i..i + n], &ux[j..j + n]),
            (&uy[i..i + n], &uy[j..j + n]),
            h,
        );
    }
}

/// [`chunk_pass`] compiled for AVX2 (4 lanes; the same operations, so the same results).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn chunk_pass_avx2(lat: &Lattice, co: (usize, usize), u: (&[f64], &[f64]), hn2: &mut [f64]) {
    chunk_pass(lat, co, u, hn2)
}

/// [`chunk_pass`] with AVX2 where the processor has it.
fn chunk_pass_best(lat: &Lattice, co: (usize, usize), u: (&[f64], &[f64]), hn2: &mut [f64]) {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the processor supports AVX2 (checked just above)
        return unsafe { chunk_pass_avx2(lat, co, u, hn2) };
    }
    chunk_pass(lat, co, u, hn2)
}

/// s_b(v) with its slack (the bound's first term, [`Fast::candidates`]); -inf for a broken
/// bond.
#[inline(always)]
fn v_slack(v: f64) -> f64 {
    if v == f64::NEG_INFINITY {
        v
    } else {
        v + BOUND_SLACK * v.abs()
    }
}

/// The largest value of `f` over each block of `x` (-inf for an empty one).
fn block_max(x: &[f64], out: &mut [f64], f: impl Fn(f64) -> f64) {
    for (xb, o) in x.chunks(SCREEN_BLOCK).zip(out.iter_mut()) {
        *o = xb.iter().fold(f64::NEG_INFINITY, |m, &v| m.max(f(v)));
    }
}

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

#[cfg(test)]
mod tests {
    use super::*;

    /// The lattice order's column pass, with and without AVX2, bounds every bond's own stretch
    /// (Bond::stretch) from above, both passes to the same bits; runs never cross a chunk.
    #[test]
    fn lattice_pass_bounds_each_bond() {
        // the bonds of a 70 x 130 grid within distance 2 (forward half), some left out
        let (nx, ny) = (70usize, 130usize);
        let node = |i: usize, j: usize| (j * (nx + 1) + i) as u32;
        let mut bonds = Vec::new();
        for j in 0..=ny {
            for i in 0..=nx {
                for (di, dj) in [
                    (1i64, 0i64),
                    (2, 0),
                    (-1, 1),
                    (0, 1),
                    (1, 1),
                    (0, 2),
                    (-2, 1),
                ] {
                    let (a, b) = (i as i64 + di, j as i64 + dj);
                    if a < 0 || a > nx as i64 || b > ny as i64 || (i * 7 + j * 3) % 11 == 0 {
                        continue;
                    }
                    bonds.push(Bond {
                        i: node(i, j),
                        j: node(a as usize, b as usize),
                        xi: [di as f64 * 0.1, dj as f64 * 0.1],
                        beta: 1.0,
                    });
                }
            }
        }
        assert!(bonds.len() > 2 * BOND_CHUNK);
        let lat = Lattice::new(&bonds).unwrap();
        let nn = (nx + 1) * (ny + 1);
        let u: Vec<f64> = (0..2 * nn)
            .map(|k| ((k * 37) % 101) as f64 * 1e-3 - 0.05)
            .collect();
        let (ux, uy): (Vec<f64>, Vec<f64>) = u.chunks(2).map(|c| (c[0], c[1])).unzip();
        let mut plain = vec![0.0; bonds.len()];
        let mut best = vec![0.0; bonds.len()];
        for (c, (hp, hb)) in plain
            .chunks_mut(BOND_CHUNK)
            .zip(best.chunks_mut(BOND_CHUNK))
            .enumerate()
        {
            chunk_pass(&lat, (c, c * BOND_CHUNK), (&ux, &uy), hp);
            chunk_pass_best(&lat, (c, c * BOND_CHUNK), (&ux, &uy), hb);
        }
        assert!(plain
            .iter()
            .zip(&best)
            .all(|(a, b)| a.to_bits() == b.to_bits()));
        for (p, &b) in lat.perm.iter().enumerate() {
            let s = bonds[b as usize].stretch(&u);
            assert!(
                plain[p].sqrt() >= s.abs() && plain[p].sqrt() <= s.abs() * (1.0 + 1e-12) + 1e-15
            );
            assert_eq!(lat.pos[b as usize] as usize, p);
        }
        for r in &lat.runs {
            assert_eq!(r.start / BOND_CHUNK, (r.start + r.len - 1) / BOND_CHUNK);
        }
    }
}
