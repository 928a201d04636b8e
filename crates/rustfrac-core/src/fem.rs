//! Q4 plane elasticity (paper section 2.1.1, eqs. 4-14): shape functions, element stiffness,
//! parallel assembly on a pattern built once, Dirichlet conditions by elimination, reactions,
//! stresses and energy.
//!
//! The standard dofs of node n are 2n (u1) and 2n + 1 (u2).

use crate::error::{Error, Result};
use crate::material::Elastic;
use crate::mesh::{Mesh, Side};
use crate::quadrature::{subquad_rule, QPoint};
use crate::solver::{check_condition, Cholesky, ConditionEstimate};
use crate::sparse::{CscMatrix, Pattern, Reduction};

/// Bilinear shape functions N1..N4 at (xi, eta), eq. (6).
#[inline]
pub fn shape(xi: f64, eta: f64) -> [f64; 4] {
    [
        0.25 * (1.0 - xi) * (1.0 - eta),
        0.25 * (1.0 + xi) * (1.0 - eta),
        0.25 * (1.0 + xi) * (1.0 + eta),
        0.25 * (1.0 - xi) * (1.0 + eta),
    ]
}

/// Derivatives of the shape functions w.r.t. (xi, eta): [dN/dxi, dN/deta].
#[inline]
pub fn dshape(xi: f64, eta: f64) -> [[f64; 4]; 2] {
    [
        [
            -0.25 * (1.0 - eta),
            0.25 * (1.0 - eta),
            0.25 * (1.0 + eta),
            -0.25 * (1.0 + eta),
        ],
        [
            -0.25 * (1.0 - xi),
            -0.25 * (1.0 + xi),
            0.25 * (1.0 + xi),
            0.25 * (1.0 - xi),
        ],
    ]
}

/// Physical position, global shape-function gradients [dN/dx1, dN/dx2] and det J at (xi, eta)
/// (eqs. 8-11).
#[inline]
pub fn geometry(xy: &[[f64; 2]; 4], xi: f64, eta: f64) -> ([f64; 2], [[f64; 4]; 2], f64) {
    let n = shape(xi, eta);
    let dn = dshape(xi, eta);
    let mut x = [0.0; 2];
    let mut j = [[0.0; 2]; 2]; // j[a][b] = d x_b / d xi_a
    for k in 0..4 {
        x[0] += n[k] * xy[k][0];
        x[1] += n[k] * xy[k][1];
        for a in 0..2 {
            j[a][0] += dn[a][k] * xy[k][0];
            j[a][1] += dn[a][k] * xy[k][1];
        }
    }
    let det = j[0][0] * j[1][1] - j[0][1] * j[1][0];
    let inv = [
        [j[1][1] / det, -j[0][1] / det],
        [-j[1][0] / det, j[0][0] / det],
    ];
    let mut g = [[0.0; 4]; 2];
    for k in 0..4 {
        g[0][k] = inv[0][0] * dn[0][k] + inv[0][1] * dn[1][k];
        g[1][k] = inv[1][0] * dn[0][k] + inv[1][1] * dn[1][k];
    }
    (x, g, det)
}

/// Adds w * B_a^T D B_b to `k` (row-major na x nb) where the columns of B are given as
/// (d/dx1, d/dx2) pairs of scalar basis functions, one pair per scalar function; each scalar
/// function carries two dofs (u1, u2). Used for standard and enriched blocks alike (eq. 26).
#[inline]
pub fn add_btdb(k: &mut [f64], grads: &[[f64; 2]], d: &[[f64; 3]; 3], w: f64) {
    let nf = grads.len();
    let nd = 2 * nf;
    for (a, ga) in grads.iter().enumerate() {
        // B columns of function a: (ga0, 0, ga1) for u1 and (0, ga1, ga0) for u2
        // D * B_col
        let db1 = [
            d[0][0] * ga[0] + d[0][2] * ga[1],
            d[1][0] * ga[0] + d[1][2] * ga[1],
            d[2][0] * ga[0] + d[2][2] * ga[1],
        ];
        let db2 = [
            d[0][1] * ga[1] + d[0][2] * ga[0],
            d[1][1] * ga[1] + d[1][2] * ga[0],
            d[2][1] * ga[1] + d[2][2] * ga[0],
        ];
        for (b, gb) in grads.iter().enumerate() {
            // B_b^T (D B_a)
            let r1 = [gb[0], 0.0, gb[1]];
            let r2 = [0.0, gb[1], gb[0]];
            let dot = |r: &[f64; 3], c: &[f64; 3]| r[0] * c[0] + r[1] * c[1] + r[2] * c[2];
            k[(2 * b) * nd + 2 * a] += w * dot(&r1, &db1);
            k[(2 * b) * nd + 2 * a + 1] += w * dot(&r1, &db2);
            k[(2 * b + 1) * nd + 2 * a] += w * dot(&r2, &db1);
            k[(2 * b + 1) * nd + 2 * a + 1] += w * dot(&r2, &db2);
        }
    }
}

