//! The growth solve that reuses one factorisation: static condensation onto the enriched unknowns.
//!
//! The free unknowns of every growth step are the standard dofs S (same mesh, same Dirichlet
//! conditions and forces for the whole growth) and the enriched dofs E (they change with the
//! cracks). The standard-standard block K_SS is the stiffness of the uncracked plate: an enriched
//! element's standard-standard block is the same polynomial integrand integrated exactly by its
//! finer rule ([`crate::xfem::integration`]), so it equals the plain block up to round-off, and
//! K_SS = A is assembled from the plain blocks and factorised once (A = S^-1 P^T L L^T P S^-1,
//! [`crate::la::Cholesky`]). Each step then solves the block system by the Schur complement
//! onto E:
//!
//!   S_E = K_EE - K_ES A^-1 K_SE,  S_E u_E = r_E - K_ES A^-1 r_S,  A u_S = r_S - K_SE u_E,
//!
//! (r = f - K_fP u_P, the Dirichlet elimination). With w_j = L^-1 P S k_j for the column k_j of
//! K_SE, (K_ES A^-1 K_SE)_ij = w_i . w_j; k_j has a few nonzeros (the standard dofs of the
//! elements around its node), so w_j is a forward solve along the elimination-tree paths of
//! those dofs ([`crate::la::SparseForward`]). Columns are cached by their exact content (row and
//! value bits): an enriched dof whose K_SE column did not change since the last step (a Heaviside
//! dof of elements the crack crossed before) keeps its w and its products with the other cached
//! columns, and only the new columns (the tip dofs and the Heaviside dofs near the tip) are solved
//! and multiplied (blocked, [`crate::la::SparseForward::solve_many`]). A^-1 r_S and
//! L^-1 P S r_S are fixed (once for the growth). Per step: the enriched element blocks, the new
//! columns' path solves and products, the dense Cholesky of the equilibrated S_E (|E| ~
//! 10^2-10^3) and, for u_S = S P^T L^-T (L^-1 P S r_S - sum_j u_Ej w_j), one dense backward
//! half-solve, which bounds the step on large meshes (benches/RESULTS.md). The reference path, a
//! full factorisation per step ([`crate::xfem::plate`]), stays the oracle
//! (`xfem::run_reference`, tests/suite/xfem_growth_reuse.rs).
//!
//! Checks: the pivots of A and of the equilibrated S_E (the pivots of the LDL^T factorisation of
//! the equilibrated K with E eliminated last) below [`PIVOT_TOL`] are a singular system, and
//! their ratio above [`crate::la::COND_SINGULAR`] a numerically singular one. Condition estimate
//! ([`ConditionEstimate`] of the equilibrated K^ = D^-1/2 K D^-1/2 as before): ||K^||_1 (exact)
//! times the larger of the Hager-Higham estimates of ||A^^-1||_1 (once per growth) and of
//! ||S^_E^-1||_1, where S^_E^-1 = (K^^-1)_EE is a principal block of K^^-1 (so its norm is a lower
//! bound of ||K^^-1||_1) and A^^-1 <= (K^^-1)_SS in the Loewner order; the ill-conditioning of
//! XFEM systems sits in the enriched block. Measured against the full estimate in
//! tests/suite/xfem_growth_reuse.rs.

use super::model::XfemModel;
use super::plate::{PlateConditions, PlateProblem, PlateSolve};
use crate::error::{Error, Result};
use crate::la::condition::hager_higham;
use crate::la::{
    check_condition, Cholesky, ConditionEstimate, CscMatrix, Pattern, Reduction, SparseColumn,
    SparseForward, CONDITION_ITERATIONS, PIVOT_TOL,
};
use faer::linalg::solvers::Solve;
use faer::{Mat, MatMut, Side};
use rayon::prelude::*;
use std::collections::HashMap;

const NONE: usize = usize::MAX;

/// Free standard unknowns from which the path solves and products of a step run in parallel
/// (below, the work is a few milliseconds and threads cost more than they save on a loaded
/// machine).
const PARALLEL_MIN_UNKNOWNS: usize = 100_000;

