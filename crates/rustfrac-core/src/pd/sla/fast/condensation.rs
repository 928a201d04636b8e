//! Condensation of the splice system onto the PD unknowns (the fast solver's setup).
//!
//! The dofs are fixed, free FEM (F) or free PD (P). The FEM rows never change when a bond breaks,
//! so y = y0 - Z x with Z = K_FF^{-1} K_FP, and S x = g with S = K_PP - K_PF Z (dense,
//! n_P x n_P). Of Z only the rows at the *ring* are kept: the F dofs coupled to PD rows (K_PF
//! columns), the CMOD, load and probe dofs. K_FP has rows only at H, the F dofs of hybrid
//! elements, so with the interface I = ring u H, Z_ring = ((K_FF^{-1})_II K_IP)_ring: one sparse
//! Cholesky of K_FF with I ordered last (nested dissection on the rest) gives
//! (K_FF^{-1})_II = (L_II L_II^T)^{-1} from its dense trailing block ([`InterfaceCholesky`];
//! |I| = 1164 of 102 499 on the paper's case), and the same factor gives y0. Earlier versions
//! solved K_FF for each of the |pc| = 256 columns of K_FP (0.87 s on the paper's case; now
//! 0.16 s at load 6, benches/RESULTS.md). sigma22 and CMOD
//! are linear functionals of u, condensed once into constants plus coefficients on x, their Z
//! parts by one adjoint solve: q_F . Z = (K_FF^{-1} q_F) . K_FP. [`Fast::new`] runs these phases;
//! `condense` builds and factorises S (also at every re-condensation); the dense S in two stages,
//! since K_PF Z changes only its rows and columns at the FEM coupling ([`dense_lead`]).

use super::base::{Base, Bordered, SparseFactor};
use super::Columns;

use super::{Fast, SchurKind, CLS_F, CLS_FIXED, CLS_P};
use crate::error::{Error, Result};
use crate::la::{CscMatrix, InterfaceCholesky, LeadingLu, Reduction, DENSE_PIVOT_TOL};
use crate::pd::cost::auto_refactor_every;
use crate::pd::sla::engine::{separated, timing};
use crate::pd::splice::{SpliceModel, Spring};
use faer::{Mat, Par};
use std::sync::Arc;
use std::time::Instant;

/// The Cholesky factor of K_FF with the interface last, and the interface's F indices.
type Factor = (InterfaceCholesky, Vec<usize>);

/// The dof classes: `cls[d]` (fixed, F or P), `idx[d]` the index of dof d in its class, the P dofs
/// in order and the number of F dofs.
struct DofClasses {
    cls: Vec<u8>,
    idx: Vec<usize>,
    p_dofs: Vec<usize>,
    nf: usize,
}

/// From the pattern: `pc`, the P indices of the columns of K_FP (PD columns with FEM rows); the
/// ring, the F dofs coupled to PD rows (K_PF columns) and the CMOD dofs, with each dof's position
/// in it (`usize::MAX` elsewhere).
struct Coupling {
    pc: Vec<usize>,
    ring: Vec<usize>,
    ring_pos: Vec<usize>,
}

/// sigma22 = q . u with q = sum of the top y rows / (W h), CMOD = e . u, condensed: a constant
/// (fixed and y0 parts) plus coefficients on x (the Z parts are subtracted by [`z_ring`]).
struct Functionals {
    sig_const: f64,
    sig_coef: Vec<f64>,
    cmod_const: f64,
    cmod_coef: Vec<f64>,
    /// the response's coefficient on each row of K u ([`crate::pd::splice::Response`])
    resp_coef: Vec<f64>,
    wh: f64,
}

/// The condensation's FEM part: dof classes, coupling sets, the Cholesky of K_FF and y0, the
/// functionals and Z at the ring. It does not depend on the form of S, so the engine computes it
/// while the cost model chooses that form.
pub(in crate::pd::sla) struct FemPart {
    dc: DofClasses,
    cp: Coupling,
    f_red: Reduction,
    ichol: Option<Factor>,
    y0: Vec<f64>,
    fun: Functionals,
    z_ring: Vec<f64>,
    probe_dofs: Vec<usize>,
}

impl FemPart {
    /// The FEM part of the condensation of `k` ([`FemPart`]), the Cholesky of K_FF on the threads
    /// `par`.
    pub(in crate::pd::sla) fn new(
        model: &SpliceModel,
        k: &CscMatrix,
        probe_dofs: &[usize],
        par: Par,
    ) -> Result<Self> {
        let dc = dof_classes(model);
        let t0 = Instant::now();
        let cp = coupling_sets(model, k, &dc, probe_dofs);
        let (f_red, ichol) = fem_block(model, k, &dc, &cp, par, t0)?;
        let (q, e, resp_coef) = response_rows(model, k);
        let (y0, qe) = fem_solves(model, k, &dc, &f_red, ichol.as_ref(), (&q, &e))?;
        let mut fun = functionals(model, &dc, &y0, (q, e, resp_coef));
        let z_ring = z_ring(k, &dc, ichol.as_ref(), &cp, &qe, &mut fun)?;
        timing("fast: Z = K_FF^-1 K_FP", t0);
        Ok(Self {
            dc,
            cp,
            f_red,
            ichol,
            y0,
            fun,
            z_ring,
            probe_dofs: probe_dofs.to_vec(),
        })
    }
}

