//! Sequentially linear analysis (SLA, Ni et al. 2019; paper section 3) of the CCM-PD (or pure PD)
//! plate, and the drivers the Python bindings call ([`run`]).
//!
//! Each step solves the current (linear) model once at the reference load, computes the stretch of
//! every intact bond, takes lambda = min s0 / s over the bonds in tension, records (lambda,
//! sigma22, CMOD, u0 = lambda u0_ref) at that load, and breaks the critical bond (or, with
//! `tie_tol > 0`, every bond whose load factor is within that relative tolerance of lambda). Ties
//! closer than 1e-10 (mirror bonds in mode I) are broken deterministically: the lowest bond index
//! goes first, so two solvers that agree to round-off produce the same sequence.
//!
//! Two solvers:
//! * **oracle** (`fast = false`): reassemble the splice matrix and refactorise it (sparse LU,
//!   symbolic analysis reused) at every step.
//! * **fast** (default): condense once. The FEM rows never change when a bond breaks, so with
//!   y = free FEM dofs and x = PD dofs, y = y0 - Z x where Z = K_FF^{-1} K_FP (sparse Cholesky of the
//!   SPD FEM block, one multi-RHS solve for the few PD columns touched by hybrid elements), and
//!   S x = g with S = K_PP - K_PF Z, dense and small (2 x PD nodes). S is inverted once; a broken bond
//!   is a rank-1 change of S and g (a on the PD rows of its ends), handled by Sherman-Morrison-
//!   Woodbury with the capacitance inverse grown by bordering (O(k^2) per break). The Schur pivot
//!   of the bordering is the ratio det(S_k+1)/det(S_k): when it vanishes the body has separated
//!   (status "separated", never NaN). Optional periodic re-condensation (`refactor_every`).

//!
//! Entry point for the bindings: build [`CcmPdParams`] (start from [`CcmPdParams::paper`] and
//! override fields; `method` = [`Method::CcmPd`] or [`Method::Pd`]), call
//! [`run`]`(&params, &|step, max_steps| ...)`, read [`CcmPdResult`]. Every parameter is validated
//! ([`Error::InvalidInput`] names it and its range); a separated body ends the run with status
//! "separated" (never NaN); faer panics are caught inside the solver wrappers.

use crate::coupling::{ModelSpec, SpliceModel};
use crate::error::{check_finite, check_positive, Error, Result};
use crate::loading::{Grip, PlateLoad};
use crate::material::Elastic;
use crate::pd::{damage, BYTES_PER_BOND};
use crate::solver::{Cholesky, Lu};
use crate::sparse::{CscMatrix, Reduction};
use faer::linalg::solvers::DenseSolveCore;
use faer::Mat;
use rayon::prelude::*;
use std::time::Instant;

/// Options of the sequentially linear analysis.
#[derive(Debug, Clone, PartialEq)]
pub struct SlaParams {
    /// number of SLA steps (bond-break events); 0 = only the linear solution
    pub max_steps: usize,
    /// stop when the crack (pre-crack + broken bonds, along the pre-crack direction) reaches this
    pub stop_crack_length: Option<f64>,
    /// break together every bond with load factor <= lambda (1 + tie_tol); 0 = one bond per step
    pub tie_tol: f64,
    /// fast solver: re-condense after this many breaks (0 = never)
    pub refactor_every: usize,
    /// condensation + Sherman-Morrison-Woodbury (true) or refactorise every step (false, oracle)
    pub fast: bool,
    /// steps after which the damage field is stored (besides the final one)
    pub damage_at_steps: Vec<usize>,
}

impl Default for SlaParams {
    fn default() -> Self {
        Self {
            max_steps: 500,
            stop_crack_length: None,
            tie_tol: 0.0,
            refactor_every: 0,
            fast: true,
            damage_at_steps: Vec::new(),
        }
    }
}

/// Model choice: splice coupling with PD rectangles, or PD everywhere.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Method {
    CcmPd,
    Pd,
}

impl Method {
    /// Parses "ccm_pd" | "pd".
    pub fn parse(s: &str) -> Result<Self> {
        match s {
            "ccm_pd" => Ok(Method::CcmPd),
            "pd" => Ok(Method::Pd),
            _ => Err(Error::invalid("method", "'ccm_pd' or 'pd'", s)),
        }
    }
    pub fn name(&self) -> &'static str {
        match self {
            Method::CcmPd => "ccm_pd",
            Method::Pd => "pd",
        }
    }
}