/// Stiffness of one Q4 element (eq. 12), row-major 8 x 8, integrated with `rule`.
/// For rectangles the 2 x 2 Gauss rule is exact.
pub fn element_stiffness(xy: &[[f64; 2]; 4], mat: &Elastic, rule: &[QPoint], out: &mut Vec<f64>) {
    out.clear();
    out.resize(64, 0.0);
    let d = mat.d_matrix();
    for q in rule {
        let (_, g, det) = geometry(xy, q.xi, q.eta);
        let grads: [[f64; 2]; 4] = std::array::from_fn(|k| [g[0][k], g[1][k]]);
        add_btdb(out, &grads, &d, q.w * det * mat.thickness);
    }
}

/// Strain (xx, yy, 2xy) from global gradients and element displacements (u1, u2 per node).
#[inline]
pub fn strain(g: &[[f64; 4]; 2], ue: &[f64; 8]) -> [f64; 3] {
    let mut e = [0.0; 3];
    for k in 0..4 {
        e[0] += g[0][k] * ue[2 * k];
        e[1] += g[1][k] * ue[2 * k + 1];
        e[2] += g[1][k] * ue[2 * k] + g[0][k] * ue[2 * k + 1];
    }
    e
}

/// sigma = D eps.
#[inline]
pub fn stress(d: &[[f64; 3]; 3], eps: &[f64; 3]) -> [f64; 3] {
    std::array::from_fn(|i| d[i][0] * eps[0] + d[i][1] * eps[1] + d[i][2] * eps[2])
}

/// A Q4 plane-elasticity model on a mesh: standard dofs only.
pub struct FemModel {
    pub mesh: Mesh,
    pub material: Elastic,
    /// element quadrature (2 x 2 Gauss by default: exact for rectangles)
    pub rule: Vec<QPoint>,
    blocks: Vec<Vec<usize>>,
    pattern: Pattern,
}

impl FemModel {
    /// Builds the model and its sparsity pattern (once). `gauss` is the points per direction.
    pub fn new(mesh: Mesh, material: Elastic, gauss: usize) -> Result<Self> {
        if !(1..=5).contains(&gauss) {
            return Err(Error::invalid("gauss", "1..=5 points per direction", gauss));
        }
        let blocks: Vec<Vec<usize>> = mesh
            .elements
            .iter()
            .map(|e| e.iter().flat_map(|&n| [2 * n, 2 * n + 1]).collect())
            .collect();
        let pattern = Pattern::symmetric(2 * mesh.n_nodes(), &blocks)?;
        Ok(Self {
            mesh,
            material,
            rule: subquad_rule(1, gauss),
            blocks,
            pattern,
        })
    }

    pub fn n_dofs(&self) -> usize {
        2 * self.mesh.n_nodes()
    }

    /// Position of every dof (its node's coordinates), for the nested-dissection ordering.
    pub fn dof_positions(&self) -> Vec<[f64; 2]> {
        self.mesh.coords.iter().flat_map(|&c| [c, c]).collect()
    }

    /// Global stiffness (full symmetric storage), assembled in parallel.
    pub fn stiffness(&self) -> CscMatrix {
        self.pattern.assemble(&self.blocks, &self.blocks, |e, out| {
            element_stiffness(
                &self.mesh.element_coords(e),
                &self.material,
                &self.rule,
                out,
            )
        })
    }

    /// Consistent nodal forces of a uniform traction `t` (force per area) on one side.
    pub fn traction_forces(&self, side: Side, t: [f64; 2], f: &mut [f64]) {
        edge_traction(&self.mesh, side, t, self.material.thickness, f)
    }

