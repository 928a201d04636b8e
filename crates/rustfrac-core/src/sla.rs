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
//!   (status "separated", never NaN). Periodic re-condensation (`refactor_every`; by default
//!   [`auto_refactor_every`]) bounds the stored update vectors, so a run of any length keeps its
//!   memory at O(bonds + n_P^2): per step only the history row (about 100 bytes) is kept.
//!
//! **Detached nodes.** A PD node's rows hold only its bonds. When its intact bonds give no
//! stiffness along some direction of its free dofs (all broken, or the remaining ones parallel),
//! the system would be singular although the body has not separated. Such a node is *grounded*
//! along that direction by a spring ([`crate::coupling::Spring`], applied before the bond break
//! that needs it, so every intermediate matrix stays regular): with no external force it carries
//! none there, so no other result changes. Every grounding is reported (`detached_nodes`, a
//! warning); the pre-crack can detach nodes too (step 0). Only a true separation (a part of the
//! body no longer held: the Schur pivot vanishes, or the load path is cut) ends the run.
//!
//! **Checkpoints** ([`crate::checkpoint`]): every `checkpoint_every` steps (and when cancelled) the
//! broken-bond sequence and the history are written; `resume_from` replays them and continues, bit
//! for bit the same as an uninterrupted run.
//!
//! Entry point for the bindings: build [`CcmPdParams`] (start from [`CcmPdParams::paper`] and
//! override fields of its `model` ([`ModelSpec`]; `model.method` = [`Method::CcmPd`] or
//! [`Method::Pd`]) and `sla` ([`SlaParams`])), call [`run`]`(&params, &|step, max_steps| true)`
//! (return `false` to stop: status "cancelled"), read [`CcmPdResult`]. Every parameter is
//! validated ([`Error::InvalidInput`] names it and its range): the SLA options by
//! [`SlaParams::validate`], the model when it is built ([`SpliceModel::new`]); a separated body
//! ends the run with status "separated" (never NaN); faer panics are caught inside the solver
//! wrappers.

use crate::checkpoint;
pub use crate::coupling::Method;
use crate::coupling::{ModelSpec, SpliceModel, Spring};
use crate::error::{check_finite, check_positive, Error, Result};
use crate::loading::Grip;
use crate::pd::{damage, BYTES_PER_BOND};
use crate::solver::{Cholesky, Lu};
use crate::sparse::{CscMatrix, Reduction};
use crate::warning::{Warning, WarningKind};
use faer::linalg::solvers::DenseSolveCore;
use faer::Mat;
use rayon::prelude::*;
use std::path::PathBuf;
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
    /// fast solver: re-condense after this many low-rank updates (0 = automatic: when the stored
    /// update vectors reach [`auto_refactor_every`] of the condensed size, which bounds their
    /// memory by about 3/4 of the condensed inverse; see the module docs)
    pub refactor_every: usize,
    /// condensation + Sherman-Morrison-Woodbury (true) or refactorise every step (false, oracle)
    pub fast: bool,
    /// steps after which the damage field is stored (besides the final one)
    pub damage_at_steps: Vec<usize>,
    /// write a checkpoint to `checkpoint_path` after every this many steps (0 = never); a
    /// cancelled run writes one too
    pub checkpoint_every: usize,
    /// checkpoint file (written atomically: a temporary file in the same directory, then renamed)
    pub checkpoint_path: Option<PathBuf>,
    /// resume from this checkpoint: the model is rebuilt, the checkpoint's steps are replayed
    /// exactly (same low-rank updates in the same order) and the run continues; the history is the
    /// same bit for bit as an uninterrupted run's
    pub resume_from: Option<PathBuf>,
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
            checkpoint_every: 0,
            checkpoint_path: None,
            resume_from: None,
        }
    }
}

/// The automatic re-condensation interval of the fast solver for `n_p` condensed unknowns:
/// max(64, n_p / 2), at most 4096. Re-condensing costs O(n_p^3), a step with k stored updates
/// O(k n_p), so intervals of order n_p balance the two; n_p / 2 keeps the update vectors (k n_p)
/// and the capacitance inverse (k^2) below 3/4 of the condensed inverse (n_p^2), so the solver's
/// memory does not grow with the number of steps. The paper's case (n_p = 2080) never reaches it
/// in 500 steps.
pub fn auto_refactor_every(n_p: usize) -> usize {
    (n_p / 2).clamp(64, 4096)
}