/// Everything a CCM-PD / PD run needs (the paper's values in [`CcmPdParams::paper`]).
#[derive(Debug, Clone)]
pub struct CcmPdParams {
    pub method: Method,
    pub width: f64,
    pub height: f64,
    pub dx: f64,
    pub m: usize,
    pub material: Elastic,
    pub g0: f64,
    /// PD rectangles [x0, y0, x1, y1] (ignored by `Method::Pd`)
    pub pd_regions: Vec<[f64; 4]>,
    /// pre-crack polyline, first point at the crack mouth
    pub precrack: Vec<[f64; 2]>,
    pub load: PlateLoad,
    pub sla: SlaParams,
}

impl CcmPdParams {
    /// The paper's benchmark: W = 11, L = 21, dx = 1/15, m = 4, PD rectangle 2.73 x 1.67 centred at
    /// (1.70, 10.5), E = 10000, nu = 0.25, G0 = 0.367, plane strain, h = 1, u0 = 0.01, u1 free.
    pub fn paper() -> Self {
        use crate::material::Plane;
        Self {
            method: Method::CcmPd,
            width: 11.0,
            height: 21.0,
            dx: 1.0 / 15.0,
            m: 4,
            material: Elastic {
                e: 10000.0,
                nu: 0.25,
                plane: Plane::Strain,
                thickness: 1.0,
            },
            g0: 0.367,
            pd_regions: vec![[
                1.70 - 2.73 / 2.0,
                10.5 - 1.67 / 2.0,
                1.70 + 2.73 / 2.0,
                10.5 + 1.67 / 2.0,
            ]],
            precrack: vec![[0.0, 10.5], [1.1, 10.5]],
            load: PlateLoad {
                grip: Grip::Free,
                u0: 0.01,
                traction: 0.0,
            },
            sla: SlaParams::default(),
        }
    }

    /// The model part of the parameters.
    pub fn spec(&self) -> ModelSpec {
        ModelSpec {
            width: self.width,
            height: self.height,
            dx: self.dx,
            m: self.m,
            material: self.material,
            g0: self.g0,
            pd_regions: self.pd_regions.clone(),
            all_pd: self.method == Method::Pd,
            precrack: self.precrack.clone(),
            load: self.load,
        }
    }
}

/// One SLA step, recorded at the load that breaks its bond(s).
#[derive(Debug, Clone, PartialEq)]
pub struct SlaStep {
    /// 1-based step number
    pub step: usize,
    /// load factor lambda = min s0 / s
    pub lambda: f64,
    /// sigma22 at lambda
    pub sigma22: f64,
    /// CMOD at lambda
    pub cmod: f64,
    /// grip displacement lambda u0_ref
    pub u0: f64,
    /// bonds broken in this step (indices into the bond list; the first is the critical one)
    pub bonds: Vec<usize>,
    /// end nodes of the critical bond
    pub nodes: [usize; 2],
    /// crack length after the step
    pub crack_length: f64,
}

/// Result of a run.
#[derive(Debug, Clone)]
pub struct CcmPdResult {
    pub method: String,
    /// grip variant that ran ("free" | "clamped" | "traction")
    pub grip: String,
    /// "fast (condensation + SMW)" or "oracle (refactorise every step)", with fallbacks explained
    pub solver: String,
    /// displacements of all grid nodes (2 per node) at the reference load before any SLA break
    pub u: Vec<f64>,
    /// displacements at the reference load in the final state (after the last break)
    pub u_final: Vec<f64>,
    pub node_xy: Vec<[f64; 2]>,
    pub n_nodes: usize,
    pub n_dofs: usize,
    pub n_pd_nodes: usize,
    pub n_bonds: usize,
    pub n_precrack_bonds: usize,
    pub n_removed_elements: usize,
    pub bytes_per_bond: usize,
    pub gamma: f64,
    pub c: f64,
    pub s0: f64,
    pub delta: f64,
    /// sigma22 and CMOD at the reference load, before any SLA break
    pub sigma22: f64,
    pub cmod: f64,
    /// sum of all external nodal forces (x, y) at the reference load (splice imbalance)
    pub out_of_balance: [f64; 2],
    /// the node carrying u1 = 0 (grip "free") and its coordinates
    pub anchor_node: usize,
    pub anchor_xy: [f64; 2],
    pub history: Vec<SlaStep>,
    /// damage index of every PD node (order of `pd_nodes`) at the end
    pub damage: Vec<f64>,
    /// (step, damage of every PD node after that step) for the requested steps
    pub damage_at: Vec<(usize, Vec<f64>)>,
    pub pd_nodes: Vec<usize>,
    pub pd_node_xy: Vec<[f64; 2]>,
    /// which bonds are broken at the end (pre-crack included)
    pub broken: Vec<bool>,
    /// bond end nodes
    pub bond_nodes: Vec<[usize; 2]>,
    /// "completed" | "crack_length_reached" | "separated" | "no_bond_in_tension"
    pub status: String,
    pub n_refactorisations: usize,
    pub setup_seconds: f64,
    pub sla_seconds: f64,
    /// peak resident memory of the process (VmHWM), if the OS reports it
    pub peak_memory_bytes: Option<u64>,
}