impl<'a> Fast<'a> {
    /// The condensation of the matrix `k` of the state (`broken`, `springs`) from its FEM part
    /// ([`FemPart`]): S and its factor.
    pub(in crate::pd::sla) fn new(
        model: &'a SpliceModel,
        k: Arc<CscMatrix>,
        (broken, springs): (&[bool], &[Spring]),
        part: FemPart,
        refactor_every: usize,
        (kind, analysed, first_s): (SchurKind, Option<SparseFactor>, Option<CscMatrix>),
        lead: Option<LeadingLu>,
    ) -> Result<Self> {
        let t0 = Instant::now();
        let FemPart {
            dc,
            cp,
            f_red,
            ichol,
            y0,
            fun,
            z_ring,
            probe_dofs,
        } = part;
        let (np, nring) = (dc.p_dofs.len(), cp.ring.len());
        let chol = ichol.map(|(c, _)| c.into_cholesky());
        let mut me = Self {
            model,
            cls: dc.cls,
            idx: dc.idx,
            p_dofs: dc.p_dofs,
            f_red,
            chol,
            y0,
            pc: cp.pc,
            ring: cp.ring,
            ring_pos: cp.ring_pos,
            z_ring,
            sig_const: fun.sig_const,
            cmod_const: fun.cmod_const,
            needed: Vec::new(),
            needed_mask: vec![false; np],
            ring_needed: Vec::new(),
            ring_needed_mask: vec![false; nring],
            sig_nz: super::nonzeros(&fun.sig_coef),
            cmod_nz: super::nonzeros(&fun.cmod_coef),
            scr: Default::default(),
            base: analysed.map_or(Base::None, |f| Base::Sparse(Box::new(f))),
            columns: Columns::default(),
            kind,
            lead,
            p_xy: Vec::new(),
            x0: Vec::new(),
            v: Vec::new(),
            w: Default::default(),
            bt: Vec::new(),
            cinv: Vec::new(),
            cs: 0,
            refactor_every: if refactor_every > 0 {
                refactor_every
            } else {
                auto_refactor_every(np)
            },
            max_rank: 0,
            broken: broken.to_vec(),
            springs: springs.to_vec(),
            n_fact: 0,
            lu_fallbacks: 0,
            u_full: model.prescribed.clone(),
            u_scale: 0.0,
            resp_coef: fun.resp_coef,
            wh: fun.wh,
            sig_bonds: Vec::new(),
            k0: Arc::clone(&k),
            first_s,
        };
        me.p_xy = dof_xy(model, &me.p_dofs);
        let nz: Vec<usize> = (me.sig_nz.iter().chain(&me.cmod_nz))
            .map(|&(p, _)| me.p_dofs[p])
            .collect();
        let load = model.response.load_dofs();
        me.need(nz.into_iter().chain(load).chain(probe_dofs));
        me.condense(&k)?;
        timing("fast: condensed and factorised", t0);
        Ok(me)
    }

    /// Builds S = K_PP - K_PF Z and g from the current matrix, factorises S, resets the SMW state.
    pub(super) fn condense(&mut self, k: &CscMatrix) -> Result<()> {
        let t0 = Instant::now();
        // particular vector: prescribed values, y0 at F
        let mut w0 = self.model.prescribed.clone();
        for (d, w) in w0.iter_mut().enumerate() {
            match self.cls[d] {
                CLS_F => *w = self.y0[self.idx[d]],
                CLS_P => *w = 0.0,
                _ => {}
            }
        }
        let kw = k.matvec(&w0);
        let g: Vec<f64> = self
            .p_dofs
            .iter()
            .map(|&d| self.model.f[d] - kw[d])
            .collect();
        match self.kind {
            SchurKind::Dense => self.condense_dense(k, t0)?,
            SchurKind::Sparse => self.condense_sparse(k, t0)?,
        }
        let x0 = self.base.solve(&g)?;
        if x0.iter().any(|v| !v.is_finite()) {
            return Err(separated("non-finite condensed solution".into()));
        }
        self.v = x0.clone();
        self.x0 = x0;
        self.w.clear();
        self.bt.clear();
        self.screen_start();
        timing("fast: solved, screening started", t0);
        self.n_fact += 1;
        Ok(())
    }