/// Everything a CCM-PD / PD run needs: the model and the SLA options (the paper's values in
/// [`CcmPdParams::paper`]).
#[derive(Debug, Clone)]
pub struct CcmPdParams {
    /// plate, grid, horizon, material, G0, PD rectangles, pre-crack, load and method
    pub model: ModelSpec,
    pub sla: SlaParams,
}

impl CcmPdParams {
    /// The paper's benchmark ([`ModelSpec::paper`]) with the default SLA options.
    pub fn paper() -> Self {
        Self {
            model: ModelSpec::paper(),
            sla: SlaParams::default(),
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
    /// PD nodes that lost all stiffness along some direction in this step (every bond broken, or
    /// the remaining ones parallel) and were grounded along it (they carry no force there)
    pub detached: Vec<usize>,
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
    /// "completed" | "crack_length_reached" | "separated" | "no_bond_in_tension" | "cancelled"
    pub status: String,
    pub n_refactorisations: usize,
    /// largest number of low-rank update vectors the fast solver held at once (0 for the oracle);
    /// bounded by the re-condensation interval
    pub max_update_rank: usize,
    /// the re-condensation interval in use (fast solver; 0 for the oracle)
    pub refactor_interval: usize,
    /// (step, node) of every grounding of a detached node; step 0 = detached by the pre-crack
    pub detached_nodes: Vec<(usize, usize)>,
    /// accuracy warnings (e.g. m < 2, detached nodes); the run went on
    pub warnings: Vec<Warning>,
    /// steps replayed from `resume_from` (0 without resume)
    pub resumed_steps: usize,
    /// checkpoints written by this run
    pub n_checkpoints: usize,
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

impl SlaParams {
    /// Checks every option (the model is validated when it is built, [`SpliceModel::new`]).
    pub fn validate(&self) -> Result<()> {
        if self.max_steps > 1_000_000 {
            return Err(Error::invalid("max_steps", "0..=1000000", self.max_steps));
        }
        if let Some(l) = self.stop_crack_length {
            check_positive("stop_crack_length", l)?;
        }
        check_finite("tie_tol", self.tie_tol)?;
        if !(0.0..1.0).contains(&self.tie_tol) {
            return Err(Error::invalid("tie_tol", "0 <= tie_tol < 1", self.tie_tol));
        }
        if self.checkpoint_every > 0 && self.checkpoint_path.is_none() {
            return Err(Error::invalid(
                "checkpoint_path",
                "a file path when checkpoint_every > 0",
                "none",
            ));
        }
        Ok(())
    }
}

/// A state of the model at the reference load.
struct State {
    sigma22: f64,
    cmod: f64,
}

/// One change of the model between two solves: a bond removed, or a grounding spring added.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Update {
    Break(usize),
    Ground(Spring),
}

trait Engine {
    fn state(&mut self) -> Result<State>;
    /// displacements of the last `state`, valid at least at every bond end dof
    fn u(&self) -> &[f64];
    /// Applies one change; Err(Separated) when the body separates.
    fn apply(&mut self, upd: Update) -> Result<()>;
    fn full_u(&mut self) -> Result<Vec<f64>>;
    fn n_refactorisations(&self) -> usize;
    /// largest number of stored low-rank update vectors so far (0: none kept)
    fn max_update_rank(&self) -> usize;
}

/// Refactorise-every-step oracle.
struct Oracle<'a> {
    model: &'a SpliceModel,
    red: Reduction,
    lu: Lu,
    k: CscMatrix,
    dirty: bool,
    broken: Vec<bool>,
    springs: Vec<Spring>,
    n_fact: usize,
    /// max |u| of the first solve, the scale for the separation test
    u_scale: f64,
    u: Vec<f64>,
}

impl<'a> Oracle<'a> {
    fn new(
        model: &'a SpliceModel,
        broken: &[bool],
        springs: &[Spring],
        k: &CscMatrix,
    ) -> Result<Self> {
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
            springs: springs.to_vec(),
            n_fact: 1,
            u_scale: 0.0,
            u: Vec::new(),
        })
    }
    fn refresh(&mut self) -> Result<()> {
        if self.dirty {
            self.k = self.model.assemble_with(&self.broken, &self.springs);
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
    fn apply(&mut self, upd: Update) -> Result<()> {
        match upd {
            Update::Break(b) => self.broken[b] = true,
            Update::Ground(s) => self.springs.push(s),
        }
        self.dirty = true;
        Ok(())
    }
    fn full_u(&mut self) -> Result<Vec<f64>> {
        self.state()?;
        Ok(self.u.clone())
    }
    fn u(&self) -> &[f64] {
        &self.u
    }
    fn n_refactorisations(&self) -> usize {
        self.n_fact
    }
    fn max_update_rank(&self) -> usize {
        0
    }
}

/// One column block of Z: (first column, width, ring rows (row-major |ring| x width), sigma22
/// and CMOD functionals of its columns).
type ZBlock = (usize, usize, Vec<f64>, Vec<f64>, Vec<f64>);

/// A Schur pivot of the SMW bordering below this (but above 1e-10) is checked by a fresh
/// condensation: legitimate breaks give pivots of order 1e-2..1 (the paper's 500 steps: none
/// below 1e-3), a mechanism gives round-off (1e-6 after a few hundred updates).
const SUSPICIOUS_PIVOT: f64 = 1e-4;

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
    /// capacitance inverse, k x k in row-major storage of row stride `cs` (updated in place, the
    /// storage grows by doubling: no allocation per step)
    cinv: Vec<f64>,
    cs: usize,
    refactor_every: usize,
    max_rank: usize,
    /// the model state the engine represents (for re-condensation)
    broken: Vec<bool>,
    springs: Vec<Spring>,
    n_fact: usize,
    u_full: Vec<f64>,
    /// the matrix at the start (its FEM rows never change)
    k0: CscMatrix,
    is_top_y: Vec<bool>,
    wh: f64,
    /// updates that changed rows of top-edge y dofs: sigma22 loses c (b . u) for each
    sig_bonds: Vec<(f64, [usize; 4], [f64; 4])>,
}