/// The part of the system fixed for the whole growth: K_SS factorised, r_S and A^-1 r_S.
struct Fixed {
    /// the standard part of the Dirichlet mask, prescribed values and forces it was built for
    mask: Vec<bool>,
    up: Vec<f64>,
    f: Vec<f64>,
    /// standard dof -> free standard index (or NONE), free index -> dof
    map: Vec<usize>,
    /// the plain standard stiffness, all standard dofs (reactions)
    k_std: CscMatrix,
    chol: Cholesky,
    tree: SparseForward,
    /// r_S = f_S - K_SP u_P, A^-1 r_S and L^-1 P S r_S
    y: Vec<f64>,
    v: Vec<f64>,
    /// D^-1/2 of the free standard dofs
    s: Vec<f64>,
    /// column sums of |A^| (free standard columns, unscaled by their own s)
    abs_sums: Vec<f64>,
    /// smallest and largest pivot of A^
    pivots: (f64, f64),
    /// Hager-Higham estimate of ||A^^-1||_1 (when the condition estimate is asked for)
    inv_norm: Option<f64>,
}

impl Fixed {
    fn new(
        model: &XfemModel,
        mask: &[bool],
        up: &[f64],
        f: &[f64],
        condition: bool,
    ) -> Result<Self> {
        let ns = model.n_std;
        let blocks: Vec<Vec<usize>> = model
            .mesh
            .elements
            .iter()
            .map(|c| c.iter().flat_map(|&n| [2 * n, 2 * n + 1]).collect())
            .collect();
        let k_std = Pattern::symmetric(ns, &blocks)?
            .into_matrix(&blocks, &blocks, |e, out| model.plain_block(e, out));
        let red = Reduction::new(&k_std, mask)?;
        let a = red.reduce(&k_std);
        let xy: Vec<[f64; 2]> = red.free.iter().map(|&d| model.mesh.coords[d / 2]).collect();
        let chol = Cholesky::new_with(&a, Some(&xy))?;
        let tree = SparseForward::new(&chol)?;
        let rhs = red.rhs(&k_std, f, up);
        let y = chol.solve(&rhs)?;
        let v = tree.forward_dense(&chol, &rhs);
        let diag: Vec<f64> = (0..a.ncols)
            .map(|c| a.find(c, c).map_or(0.0, |k| a.val[k]))
            .collect();
        let pivots = chol.pivot_range(&diag)?;
        let s: Vec<f64> = diag.iter().map(|d| 1.0 / d.sqrt()).collect();
        let abs_sums = (0..a.ncols)
            .map(|c| {
                (a.col_ptr[c]..a.col_ptr[c + 1])
                    .map(|k| a.val[k].abs() * s[a.row_idx[k]])
                    .sum()
            })
            .collect();
        let inv_norm = if condition {
            Some(chol.inverse_norm_estimate(&diag)?)
        } else {
            None
        };
        Ok(Self {
            mask: mask.to_vec(),
            up: up.to_vec(),
            f: f.to_vec(),
            map: red.map,
            k_std,
            chol,
            tree,
            y,
            v,
            s,
            abs_sums,
            pivots,
            inv_norm,
        })
    }
}

/// The w_j of the enriched columns, keyed by the column's exact content, and their products.
#[derive(Default)]
struct ColumnCache {
    slot_of: HashMap<Vec<u64>, usize>,
    /// by slot: the column's key and w (None: a free slot)
    cols: Vec<Option<(Vec<u64>, SparseColumn)>>,
    /// products w_i . w_j, `cap` x `cap` by slot
    t: Vec<f64>,
    cap: usize,
}

impl ColumnCache {
    /// Frees every slot not in `keep`.
    fn retain(&mut self, keep: &[bool]) {
        for (slot, c) in self.cols.iter_mut().enumerate() {
            if !keep.get(slot).copied().unwrap_or(false) {
                if let Some((key, _)) = c.take() {
                    self.slot_of.remove(&key);
                }
            }
        }
    }

    /// A free slot (growing the product table when full).
    fn free_slot(&mut self) -> usize {
        if let Some(s) = self.cols.iter().position(Option::is_none) {
            return s;
        }
        let s = self.cols.len();
        self.cols.push(None);
        if s >= self.cap {
            let cap = (2 * self.cap).max(64);
            let mut t = vec![0.0; cap * cap];
            for i in 0..self.cap {
                t[i * cap..i * cap + self.cap]
                    .copy_from_slice(&self.t[i * self.cap..(i + 1) * self.cap]);
            }
            self.t = t;
            self.cap = cap;
        }
        s
    }
}

/// The enriched part of one step's system: K_SE by columns (free standard index, value), the
/// dense K_EE, r_E, and the enriched element blocks (for the reactions).
struct Enriched {
    /// free enriched dofs
    dofs: Vec<usize>,
    cols: Vec<Vec<(usize, f64)>>,
    kee: Mat<f64>,
    rhs: Vec<f64>,
    blocks: Vec<(usize, Vec<f64>)>,
}