    /// S = K_PP - K_PF Z as a sparse matrix ([`schur_sparse`]), factorised (symbolic analysis at
    /// the first condensation only).
    fn condense_sparse(&mut self, k: &CscMatrix, t0: Instant) -> Result<()> {
        if matches!(&self.base, Base::Sparse(f) if matches!(**f, SparseFactor::Bordered(_))) {
            if !super::base::lu_form_forced() && self.condense_bordered(k, t0)? {
                return Ok(());
            }
            // K_PP is not symmetric positive definite: the LU of S from now on
            self.base = Base::None;
            self.lu_fallbacks += 1;
        }
        let cp = CouplingRef {
            pc: &self.pc,
            ring: &self.ring,
            ring_pos: &self.ring_pos,
        };
        // pure PD's S (= K_PP) of the first condensation comes built from the cost model
        let first = self.first_s.take().filter(|_| self.n_fact == 0);
        let s = first.unwrap_or_else(|| {
            schur_sparse(
                k,
                &self.cls,
                &self.idx,
                &self.p_dofs,
                &cp,
                Some(&self.z_ring),
            )
        });
        timing("fast: sparse S = K_PP - K_PF Z built", t0);
        if !matches!(self.base, Base::Sparse(_)) {
            let symmetric = self.chol.is_none();
            self.base = Base::Sparse(Box::new(SparseFactor::analyze(&s, symmetric, &self.p_xy)?));
            timing("fast: sparse S analysed (ordering, supernodes)", t0);
        }
        if let Base::Sparse(f) = &mut self.base {
            f.factorize(&s)?;
        }
        self.columns.clear();
        timing("fast: sparse S factorised", t0);
        Ok(())
    }

    /// The nonzero entries of K_{P,ring} as (P index, ring position, value), ring dof by ring
    /// dof: the FEM coupling K_PF Z = K_{P,ring} Z_ring of both forms of S.
    fn p_ring_entries<'k>(
        &'k self,
        k: &'k CscMatrix,
    ) -> impl Iterator<Item = (usize, usize, f64)> + 'k {
        self.ring.iter().flat_map(move |&fd| {
            (k.col_ptr[fd]..k.col_ptr[fd + 1]).filter_map(move |kk| {
                let (r, v) = (k.row_idx[kk], k.val[kk]);
                (self.cls[r] == CLS_P && v != 0.0).then(|| (self.idx[r], self.ring_pos[fd], v))
            })
        })
    }

    /// The bordered form of S = K_PP + F E^T (`base.rs`): K_PP by Cholesky, then the Woodbury
    /// border. Ok(false) when K_PP is not symmetric (to round-off) or not positive definite.
    fn condense_bordered(&mut self, k: &CscMatrix, t0: Instant) -> Result<bool> {
        // K_{P,ring}'s entries by P row (for F below)
        let mut ent: Vec<(usize, usize, f64)> = self.p_ring_entries(k).collect();
        ent.sort_by_key(|e| e.0);
        let Base::Sparse(f) = &mut self.base else {
            return Ok(false);
        };
        let SparseFactor::Bordered(b) = f.as_mut() else {
            return Ok(false);
        };
        let kpp = kpp_sparse(k, &self.cls, &self.idx, &self.p_dofs);
        if !b.symmetric(&kpp) {
            return Ok(false);
        }
        let np = self.p_dofs.len();
        let npc = self.pc.len();
        // F = -K_{P,ring} Z_ring on the pc columns, column-major n_P x |pc|: blocks of rows
        // accumulated row-major (contiguous in Z_ring's rows) and written out by columns
        let mut fm = vec![0.0; np * npc];
        let mut blk = vec![0.0; F_BLOCK * npc];
        for group in ent.chunk_by(|a, b| a.0 / F_BLOCK == b.0 / F_BLOCK) {
            let r0 = group[0].0 / F_BLOCK * F_BLOCK;
            let nr = F_BLOCK.min(np - r0);
            blk.fill(0.0);
            for &(pr, rp, v) in group {
                let zrow = &self.z_ring[rp * npc..(rp + 1) * npc];
                let brow = &mut blk[(pr - r0) * npc..(pr - r0 + 1) * npc];
                for (f, &z) in brow.iter_mut().zip(zrow) {
                    *f -= v * z;
                }
            }
            for t in 0..npc {
                for (i, f) in fm[t * np + r0..t * np + r0 + nr].iter_mut().enumerate() {
                    *f = blk[i * npc + t];
                }
            }
        }
        timing("fast: K_PP and its FEM border built", t0);
        if !b.factorize(&kpp, fm)? {
            return Ok(false);
        }
        self.columns.clear();
        timing("fast: K_PP factorised (Cholesky), FEM border solved", t0);
        Ok(true)
    }

    /// S = K_PP - K_PF Z dense, factorised in place (LU) in two stages ([`LeadingLu`]): K_PF Z
    /// changes only the rows and columns of the PD unknowns coupled to the FEM part (T, ordered
    /// last by [`schur_order`]), so the LU of the rest does not depend on Z; at the first
    /// condensation it was made beside the FEM part ([`dense_lead`]), here at the later ones.
    /// Then the correction goes into the trailing block and only that is factorised.
    fn condense_dense(&mut self, k: &CscMatrix, t0: Instant) -> Result<()> {
        let npc = self.pc.len();
        let (order, pos, n1) =
            schur_order(k, &self.cls, &self.idx, &self.p_dofs, &self.ring, &self.pc);
        let mut lead = match self.lead.take() {
            Some(l) => l,
            None => {
                let s = kpp_block(k, &self.cls, &self.idx, &self.p_dofs, &pos);
                LeadingLu::new(s, n1, Some(order), faer::get_global_parallelism())?
            }
        };
        let in_t = |p: usize| {
            pos[p].checked_sub(n1).ok_or_else(|| Error::Internal {
                detail: "a PD unknown changed by K_PF Z outside the trailing block".into(),
            })
        };
        let pct = self
            .pc
            .iter()
            .map(|&p| in_t(p))
            .collect::<Result<Vec<_>>>()?;
        if lead.n1() != n1 {
            return Err(Error::Internal {
                detail: "the leading block of the dense S does not match its order".into(),
            });
        }
        let mut t = lead.trailing_mut();
        for (pr, rp, v) in self.p_ring_entries(k) {
            let zrow = &self.z_ring[rp * npc..(rp + 1) * npc];
            let tr = in_t(pr)?;
            for (&tc, &z) in pct.iter().zip(zrow) {
                t[(tr, tc)] -= v * z;
            }
        }
        timing("fast: S = K_PP - K_PF Z built", t0);
        let lu = lead
            .finish(DENSE_PIVOT_TOL, faer::get_global_parallelism())
            .map_err(|e| match e {
                Error::Singular { detail } => {
                    separated(format!("condensed PD matrix is singular ({detail})"))
                }
                e => e,
            })?;
        self.base = Base::Dense(Box::new(lu));
        self.columns.clear();
        timing("fast: S factorised (dense LU)", t0);
        Ok(())
    }
}