    /// Consistent nodal forces of a body force b(x) (force per volume), 3 x 3 Gauss per element.
    pub fn body_forces(&self, b: impl Fn(f64, f64) -> [f64; 2]) -> Vec<f64> {
        let mut f = vec![0.0; self.n_dofs()];
        let rule = subquad_rule(1, 3);
        for (e, conn) in self.mesh.elements.iter().enumerate() {
            let xy = self.mesh.element_coords(e);
            for q in &rule {
                let (x, _, det) = geometry(&xy, q.xi, q.eta);
                let n = shape(q.xi, q.eta);
                let bv = b(x[0], x[1]);
                let w = q.w * det * self.material.thickness;
                for k in 0..4 {
                    f[2 * conn[k]] += w * n[k] * bv[0];
                    f[2 * conn[k] + 1] += w * n[k] * bv[1];
                }
            }
        }
        f
    }

    /// Element displacement vector.
    pub fn element_u(&self, e: usize, u: &[f64]) -> [f64; 8] {
        let c = self.mesh.elements[e];
        std::array::from_fn(|i| u[2 * c[i / 2] + i % 2])
    }

    /// Stresses at the 2 x 2 Gauss points of every element: (n_elements * 4) x 3, plus the points.
    pub fn gauss_stresses(&self, u: &[f64]) -> (Vec<[f64; 2]>, Vec<[f64; 3]>) {
        let d = self.material.d_matrix();
        let rule = subquad_rule(1, 2);
        let mut pts = Vec::with_capacity(4 * self.mesh.n_elements());
        let mut sig = Vec::with_capacity(4 * self.mesh.n_elements());
        for e in 0..self.mesh.n_elements() {
            let xy = self.mesh.element_coords(e);
            let ue = self.element_u(e, u);
            for q in &rule {
                let (x, g, _) = geometry(&xy, q.xi, q.eta);
                pts.push(x);
                sig.push(stress(&d, &strain(&g, &ue)));
            }
        }
        (pts, sig)
    }

    /// Nodal stresses: element corner values averaged over the elements sharing a node.
    pub fn nodal_stresses(&self, u: &[f64]) -> Vec<[f64; 3]> {
        let d = self.material.d_matrix();
        let mut acc = vec![[0.0; 3]; self.mesh.n_nodes()];
        let mut cnt = vec![0usize; self.mesh.n_nodes()];
        let corners = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)];
        for (e, conn) in self.mesh.elements.iter().enumerate() {
            let xy = self.mesh.element_coords(e);
            let ue = self.element_u(e, u);
            for (k, &(xi, eta)) in corners.iter().enumerate() {
                let (_, g, _) = geometry(&xy, xi, eta);
                let s = stress(&d, &strain(&g, &ue));
                for c in 0..3 {
                    acc[conn[k]][c] += s[c];
                }
                cnt[conn[k]] += 1;
            }
        }
        acc.iter()
            .zip(&cnt)
            .map(|(a, &c)| a.map(|v| v / c.max(1) as f64))
            .collect()
    }

    /// L2 norm of the displacement error and energy norm of the error against an exact field
    /// `exact(x, y) -> (u, grad u)` with grad u = [[du1/dx1, du1/dx2], [du2/dx1, du2/dx2]],
    /// integrated with 4 x 4 Gauss points per element.
    pub fn error_norms(
        &self,
        u: &[f64],
        exact: impl Fn(f64, f64) -> ([f64; 2], [[f64; 2]; 2]),
    ) -> (f64, f64) {
        let d = self.material.d_matrix();
        let rule = subquad_rule(1, 4);
        let (mut l2, mut en) = (0.0, 0.0);
        for e in 0..self.mesh.n_elements() {
            let xy = self.mesh.element_coords(e);
            let ue = self.element_u(e, u);
            for q in &rule {
                let (x, g, det) = geometry(&xy, q.xi, q.eta);
                let n = shape(q.xi, q.eta);
                let (ux, gx) = exact(x[0], x[1]);
                let uh = [
                    (0..4).map(|k| n[k] * ue[2 * k]).sum::<f64>(),
                    (0..4).map(|k| n[k] * ue[2 * k + 1]).sum::<f64>(),
                ];
                let eh = strain(&g, &ue);
                let ex = [gx[0][0], gx[1][1], gx[0][1] + gx[1][0]];
                let de = [eh[0] - ex[0], eh[1] - ex[1], eh[2] - ex[2]];
                let sd = stress(&d, &de);
                let w = q.w * det * self.material.thickness;
                l2 += w * ((uh[0] - ux[0]).powi(2) + (uh[1] - ux[1]).powi(2));
                en += w * (de[0] * sd[0] + de[1] * sd[1] + de[2] * sd[2]);
            }
        }
        (l2.sqrt(), en.sqrt())
    }
}