impl Enriched {
    fn new(model: &XfemModel, fx: &Fixed, mask: &[bool], up: &[f64], f: &[f64]) -> Self {
        let ns = model.n_std;
        let mut idx = vec![NONE; model.n_dofs - ns];
        let mut dofs = Vec::new();
        for d in ns..model.n_dofs {
            if !mask[d] {
                idx[d - ns] = dofs.len();
                dofs.push(d);
            }
        }
        let ne = dofs.len();
        let mut cols: Vec<Vec<(usize, f64)>> = vec![Vec::new(); ne];
        let mut kee = Mat::<f64>::zeros(ne, ne);
        let mut rhs: Vec<f64> = dofs.iter().map(|&d| f[d]).collect();
        let mut blocks = Vec::new();
        for (e, en) in model.enriched_elements() {
            let mut blk = Vec::new();
            model.element_block(e, &mut blk);
            let nd = en.dofs.len();
            for (b, &db) in en.dofs.iter().enumerate() {
                if db < ns || idx[db - ns] == NONE {
                    continue;
                }
                let j = idx[db - ns];
                for (a, &da) in en.dofs.iter().enumerate() {
                    let v = blk[a * nd + b];
                    if da < ns {
                        match fx.map[da] {
                            NONE => rhs[j] -= blk[b * nd + a] * up[da],
                            r => cols[j].push((r, v)),
                        }
                    } else if idx[da - ns] != NONE {
                        kee[(idx[da - ns], j)] += v;
                    } else {
                        rhs[j] -= blk[b * nd + a] * up[da];
                    }
                }
            }
            blocks.push((e, blk));
        }
        for c in &mut cols {
            c.sort_by_key(|x| x.0);
            let mut merged: Vec<(usize, f64)> = Vec::with_capacity(c.len());
            for &(r, v) in c.iter() {
                match merged.last_mut() {
                    Some(last) if last.0 == r => last.1 += v,
                    _ => merged.push((r, v)),
                }
            }
            *c = merged;
        }
        Self {
            dofs,
            cols,
            kee,
            rhs,
            blocks,
        }
    }
}

/// The condensed growth solver: the fixed part built at the first step it solves (and again if
/// the standard conditions ever changed) and the column cache.
#[derive(Default)]
pub(super) struct CondensedSolver {
    fixed: Option<Fixed>,
    cache: ColumnCache,
}

impl CondensedSolver {
    /// One solve of `model` at the reference load of `plate`, as [`PlateProblem::solve`] (the
    /// same conditions, responses and checks; `what` names the solve) but by condensation on the
    /// enriched dofs (module documentation).
    pub(super) fn solve(
        &mut self,
        plate: &PlateProblem,
        model: &XfemModel,
        what: &str,
    ) -> Result<PlateSolve> {
        let c = plate.conditions(model)?;
        let (mask, up) = c.bc.to_mask(model.n_dofs)?;
        let ns = model.n_std;
        // the condensation assumes homogeneous conditions on enriched dofs (holes' removed
        // nodes: 0); anything else takes the reference path
        if (ns..model.n_dofs).any(|d| mask[d] && up[d] != 0.0) {
            return plate.solve(model, what);
        }
        let valid = self.fixed.as_ref().is_some_and(|fx| {
            fx.mask[..] == mask[..ns] && fx.up[..] == up[..ns] && fx.f[..] == c.f[..ns]
        });
        if !valid {
            self.fixed = Some(Fixed::new(
                model,
                &mask[..ns],
                &up[..ns],
                &c.f[..ns],
                plate.condition,
            )?);
            self.cache = ColumnCache::default();
        }
        let Some(fx) = self.fixed.as_ref() else {
            return Err(Error::Internal {
                detail: "condensed growth solve without its factorisation".into(),
            });
        };
        let en = Enriched::new(model, fx, &mask, &up, &c.f);
        let slots = update_cache(&mut self.cache, fx, &en.cols);
        let (u, condition) = solve_condensed(fx, &self.cache, &slots, &en, what, plate.condition)?;
        let mut full = up;
        for (i, &d) in fx.map.iter().enumerate() {
            if d != NONE {
                full[i] = u.0[d];
            }
        }
        for (j, &d) in en.dofs.iter().enumerate() {
            full[d] = u.1[j];
        }
        let reactions = reactions(model, fx, &en, &full, &c);
        plate.finish(model, &c, full, &reactions, condition)
    }
}

