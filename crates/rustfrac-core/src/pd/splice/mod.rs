//! Splice CCM-PD coupling (paper section 2.2.2, eq. 58; docs/design.md, "The splice coupling").
//!
//! Every node of one tensor grid is a FEM node or a PD node; PD nodes are those inside the
//! given rectangles (closed, tolerance 1e-9 dx), or all nodes for the pure PD model. The grid is
//! uniform (spacing dx, the paper's) or, with `pd.fem_grading` > 1, graded away from the PD
//! rectangles (`graded.rs`: uniform dx over the PD rectangles plus a band of m + 1 elements).
//!
//! * FEM rows: every Q4 element (exact 2 x 2 Gauss stiffness of its rectangle: one shared dx x dx
//!   square, own matrices for graded or cut elements) with at least one FEM node writes the rows
//!   of its FEM nodes only (all 8 columns): hybrid elements included.
//! * PD rows: every bond of a PD node (to PD or FEM nodes of its family) writes the rows of its PD
//!   end(s) only. PD rows hold forces (the bond force density times both node volumes), so PD and
//!   FEM rows, reactions and residuals are comparable.
//! * The matrix is not symmetric: it is factorised with the general sparse LU (oracle path) or
//!   condensed onto the PD unknowns ([`crate::pd::sla`]).
//!
//! The pre-crack (`precrack.rs`) breaks the bonds that cross it and removes the elements it cuts;
//! the plate's edges are loaded through edge node rows or volumetric boundary layers
//! (`boundary.rs`); PD nodes left without stiffness in some direction are grounded by springs
//! (`springs.rs`). [`SpliceModel::new`] builds the model in named phases (`build.rs`).

mod boundary;
mod build;
mod graded;
mod holes;
mod precrack;
mod regions;
mod response;
mod springs;

pub use response::{ProbeFunctional, Response};

pub use crate::geometry::bond_crosses;
pub(crate) use springs::Spring;

use crate::error::Result;
use crate::fe::loading::PlateEdges;
use crate::fe::regions::RegionConditions;
use crate::fe::Dirichlet;
use crate::la::Lu;
use crate::la::{CscMatrix, Pattern, Reduction};
use crate::pd::surface_correction::SurfaceFactors;
use crate::pd::{Bond, Grid, PdConstants};
use crate::problem::{PdMethod, Problem};
use crate::warning::Warning;

/// The assembled description of a coupled model (everything but the matrix values).
pub struct SpliceModel {
    /// the problem it discretises (method "pd" or "ccm_pd")
    pub problem: Problem,
    /// every node PD (method "pd": the pure PD model with volumetric boundary layers)
    pub all_pd: bool,
    /// the pre-crack polyline in plate coordinates (first point = crack mouth; empty for none)
    pub precrack: Vec<[f64; 2]>,
    pub grid: Grid,
    pub pd: PdConstants,
    pub is_pd: Vec<bool>,
    /// PD node ids, ascending
    pub pd_nodes: Vec<usize>,
    /// FEM elements that contribute (at least one FEM node, not cut by the pre-crack)
    pub elements: Vec<[usize; 4]>,
    /// elements removed because the pre-crack cuts them
    pub n_removed_elements: usize,
    pub bonds: Vec<Bond>,
    /// bonds broken by the pre-crack
    pub precrack_broken: Vec<bool>,
    /// element stiffness of the whole dx x dx square, row-major 8 x 8
    pub ke: Vec<f64>,
    /// the elements with their own stiffness matrix: cut by a FEM hole (`holes.rs`) or of
    /// another size than dx x dx (a graded grid, `graded.rs`); empty without either
    pub own_ke: ElementStiffness,
    rows_of: Vec<Vec<usize>>,
    cols_of: Vec<Vec<usize>>,
    pattern: Pattern,
    pub edges: PlateEdges,
    pub bc: Dirichlet,
    /// external forces (traction grip)
    pub f: Vec<f64>,
    /// node carrying the u1 = 0 anchor (bottom-right corner)
    pub anchor: usize,
    pub mask: Vec<bool>,
    /// prescribed values (reference load) at constrained dofs, zero elsewhere
    pub prescribed: Vec<f64>,
    /// material nodes (holes: the centre rule, `holes.rs`; removed nodes have both dofs fixed
    /// to zero and no bond)
    pub material: Vec<bool>,
    /// supports and loads on regions (their layer node sets; None: the grips)
    pub regions: Option<RegionConditions>,
    /// the history's load responses (sigma22 or the primary region's; u0)
    pub response: Response,
    /// (node below, node above, unit normal) at the crack mouth, for the CMOD
    pub cmod_nodes: Option<(usize, usize, [f64; 2])>,
    /// the vertex of `precrack` where the CMOD is read
    mouth: usize,
    /// bonds of each node (CSR over nodes: `node_bonds[node_bond_ptr[n]..node_bond_ptr[n + 1]]`)
    node_bond_ptr: Vec<usize>,
    node_bonds: Vec<u32>,
    /// accuracy warnings about the discretisation (e.g. m < 2: too few bonds per node)
    pub warnings: Vec<Warning>,
    /// the surface correction's bond factors (`pd.surface_correction = "energy"`,
    /// [`crate::pd::surface_correction`]); None: the paper's bonds
    pub surface: Option<SurfaceFactors>,
    /// the critical stretch's calibration applied to `pd.s0` (`pd.s0_calibration`)
    pub s0_calibration: crate::problem::Calibration,
    /// the linear peridynamic solid (`pd.model = "lps"`, [`crate::pd::lps`]); None: bond-based
    pub lps: Option<crate::pd::lps::LpsModel>,
}