/// Peak resident set size of this process (Linux `VmHWM`), if available.
pub fn peak_memory_bytes() -> Option<u64> {
    let s = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = s.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}

fn validate_sla(p: &SlaParams) -> Result<()> {
    if p.max_steps > 1_000_000 {
        return Err(Error::invalid("max_steps", "0..=1000000", p.max_steps));
    }
    if let Some(l) = p.stop_crack_length {
        check_positive("stop_crack_length", l)?;
    }
    check_finite("tie_tol", p.tie_tol)?;
    if !(0.0..1.0).contains(&p.tie_tol) {
        return Err(Error::invalid("tie_tol", "0 <= tie_tol < 1", p.tie_tol));
    }
    Ok(())
}

/// A state of the model at the reference load.
struct State {
    sigma22: f64,
    cmod: f64,
}

trait Engine {
    fn state(&mut self) -> Result<State>;
    /// displacements of the last `state`, valid at least at every bond end dof
    fn u(&self) -> &[f64];
    /// Removes bond `b`; Err(Separated) when the body separates.
    fn break_bond(&mut self, b: usize, broken_now: &[bool]) -> Result<()>;
    fn full_u(&mut self, broken_now: &[bool]) -> Result<Vec<f64>>;
    fn n_refactorisations(&self) -> usize;
}

/// Refactorise-every-step oracle.
struct Oracle<'a> {
    model: &'a SpliceModel,
    red: Reduction,
    lu: Lu,
    k: CscMatrix,
    dirty: bool,
    broken: Vec<bool>,
    n_fact: usize,
    /// max |u| of the first solve, the scale for the separation test
    u_scale: f64,
    u: Vec<f64>,
}

impl<'a> Oracle<'a> {
    fn new(model: &'a SpliceModel, broken: &[bool], k: &CscMatrix) -> Result<Self> {
        let k = k.clone();
        let red = Reduction::new(&k, &model.mask)?;
        let kff = red.reduce(&k);
        let lu = Lu::new(&kff)?;
        Ok(Self {
            model,
            red,
            lu,
            k,
            dirty: false,
            broken: broken.to_vec(),
            n_fact: 1,
            u_scale: 0.0,
            u: Vec::new(),
        })
    }
    fn refresh(&mut self) -> Result<()> {
        if self.dirty {
            self.k = self.model.assemble(&self.broken);
            let kff = self.red.reduce(&self.k);
            self.lu.factorize(&kff)?;
            self.n_fact += 1;
            self.dirty = false;
        }
        Ok(())
    }
}

fn separated(detail: String) -> Error {
    Error::Separated { detail }
}

impl Engine for Oracle<'_> {
    fn state(&mut self) -> Result<State> {
        self.refresh()?;
        let s = crate::coupling::solve_with(self.model, &self.k, &self.red, &self.lu)
            .map_err(|e| separated(format!("oracle solve failed: {e}")))?;
        if s.residual.is_nan() || s.residual >= 1e-6 {
            return Err(separated(format!(
                "residual {:.3e} of the refactorised system (numerically singular)",
                s.residual
            )));
        }
        // a separated part floats: its displacement is set by round-off and is huge
        let umax = s.u.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        if self.u_scale == 0.0 {
            self.u_scale = umax;
        } else if umax > 1e4 * self.u_scale {
            return Err(separated(format!(
                "displacements grew from {:.3e} to {umax:.3e} (singular system)",
                self.u_scale
            )));
        }
        self.u = s.u;
        Ok(State {
            sigma22: s.sigma22,
            cmod: s.cmod,
        })
    }
    fn break_bond(&mut self, b: usize, _: &[bool]) -> Result<()> {
        self.broken[b] = true;
        self.dirty = true;
        Ok(())
    }
    fn full_u(&mut self, _: &[bool]) -> Result<Vec<f64>> {
        self.state()?;
        Ok(self.u.clone())
    }
    fn u(&self) -> &[f64] {
        &self.u
    }
    fn n_refactorisations(&self) -> usize {
        self.n_fact
    }
}