/// The order of the P unknowns in the dense S: the rest first, then T, the unknowns whose rows
/// or columns K_PF Z changes (the PD rows coupled to the ring's FEM dofs, and `pc`). Returns the
/// order (its i-th unknown's P index), each P index's position in it, and the size of the rest.
fn schur_order(
    k: &CscMatrix,
    cls: &[u8],
    idx: &[usize],
    p_dofs: &[usize],
    ring: &[usize],
    pc: &[usize],
) -> (Vec<usize>, Vec<usize>, usize) {
    let np = p_dofs.len();
    let mut in_t = vec![false; np];
    for &p in pc {
        in_t[p] = true;
    }
    for &fd in ring {
        for &r in &k.row_idx[k.col_ptr[fd]..k.col_ptr[fd + 1]] {
            if cls[r] == CLS_P {
                in_t[idx[r]] = true;
            }
        }
    }
    let order: Vec<usize> = (0..np)
        .filter(|&p| !in_t[p])
        .chain((0..np).filter(|&p| in_t[p]))
        .collect();
    let n1 = order.iter().take_while(|&&p| !in_t[p]).count();
    let mut pos = vec![0; np];
    for (i, &p) in order.iter().enumerate() {
        pos[p] = i;
    }
    (order, pos, n1)
}

/// K_PP as a dense n_P x n_P matrix in the order `pos` (P index -> row and column), the start
/// of the dense S = K_PP - K_PF Z.
fn kpp_block(
    k: &CscMatrix,
    cls: &[u8],
    idx: &[usize],
    p_dofs: &[usize],
    pos: &[usize],
) -> Mat<f64> {
    let np = p_dofs.len();
    let mut s = Mat::<f64>::zeros(np, np);
    for (pcol, &c) in p_dofs.iter().enumerate() {
        let col = s.col_as_slice_mut(pos[pcol]);
        for kk in k.col_ptr[c]..k.col_ptr[c + 1] {
            let r = k.row_idx[kk];
            if cls[r] == CLS_P {
                col[pos[idx[r]]] += k.val[kk];
            }
        }
    }
    s
}

