//! The fast solver (default, `fast = true`): condense once, then low-rank updates.
//!
//! The FEM rows never change when a bond breaks, so with y = free FEM dofs and x = PD dofs,
//! y = y0 - Z x where Z = K_FF^{-1} K_FP, and S x = g with S = K_PP - K_PF Z, dense and small
//! (2 x PD nodes): `condensation.rs`. K_FP and K_PF touch only a thin interface I of FEM dofs, so
//! S needs only (K_FF^{-1})_II: one sparse Cholesky of the SPD FEM block with I ordered last
//! gives it from the factor's dense trailing block ([`crate::la::InterfaceCholesky`]). S is factorised
//! once, dense LU in place in two stages, the PD block away from the FEM coupling first (beside the
//! FEM factorisation; [`crate::la::LeadingLu`]), or, for large PD regions, sparse (`base.rs`, chosen
//! by `crate::pd::cost`), and
//! the columns of S^{-1} the breaks need are solved with it (`columns.rs`); a broken bond is a rank-1
//! change of S and g (a on the PD rows of its ends), handled by Sherman-Morrison-Woodbury with the
//! capacitance inverse grown by bordering (O(k^2) per break): `smw.rs`. The Schur pivot of the
//! bordering is the ratio det(S_k+1)/det(S_k): when it vanishes the body has separated (status
//! "separated", never NaN). Periodic re-condensation (`refactor_every`; by default
//! [`super::auto_refactor_every`]) bounds the stored update vectors, so a run of any length keeps
//! its memory at O(bonds + n_P^2).

mod base;
mod columns;
mod condensation;
mod screened_step;
mod screening;
mod smw;
mod update_columns;

pub use base::force_lu_form;
pub(super) use base::SparseFactor;
pub(super) use condensation::{bordered_analysis, dense_lead, schur_pattern, FemPart};
pub use screening::force_screening;

use super::engine::{all_stretches, separated, Engine, State, Update, U_GROWTH_SEPARATED};
use crate::error::Result;
use crate::la::Cholesky;
use crate::la::{CscMatrix, Reduction};
use crate::pd::splice::{SpliceModel, Spring};
use base::Base;
use columns::Columns;
use faer::linalg::matmul::matmul;
use faer::{Accum, ColMut, ColRef, MatRef, Par};
use std::sync::Arc;

/// Dof classes of the condensation.
const CLS_FIXED: u8 = 0;
const CLS_F: u8 = 1;
const CLS_P: u8 = 2;

/// The form of the base condensed system S_0 (`base.rs`): a dense LU or a sparse factor.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum SchurKind {
    Dense,
    Sparse,
}

/// Condensation onto the PD dofs + Sherman-Morrison-Woodbury.
pub(super) struct Fast<'a> {
    model: &'a SpliceModel,
    cls: Vec<u8>,
    /// dof -> index in its class
    idx: Vec<usize>,
    p_dofs: Vec<usize>,
    f_red: Reduction,
    chol: Option<Cholesky>,
    /// y0 at all free FEM dofs (index = F index)
    y0: Vec<f64>,
    /// P indices of the columns of K_FP
    pc: Vec<usize>,
    /// F dofs coupled to PD rows (K_PF columns) and the CMOD dofs: full dof ids
    ring: Vec<usize>,
    /// dof -> position in `ring`
    ring_pos: Vec<usize>,
    /// Z rows at the ring, row-major |ring| x |pc|
    z_ring: Vec<f64>,
    sig_const: f64,
    cmod_const: f64,
    /// the base condensed matrix S_0: its dense LU or its sparse factor (`base.rs`)
    base: Base,
    /// kept columns of S_0^{-1} (sparse base; `columns.rs`)
    columns: Columns,
    /// which form of S_0 to build at each condensation
    kind: SchurKind,
    /// the leading stage of the dense S's LU made beside the FEM part, for the first
    /// condensation (`condensation.rs`)
    lead: Option<crate::la::LeadingLu>,
    /// positions of the P dofs (nested dissection of the sparse Cholesky)
    p_xy: Vec<[f64; 2]>,
    x0: Vec<f64>,
    v: Vec<f64>,
    /// the P unknowns where every state computes x: the nonzeros of the sigma22 and CMOD
    /// coefficients, the load displacement's, the probes' and the loaded-edge bonds' PD dofs
    /// ([`Self::need`])
    needed: Vec<usize>,
    needed_mask: Vec<bool>,
    /// the ring positions where a screened state computes u (the FEM dofs among the load
    /// displacement's, the probes' and the loaded-edge bonds'; [`Self::need`])
    ring_needed: Vec<usize>,
    ring_needed_mask: Vec<bool>,
    /// nonzeros (P index, value) of `sig_coef` and `cmod_coef`
    sig_nz: Vec<(usize, f64)>,
    cmod_nz: Vec<(usize, f64)>,
    /// bond screening (`screening.rs`)
    scr: screening::Screening,
    // SMW state
    w: update_columns::UpdateColumns,
    bt: Vec<Vec<(usize, f64)>>,
    /// capacitance inverse, k x k in row-major storage of row stride `cs` (updated in place, the
    /// storage grows by doubling: no allocation per step)
    cinv: Vec<f64>,
    cs: usize,
    pub(super) refactor_every: usize,
    max_rank: usize,
    /// the model state the engine represents (for re-condensation)
    broken: Vec<bool>,
    springs: Vec<Spring>,
    n_fact: usize,
    /// 1 once the sparse form fell back from the bordered Cholesky to the LU of S (kept from
    /// then on: the base is the LU's)
    lu_fallbacks: usize,
    u_full: Vec<f64>,
    /// largest |u| at the needed dofs of the first state (0 before it): the scale of the
    /// accuracy check of [`Engine::state`]
    u_scale: f64,
    /// the matrix at the start (its FEM rows never change)
    k0: Arc<CscMatrix>,
    /// pure PD's S for the first condensation, built by the cost model (`schur_pattern`)
    first_s: Option<CscMatrix>,
    /// the response's coefficient on each row of K u (sigma22: 1 on the top edge's x2 rows)
    resp_coef: Vec<f64>,
    wh: f64,
    /// updates that changed rows of top-edge y dofs: sigma22 loses c (b . u) for each
    sig_bonds: Vec<(f64, [usize; 4], [f64; 4])>,
}