/// Consistent nodal forces of a uniform traction on one side of a structured mesh (linear edges:
/// half the edge force to each end node).
pub fn edge_traction(mesh: &Mesh, side: Side, t: [f64; 2], thickness: f64, f: &mut [f64]) {
    for [a, b] in mesh.side_edges(side) {
        let (pa, pb) = (mesh.coords[a], mesh.coords[b]);
        let len = ((pb[0] - pa[0]).powi(2) + (pb[1] - pa[1]).powi(2)).sqrt();
        for n in [a, b] {
            f[2 * n] += 0.5 * len * thickness * t[0];
            f[2 * n + 1] += 0.5 * len * thickness * t[1];
        }
    }
}

/// Prescribed dof values (Dirichlet conditions): (dof, value) pairs; a dof listed twice must
/// carry the same value.
#[derive(Debug, Clone, Default)]
pub struct Dirichlet {
    pub dofs: Vec<(usize, f64)>,
}

impl Dirichlet {
    /// Prescribes component `comp` (0: u1, 1: u2) of `nodes` to `value` (dof = 2 n + comp).
    pub fn fix(&mut self, nodes: &[usize], comp: usize, value: f64) {
        for &n in nodes {
            self.dofs.push((2 * n + comp, value));
        }
    }

    /// (mask, values) over `n` dofs; refuses conflicting or out-of-range entries.
    pub fn to_mask(&self, n: usize) -> Result<(Vec<bool>, Vec<f64>)> {
        let mut mask = vec![false; n];
        let mut vals = vec![0.0; n];
        for &(d, v) in &self.dofs {
            if d >= n {
                return Err(Error::invalid("Dirichlet dof", &format!("< {n}"), d));
            }
            if !v.is_finite() {
                return Err(Error::invalid(
                    "prescribed displacement",
                    "a finite number",
                    v,
                ));
            }
            if mask[d] && vals[d] != v {
                return Err(Error::invalid(
                    "Dirichlet conditions",
                    "one value per dof",
                    format!("dof {d} prescribed to {} and {v}", vals[d]),
                ));
            }
            mask[d] = true;
            vals[d] = v;
        }
        Ok((mask, vals))
    }