/// The leading stage of the dense S's LU at the first condensation, on its own ([`LeadingLu`]
/// of K_PP in the order of [`schur_order`], on one thread): it does not depend on Z, so the
/// engine makes it beside the FEM part ([`FemPart`]), which also touches its fresh memory (n_P^2
/// values, 35 MB on the paper's case) while the FEM block factorises.
pub(in crate::pd::sla) fn dense_lead(
    model: &SpliceModel,
    k: &CscMatrix,
    probe_dofs: &[usize],
) -> Result<LeadingLu> {
    let t0 = Instant::now();
    let dc = dof_classes(model);
    let cp = coupling_sets(model, k, &dc, probe_dofs);
    let (order, pos, n1) = schur_order(k, &dc.cls, &dc.idx, &dc.p_dofs, &cp.ring, &cp.pc);
    let s = kpp_block(k, &dc.cls, &dc.idx, &dc.p_dofs, &pos);
    let lead = LeadingLu::new(s, n1, Some(order), Par::Seq)?;
    let what = format!(
        "engine: LU of the dense S's PD block ({n1} of {} unknowns, beside the FEM part)",
        dc.p_dofs.len()
    );
    timing(&what, t0);
    Ok(lead)
}

/// The position of the node of each dof (dofs 2n and 2n + 1 belong to node n).
fn dof_xy(model: &SpliceModel, dofs: &[usize]) -> Vec<[f64; 2]> {
    dofs.iter().map(|&d| model.grid.xy(d / 2)).collect()
}

fn dof_classes(model: &SpliceModel) -> DofClasses {
    let n = model.n_dofs();
    let mut cls = vec![CLS_FIXED; n];
    let mut idx = vec![usize::MAX; n];
    let mut p_dofs = Vec::new();
    let mut nf = 0;
    for d in 0..n {
        if model.mask[d] {
            continue;
        }
        if model.is_pd[d / 2] {
            cls[d] = CLS_P;
            idx[d] = p_dofs.len();
            p_dofs.push(d);
        } else {
            cls[d] = CLS_F;
            idx[d] = nf;
            nf += 1;
        }
    }
    DofClasses {
        cls,
        idx,
        p_dofs,
        nf,
    }
}

/// The interface of the partial factorisation, as F indices: the ring (K_PF columns, CMOD, load
/// and probe dofs) and the F rows of K_FP.
fn interface(k: &CscMatrix, dc: &DofClasses, cp: &Coupling) -> Vec<usize> {
    let mut on = vec![false; dc.nf];
    for &d in &cp.ring {
        on[dc.idx[d]] = true;
    }
    for &p in &cp.pc {
        let c = dc.p_dofs[p];
        for &r in &k.row_idx[k.col_ptr[c]..k.col_ptr[c + 1]] {
            if dc.cls[r] == CLS_F {
                on[dc.idx[r]] = true;
            }
        }
    }
    (0..dc.nf).filter(|&f| on[f]).collect()
}

/// The Cholesky factor of K_FF with the interface ([`interface`]) eliminated last (none without
/// free FEM dofs) with the interface's F indices, and y0 = K_FF^{-1} (f_F - K_F0 u0), the FEM
/// displacements with the PD dofs held at zero.
fn fem_block(
    model: &SpliceModel,
    k: &CscMatrix,
    dc: &DofClasses,
    cp: &Coupling,
    par: Par,
    t0: Instant,
) -> Result<(Reduction, Option<Factor>)> {
    let (n, cls, nf) = (model.n_dofs(), &dc.cls, dc.nf);
    let mask_f: Vec<bool> = (0..n).map(|d| cls[d] != CLS_F).collect();
    let f_red = Reduction::new(k, &mask_f)?;
    let ichol = if nf > 0 {
        let iface = interface(k, dc, cp);
        // geometric nested dissection on the rest (factor 10.29 M values against 10.54 M with AMD
        // on the paper's case, the factorisation 0.39-0.48 s against 0.51-0.53 s, whole process
        // 0.95 x; benches/RESULTS.md)
        let xy = dof_xy(model, &f_red.free);
        let c = InterfaceCholesky::new(&f_red.reduce(k), &iface, Some(&xy), par).map_err(|e| {
            Error::Singular {
                detail: format!("FEM block of the splice matrix: {e}"),
            }
        })?;
        Some((c, iface))
    } else {
        None
    };
    if let Some((c, iface)) = &ichol {
        let what = format!(
            "fast: Cholesky of K_FF ({nf} dofs, interface of {} last, factor nnz {})",
            iface.len(),
            c.cholesky().factor_nnz()
        );
        timing(&what, t0);
    }
    Ok((f_red, ichol))
}