/// The stiffness matrices of the FEM elements that are not the shared dx x dx square: cut by
/// holes (their material part's rule, [`crate::fe::fictitious`]) or graded (`graded.rs`), by
/// index into [`SpliceModel::elements`].
#[derive(Debug, Clone, Default)]
pub struct ElementStiffness {
    /// per element: index into `ke` (u32::MAX: a whole element, the shared square)
    slot: Vec<u32>,
    /// row-major 8 x 8 matrices, one after the other
    ke: Vec<f64>,
}

impl ElementStiffness {
    pub(crate) fn push(&mut self, element: usize, ke: &[f64]) {
        if self.slot.len() <= element {
            self.slot.resize(element + 1, u32::MAX);
        }
        self.slot[element] = (self.ke.len() / 64) as u32;
        self.ke.extend_from_slice(ke);
    }

    /// The matrix of element `e` if it has its own.
    pub fn of(&self, e: usize) -> Option<&[f64]> {
        match self.slot.get(e) {
            Some(&k) if k != u32::MAX => Some(&self.ke[64 * k as usize..64 * (k as usize + 1)]),
            _ => None,
        }
    }

    /// Number of elements with their own matrix.
    pub fn len(&self) -> usize {
        self.ke.len() / 64
    }

    pub fn is_empty(&self) -> bool {
        self.ke.is_empty()
    }
}

/// A static solution of the coupled model.
#[derive(Debug, Clone)]
pub struct StaticSolution {
    pub u: Vec<f64>,
    /// K u - f at every dof
    pub reactions: Vec<f64>,
    pub sigma22: f64,
    pub cmod: f64,
    /// sum over all nodes of the external forces (reactions + applied) per component: zero for a
    /// balanced model, small but not zero for the splice coupling
    pub out_of_balance: [f64; 2],
    /// relative residual of the free equations
    pub residual: f64,
}

impl SpliceModel {
    /// The PD options of the problem.
    pub fn pd_method(&self) -> &PdMethod {
        self.problem
            .pd()
            .expect("a PD problem (checked when the model was built)")
    }

    pub fn n_dofs(&self) -> usize {
        2 * self.grid.n_nodes()
    }

    /// Bond rank-1 data: alpha (times the surface correction's factor, if any) and the unit
    /// vector n; the bond adds alpha a b^T to the matrix with
    /// a = [n at dofs(i); -n at dofs(j) if j is PD] and b = [n at dofs(i); -n at dofs(j)].
    pub(crate) fn bond_alpha_n(&self, b: usize) -> (f64, [f64; 2]) {
        let bond = &self.bonds[b];
        let l = bond.length();
        let alpha = match &self.surface {
            Some(sf) => self.pd.bond_alpha(bond) * sf.bond[b],
            None => self.pd.bond_alpha(bond),
        };
        (alpha, [bond.xi[0] / l, bond.xi[1] / l])
    }

    /// Bonds of node `n` (indices into `bonds`).
    pub(crate) fn bonds_of(&self, n: usize) -> &[u32] {
        &self.node_bonds[self.node_bond_ptr[n]..self.node_bond_ptr[n + 1]]
    }