impl Engine for Fast<'_> {
    /// The state from the SMW updates, checked: displacements (at the dofs every state computes)
    /// beyond [`U_GROWTH_SEPARATED`] times the first state's are recomputed by a fresh
    /// condensation of the current model, and a separation when they stay so (the oracle's
    /// rule), so an inaccurate update is never returned.
    fn state(&mut self) -> Result<State> {
        let st = self.updated_state()?;
        let umax = self.needed_umax();
        if self.u_scale == 0.0 {
            self.u_scale = umax;
        }
        if umax <= U_GROWTH_SEPARATED * self.u_scale {
            return Ok(st);
        }
        let t0 = std::time::Instant::now();
        let k = self.model.assemble_with(&self.broken, &self.springs);
        self.condense(&k).map_err(|e| {
            separated(format!(
                "displacements grew from {:.3e} to {umax:.3e}, and the re-condensed system is \
                 singular: {e}",
                self.u_scale
            ))
        })?;
        super::engine::timing("fast: state recomputed by a fresh condensation", t0);
        let st = self.updated_state()?;
        let fresh = self.needed_umax();
        if fresh > U_GROWTH_SEPARATED * self.u_scale {
            return Err(separated(format!(
                "displacements grew from {:.3e} to {fresh:.3e} (re-condensed: singular system)",
                self.u_scale
            )));
        }
        Ok(st)
    }

    fn stretches(
        &mut self,
        model: &SpliceModel,
        broken: &[bool],
        scale: Option<&[f64]>,
        tol: f64,
        out: &mut [f64],
        only: &mut Vec<usize>,
    ) -> bool {
        if self.scr.on {
            self.screened_stretches(scale, tol, out, only);
            true
        } else {
            all_stretches(model, broken, &self.u_full, out);
            false
        }
    }

    fn apply(&mut self, upd: Update) -> Result<()> {
        if self.w.len() >= self.refactor_every {
            // re-condense with the state so far, then apply this update by SMW
            let k = self.model.assemble_with(&self.broken, &self.springs);
            self.condense(&k)?;
        }
        let (a, bt, beta0) = match upd {
            Update::Break(b) => self.bond_update(b)?,
            Update::Ground(sp) => self.spring_update(sp),
        };
        self.smw_append(a, bt, beta0, upd)?;
        match upd {
            Update::Break(b) => {
                self.broken[b] = true;
                self.screen_broken(b);
            }
            Update::Ground(sp) => self.springs.push(sp),
        }
        Ok(())
    }

    fn n_refactorisations(&self) -> usize {
        self.n_fact
    }
    fn max_update_rank(&self) -> usize {
        self.max_rank
    }
    fn inverse_columns(&self) -> usize {
        self.columns.computed
    }
    fn screening(&self) -> (usize, usize) {
        (self.scr.steps, self.scr.evaluated)
    }
    fn lu_fallbacks(&self) -> usize {
        self.lu_fallbacks
    }
    fn u(&self) -> &[f64] {
        &self.u_full
    }

    fn full_u(&mut self) -> Result<Vec<f64>> {
        self.state()?;
        let y = std::mem::take(&mut self.scr.y);
        let x = self.x_full(&y);
        self.scr.y = y;
        all_finite(&x)?;
        for (&d, &xv) in self.p_dofs.iter().zip(&x) {
            self.u_full[d] = xv;
        }
        let mut u = self.u_full.clone();
        if let Some(ch) = &self.chol {
            // y = y0 - K_FF^{-1} K_FP x
            let k = &self.k0;
            let mut xv = vec![0.0; u.len()];
            for &d in &self.p_dofs {
                xv[d] = u[d];
            }
            let kx = k.matvec(&xv);
            let mut rhs: Vec<f64> = self.f_red.free.iter().map(|&d| kx[d]).collect();
            ch.solve_in_place(&mut rhs)?;
            for (fi, &d) in self.f_red.free.iter().enumerate() {
                u[d] = self.y0[fi] - rhs[fi];
            }
        }
        Ok(u)
    }
}