/// The solves with K_FF, all three as one 3-column solve (each solve call reads the whole factor,
/// 82 MB on the paper's case, forward and back): y0 = K_FF^{-1} (f_F - K_F0 u0) and the adjoint vectors K_FF^{-1} q_F,
/// K_FF^{-1} e_F of sigma22 and CMOD ([`z_ring`]). Returns y0 and the adjoint vectors (q's then
/// e's, each of length n_F); all empty without free FEM dofs.
fn fem_solves(
    model: &SpliceModel,
    k: &CscMatrix,
    dc: &DofClasses,
    f_red: &Reduction,
    ichol: Option<&Factor>,
    (q, e): (&[f64], &[f64]),
) -> Result<(Vec<f64>, Vec<f64>)> {
    let Some((c, _)) = ichol else {
        return Ok((Vec::new(), Vec::new()));
    };
    let nf = dc.nf;
    let mut rhs = f_red.rhs(k, &model.f, &model.prescribed);
    rhs.resize(3 * nf, 0.0);
    for (d, &cl) in dc.cls.iter().enumerate() {
        if cl == CLS_F {
            rhs[nf + dc.idx[d]] = q[d];
            rhs[2 * nf + dc.idx[d]] = e[d];
        }
    }
    c.cholesky().solve_in_place(&mut rhs)?;
    let qe = rhs.split_off(nf);
    Ok((rhs, qe))
}

/// The coupling sets of the condensation, from the pattern of `k` ([`Coupling`]); the ring also
/// holds the load displacement's and the probes' (`probe_dofs`) FEM dofs.
fn coupling_sets(
    model: &SpliceModel,
    k: &CscMatrix,
    dc: &DofClasses,
    probe_dofs: &[usize],
) -> Coupling {
    let (n, cls, idx, np) = (model.n_dofs(), &dc.cls, &dc.idx, dc.p_dofs.len());
    let mut pc = Vec::new();
    let mut pc_pos = vec![usize::MAX; np];
    let mut ring_flag = vec![false; n];
    for c in 0..n {
        let rows = &k.row_idx[k.col_ptr[c]..k.col_ptr[c + 1]];
        match cls[c] {
            CLS_P if rows.iter().any(|&r| cls[r] == CLS_F) => {
                pc_pos[idx[c]] = pc.len();
                pc.push(idx[c]);
            }
            CLS_F if rows.iter().any(|&r| cls[r] == CLS_P) => {
                ring_flag[c] = true;
            }
            _ => {}
        }
    }
    if let Some((lo, hi, _)) = model.cmod_nodes {
        for d in [2 * lo, 2 * lo + 1, 2 * hi, 2 * hi + 1] {
            if cls[d] == CLS_F {
                ring_flag[d] = true;
            }
        }
    }
    // the load displacement of region scenes is read from u
    for d in model.response.load_dofs().chain(probe_dofs.iter().copied()) {
        if cls[d] == CLS_F {
            ring_flag[d] = true;
        }
    }
    let ring: Vec<usize> = (0..n).filter(|&d| ring_flag[d]).collect();
    let mut ring_pos = vec![usize::MAX; n];
    for (r, &d) in ring.iter().enumerate() {
        ring_pos[d] = r;
    }
    Coupling { pc, ring, ring_pos }
}

/// The rows of the sigma22 and CMOD functionals on u: q = sum of the response's rows of K / (W h)
/// and e (the CMOD's node pair), with the response's coefficient on each row of K u.
fn response_rows(model: &SpliceModel, k: &CscMatrix) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    let n = model.n_dofs();
    let wh = model.response.divisor;
    let resp_coef = model.response.dense_rows(n);
    let mut q = vec![0.0; n];
    for (c, qc) in q.iter_mut().enumerate() {
        for kk in k.col_ptr[c]..k.col_ptr[c + 1] {
            let r = resp_coef[k.row_idx[kk]];
            if r != 0.0 {
                *qc += k.val[kk] * r / wh;
            }
        }
    }
    let mut e = vec![0.0; n];
    if let Some((lo, hi, nr)) = model.cmod_nodes {
        e[2 * hi] += nr[0];
        e[2 * hi + 1] += nr[1];
        e[2 * lo] -= nr[0];
        e[2 * lo + 1] -= nr[1];
    }
    (q, e, resp_coef)
}

/// The sigma22 and CMOD functionals before the Z correction ([`Functionals`]) from their rows
/// ([`response_rows`]) and y0.
fn functionals(
    model: &SpliceModel,
    dc: &DofClasses,
    y0: &[f64],
    (q, e, resp_coef): (Vec<f64>, Vec<f64>, Vec<f64>),
) -> Functionals {
    let (n, cls, idx, np) = (model.n_dofs(), &dc.cls, &dc.idx, dc.p_dofs.len());
    let wh = model.response.divisor;
    let (mut sig_const, mut cmod_const) = (0.0, 0.0);
    let mut sig_coef = vec![0.0; np];
    let mut cmod_coef = vec![0.0; np];
    for d in 0..n {
        match cls[d] {
            CLS_FIXED => {
                sig_const += q[d] * model.prescribed[d];
                cmod_const += e[d] * model.prescribed[d];
            }
            CLS_F => {
                sig_const += q[d] * y0[idx[d]];
                cmod_const += e[d] * y0[idx[d]];
            }
            _ => {
                sig_coef[idx[d]] += q[d];
                cmod_coef[idx[d]] += e[d];
            }
        }
    }
    Functionals {
        sig_const,
        sig_coef,
        cmod_const,
        cmod_coef,
        resp_coef,
        wh,
    }
}

