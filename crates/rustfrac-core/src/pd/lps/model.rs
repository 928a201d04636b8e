//! The LPS model on the splice model's bonds (docs/design.md, "The linear peridynamic solid").
//!
//! With the weights w_b of [`super::influence`] and the node volumes V (the cell's part inside
//! the plate: half on the outline's edges, a quarter at its corners, so that the PD body is the
//! plate), node i's weighted volume (the discrete sum, consistent with the quadrature) and
//! dilatation are
//!
//!   m_i = sum_b w_b |xi_b|^2 V_j,   theta_i = (2 / m_i) sum_b w_b |xi_b| e_b V_j,
//!
//! over its bonds b (either end), e_b = n . (u_j - u_i) the linearised extension. Its strain
//! energy density and the body's energy are
//!
//!   W_i = a theta_i^2 + (4 mu / m_i) sum_b w_b e_b^2 V_j,   a = kappa' / 2 - mu,
//!   Pi = sum_i V_i W_i,
//!
//! (eq. L1 of the design; the continuum W for a uniform strain in the bulk), and the matrix is
//! its Hessian: per bond 2 V_i V_j w_b (b_i + b_j) g g^T (b_i = 4 mu / m_i, g = dofs of -n at i and
//! n at j) and per node 2 a V_i d_i d_i^T (d_i the gradient of theta_i, a dense block over the
//! node's family). It is symmetric positive semi-definite for every nu in range, with the null
//! space of the pairwise part alone (Cauchy-Schwarz on theta_i; the design), so the grounding
//! rules of bond-based PD apply unchanged.
//!
//! m_i is computed once from the bonds the pre-crack leaves (the pre-crack's faces are free
//! surfaces); a bond broken by the SLA leaves m_i and drops out of both ends' theta and of the
//! pairwise part (omega set to 0 for a broken bond with m of the reference configuration). So a
//! break changes the node blocks of both end nodes' families: the matrix is rebuilt per step
//! (the oracle engine; a low-rank update of rank 2 + 2 per break is the fast engines' future).

use super::influence::weight;
use super::LpsConstants;
use crate::error::Result;
use crate::la::{CscMatrix, Pattern};
use crate::pd::{Bond, Grid};

/// The LPS model of a pure PD splice model's bonds.
#[derive(Debug, Clone)]
pub struct LpsModel {
    pub consts: LpsConstants,
    bonds: Vec<Bond>,
    /// per bond: the weight w_b (0 for the pre-crack's bonds)
    pub weight: Vec<f64>,
    /// per node: the weighted volume m_i (0 for a node without bonds)
    pub m: Vec<f64>,
    /// per node: its volume V_i, the part of its dx x dx cell inside the plate (half on an
    /// edge of the outline, a quarter at a corner)
    pub vol: Vec<f64>,
    /// bonds of each node (CSR: `node_bonds[ptr[n]..ptr[n + 1]]`)
    ptr: Vec<usize>,
    node_bonds: Vec<u32>,
    rows_of: Vec<Vec<usize>>,
    cols_of: Vec<Vec<usize>>,
    pattern: Pattern,
}

impl LpsModel {
    /// The weights, weighted volumes and the matrix pattern (a block per bond, then a block
    /// per node over its family) of `bonds` on `grid`, with `precrack_broken` left out of m.
    pub fn new(
        consts: LpsConstants,
        grid: &Grid,
        bonds: &[Bond],
        precrack_broken: &[bool],
    ) -> Result<Self> {
        let dx = grid.dx;
        let v = consts.volume;
        let weight: Vec<f64> = bonds
            .iter()
            .zip(precrack_broken)
            .map(|(b, &pre)| {
                if pre {
                    return 0.0;
                }
                let (a, c) = ((b.xi[0] / dx).round(), (b.xi[1] / dx).round());
                weight(consts.influence, consts.c4, consts.m, a, c, b.beta)
            })
            .collect();
        let nn = grid.n_nodes();
        let vol: Vec<f64> = (0..nn)
            .map(|n| {
                let (i, j) = grid.ij(n);
                let fx = if i == 0 || i == grid.nx { 0.5 } else { 1.0 };
                let fy = if j == 0 || j == grid.ny { 0.5 } else { 1.0 };
                v * fx * fy
            })
            .collect();
        let mut m = vec![0.0; nn];
        for (b, &w) in bonds.iter().zip(&weight) {
            let l2 = b.xi[0] * b.xi[0] + b.xi[1] * b.xi[1];
            let (i, j) = (b.i as usize, b.j as usize);
            m[i] += w * l2 * vol[j];
            m[j] += w * l2 * vol[i];
        }
        let (ptr, node_bonds) = crate::pd::bonds::incidence(nn, bonds);
        let mut rows_of = Vec::with_capacity(bonds.len() + nn);
        for b in bonds {
            let (i, j) = (b.i as usize, b.j as usize);
            rows_of.push(vec![2 * i, 2 * i + 1, 2 * j, 2 * j + 1]);
        }
        for n in 0..nn {
            let mut r = vec![2 * n, 2 * n + 1];
            for &k in &node_bonds[ptr[n]..ptr[n + 1]] {
                let o = other(&bonds[k as usize], n);
                r.extend([2 * o, 2 * o + 1]);
            }
            rows_of.push(r);
        }
        let cols_of = rows_of.clone();
        let pattern = Pattern::new(2 * nn, &rows_of, &cols_of)?;
        Ok(Self {
            consts,
            bonds: bonds.to_vec(),
            weight,
            m,
            vol,
            ptr,
            node_bonds,
            rows_of,
            cols_of,
            pattern,
        })
    }

    /// Bonds of node `n`.
    pub fn bonds_of(&self, n: usize) -> &[u32] {
        &self.node_bonds[self.ptr[n]..self.ptr[n + 1]]
    }