/// The slot of every enriched column: cached ones kept, the others solved (forward path solves,
/// in parallel) and their products with every current column computed; the rest evicted.
fn update_cache(cache: &mut ColumnCache, fx: &Fixed, cols: &[Vec<(usize, f64)>]) -> Vec<usize> {
    let keys: Vec<Vec<u64>> = cols
        .iter()
        .map(|c| {
            c.iter()
                .flat_map(|&(r, v)| [r as u64, v.to_bits()])
                .collect()
        })
        .collect();
    let mut slots: Vec<usize> = keys
        .iter()
        .map(|k| cache.slot_of.get(k).copied().unwrap_or(NONE))
        .collect();
    let mut keep = vec![false; cache.cols.len()];
    for &s in slots.iter().filter(|&&s| s != NONE) {
        keep[s] = true;
    }
    cache.retain(&keep);
    let new: Vec<usize> = (0..cols.len()).filter(|&j| slots[j] == NONE).collect();
    // blocked path solves, in two halves on a large factor (the new columns share most of their
    // paths: they belong to the elements around the tips)
    let parallel = fx.y.len() >= PARALLEL_MIN_UNKNOWNS;
    let solve_part = |part: &[usize]| {
        let bs: Vec<Vec<(usize, f64)>> = part.iter().map(|&j| cols[j].clone()).collect();
        fx.tree.solve_many(&fx.chol, &bs, &mut fx.tree.work())
    };
    let ws: Vec<SparseColumn> = if parallel {
        let half = new.len().div_ceil(2).max(1);
        new.par_chunks(half).map(solve_part).flatten().collect()
    } else {
        solve_part(&new)
    };
    let mut new_slots = Vec::with_capacity(new.len());
    for (&j, w) in new.iter().zip(ws) {
        // two columns with the same content share a slot
        if let Some(&s) = cache.slot_of.get(&keys[j]) {
            slots[j] = s;
            continue;
        }
        let s = cache.free_slot();
        cache.cols[s] = Some((keys[j].clone(), w));
        cache.slot_of.insert(keys[j].clone(), s);
        slots[j] = s;
        new_slots.push(s);
    }
    let mut live: Vec<usize> = slots.clone();
    live.sort_unstable();
    live.dedup();
    let w_of = |s: usize| cache.cols[s].as_ref().map(|c| &c.1);
    let row = |&sn: &usize| -> Vec<f64> {
        let wn = w_of(sn);
        live.iter()
            .map(|&sl| match (wn, w_of(sl)) {
                (Some(a), Some(b)) => a.dot(b),
                _ => 0.0,
            })
            .collect()
    };
    let rows: Vec<Vec<f64>> = if parallel {
        new_slots.par_iter().map(row).collect()
    } else {
        new_slots.iter().map(row).collect()
    };
    let cap = cache.cap;
    for (&sn, row) in new_slots.iter().zip(rows) {
        for (&sl, v) in live.iter().zip(row) {
            cache.t[sn * cap + sl] = v;
            cache.t[sl * cap + sn] = v;
        }
    }
    slots
}