    /// Checks that the prescribed dofs remove the three rigid-body modes of the plane body whose
    /// nodes are `node_xy` (dofs 2 n + comp; dofs beyond 2 node_xy.len(), e.g. XFEM enrichment,
    /// have no rigid modes of their own and are ignored), before any factorisation; a free mode
    /// is [`Error::Singular`] naming it.
    ///
    /// A prescribed u1 at (x, y) removes the combinations of the modes (x1 translation, x2
    /// translation, rotation about the centre) with r^T c = 0, r = [1, 0, -y'], a prescribed u2
    /// r = [0, 1, x'], with (x', y') the position relative to the centre of the nodes' bounding box
    /// divided by its half diagonal (scale and translation invariant). The modes are all removed
    /// iff N = sum r r^T has rank 3: every eigenvalue above 1e-10 x the largest (a geometrically
    /// degenerate set, e.g. two u1 conditions 1e-5 of the plate size apart as the only rotation
    /// restraint, counts as free).
    pub fn check_rigid_modes(&self, node_xy: &[[f64; 2]]) -> Result<()> {
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for p in node_xy {
            for c in 0..2 {
                lo[c] = lo[c].min(p[c]);
                hi[c] = hi[c].max(p[c]);
            }
        }
        let centre = [0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1])];
        let half = 0.5 * ((hi[0] - lo[0]).powi(2) + (hi[1] - lo[1]).powi(2)).sqrt();
        let half = if half.is_finite() && half > 0.0 {
            half
        } else {
            1.0
        };
        let mut n = [[0.0f64; 3]; 3];
        for &(d, _) in &self.dofs {
            let node = d / 2;
            if node >= node_xy.len() {
                continue;
            }
            let x = (node_xy[node][0] - centre[0]) / half;
            let y = (node_xy[node][1] - centre[1]) / half;
            let r = if d % 2 == 0 {
                [1.0, 0.0, -y]
            } else {
                [0.0, 1.0, x]
            };
            for i in 0..3 {
                for j in 0..3 {
                    n[i][j] += r[i] * r[j];
                }
            }
        }
        let (lam, vecs) = sym3_eigen(n);
        let lmax = lam.iter().fold(0.0f64, |a, &l| a.max(l));
        let null: Vec<[f64; 3]> = (0..3)
            .filter(|&k| lam[k].is_nan() || lam[k] <= 1e-10 * lmax)
            .map(|k| vecs[k])
            .collect();
        if null.is_empty() {
            return Ok(());
        }
        // canonical modes lying in the null space by name, then the rest of the null space
        // (orthogonal to them) described as a translation direction or a rotation centre
        const NAMES: [&str; 3] = ["x1 translation", "x2 translation", "rotation"];
        let mut basis: Vec<[f64; 3]> = Vec::new();
        let mut names: Vec<String> = Vec::new();
        for m in 0..3 {
            if null.iter().map(|v| v[m] * v[m]).sum::<f64>() > 1.0 - 1e-6 {
                let mut e = [0.0; 3];
                e[m] = 1.0;
                basis.push(e);
                names.push(NAMES[m].to_string());
            }
        }
        for v in &null {
            let mut w = *v;
            for b in &basis {
                let d: f64 = (0..3).map(|i| w[i] * b[i]).sum();
                for i in 0..3 {
                    w[i] -= d * b[i];
                }
            }
            let nw = (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]).sqrt();
            if basis.len() == null.len() || nw < 0.5 {
                continue;
            }
            let w = [w[0] / nw, w[1] / nw, w[2] / nw];
            basis.push(w);
            names.push(if w[2].abs() < 1e-6 {
                format!("translation along ({:.3}, {:.3})", w[0], w[1])
            } else {
                // u = (w0 - w2 y', w1 + w2 x') vanishes at x' = -w1 / w2, y' = w0 / w2
                format!(
                    "rotation about ({:.6e}, {:.6e})",
                    centre[0] - half * w[1] / w[2],
                    centre[1] + half * w[0] / w[2]
                )
            });
        }
        let modes = names.join(", ");
        Err(Error::Singular {
            detail: format!(
                "the Dirichlet conditions leave {} rigid-body mode(s) free: {modes} (prescribe \
                 displacements that remove the x1 and x2 translations and the rotation)",
                null.len()
            ),
        })
    }
}

/// Eigenvalues and unit eigenvectors (`vecs[k]` belongs to `lam[k]`) of a symmetric 3 x 3 matrix
/// by cyclic Jacobi rotations (converges quadratically; 50 sweeps is far beyond need).
fn sym3_eigen(mut a: [[f64; 3]; 3]) -> ([f64; 3], [[f64; 3]; 3]) {
    let mut v = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    for _ in 0..50 {
        let off = a[0][1].powi(2) + a[0][2].powi(2) + a[1][2].powi(2);
        let diag = a[0][0].powi(2) + a[1][1].powi(2) + a[2][2].powi(2);
        if off <= 1e-36 * diag || off == 0.0 {
            break;
        }
        for (p, q) in [(0, 1), (0, 2), (1, 2)] {
            if a[p][q] == 0.0 {
                continue;
            }
            let theta = 0.5 * (a[q][q] - a[p][p]) / a[p][q];
            let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
            let t = if theta == 0.0 { 1.0 } else { t };
            let c = 1.0 / (t * t + 1.0).sqrt();
            let s = t * c;
            // A <- J^T A J with J the rotation in the (p, q) plane
            for row in a.iter_mut() {
                let (akp, akq) = (row[p], row[q]);
                row[p] = c * akp - s * akq;
                row[q] = s * akp + c * akq;
            }
            let (rp, rq) = (a[p], a[q]);
            for (k, (apk, aqk)) in rp.iter().zip(&rq).enumerate() {
                a[p][k] = c * apk - s * aqk;
                a[q][k] = s * apk + c * aqk;
            }
            for row in v.iter_mut() {
                let (vp, vq) = (row[p], row[q]);
                row[p] = c * vp - s * vq;
                row[q] = s * vp + c * vq;
            }
        }
    }
    let lam = [a[0][0], a[1][1], a[2][2]];
    let vecs = [
        [v[0][0], v[1][0], v[2][0]],
        [v[0][1], v[1][1], v[2][1]],
        [v[0][2], v[1][2], v[2][2]],
    ];
    (lam, vecs)
}