/// Z = K_FF^{-1} K_FP at the ring: K_FP has rows only at the interface I, so
/// Z_I = (K_FF^{-1})_II K_IP from the trailing block of the factor ([`InterfaceCholesky`]).
/// Returns Z's ring rows (row-major |ring| x |pc|) and subtracts the Z parts from the
/// functionals' coefficients: q_F . Z = (K_FF^{-1} q_F) . K_FP with the adjoint vectors `qe`
/// ([`fem_solves`]).
fn z_ring(
    k: &CscMatrix,
    dc: &DofClasses,
    ichol: Option<&Factor>,
    cp: &Coupling,
    qe: &[f64],
    fun: &mut Functionals,
) -> Result<Vec<f64>> {
    let (cls, idx, p_dofs, nf) = (&dc.cls, &dc.idx, &dc.p_dofs, dc.nf);
    let (pc, ring) = (&cp.pc, &cp.ring);
    let npc = pc.len();
    let mut z_ring = vec![0.0; ring.len() * npc];
    let Some((ch, iface)) = ichol else {
        return Ok(z_ring);
    };
    let mut ipos = vec![usize::MAX; nf];
    for (i, &f) in iface.iter().enumerate() {
        ipos[f] = i;
    }
    let mut zi = Mat::<f64>::zeros(iface.len(), npc);
    for (t, &p) in pc.iter().enumerate() {
        let col = p_dofs[p];
        for kk in k.col_ptr[col]..k.col_ptr[col + 1] {
            let r = k.row_idx[kk];
            if cls[r] == CLS_F {
                zi[(ipos[idx[r]], t)] = k.val[kk];
            }
        }
    }
    ch.apply_inverse_ii(zi.as_mut());
    for (r, &d) in ring.iter().enumerate() {
        let i = ipos[idx[d]];
        for t in 0..npc {
            z_ring[r * npc + t] = zi[(i, t)];
        }
    }
    // the functionals: the adjoint vectors K_FF^{-1} q_F and K_FF^{-1} e_F ([`fem_solves`])
    for &p in pc {
        let col = p_dofs[p];
        for kk in k.col_ptr[col]..k.col_ptr[col + 1] {
            let r = k.row_idx[kk];
            if cls[r] == CLS_F {
                fun.sig_coef[p] -= qe[idx[r]] * k.val[kk];
                fun.cmod_coef[p] -= qe[nf + idx[r]] * k.val[kk];
            }
        }
    }
    Ok(z_ring)
}

/// The coupling sets, borrowed (from a [`Coupling`] or from a [`Fast`]).
struct CouplingRef<'c> {
    pc: &'c [usize],
    ring: &'c [usize],
    ring_pos: &'c [usize],
}