/// One column block of Z: (first column, width, ring rows (row-major |ring| x width), sigma22
/// and CMOD functionals of its columns).
type ZBlock = (usize, usize, Vec<f64>, Vec<f64>, Vec<f64>);

/// Dof classes of the condensation.
const CLS_FIXED: u8 = 0;
const CLS_F: u8 = 1;
const CLS_P: u8 = 2;

/// Condensation onto the PD dofs + Sherman-Morrison-Woodbury.
struct Fast<'a> {
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
    sig_coef: Vec<f64>,
    cmod_const: f64,
    cmod_coef: Vec<f64>,
    /// inverse of the base condensed matrix, n_P x n_P
    sinv: Mat<f64>,
    x0: Vec<f64>,
    v: Vec<f64>,
    // SMW state
    w: Vec<Vec<f64>>,
    bt: Vec<Vec<(usize, f64)>>,
    cinv: Vec<f64>,
    refactor_every: usize,
    n_fact: usize,
    u_full: Vec<f64>,
    /// the matrix at the start (its FEM rows never change)
    k0: CscMatrix,
    is_top_y: Vec<bool>,
    wh: f64,
    /// broken bonds that wrote PD rows of top-edge nodes: sigma22 loses c (b . u) for each
    sig_bonds: Vec<(f64, [usize; 4], [f64; 4])>,
}