impl Fast<'_> {
    /// The state from the SMW updates (unchecked: [`Engine::state`] checks it).
    fn updated_state(&mut self) -> Result<State> {
        let y = self.smw_coefficients();
        all_finite(&y)?;
        if self.scr.on {
            // x only where the state needs it, u at the ring dofs it reads; the bonds' ends as
            // `stretches` evaluates them
            self.scr.epoch = self.scr.epoch.wrapping_add(1);
            if self.scr.stamp.len() != self.p_dofs.len()
                || self.scr.ring_stamp.len() != self.ring.len()
                || self.scr.epoch == 0
            {
                self.scr.stamp = vec![0; self.p_dofs.len()];
                self.scr.ring_stamp = vec![0; self.ring.len()];
                self.scr.epoch = 1;
            }
            for &p in &self.needed {
                self.u_full[self.p_dofs[p]] = self.x_at(p, &y);
                self.scr.stamp[p] = self.scr.epoch;
            }
            self.scr.y = y;
            for i in 0..self.ring_needed.len() {
                self.ring_at(self.ring_needed[i]);
            }
        } else {
            let x = self.x_full(&y);
            all_finite(&x)?;
            for (&d, &xv) in self.p_dofs.iter().zip(&x) {
                self.u_full[d] = xv;
            }
            let xpc: Vec<f64> = self.pc.iter().map(|&p| x[p]).collect();
            let mut u = std::mem::take(&mut self.u_full);
            self.ring_into(&xpc, true, &mut u);
            self.u_full = u;
            self.scr.y = y;
        }
        all_finite(self.needed.iter().map(|&p| &self.u_full[self.p_dofs[p]]))?;
        all_finite(self.ring_needed.iter().map(|&r| &self.u_full[self.ring[r]]))?;
        let at = |nz: &[(usize, f64)]| -> f64 {
            nz.iter()
                .map(|&(p, c)| c * self.u_full[self.p_dofs[p]])
                .sum()
        };
        let mut sigma22 = self.sig_const + at(&self.sig_nz);
        for (c, dofs, bv) in &self.sig_bonds {
            let bu: f64 = (0..4).map(|t| bv[t] * self.u_full[dofs[t]]).sum();
            sigma22 -= c * bu;
        }
        let cmod = self.cmod_const + at(&self.cmod_nz);
        self.scr.ynorm = self.scr.y.iter().map(|v| v * v).sum::<f64>().sqrt();
        Ok(State { sigma22, cmod })
    }

    /// The largest |u| at the dofs every state computes (the needed P and ring dofs).
    fn needed_umax(&self) -> f64 {
        let p = self.needed.iter().map(|&p| self.u_full[self.p_dofs[p]]);
        let r = self.ring_needed.iter().map(|&r| self.u_full[self.ring[r]]);
        p.chain(r).fold(0.0f64, |a, v| a.max(v.abs()))
    }

    /// Z_ring x_pc: one matrix-vector product (SIMD kernels).
    fn z_ring_times(&self, xpc: &[f64]) -> Vec<f64> {
        let npc = self.pc.len();
        let mut zx = vec![0.0; self.ring.len()];
        if npc > 0 {
            matmul(
                ColMut::from_slice_mut(&mut zx).as_mat_mut(),
                Accum::Replace,
                MatRef::from_row_major_slice(&self.z_ring, self.ring.len(), npc),
                ColRef::from_slice(xpc).as_mat(),
                1.0,
                Par::Seq,
            );
        }
        zx
    }

    /// Adds the PD dofs among `dofs` to the unknowns every state computes x at, and their ring
    /// dofs to those where a screened state computes u.
    fn need(&mut self, dofs: impl IntoIterator<Item = usize>) {
        for d in dofs {
            match self.cls[d] {
                CLS_P => {
                    let p = self.idx[d];
                    if !self.needed_mask[p] {
                        self.needed_mask[p] = true;
                        self.needed.push(p);
                    }
                }
                CLS_F if self.ring_pos[d] != usize::MAX => {
                    let r = self.ring_pos[d];
                    if !self.ring_needed_mask[r] {
                        self.ring_needed_mask[r] = true;
                        self.ring_needed.push(r);
                    }
                }
                _ => {}
            }
        }
    }
}

/// The nonzeros (index, value) of a dense vector.
fn nonzeros(v: &[f64]) -> Vec<(usize, f64)> {
    v.iter()
        .enumerate()
        .filter(|(_, c)| **c != 0.0)
        .map(|(p, &c)| (p, c))
        .collect()
}

/// A separation when any of `x` is not finite (the SMW coefficients or the PD displacements of a
/// state: a vanishing pivot gone unnoticed makes them so).
fn all_finite<'v>(x: impl IntoIterator<Item = &'v f64>) -> Result<()> {
    if x.into_iter().all(|v| v.is_finite()) {
        Ok(())
    } else {
        Err(separated("non-finite PD displacements".into()))
    }
}