/// A linear system K u = f with Dirichlet elimination, factorised once by Cholesky, reusable for
/// new loads (several right-hand sides) and refactorisable with new values on the same pattern.
pub struct LinearSystem {
    pub k: CscMatrix,
    pub reduction: Reduction,
    pub prescribed: Vec<f64>,
    chol: Cholesky,
}

/// Solution of a linear static problem.
#[derive(Debug, Clone)]
pub struct Solution {
    /// displacements, all dofs
    pub u: Vec<f64>,
    /// reactions K u - f, all dofs (zero up to round-off at free dofs)
    pub reactions: Vec<f64>,
    /// strain energy 1/2 u^T K u
    pub energy: f64,
    /// relative residual ||K_ff u_f - rhs_f|| / ||rhs_f||
    pub residual: f64,
}

impl LinearSystem {
    /// Eliminates the Dirichlet dofs and factorises K_ff (SPD) with Cholesky (AMD ordering).
    pub fn new(k: CscMatrix, bc: &Dirichlet) -> Result<Self> {
        Self::with_positions(k, bc, None)
    }

    /// As [`LinearSystem::new`], with the position of every dof for a nested-dissection ordering
    /// (recommended above ~1e4 unknowns).
    pub fn with_positions(
        k: CscMatrix,
        bc: &Dirichlet,
        dof_xy: Option<&[[f64; 2]]>,
    ) -> Result<Self> {
        let (mask, prescribed) = bc.to_mask(k.ncols)?;
        let mut reduction = Reduction::new(&k, &mask)?;
        let free_xy: Option<Vec<[f64; 2]>> =
            dof_xy.map(|xy| reduction.free.iter().map(|&d| xy[d]).collect());
        let chol = reduction.with_reduced(&k, |kff| Cholesky::new_with(kff, free_xy.as_deref()))?;
        Ok(Self {
            k,
            reduction,
            prescribed,
            chol,
        })
    }

    /// Replaces the matrix values (same pattern) and refactorises, reusing the symbolic analysis.
    pub fn refactor(&mut self, k: CscMatrix) -> Result<()> {
        let chol = &mut self.chol;
        self.reduction.with_reduced(&k, |kff| chol.factorize(kff))?;
        self.k = k;
        Ok(())
    }

    /// Condition estimate of the factorised K_ff (see [`ConditionEstimate`]; two extra solves
    /// with the factor, K_ff read in place, no refactorisation).
    pub fn condition_estimate(&self) -> Result<ConditionEstimate> {
        self.chol.condition_estimate_free(
            &self.k,
            &self.reduction.map,
            &self.reduction.free,
            crate::solver::CONDITION_ITERATIONS,
        )
    }

    /// The condition check every plate solve makes after factorising: with `estimate`, the
    /// condition estimate (2 extra solves) is returned; without, only the free pivot ratio (a
    /// lower bound of the same number, [`ConditionEstimate::pivot_ratio`]) is computed and None
    /// returned. Either above [`crate::solver::COND_SINGULAR`] is [`Error::Singular`]
    /// ("numerically singular", [`crate::solver::check_condition`]); `what` names the solve.
    pub fn checked_condition(
        &self,
        what: &str,
        estimate: bool,
    ) -> Result<Option<ConditionEstimate>> {
        if estimate {
            let c = self.condition_estimate()?;
            check_condition(what, c.value())?;
            Ok(Some(c))
        } else {
            let diag: Vec<f64> = self
                .reduction
                .free
                .iter()
                .map(|&c| self.k.find(c, c).map_or(0.0, |k| self.k.val[k]))
                .collect();
            check_condition(what, self.chol.pivot_ratio(&diag)?)?;
            Ok(None)
        }
    }