impl<'a> Fast<'a> {
    fn new(model: &'a SpliceModel, k: &CscMatrix, refactor_every: usize) -> Result<Self> {
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
        let np = p_dofs.len();
        let t0 = Instant::now();
        let k = k.clone();
        // K_FF and its Cholesky factorisation
        let mask_f: Vec<bool> = (0..n).map(|d| cls[d] != CLS_F).collect();
        let f_red = Reduction::new(&k, &mask_f)?;
        let chol = if nf > 0 {
            Some(
                Cholesky::new(&f_red.reduce(&k)).map_err(|e| Error::Singular {
                    detail: format!("FEM block of the splice matrix: {e}"),
                })?,
            )
        } else {
            None
        };
        timing("fast: Cholesky of K_FF", t0);
        let y0 = match &chol {
            Some(c) => c.solve(&f_red.rhs(&k, &model.f, &model.prescribed))?,
            None => Vec::new(),
        };
        // pattern-based coupling sets
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
        let ring: Vec<usize> = (0..n).filter(|&d| ring_flag[d]).collect();
        let mut ring_pos = vec![usize::MAX; n];
        for (r, &d) in ring.iter().enumerate() {
            ring_pos[d] = r;
        }
        // functionals: sigma22 = q . u with q = sum of the top y rows / (W h); CMOD = e . u
        let wh = model.spec.width * model.spec.material.thickness;
        let mut is_top_y = vec![false; n];
        for &t in &model.edges.top {
            is_top_y[2 * t + 1] = true;
        }
        let mut q = vec![0.0; n];
        for (c, qc) in q.iter_mut().enumerate() {
            for kk in k.col_ptr[c]..k.col_ptr[c + 1] {
                if is_top_y[k.row_idx[kk]] {
                    *qc += k.val[kk] / wh;
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
        // Z = K_FF^{-1} K_FP, column blocks; keep the ring rows and the functionals
        let npc = pc.len();
        let mut z_ring = vec![0.0; ring.len() * npc];
        if let Some(ch) = &chol {
            let f_dofs = &f_red.free;
            let blk_size: usize = std::env::var("RUSTFRAC_ZBLK")
                .ok()
                .and_then(|s| s.parse().ok())
                .filter(|&b: &usize| b > 0)
                .unwrap_or(32);
            let starts: Vec<usize> = (0..npc).step_by(blk_size).collect();
            // column blocks solved concurrently (the supernodal triangular solves themselves
            // parallelise poorly); each block keeps only its ring rows and functionals
            let blocks: Vec<Result<ZBlock>> = starts
                .par_iter()
                .map(|&c0| {
                    let nb = blk_size.min(npc - c0);
                    let mut blk = vec![0.0; nf * nb];
                    for t in 0..nb {
                        let col = p_dofs[pc[c0 + t]];
                        for kk in k.col_ptr[col]..k.col_ptr[col + 1] {
                            let r = k.row_idx[kk];
                            if cls[r] == CLS_F {
                                blk[t * nf + idx[r]] = k.val[kk];
                            }
                        }
                    }
                    ch.solve_in_place(&mut blk)?;
                    let mut zr = vec![0.0; ring.len() * nb];
                    let mut sq = vec![0.0; nb];
                    let mut se = vec![0.0; nb];
                    for t in 0..nb {
                        let zc = &blk[t * nf..(t + 1) * nf];
                        for (fi, &d) in f_dofs.iter().enumerate() {
                            sq[t] += q[d] * zc[fi];
                            se[t] += e[d] * zc[fi];
                        }
                        for (r, &d) in ring.iter().enumerate() {
                            zr[r * nb + t] = zc[idx[d]];
                        }
                    }
                    Ok((c0, nb, zr, sq, se))
                })
                .collect();
            for bl in blocks {
                let (c0, nb, zr, sq, se) = bl?;
                for t in 0..nb {
                    sig_coef[pc[c0 + t]] -= sq[t];
                    cmod_coef[pc[c0 + t]] -= se[t];
                    for r in 0..ring.len() {
                        z_ring[r * npc + c0 + t] = zr[r * nb + t];
                    }
                }
            }
        }
        let mut me = Self {
            model,
            cls,
            idx,
            p_dofs,
            f_red,
            chol,
            y0,
            pc,
            ring,
            ring_pos,
            z_ring,
            sig_const,
            sig_coef,
            cmod_const,
            cmod_coef,
            sinv: Mat::zeros(0, 0),
            x0: Vec::new(),
            v: Vec::new(),
            w: Vec::new(),
            bt: Vec::new(),
            cinv: Vec::new(),
            refactor_every,
            n_fact: 0,
            u_full: model.prescribed.clone(),
            is_top_y,
            wh,
            sig_bonds: Vec::new(),
            k0: CscMatrix {
                nrows: 0,
                ncols: 0,
                col_ptr: vec![0],
                row_idx: Vec::new(),
                val: Vec::new(),
            },
        };
        timing("fast: Z = K_FF^-1 K_FP", t0);
        me.condense(&k)?;
        timing("fast: condensed and inverted", t0);
        me.k0 = k;
        Ok(me)
    }

    /// Builds S = K_PP - K_PF Z and g from the current matrix, inverts S, resets the SMW state.
    fn condense(&mut self, k: &CscMatrix) -> Result<()> {
        let np = self.p_dofs.len();
        let npc = self.pc.len();
        let mut s = Mat::<f64>::zeros(np, np);
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
        for (pcol, &c) in self.p_dofs.iter().enumerate() {
            let col = s.col_as_slice_mut(pcol);
            for kk in k.col_ptr[c]..k.col_ptr[c + 1] {
                let r = k.row_idx[kk];
                if self.cls[r] == CLS_P {
                    col[self.idx[r]] += k.val[kk];
                }
            }
        }
        for &fd in &self.ring {
            let rp = self.ring_pos[fd];
            let zrow = &self.z_ring[rp * npc..(rp + 1) * npc];
            for kk in k.col_ptr[fd]..k.col_ptr[fd + 1] {
                let r = k.row_idx[kk];
                let v = k.val[kk];
                if self.cls[r] == CLS_P && v != 0.0 {
                    let pr = self.idx[r];
                    for (t, &z) in zrow.iter().enumerate() {
                        s[(pr, self.pc[t])] -= v * z;
                    }
                }
            }
        }
        let lu = s.partial_piv_lu();
        let ud = lu.U().diagonal();
        let (mut dmin, mut dmax) = (f64::INFINITY, 0.0f64);
        for i in 0..np {
            let a = ud[i].abs();
            dmin = dmin.min(a);
            dmax = dmax.max(a);
        }
        if np > 0 && (dmin.is_nan() || dmin <= 1e-13 * dmax) {
            return Err(separated(format!(
                "condensed PD matrix is singular (pivot ratio {:.3e})",
                dmin / dmax
            )));
        }
        self.sinv = lu.inverse();
        let mut x0 = vec![0.0; np];
        for (j, &gj) in g.iter().enumerate() {
            if gj != 0.0 {
                for (x, &a) in x0.iter_mut().zip(self.sinv.col_as_slice(j)) {
                    *x += a * gj;
                }
            }
        }
        if x0.iter().any(|v| !v.is_finite()) {
            return Err(separated("non-finite condensed solution".into()));
        }
        self.v = x0.clone();
        self.x0 = x0;
        self.w.clear();
        self.bt.clear();
        self.cinv.clear();
        self.n_fact += 1;
        Ok(())
    }

    fn x(&self) -> Vec<f64> {
        let k = self.w.len();
        let z: Vec<f64> = self
            .bt
            .iter()
            .map(|b| b.iter().map(|&(p, val)| val * self.v[p]).sum())
            .collect();
        let mut y = vec![0.0; k];
        for (i, yi) in y.iter_mut().enumerate() {
            let row = &self.cinv[i * k..(i + 1) * k];
            *yi = row.iter().zip(&z).map(|(a, b)| a * b).sum();
        }
        let mut x = self.v.clone();
        for (wc, &yc) in self.w.iter().zip(&y) {
            for (xi, &wi) in x.iter_mut().zip(wc) {
                *xi += wi * yc;
            }
        }
        x
    }
}

impl Engine for Fast<'_> {
    fn state(&mut self) -> Result<State> {
        let x = self.x();
        if x.iter().any(|v| !v.is_finite()) {
            return Err(separated("non-finite PD displacements".into()));
        }
        let npc = self.pc.len();
        for (p, &d) in self.p_dofs.iter().enumerate() {
            self.u_full[d] = x[p];
        }
        let xpc: Vec<f64> = self.pc.iter().map(|&p| x[p]).collect();
        for (r, &d) in self.ring.iter().enumerate() {
            let zrow = &self.z_ring[r * npc..(r + 1) * npc];
            let zx: f64 = zrow.iter().zip(&xpc).map(|(a, b)| a * b).sum();
            self.u_full[d] = self.y0[self.idx[d]] - zx;
        }
        let mut sigma22 = self.sig_const + dot(&self.sig_coef, &x);
        for (c, dofs, bv) in &self.sig_bonds {
            let bu: f64 = (0..4).map(|t| bv[t] * self.u_full[dofs[t]]).sum();
            sigma22 -= c * bu;
        }
        let cmod = self.cmod_const
            + self
                .cmod_coef
                .iter()
                .zip(&x)
                .map(|(a, b)| a * b)
                .sum::<f64>();
        Ok(State { sigma22, cmod })
    }

    fn break_bond(&mut self, b: usize, broken_now: &[bool]) -> Result<()> {
        if self.refactor_every > 0 && self.w.len() >= self.refactor_every {
            // re-condense with every bond broken so far except b, then apply b by SMW
            let mut before = broken_now.to_vec();
            before[b] = false;
            let k = self.model.assemble(&before);
            self.condense(&k)?;
        }
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
            if self.is_top_y[d] && model.is_pd[d / 2] && (t < 2 || model.is_pd[j]) {
                c_top += alpha * bv[t] / self.wh;
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
        // w = S0^{-1} a
        let mut w = vec![0.0; np];
        for &(p, val) in &a {
            for (wi, &s) in w.iter_mut().zip(self.sinv.col_as_slice(p)) {
                *wi += s * val;
            }
        }
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
        let e = &self.cinv;
        let ec: Vec<f64> = (0..k)
            .map(|r| (0..k).map(|c| e[r * k + c] * col[c]).sum())
            .collect();
        let re: Vec<f64> = (0..k)
            .map(|c| (0..k).map(|r| row[r] * e[r * k + c]).sum())
            .collect();
        let s = d - row.iter().zip(&ec).map(|(a, b)| a * b).sum::<f64>();
        if s.is_nan() || s.abs() <= 1e-10 {
            return Err(separated(format!(
                "breaking bond {b} ({i}-{j}) makes the system singular (Schur pivot {s:.3e})"
            )));
        }
        let k1 = k + 1;
        let mut ne = vec![0.0; k1 * k1];
        for r in 0..k {
            for c in 0..k {
                ne[r * k1 + c] = e[r * k + c] + ec[r] * re[c] / s;
            }
            ne[r * k1 + k] = -ec[r] / s;
        }
        for c in 0..k {
            ne[k * k1 + c] = -re[c] / s;
        }
        ne[k * k1 + k] = 1.0 / s;
        self.cinv = ne;
        for (vi, &wi) in self.v.iter_mut().zip(&w) {
            *vi += wi * beta0;
        }
        self.w.push(w);
        self.bt.push(bt);
        Ok(())
    }

    fn full_u(&mut self, _: &[bool]) -> Result<Vec<f64>> {
        self.state()?;
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

    fn n_refactorisations(&self) -> usize {
        self.n_fact
    }
    fn u(&self) -> &[f64] {
        &self.u_full
    }
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

fn timing(what: &str, t0: Instant) {
    if std::env::var_os("RUSTFRAC_TIMING").is_some() {
        eprintln!(
            "[rustfrac timing] {what}: {:.3} s",
            t0.elapsed().as_secs_f64()
        );
    }
}

fn crack_length(model: &SpliceModel, broken: &[bool]) -> f64 {
    let pc = &model.spec.precrack;
    let (p0, t, l0) = if pc.len() >= 2 {
        let d = [pc[1][0] - pc[0][0], pc[1][1] - pc[0][1]];
        let l = (d[0] * d[0] + d[1] * d[1]).sqrt();
        let l0: f64 = pc
            .windows(2)
            .map(|s| ((s[1][0] - s[0][0]).powi(2) + (s[1][1] - s[0][1]).powi(2)).sqrt())
            .sum();
        (pc[0], [d[0] / l, d[1] / l], l0)
    } else {
        ([0.0, 0.0], [1.0, 0.0], 0.0)
    };
    let mut len = l0;
    for (b, bond) in model.bonds.iter().enumerate() {
        if broken[b] && !model.precrack_broken[b] {
            let xi = model.grid.xy(bond.i as usize);
            let mid = [xi[0] + 0.5 * bond.xi[0], xi[1] + 0.5 * bond.xi[1]];
            len = len.max((mid[0] - p0[0]) * t[0] + (mid[1] - p0[1]) * t[1]);
        }
    }
    len
}

/// Runs a CCM-PD (or pure PD) model: linear solution at the reference load, then the SLA.
/// `progress(step, max_steps)` is called after every step.
pub fn run(params: &CcmPdParams, progress: &(dyn Fn(usize, usize) + Sync)) -> Result<CcmPdResult> {
    validate_sla(&params.sla)?;
    let t0 = Instant::now();
    let model = SpliceModel::new(&params.spec())?;
    timing("model built", t0);
    let mut broken = model.precrack_broken.clone();
    const DENSE_LIMIT: usize = 6000;
    let n_pd_free = (0..model.n_dofs())
        .filter(|&d| !model.mask[d] && model.is_pd[d / 2])
        .count();
    let k0 = model.assemble(&broken);
    let mut solver = String::new();
    let mut engine: Box<dyn Engine + '_> = if params.sla.fast && n_pd_free <= DENSE_LIMIT {
        solver.push_str(
            "fast (FEM condensed by Cholesky, dense PD system + Sherman-Morrison-Woodbury)",
        );
        Box::new(Fast::new(&model, &k0, params.sla.refactor_every)?)
    } else {
        solver.push_str("oracle (sparse LU refactorised every step)");
        if params.sla.fast {
            solver.push_str(&format!(
                "; fast path not applicable ({n_pd_free} free PD dofs > dense limit {DENSE_LIMIT})"
            ));
        }
        Box::new(Oracle::new(&model, &broken, &k0)?)
    };
    timing("engine ready", t0);
    // reference solution before breaking (u from the engine, reactions from the full matrix)
    let u0_full = engine.full_u(&broken)?;
    let sol0 = model.postprocess(&k0, u0_full, 0.0);
    drop(k0);
    let setup_seconds = t0.elapsed().as_secs_f64();
    timing("setup done", t0);

    let t1 = Instant::now();
    let s0 = model.pd.s0;
    let max_steps = params.sla.max_steps;
    let mut history = Vec::new();
    let mut damage_at = Vec::new();
    let mut status = "completed".to_string();
    let mut lam = vec![f64::INFINITY; model.bonds.len()];
    for step in 1..=max_steps {
        let st = match engine.state() {
            Ok(s) => s,
            Err(Error::Separated { .. }) => {
                status = "separated".into();
                break;
            }
            Err(e) => return Err(e),
        };
        // under displacement grips a cut load path leaves both parts held by their own grip: the
        // system stays regular but carries no load any more
        if params.load.grip != Grip::Traction && st.sigma22.abs() <= 1e-9 * sol0.sigma22.abs() {
            status = "separated".into();
            break;
        }
        let mut lmin = f64::INFINITY;
        for (b, bond) in model.bonds.iter().enumerate() {
            lam[b] = f64::INFINITY;
            if broken[b] {
                continue;
            }
            let s = bond.stretch(engine.u());
            if s > 0.0 {
                lam[b] = s0 / s;
                lmin = lmin.min(lam[b]);
            }
        }
        if !lmin.is_finite() {
            status = "no_bond_in_tension".into();
            break;
        }
        let tol = params.sla.tie_tol.max(1e-10);
        let mut sel: Vec<usize> = (0..model.bonds.len())
            .filter(|&b| lam[b] <= lmin * (1.0 + tol))
            .collect();
        if params.sla.tie_tol == 0.0 {
            sel.truncate(1);
        }
        let first = sel[0];
        let mut sep = false;
        for &b in &sel {
            broken[b] = true;
            match engine.break_bond(b, &broken) {
                Ok(()) => {}
                Err(Error::Separated { detail }) => {
                    timing(&detail, t1);
                    sep = true;
                    break;
                }
                Err(e) => return Err(e),
            }
        }
        let cl = crack_length(&model, &broken);
        let bf = &model.bonds[first];
        history.push(SlaStep {
            step,
            lambda: lmin,
            sigma22: lmin * st.sigma22,
            cmod: lmin * st.cmod,
            u0: lmin * params.load.u0,
            bonds: sel,
            nodes: [bf.i as usize, bf.j as usize],
            crack_length: cl,
        });
        if params.sla.damage_at_steps.contains(&step) {
            damage_at.push((
                step,
                damage(model.grid.n_nodes(), &model.bonds, &broken, &model.pd_nodes),
            ));
        }
        progress(step, max_steps);
        if sep {
            status = "separated".into();
            break;
        }
        if let Some(l) = params.sla.stop_crack_length {
            if cl >= l {
                status = "crack_length_reached".into();
                break;
            }
        }
    }
    let u_final = if status == "separated" {
        Vec::new()
    } else {
        engine.full_u(&broken)?
    };
    let sla_seconds = t1.elapsed().as_secs_f64();
    let nn = model.grid.n_nodes();
    Ok(CcmPdResult {
        method: params.method.name().into(),
        grip: params.load.grip.name().into(),
        solver,
        u: sol0.u,
        u_final,
        node_xy: (0..nn).map(|n| model.grid.xy(n)).collect(),
        n_nodes: nn,
        n_dofs: model.n_dofs(),
        n_pd_nodes: model.pd_nodes.len(),
        n_bonds: model.bonds.len(),
        n_precrack_bonds: model.precrack_broken.iter().filter(|&&b| b).count(),
        n_removed_elements: model.n_removed_elements,
        bytes_per_bond: BYTES_PER_BOND,
        gamma: model.pd.gamma,
        c: model.pd.c,
        s0,
        delta: model.pd.delta,
        sigma22: sol0.sigma22,
        cmod: sol0.cmod,
        out_of_balance: sol0.out_of_balance,
        anchor_node: model.anchor,
        anchor_xy: model.grid.xy(model.anchor),
        history,
        damage: damage(nn, &model.bonds, &broken, &model.pd_nodes),
        damage_at,
        pd_node_xy: model.pd_nodes.iter().map(|&n| model.grid.xy(n)).collect(),
        pd_nodes: model.pd_nodes.clone(),
        bond_nodes: model
            .bonds
            .iter()
            .map(|b| [b.i as usize, b.j as usize])
            .collect(),
        broken,
        status,
        n_refactorisations: engine.n_refactorisations(),
        setup_seconds,
        sla_seconds,
        peak_memory_bytes: peak_memory_bytes(),
    })
}