/// S = K_PP - K_PF Z as a sparse matrix on the P indices: the P x P entries of `k` plus the block
/// (rows R = the P rows with an entry in a ring column) x (columns `pc`), -K_{R,ring} Z_ring,
/// stored whole (zeros included) so that the pattern is that of every state. `z_ring` None: the
/// pattern only (values 0). Pure PD has no ring: S = K_PP.
fn schur_sparse(
    k: &CscMatrix,
    cls: &[u8],
    idx: &[usize],
    p_dofs: &[usize],
    cp: &CouplingRef<'_>,
    z_ring: Option<&[f64]>,
) -> CscMatrix {
    let np = p_dofs.len();
    let npc = cp.pc.len();
    // block rows and their accumulated -K_{R,ring} Z_ring (row-major |R| x npc)
    let mut rpos = vec![usize::MAX; np];
    let mut rows: Vec<usize> = Vec::new();
    let mut block: Vec<f64> = Vec::new();
    for &fd in cp.ring {
        let rp = cp.ring_pos[fd];
        for kk in k.col_ptr[fd]..k.col_ptr[fd + 1] {
            let r = k.row_idx[kk];
            if cls[r] != CLS_P {
                continue;
            }
            let pr = idx[r];
            if rpos[pr] == usize::MAX {
                rpos[pr] = rows.len();
                rows.push(pr);
                block.extend(std::iter::repeat_n(0.0, npc));
            }
            if let Some(z) = z_ring {
                let v = k.val[kk];
                if v != 0.0 {
                    let zrow = &z[rp * npc..(rp + 1) * npc];
                    let brow = &mut block[rpos[pr] * npc..(rpos[pr] + 1) * npc];
                    for (b, &zz) in brow.iter_mut().zip(zrow) {
                        *b -= v * zz;
                    }
                }
            }
        }
    }
    // column by column: the P rows of K's column (ascending, as P indices follow the dofs) merged
    // with the block's rows (ascending) where the column is one of `pc`
    let mut pc_pos = vec![usize::MAX; np];
    for (t, &p) in cp.pc.iter().enumerate() {
        pc_pos[p] = t;
    }
    let mut order: Vec<usize> = (0..rows.len()).collect();
    order.sort_unstable_by_key(|&ri| rows[ri]);
    let mut col_ptr = Vec::with_capacity(np + 1);
    col_ptr.push(0);
    let mut row_idx = Vec::with_capacity(k.nnz() + rows.len() * npc);
    let mut val = Vec::with_capacity(row_idx.capacity());
    let mut kcol: Vec<(usize, f64)> = Vec::new();
    for (pcol, &c) in p_dofs.iter().enumerate() {
        kcol.clear();
        for kk in k.col_ptr[c]..k.col_ptr[c + 1] {
            let r = k.row_idx[kk];
            if cls[r] == CLS_P {
                let v = if z_ring.is_some() { k.val[kk] } else { 0.0 };
                kcol.push((idx[r], v));
            }
        }
        let t = pc_pos[pcol];
        let brow = |i: usize| {
            let ri = order[i];
            (rows[ri], block[ri * npc + t])
        };
        let nb = if t == usize::MAX { 0 } else { order.len() };
        let (mut i, mut j) = (0, 0);
        while i < kcol.len() || j < nb {
            let a = kcol.get(i).copied();
            let b = (j < nb).then(|| brow(j));
            let (r, v) = match (a, b) {
                (Some(a), Some(b)) if a.0 == b.0 => {
                    i += 1;
                    j += 1;
                    (a.0, a.1 + b.1)
                }
                (Some(a), Some(b)) if a.0 < b.0 => {
                    i += 1;
                    a
                }
                (Some(a), None) => {
                    i += 1;
                    a
                }
                (_, Some(b)) => {
                    j += 1;
                    b
                }
                (None, None) => unreachable!("the loop condition"),
            };
            row_idx.push(r);
            val.push(v);
        }
        col_ptr.push(row_idx.len());
    }
    CscMatrix {
        nrows: np,
        ncols: np,
        col_ptr,
        row_idx,
        val,
    }
}

/// Rows of F the bordered form builds at once (`condense_bordered`).
const F_BLOCK: usize = 64;

/// K_PP, the P x P entries of `k` (values included, zeros kept: the pattern of every state).
fn kpp_sparse(k: &CscMatrix, cls: &[u8], idx: &[usize], p_dofs: &[usize]) -> CscMatrix {
    let no_border = CouplingRef {
        pc: &[],
        ring: &[],
        ring_pos: &[],
    };
    schur_sparse(k, cls, idx, p_dofs, &no_border, Some(&[]))
}

/// The bordered form's symbolic analysis (`base.rs`): K_PP's pattern ordered by nested
/// dissection on the node positions, for the CCM-PD model of `k`; then K_PP itself factorised
/// ([`Bordered::lead`]): the engine makes both beside the FEM part, on the cost model's thread.
pub(in crate::pd::sla) fn bordered_analysis(
    model: &SpliceModel,
    k: &CscMatrix,
    probe_dofs: &[usize],
) -> Result<SparseFactor> {
    let dc = dof_classes(model);
    let cp = coupling_sets(model, k, &dc, probe_dofs);
    let kpp = kpp_sparse(k, &dc.cls, &dc.idx, &dc.p_dofs);
    let xy = dof_xy(model, &dc.p_dofs);
    let mut b = Bordered::analyze(&kpp, &xy, &cp.pc)?;
    b.lead(&kpp)?;
    Ok(SparseFactor::Bordered(Box::new(b)))
}

/// The pattern of the sparse S ([`schur_sparse`]), whether it is symmetric (pure PD: no free FEM
/// dofs) and the positions of its unknowns, for the engine's cost estimate and the symbolic
/// analysis. Values 0, except for pure PD: there S = K_PP does not depend on the FEM part, so it is
/// built whole here and the first condensation takes it ([`Fast::new`]).
pub(in crate::pd::sla) fn schur_pattern(
    model: &SpliceModel,
    k: &CscMatrix,
    probe_dofs: &[usize],
) -> (CscMatrix, bool, Vec<[f64; 2]>) {
    let dc = dof_classes(model);
    let cp = coupling_sets(model, k, &dc, probe_dofs);
    let cr = CouplingRef {
        pc: &cp.pc,
        ring: &cp.ring,
        ring_pos: &cp.ring_pos,
    };
    let pure_pd = dc.nf == 0;
    let s = schur_sparse(
        k,
        &dc.cls,
        &dc.idx,
        &dc.p_dofs,
        &cr,
        pure_pd.then_some(&[][..]),
    );
    let xy = dof_xy(model, &dc.p_dofs);
    (s, pure_pd, xy)
}
