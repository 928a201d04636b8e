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
//! Small condensations go without it ([`crate::pd::cost::SCREEN_MIN_UNKNOWNS`]): x in full.

use rayon::prelude::*;

use crate::pd::bonds::Bond;

/// Bonds above which the screening's passes over them run on all threads.
pub(super) const PARALLEL_BONDS: usize = 1 << 15;
/// Bonds a thread takes at once in those passes (fixed: the result does not depend on threads).
pub(super) const BOND_CHUNK: usize = 4096;
/// Bonds of a block of the step's pass (a divisor of [`BOND_CHUNK`]).
pub(super) const SCREEN_BLOCK: usize = 256;
pub(super) const BLOCKS_PER_CHUNK: usize = BOND_CHUNK / SCREEN_BLOCK;
/// Relative margin of a block's test over its bonds' own tests (which it must never clear a
/// candidate of): covers the rounding of the two forms of the same inequality.
pub(super) const BLOCK_MARGIN: f64 = 1e-12;
/// Relative slack of each bound's terms, above the round-off of the exact stretches and of the
/// bounds' own accumulation (near 1e-14 of the terms; the kinds' coefficients of the column
/// passes, whose two terms may cancel, are bounded apart: [`COEF_ROUNDING`]).
pub(super) const BOUND_SLACK: f64 = 1e-9;
/// Relative margin of the cut below the tie window, for the round-off of the window's ends.
pub(super) const CUT_MARGIN: f64 = 1e-8;
/// Bonds of the largest exact stretches kept as the next step's seeds.
pub(super) const SEEDS: usize = 8;

thread_local! {
    /// Screens every condensation made on this thread, whatever its size (tests: the small
    /// cases then check the screening against the oracle).
    pub(super) static FORCE: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
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
    pub(super) lat: Lattice,
    /// stretch of each bond in the field of v (with the constant parts: y0 at the ring,
    /// prescribed values); -inf once broken
    pub(super) sv: Vec<f64>,
    /// a bound of |h_b|^2: the sum over the stored columns of the square of a bound of the
    /// bond's |stretch| in each column's field ([`add_run`])
    pub(super) hn2: Vec<f64>,
    /// per block of [`SCREEN_BLOCK`] bonds: the largest s_b(v) (1 + slack) (an upper bound
    /// once a bond broke), the largest |h_b|^2 and the smallest critical-stretch scale (1
    /// without the surface correction)
    pub(super) blk_v: Vec<f64>,
    pub(super) blk_h2: Vec<f64>,
    pub(super) blk_scale: Vec<f64>,
    /// scratch: a column's field at every dof (zero except at P and ring dofs), and its two
    /// components by node
    pub(super) uw: Vec<f64>,
    /// Z_ring w_pc of each stored update column (its ring field, negated), and Z_ring v_pc: a
    /// state's ring value is y0 - rv - R y, read at O(k) a ring dof where it is needed
    /// ([`Fast::ring_at`]) instead of the whole Z_ring x_pc (|ring| |pc|) every state
    pub(super) rw: super::update_columns::UpdateColumns,
    pub(super) rv: Vec<f64>,
    /// the ring value at ring position r is current when `ring_stamp[r] == epoch`
    pub(super) ring_stamp: Vec<u32>,
    pub(super) ux: Vec<f64>,
    pub(super) uy: Vec<f64>,
    /// the coefficients y of the last state and |y|
    pub(super) y: Vec<f64>,
    pub(super) ynorm: f64,
    /// x is current at P unknown p when `stamp[p] == epoch` (one epoch per state)
    pub(super) stamp: Vec<u32>,
    pub(super) epoch: u32,
    /// the bonds of the largest exact stretches at the last step
    pub(super) seeds: Vec<usize>,
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
pub(super) struct Lattice {
    /// position -> bond, bond -> position
    pub(super) perm: Vec<u32>,
    pub(super) pos: Vec<u32>,
    pub(super) runs: Vec<Run>,
    /// the runs of chunk c (positions c BOND_CHUNK..): `chunk_runs[c]..chunk_runs[c + 1]`
    pub(super) chunk_runs: Vec<usize>,
    pub(super) kinds: Vec<Kind>,
}

/// Bonds of one kind at positions `start..start + len` from the consecutive nodes
/// `first..first + len` to `first + offset..`.
#[derive(Clone, Copy)]
pub(super) struct Run {
    pub(super) start: usize,
    pub(super) first: usize,
    pub(super) len: usize,
    pub(super) kind: usize,
}

/// A lattice vector of bonds: the offset of the second node and the stretch coefficients
/// xi / |xi|^2.
#[derive(Clone, Copy)]
pub(super) struct Kind {
    pub(super) offset: i64,
    pub(super) coef: [f64; 2],
}

impl Lattice {
    /// The order and runs of `bonds`; None beyond 65 536 kinds (not a grid's bonds).
    pub(super) fn new(bonds: &[Bond]) -> Option<Self> {
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
pub(super) fn chunked<T: Send, F: Fn(usize, T) + Sync>(items: Vec<T>, n: usize, f: F) {
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
pub(super) const COEF_ROUNDING: f64 = 8.881_784_197_001_252e-16;

/// |h|^2 += (a bound of |h|)^2 for the bonds of a run, h = c0 (x_j - x_i) + c1 (y_j - y_i) their
/// stretches in a column's field from the kind's coefficients `c`, with their rounding (the
/// bound holds even when the two terms cancel): contiguous slices, vectorised.
#[inline(always)]
pub(super) fn add_run(
    c: [f64; 2],
    (xi, xj): (&[f64], &[f64]),
    (yi, yj): (&[f64], &[f64]),
    hn2: &mut [f64],
) {
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
pub(super) fn chunk_pass(
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
pub(super) fn chunk_pass_best(
    lat: &Lattice,
    co: (usize, usize),
    u: (&[f64], &[f64]),
    hn2: &mut [f64],
) {
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
pub(super) fn v_slack(v: f64) -> f64 {
    if v == f64::NEG_INFINITY {
        v
    } else {
        v + BOUND_SLACK * v.abs()
    }
}

/// The largest value of `f` over each block of `x` (-inf for an empty one).
pub(super) fn block_max(x: &[f64], out: &mut [f64], f: impl Fn(f64) -> f64) {
    for (xb, o) in x.chunks(SCREEN_BLOCK).zip(out.iter_mut()) {
        *o = xb.iter().fold(f64::NEG_INFINITY, |m, &v| m.max(f(v)));
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