    /// Assembles the splice matrix (PD rows scaled by node volume) with `broken` bonds removed.
    pub fn assemble(&self, broken: &[bool]) -> CscMatrix {
        if let Some(lps) = &self.lps {
            return lps.assemble(broken);
        }
        let ne = self.elements.len();
        self.pattern
            .assemble(&self.rows_of, &self.cols_of, |blk, out| {
                if blk < ne {
                    let e = &self.elements[blk];
                    let ke = self.own_ke.of(blk).unwrap_or(&self.ke);
                    for (a, &n) in e.iter().enumerate() {
                        if !self.is_pd[n] {
                            out.extend_from_slice(&ke[(2 * a) * 8..(2 * a + 1) * 8]);
                            out.extend_from_slice(&ke[(2 * a + 1) * 8..(2 * a + 2) * 8]);
                        }
                    }
                } else {
                    let b = blk - ne;
                    let nr = self.rows_of[blk].len();
                    if broken[b] {
                        out.resize(nr * 4, 0.0);
                        return;
                    }
                    let (alpha, n) = self.bond_alpha_n(b);
                    let bvec = [n[0], n[1], -n[0], -n[1]];
                    for r in 0..nr {
                        let ar = alpha * if r < 2 { n[r] } else { -n[r - 2] };
                        for bv in bvec {
                            out.push(ar * bv);
                        }
                    }
                }
            })
    }

    /// sigma22 from K u: (sum over top nodes of (K u)_2) / (W h) under the grips, the primary
    /// region's response for regions ([`Response`]).
    pub(crate) fn sigma22_from(&self, ku: &[f64]) -> f64 {
        self.response.value(ku)
    }

    /// Crack-mouth opening (u_above - u_below) . n, zero without a pre-crack.
    pub(crate) fn cmod_from(&self, u: &[f64]) -> f64 {
        match self.cmod_nodes {
            Some((lo, hi, n)) => {
                (u[2 * hi] - u[2 * lo]) * n[0] + (u[2 * hi + 1] - u[2 * lo + 1]) * n[1]
            }
            None => 0.0,
        }
    }

    /// Prescribed values at load factor `scale`.
    pub fn prescribed_at(&self, scale: f64) -> Vec<f64> {
        self.prescribed.iter().map(|v| v * scale).collect()
    }

    /// Post-processing of a full displacement vector with the matrix `k` used to compute it.
    pub(crate) fn postprocess(&self, k: &CscMatrix, u: Vec<f64>, residual: f64) -> StaticSolution {
        let ku = k.matvec(&u);
        let reactions: Vec<f64> = ku.iter().zip(&self.f).map(|(a, b)| a - b).collect();
        let mut oob = [0.0; 2];
        for (d, v) in ku.iter().enumerate() {
            oob[d % 2] += v;
        }
        StaticSolution {
            sigma22: self.sigma22_from(&ku),
            cmod: self.cmod_from(&u),
            u,
            reactions,
            out_of_balance: oob,
            residual,
        }
    }

    /// Direct solve (general sparse LU) with `broken` bonds removed, at the reference load.
    /// Nodes left without stiffness in some direction by `broken` are grounded there (the
    /// springs of `springs.rs`).
    pub fn solve(&self, broken: &[bool]) -> Result<StaticSolution> {
        let k = self.assemble_with(broken, &self.springs_for(broken));
        let red = Reduction::new(&k, &self.mask)?;
        let kff = red.reduce(&k);
        let lu = Lu::new(&kff)?;
        solve_with(self, &k, &red, &lu)
    }
}

/// Solve with an existing factorisation of the reduced matrix.
pub(crate) fn solve_with(
    model: &SpliceModel,
    k: &CscMatrix,
    red: &Reduction,
    lu: &Lu,
) -> Result<StaticSolution> {
    let rhs = red.rhs(k, &model.f, &model.prescribed);
    let uf = lu.solve(&rhs)?;
    let u = red.expand(&uf, &model.prescribed);
    let ku = k.matvec(&u);
    let (mut rn, mut bn) = (0.0f64, 0.0f64);
    for (i, &d) in red.free.iter().enumerate() {
        rn += (ku[d] - model.f[d]).powi(2);
        bn += rhs[i] * rhs[i];
    }
    let res = if bn > 0.0 {
        (rn / bn).sqrt()
    } else {
        rn.sqrt()
    };
    Ok(model.postprocess(k, u, res))
}