    /// b_i = 4 mu / m_i (0 without bonds).
    fn b(&self, n: usize) -> f64 {
        if self.m[n] > 0.0 {
            4.0 * self.consts.mu / self.m[n]
        } else {
            0.0
        }
    }

    /// a = kappa' / 2 - mu, the dilatation's coefficient in W (eq. L1).
    pub fn a(&self) -> f64 {
        0.5 * self.consts.kappa - self.consts.mu
    }

    /// The coefficients of theta_n = sum_k c_k . u_{node k}: (node, 2-vector) for each intact
    /// bond's far end, and the node's own (minus their sum); empty without weighted volume.
    fn dilatation_gradient(&self, n: usize, broken: &[bool]) -> Vec<[f64; 2]> {
        let bonds = self.bonds_of(n);
        let mut d = vec![[0.0; 2]; bonds.len() + 1];
        if self.m[n] <= 0.0 {
            return d;
        }
        let f = 2.0 / self.m[n];
        for (k, &b) in bonds.iter().enumerate() {
            let b = b as usize;
            if broken[b] || self.weight[b] == 0.0 {
                continue;
            }
            let bond = &self.bonds[b];
            // xi and n point from i to j; seen from n the far end's extension is the same
            let s = f * self.weight[b] * self.vol[other(bond, n)];
            let g = [s * bond.xi[0], s * bond.xi[1]];
            let sign = if bond.i as usize == n { 1.0 } else { -1.0 };
            d[k + 1] = [sign * g[0], sign * g[1]];
            d[0][0] -= sign * g[0];
            d[0][1] -= sign * g[1];
        }
        d
    }

    /// The dilatation theta_n of displacements `u`.
    pub fn dilatation(&self, n: usize, u: &[f64], broken: &[bool]) -> f64 {
        let d = self.dilatation_gradient(n, broken);
        let mut t = d[0][0] * u[2 * n] + d[0][1] * u[2 * n + 1];
        for (k, &b) in self.bonds_of(n).iter().enumerate() {
            let o = other(&self.bonds[b as usize], n);
            t += d[k + 1][0] * u[2 * o] + d[k + 1][1] * u[2 * o + 1];
        }
        t
    }

    /// The strain energy density W_n (eq. L1) of displacements `u`.
    pub fn energy_density(&self, n: usize, u: &[f64], broken: &[bool]) -> f64 {
        let th = self.dilatation(n, u, broken);
        let mut pair = 0.0;
        for &b in self.bonds_of(n) {
            let b = b as usize;
            if !broken[b] {
                let bond = &self.bonds[b];
                let e = bond.stretch(u) * bond.length();
                pair += self.weight[b] * e * e * self.vol[other(bond, n)];
            }
        }
        self.a() * th * th + self.b(n) * pair
    }

    /// The PD stress of node n, sum_b t_b |xi| n (x) n V with the force state
    /// t_b = (2 / m_n) (kappa' - 2 mu) theta_n w_b |xi| + (8 mu / m_n) w_b e_b (the gradient of
    /// W_n by e_b over V): (sigma_11, sigma_22, sigma_12).
    pub fn stress(&self, n: usize, u: &[f64], broken: &[bool]) -> [f64; 3] {
        let mut s = [0.0; 3];
        if self.m[n] <= 0.0 {
            return s;
        }
        let th = self.dilatation(n, u, broken);
        let c = &self.consts;
        for &b in self.bonds_of(n) {
            let b = b as usize;
            if broken[b] {
                continue;
            }
            let bond = &self.bonds[b];
            let l = bond.length();
            let e = bond.stretch(u) * l;
            let w = self.weight[b];
            let t = 2.0 / self.m[n] * (c.kappa - 2.0 * c.mu) * th * w * l
                + 8.0 * c.mu / self.m[n] * w * e;
            let (n1, n2) = (bond.xi[0] / l, bond.xi[1] / l);
            let f = t * l * self.vol[other(bond, n)];
            s[0] += f * n1 * n1;
            s[1] += f * n2 * n2;
            s[2] += f * n1 * n2;
        }
        s
    }

    /// The stiffness matrix (the Hessian of Pi, rows are forces) with `broken` bonds removed.
    pub fn assemble(&self, broken: &[bool]) -> CscMatrix {
        let nb = self.bonds.len();
        let a = self.a();
        self.pattern
            .assemble(&self.rows_of, &self.cols_of, |blk, out| {
                if blk < nb {
                    if broken[blk] || self.weight[blk] == 0.0 {
                        out.resize(16, 0.0);
                        return;
                    }
                    let bond = &self.bonds[blk];
                    let l = bond.length();
                    let n = [bond.xi[0] / l, bond.xi[1] / l];
                    let (i, j) = (bond.i as usize, bond.j as usize);
                    let k = 2.0
                        * self.vol[i]
                        * self.vol[j]
                        * self.weight[blk]
                        * (self.b(i) + self.b(j));
                    let g = [-n[0], -n[1], n[0], n[1]];
                    for gr in g {
                        for gc in g {
                            out.push(k * gr * gc);
                        }
                    }
                } else {
                    let n = blk - nb;
                    let d = self.dilatation_gradient(n, broken);
                    let f: Vec<f64> = d.iter().flat_map(|c| [c[0], c[1]]).collect();
                    let k = 2.0 * a * self.vol[n];
                    for &r in &f {
                        for &c in &f {
                            out.push(k * r * c);
                        }
                    }
                }
            })
    }
}

/// The far end of `bond` seen from node `n`.
fn other(bond: &Bond, n: usize) -> usize {
    if bond.i as usize == n {
        bond.j as usize
    } else {
        bond.i as usize
    }
}