    /// Solves for external forces `f` with the prescribed values scaled by `scale`.
    pub fn solve(&self, f: &[f64], scale: f64) -> Result<Solution> {
        let n = self.k.ncols;
        if f.len() != n {
            return Err(Error::SizeMismatch {
                what: "force vector".into(),
                expected: n,
                got: f.len(),
            });
        }
        let up: Vec<f64> = self.prescribed.iter().map(|v| v * scale).collect();
        let rhs = self.reduction.rhs(&self.k, f, &up);
        let uf = self.chol.solve(&rhs)?;
        let u = self.reduction.expand(&uf, &up);
        let ku = self.k.matvec(&u);
        let reactions: Vec<f64> = ku.iter().zip(f).map(|(a, b)| a - b).collect();
        let energy = 0.5 * u.iter().zip(&ku).map(|(a, b)| a * b).sum::<f64>();
        let (mut rn, mut bn) = (0.0f64, 0.0f64);
        for (i, &d) in self.reduction.free.iter().enumerate() {
            rn += reactions[d] * reactions[d];
            bn += rhs[i] * rhs[i];
        }
        let residual = if bn > 0.0 {
            (rn / bn).sqrt()
        } else {
            rn.sqrt()
        };
        if u.iter().any(|v| !v.is_finite()) {
            return Err(Error::Singular {
                detail: "non-finite displacements".into(),
            });
        }
        Ok(Solution {
            u,
            reactions,
            energy,
            residual,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::Plane;

    #[test]
    fn jacobi_eigen_3x3() {
        let a = [[4.0, 1.0, -2.0], [1.0, 3.0, 0.5], [-2.0, 0.5, 1.0]];
        let (lam, v) = sym3_eigen(a);
        for k in 0..3 {
            for i in 0..3 {
                let av: f64 = (0..3).map(|j| a[i][j] * v[k][j]).sum();
                assert!((av - lam[k] * v[k][i]).abs() < 1e-12, "{lam:?}");
            }
        }
    }

    #[test]
    fn rigid_modes_are_named() {
        // unit square's corners, scaled and shifted far away: the check is scale invariant
        let (s, o) = (1e-7, 1e5);
        let xy: Vec<[f64; 2]> = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]
            .iter()
            .map(|p| [o + s * p[0], o + s * p[1]])
            .collect();
        let err = |dofs: &[usize]| {
            let bc = Dirichlet {
                dofs: dofs.iter().map(|&d| (d, 0.0)).collect(),
            };
            match bc.check_rigid_modes(&xy) {
                Ok(()) => String::new(),
                Err(Error::Singular { detail }) => detail,
                Err(e) => panic!("{e}"),
            }
        };
        // u2 on the bottom and top, u1 nowhere: x1 translation free
        let e = err(&[1, 3, 5, 7]);
        assert!(
            e.contains("1 rigid-body mode(s) free: x1 translation"),
            "{e}"
        );
        assert_eq!(err(&[1, 3, 5, 7, 0]), "");
        // one u1 only (node 0): x2 translation and rotation about any point of the line y = y0
        let e = err(&[0]);
        assert!(
            e.contains("2 rigid-body mode(s) free: x2 translation, rotation about (")
                && e.contains(", 1.000000e5)"),
            "{e}"
        );
        // u1 on two nodes of a vertical line: rotation removed too, x2 translation free
        let e = err(&[0, 6]);
        assert!(
            e.contains("1 rigid-body mode(s) free: x2 translation ("),
            "{e}"
        );
        // nothing
        let e = err(&[]);
        assert!(
            e.contains("x1 translation, x2 translation, rotation"),
            "{e}"
        );
        // node 0 pinned: rotation about it
        let e = err(&[0, 1]);
        assert!(
            e.contains("1 rigid-body mode(s) free: rotation about (1.000000e5, 1.000000e5)"),
            "{e}"
        );
        // enriched dofs (beyond the nodes) are ignored
        assert!(err(&[1, 3, 100]).contains("x1 translation"));
    }

    #[test]
    fn rectangle_stiffness_2x2_is_exact() {
        let m = Elastic::new(200.0, 0.3, Plane::Strain, 2.0).unwrap();
        let xy = [[0.0, 0.0], [2.0, 0.0], [2.0, 0.5], [0.0, 0.5]];
        let (mut a, mut b) = (Vec::new(), Vec::new());
        element_stiffness(&xy, &m, &subquad_rule(1, 2), &mut a);
        element_stiffness(&xy, &m, &subquad_rule(1, 5), &mut b);
        for (x, y) in a.iter().zip(&b) {
            assert!((x - y).abs() < 1e-12 * 200.0);
        }
        // rigid translation has zero force, and K is symmetric
        for i in 0..8 {
            let fx: f64 = (0..4).map(|k| a[i * 8 + 2 * k]).sum();
            assert!(fx.abs() < 1e-10);
            for j in 0..8 {
                assert!((a[i * 8 + j] - a[j * 8 + i]).abs() < 1e-12);
            }
        }
    }
}