impl<'a> Fast<'a> {
    fn new(
        model: &'a SpliceModel,
        k: &CscMatrix,
        broken: &[bool],
        springs: &[Spring],
        refactor_every: usize,
    ) -> Result<Self> {
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
            let row = &self.cinv[i * self.cs..i * self.cs + k];
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
            Update::Break(b) => self.broken[b] = true,
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
    fn u(&self) -> &[f64] {
        &self.u_full
    }

    fn full_u(&mut self) -> Result<Vec<f64>> {
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
}

impl Fast<'_> {
    /// Rank-1 data of removing bond `b`: S changes by -a bt^T on the free PD rows, g by a beta0.
    #[allow(clippy::type_complexity)]
    fn bond_update(&mut self, b: usize) -> Result<(Vec<(usize, f64)>, Vec<(usize, f64)>, f64)> {
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
        Ok((a, bt, beta0))
    }

    /// Rank-1 data of a grounding spring k p p^T at a PD node: S changes by +k p p^T on its free
    /// dofs (a = -k p, bt = p), g does not change (its dofs carry no prescribed value).
    #[allow(clippy::type_complexity)]
    fn spring_update(&mut self, sp: Spring) -> (Vec<(usize, f64)>, Vec<(usize, f64)>, f64) {
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
                if self.is_top_y[d] {
                    c_top -= ks * sp.p[t] / self.wh;
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
    fn smw_append(
        &mut self,
        a: Vec<(usize, f64)>,
        bt: Vec<(usize, f64)>,
        beta0: f64,
        upd: Update,
    ) -> Result<()> {
        let np = self.p_dofs.len();
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

/// Grounding springs already applied, per node (at most two orthonormal directions each), and the
/// work arrays of the bounded fragment search.
struct Grounding {
    dirs: std::collections::HashMap<usize, Vec<[f64; 2]>>,
    /// visit stamps per node (`stamp[n] == epoch`: seen in the current search)
    stamp: Vec<u32>,
    epoch: u32,
}

impl Grounding {
    fn new(n_nodes: usize) -> Self {
        Self {
            dirs: Default::default(),
            stamp: vec![0; n_nodes],
            epoch: 0,
        }
    }

    /// The debris fragment containing node `n` under `broken`: its component over intact bonds
    /// when that holds at most `limit` nodes, none of them held ([`SpliceModel::is_held`]).
    /// Breadth-first, stopping at the first held node or when the limit is passed: O(limit x
    /// family). Sorted node ids.
    fn debris_fragment(
        &mut self,
        model: &SpliceModel,
        n: usize,
        broken: &[bool],
        limit: usize,
    ) -> Option<Vec<usize>> {
        if model.is_held(n) {
            return None;
        }
        self.epoch = self.epoch.wrapping_add(1);
        if self.epoch == 0 {
            self.stamp.iter_mut().for_each(|s| *s = 0);
            self.epoch = 1;
        }
        let e = self.epoch;
        self.stamp[n] = e;
        let mut seen = vec![n];
        let mut k = 0;
        while k < seen.len() {
            let a = seen[k];
            k += 1;
            for &b in model.bonds_of(a) {
                if broken[b as usize] {
                    continue;
                }
                let bond = &model.bonds[b as usize];
                let o = if bond.i as usize == a { bond.j } else { bond.i } as usize;
                if self.stamp[o] == e {
                    continue;
                }
                if model.is_held(o) || seen.len() >= limit {
                    return None;
                }
                self.stamp[o] = e;
                seen.push(o);
            }
        }
        seen.sort_unstable();
        Some(seen)
    }

    /// The new springs node `n` needs under `broken`: its null directions not yet grounded (the
    /// null space only grows as bonds break, so the missing part is orthogonal to the grounded
    /// one).
    fn needed(&mut self, model: &SpliceModel, n: usize, broken: &[bool]) -> Vec<Spring> {
        let null = model.null_directions(n, broken);
        let have = self.dirs.entry(n).or_default();
        if null.len() <= have.len() {
            return Vec::new();
        }
        let new: Vec<[f64; 2]> = if have.is_empty() {
            null
        } else {
            vec![[-have[0][1], have[0][0]]]
        };
        have.extend(&new);
        new.into_iter().map(|p| Spring { node: n, p }).collect()
    }

    /// The springs that ground node `n` in every direction of its free dofs (debris fragments).
    fn full(&mut self, model: &SpliceModel, n: usize) -> Vec<Spring> {
        let have = self.dirs.entry(n).or_default();
        let free = [!model.mask[2 * n], !model.mask[2 * n + 1]];
        let new: Vec<[f64; 2]> = match have.len() {
            0 => [[1.0, 0.0], [0.0, 1.0]]
                .into_iter()
                .zip(free)
                .filter(|(_, f)| *f)
                .map(|(p, _)| p)
                .collect(),
            1 if free[0] && free[1] => vec![[-have[0][1], have[0][0]]],
            _ => Vec::new(),
        };
        have.extend(&new);
        new.into_iter().map(|p| Spring { node: n, p }).collect()
    }

    /// Springs for node `n` under `broken`: its null directions, then, when it belongs to a debris
    /// fragment of 2..=[`DEBRIS_LIMIT`] nodes, every direction of every node of the fragment.
    fn springs(&mut self, model: &SpliceModel, n: usize, broken: &[bool]) -> Vec<(usize, Spring)> {
        let mut out: Vec<(usize, Spring)> = self
            .needed(model, n, broken)
            .into_iter()
            .map(|s| (n, s))
            .collect();
        if let Some(frag) = self.debris_fragment(model, n, broken, DEBRIS_LIMIT) {
            if frag.len() > 1 {
                for m in frag {
                    out.extend(self.full(model, m).into_iter().map(|s| (m, s)));
                }
            }
        }
        out
    }
}

/// Largest fragment of free PD nodes grounded as debris; a larger part that comes loose ends the
/// run with status "separated".
pub const DEBRIS_LIMIT: usize = 256;

/// Breaks the bonds `sel` of one step: for each bond in order, the grounding springs its end
/// nodes need once it is gone, then the bond. Returns the detached nodes and whether the body
/// separated (the remaining updates are then skipped). Used by the live run and by the replay of
/// a checkpoint, so both apply exactly the same updates in the same order.
fn advance(
    model: &SpliceModel,
    engine: &mut dyn Engine,
    broken: &mut [bool],
    grounding: &mut Grounding,
    sel: &[usize],
) -> Result<(Vec<usize>, bool)> {
    let mut detached = Vec::new();
    for &b in sel {
        broken[b] = true;
        let bond = &model.bonds[b];
        let mut ups = Vec::new();
        for n in [bond.i as usize, bond.j as usize] {
            for (m, sp) in grounding.springs(model, n, broken) {
                if !detached.contains(&m) {
                    detached.push(m);
                }
                ups.push(Update::Ground(sp));
            }
        }
        ups.push(Update::Break(b));
        for u in ups {
            match engine.apply(u) {
                Ok(()) => {}
                Err(Error::Separated { detail }) => {
                    timing(&detail, Instant::now());
                    return Ok((detached, true));
                }
                Err(e) => return Err(e),
            }
        }
    }
    Ok((detached, false))
}

/// Large temporaries of the re-condensation (three n_P x n_P matrices) alternate with the small
/// long-lived allocations of the history. glibc's allocator raises its mmap threshold
/// dynamically after the first large free, after which such matrices come from the heap and the
/// history's small blocks split the holes they leave: the resident memory then grew by about one
/// condensation's matrices per re-condensation (85 kB per step in a 1e5-step run). Fixing the
/// threshold at 4 MiB (once per process; glibc only) keeps every large block mmapped and returned
/// to the system when freed, so the memory stays flat.
fn keep_large_blocks_mmapped() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    {
        static ONCE: std::sync::Once = std::sync::Once::new();
        extern "C" {
            fn mallopt(param: i32, value: i32) -> i32;
        }
        const M_MMAP_THRESHOLD: i32 = -3;
        // SAFETY: mallopt only changes an allocator tuning parameter; it is thread safe in glibc.
        ONCE.call_once(|| unsafe {
            mallopt(M_MMAP_THRESHOLD, 4 << 20);
        });
    }
}

/// Runs a CCM-PD (or pure PD) model: linear solution at the reference load, then the SLA.
/// `progress(step, max_steps)` is called after every step; returning `false` stops the run
/// (status "cancelled", a checkpoint is written first when `checkpoint_path` is set).
pub fn run(
    params: &CcmPdParams,
    progress: &(dyn Fn(usize, usize) -> bool + Sync),
) -> Result<CcmPdResult> {
    params.sla.validate()?;
    keep_large_blocks_mmapped();
    let t0 = Instant::now();
    let model = SpliceModel::new(&params.model)?;
    timing("model built", t0);
    let mut warnings = model.warnings.clone();
    let mut broken = model.precrack_broken.clone();
    // nodes the pre-crack already detaches
    let mut grounding = Grounding::new(model.grid.n_nodes());
    let mut springs0 = Vec::new();
    let mut detached_nodes = Vec::new();
    // only nodes with a broken bond can be loose (a fragment's nodes all lost a bond)
    let touched: Vec<usize> = model
        .pd_nodes
        .iter()
        .copied()
        .filter(|&n| model.bonds_of(n).iter().any(|&b| broken[b as usize]))
        .collect();
    for n in touched {
        for (m, sp) in grounding.springs(&model, n, &broken) {
            if !detached_nodes.contains(&(0, m)) {
                detached_nodes.push((0, m));
            }
            springs0.push(sp);
        }
    }
    const DENSE_LIMIT: usize = 6000;
    let n_pd_free = (0..model.n_dofs())
        .filter(|&d| !model.mask[d] && model.is_pd[d / 2])
        .count();
    let k0 = model.assemble_with(&broken, &springs0);
    let mut solver = String::new();
    let mut refactor_interval = 0;
    let mut engine: Box<dyn Engine + '_> = if params.sla.fast && n_pd_free <= DENSE_LIMIT {
        solver.push_str(
            "fast (FEM condensed by Cholesky, dense PD system + Sherman-Morrison-Woodbury)",
        );
        let f = Fast::new(&model, &k0, &broken, &springs0, params.sla.refactor_every)?;
        refactor_interval = f.refactor_every;
        Box::new(f)
    } else {
        solver.push_str("oracle (sparse LU refactorised every step)");
        if params.sla.fast {
            solver.push_str(&format!(
                "; fast path not applicable ({n_pd_free} free PD dofs > dense limit {DENSE_LIMIT})"
            ));
        }
        Box::new(Oracle::new(&model, &broken, &springs0, &k0)?)
    };
    timing("engine ready", t0);
    // reference solution before breaking (u from the engine, reactions from the full matrix)
    let u0_full = engine.full_u()?;
    let sol0 = model.postprocess(&k0, u0_full, 0.0);
    drop(k0);
    let fp = checkpoint::fingerprint(params, model.n_dofs(), model.bonds.len());
    let max_steps = params.sla.max_steps;
    let mut history: Vec<SlaStep> = Vec::new();
    let mut damage_at = Vec::new();
    let mut status = "completed".to_string();
    // resume: replay the checkpoint's steps exactly
    let mut resumed_steps = 0;
    if let Some(path) = &params.sla.resume_from {
        let steps = checkpoint::read(path, fp, model.bonds.len(), model.grid.n_nodes())?;
        for st in steps.into_iter().take(max_steps) {
            if st.bonds.iter().any(|&b| broken[b]) {
                return Err(Error::invalid(
                    "resume_from",
                    "a checkpoint breaking every bond once",
                    format!("step {} breaks a bond twice", st.step),
                ));
            }
            let (det, sep) = advance(
                &model,
                engine.as_mut(),
                &mut broken,
                &mut grounding,
                &st.bonds,
            )?;
            detached_nodes.extend(det.iter().map(|&n| (st.step, n)));
            if params.sla.damage_at_steps.contains(&st.step) {
                damage_at.push((
                    st.step,
                    damage(model.grid.n_nodes(), &model.bonds, &broken, &model.pd_nodes),
                ));
            }
            history.push(st);
            if sep {
                status = "separated".into();
                break;
            }
        }
        resumed_steps = history.len();
    }
    let setup_seconds = t0.elapsed().as_secs_f64();
    timing("setup done", t0);

    let t1 = Instant::now();
    let s0 = model.pd.s0;
    let mut n_checkpoints = 0;
    let write_checkpoint = |history: &[SlaStep], n: &mut usize| -> Result<()> {
        if let Some(path) = &params.sla.checkpoint_path {
            checkpoint::write(path, fp, history)?;
            *n += 1;
        }
        Ok(())
    };
    let mut lam = vec![f64::INFINITY; model.bonds.len()];
    let first_step = history.len() + 1;
    for step in first_step..=max_steps {
        if status != "completed" {
            break;
        }
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
        if params.model.load.grip != Grip::Traction && st.sigma22.abs() <= 1e-9 * sol0.sigma22.abs()
        {
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
        let (detached, sep) = advance(&model, engine.as_mut(), &mut broken, &mut grounding, &sel)?;
        detached_nodes.extend(detached.iter().map(|&n| (step, n)));
        let cl = crack_length(&model, &broken);
        let bf = &model.bonds[first];
        history.push(SlaStep {
            step,
            lambda: lmin,
            sigma22: lmin * st.sigma22,
            cmod: lmin * st.cmod,
            u0: lmin * params.model.load.u0,
            bonds: sel,
            nodes: [bf.i as usize, bf.j as usize],
            detached,
            crack_length: cl,
        });
        if params.sla.damage_at_steps.contains(&step) {
            damage_at.push((
                step,
                damage(model.grid.n_nodes(), &model.bonds, &broken, &model.pd_nodes),
            ));
        }
        let every = params.sla.checkpoint_every;
        if every > 0 && step % every == 0 {
            write_checkpoint(&history, &mut n_checkpoints)?;
        }
        let go_on = progress(step, max_steps);
        if sep {
            status = "separated".into();
            break;
        }
        if !go_on {
            status = "cancelled".into();
            write_checkpoint(&history, &mut n_checkpoints)?;
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
        engine.full_u()?
    };
    if !detached_nodes.is_empty() {
        let n_pre = detached_nodes.iter().filter(|d| d.0 == 0).count();
        warnings.push(Warning::new(
            WarningKind::Discretisation,
            format!(
                "{} PD node(s) lost all stiffness along some direction (every bond broken, the \
             remaining ones parallel, or a loose fragment of at most {DEBRIS_LIMIT} nodes) and \
             were grounded there ({n_pre} by the pre-crack, the others during the SLA); they \
             carry no force along it (see detached_nodes)",
                detached_nodes.len()
            ),
        ));
    }
    let sla_seconds = t1.elapsed().as_secs_f64();
    let nn = model.grid.n_nodes();
    Ok(CcmPdResult {
        method: params.model.method.name().into(),
        grip: params.model.load.grip.name().into(),
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
        max_update_rank: engine.max_update_rank(),
        refactor_interval,
        detached_nodes,
        warnings,
        resumed_steps,
        n_checkpoints,
        setup_seconds,
        sla_seconds,
        peak_memory_bytes: peak_memory_bytes(),
    })
}