/// (u_S, u_E) and the condition estimate (module documentation).
#[allow(clippy::type_complexity)]
fn solve_condensed(
    fx: &Fixed,
    cache: &ColumnCache,
    slots: &[usize],
    en: &Enriched,
    what: &str,
    condition: bool,
) -> Result<((Vec<f64>, Vec<f64>), Option<ConditionEstimate>)> {
    let ne = en.dofs.len();
    let cap = cache.cap;
    // the equilibrated Schur complement S^_E = D_E^-1/2 (K_EE - K_ES A^-1 K_SE) D_E^-1/2
    let mut se = Vec::with_capacity(ne);
    for j in 0..ne {
        let d = en.kee[(j, j)];
        if d.is_nan() || d <= 0.0 {
            return Err(Error::NotPositiveDefinite {
                detail: format!("{what}: enriched diagonal entry {j} is {d}"),
            });
        }
        se.push(1.0 / d.sqrt());
    }
    let sh = Mat::<f64>::from_fn(ne, ne, |i, j| {
        (en.kee[(i, j)] - cache.t[slots[i] * cap + slots[j]]) * se[i] * se[j]
    });
    let singular = |detail: String| Error::Singular {
        detail: format!("{what}: {detail}"),
    };
    let llt = sh.llt(Side::Lower).map_err(|e| {
        singular(format!(
            "the Schur complement onto the enriched dofs is not positive definite ({e:?}): a \
             part of the body is (nearly) disconnected"
        ))
    })?;
    let (mut pmin, mut pmax) = fx.pivots;
    let l = llt.L();
    let mut low = 0;
    for i in 0..ne {
        let p = l[(i, i)] * l[(i, i)];
        if p.is_nan() || p <= PIVOT_TOL {
            low += 1;
        }
        pmin = pmin.min(p);
        pmax = pmax.max(p);
    }
    if low > 0 {
        return Err(singular(format!(
            "{low} pivot(s) below {PIVOT_TOL:e} x their own diagonal entry: a rigid-body mode is \
             not constrained or a part of the body is disconnected"
        )));
    }
    let pivot_ratio = pmax / pmin;
    let estimate = if condition {
        let est = if ne > 0 {
            hager_higham(ne, CONDITION_ITERATIONS, |x: &mut [f64]| -> Result<()> {
                llt.solve_in_place(MatMut::from_column_major_slice_mut(x, ne, 1));
                Ok(())
            })?
        } else {
            0.0
        };
        let cond1 = norm1(fx, en, &se) * fx.inv_norm.unwrap_or(0.0).max(est);
        if !(cond1.is_finite() && pivot_ratio.is_finite()) {
            return Err(singular(format!(
                "condition estimate is not finite (cond1 {cond1:e}, pivot ratio {pivot_ratio:e})"
            )));
        }
        let c = ConditionEstimate {
            cond1,
            pivot_ratio,
            solves: 2,
        };
        check_condition(what, c.value())?;
        Some(c)
    } else {
        check_condition(what, pivot_ratio)?;
        None
    };
    // u_E = S_E^-1 (r_E - K_ES A^-1 r_S)
    let mut ue: Vec<f64> = (0..ne)
        .map(|j| {
            let g = en.rhs[j] - en.cols[j].iter().map(|&(r, v)| v * fx.y[r]).sum::<f64>();
            g * se[j]
        })
        .collect();
    if ne > 0 {
        llt.solve_in_place(MatMut::from_column_major_slice_mut(&mut ue, ne, 1));
    }
    for (v, s) in ue.iter_mut().zip(&se) {
        *v *= s;
    }
    // u_S = A^-1 (r_S - K_SE u_E) = S P^T L^-T (L^-1 P S r_S - sum_j u_Ej w_j): the forward
    // half from the cache, the backward half dense
    let mut v = fx.v.clone();
    for (&slot, &x) in slots.iter().zip(&ue) {
        if let Some((_, w)) = &cache.cols[slot] {
            w.axpy_into(-x, &mut v);
        }
    }
    let us = fx.tree.backward(&fx.chol, v)?;
    if ue.iter().chain(&us).any(|v| !v.is_finite()) {
        return Err(singular("non-finite displacements".into()));
    }
    Ok(((us, ue), estimate))
}

/// ||K^||_1 of the equilibrated free-free matrix from the fixed column sums of |A^| and the
/// enriched columns (`se` = D_E^-1/2).
fn norm1(fx: &Fixed, en: &Enriched, se: &[f64]) -> f64 {
    let mut std_sums = fx.abs_sums.clone();
    let mut enr_sums = vec![0.0; se.len()];
    for (j, col) in en.cols.iter().enumerate() {
        for &(r, v) in col {
            std_sums[r] += v.abs() * se[j];
            enr_sums[j] += v.abs() * fx.s[r];
        }
        for (i, s) in se.iter().enumerate() {
            enr_sums[j] += en.kee[(i, j)].abs() * s;
        }
    }
    let a = std_sums
        .iter()
        .zip(&fx.s)
        .map(|(c, s)| c * s)
        .fold(0.0, f64::max);
    enr_sums
        .iter()
        .zip(se)
        .map(|(c, s)| c * s)
        .fold(a, f64::max)
}

/// Reactions K u - f (all dofs): the plain standard stiffness times u, corrected in the enriched
/// elements by their own blocks.
fn reactions(
    model: &XfemModel,
    fx: &Fixed,
    en: &Enriched,
    u: &[f64],
    c: &PlateConditions,
) -> Vec<f64> {
    let ns = model.n_std;
    let mut r = fx.k_std.matvec(&u[..ns]);
    r.resize(model.n_dofs, 0.0);
    let mut plain = Vec::new();
    for (e, blk) in &en.blocks {
        let dofs = model.element_dofs(*e);
        let nd = dofs.len();
        for (a, &da) in dofs.iter().enumerate() {
            r[da] += dofs
                .iter()
                .enumerate()
                .map(|(b, &db)| blk[a * nd + b] * u[db])
                .sum::<f64>();
        }
        model.plain_block(*e, &mut plain);
        for a in 0..8 {
            r[dofs[a]] -= (0..8).map(|b| plain[a * 8 + b] * u[dofs[b]]).sum::<f64>();
        }
    }
    for (ri, fi) in r.iter_mut().zip(&c.f) {
        *ri -= fi;
    }
    r
}
