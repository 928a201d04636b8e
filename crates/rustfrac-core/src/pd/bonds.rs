//! Bonds on the uniform grid: the grid, the bond list, the neighbour search and the damage index
//! (paper section 2.2.1, eqs. 37-45, 53).
//!
//! * Grid: nodes at the vertices of a uniform `dx` grid (the same nodes as the Q4 mesh of the
//!   coupled model); each node carries the volume of its `dx x dx` cell times the thickness.
//! * Neighbour search: cell binning with bins of one grid cell (one node per bin); the family is a
//!   fixed stencil of bin offsets computed once ([`super::partial_volume::family_stencil`]), so
//!   the search is O(N x family size).
//! * Bonds are stored once (32 bytes: two `u32` node ids, the bond vector and `beta`).
//! * Damage index (eq. 53), [`damage`].

use super::partial_volume::family_stencil;
use crate::error::{Error, Result};
use rayon::prelude::*;

/// A bond, stored once: nodes i < j (or i the PD end of a PD-FEM bond), xi = x_j - x_i, beta.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bond {
    pub i: u32,
    pub j: u32,
    pub xi: [f64; 2],
    pub beta: f64,
}

impl Bond {
    /// Length |xi|.
    pub fn length(&self) -> f64 {
        (self.xi[0] * self.xi[0] + self.xi[1] * self.xi[1]).sqrt()
    }
    /// Linearised stretch s = n . (u_j - u_i) / |xi| for displacements over all dofs (2 per node).
    pub fn stretch(&self, u: &[f64]) -> f64 {
        let (i, j) = (self.i as usize, self.j as usize);
        let l2 = self.xi[0] * self.xi[0] + self.xi[1] * self.xi[1];
        (self.xi[0] * (u[2 * j] - u[2 * i]) + self.xi[1] * (u[2 * j + 1] - u[2 * i + 1])) / l2
    }
}

/// Memory of one stored bond in bytes.
pub const BYTES_PER_BOND: usize = std::mem::size_of::<Bond>();

/// A uniform grid of (nx + 1) x (ny + 1) nodes, node (i, j) = j (nx + 1) + i, at (x0 + i dx, y0 + j dx).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Grid {
    pub nx: usize,
    pub ny: usize,
    pub dx: f64,
    pub x0: f64,
    pub y0: f64,
}

impl Grid {
    pub fn n_nodes(&self) -> usize {
        (self.nx + 1) * (self.ny + 1)
    }
    pub fn node(&self, i: usize, j: usize) -> usize {
        j * (self.nx + 1) + i
    }
    pub fn ij(&self, n: usize) -> (usize, usize) {
        (n % (self.nx + 1), n / (self.nx + 1))
    }
    pub fn xy(&self, n: usize) -> [f64; 2] {
        let (i, j) = self.ij(n);
        [self.x0 + i as f64 * self.dx, self.y0 + j as f64 * self.dx]
    }
}

/// Bonds of every node with `is_pd[n]` to every grid node of its family (PD or not), each bond
/// stored once: a PD-PD bond once with i < j, a PD-FEM bond once with i the PD node. Cell binning on
/// the grid (one node per bin) with the fixed family stencil: O(N). Parallel over source rows.
pub fn find_bonds(grid: &Grid, m: usize, is_pd: &[bool]) -> Result<Vec<Bond>> {
    find_bonds_where(grid, m, is_pd, &|_, _| true)
}

/// [`find_bonds`] keeping only the bonds (a, b) with `exists(a, b)` (holes: no bond through a
/// hole or to a removed node, `pd::splice::holes`).
pub fn find_bonds_where(
    grid: &Grid,
    m: usize,
    is_pd: &[bool],
    exists: &(dyn Fn(usize, usize) -> bool + Sync),
) -> Result<Vec<Bond>> {
    if is_pd.len() != grid.n_nodes() {
        return Err(Error::SizeMismatch {
            what: "PD node mask".into(),
            expected: grid.n_nodes(),
            got: is_pd.len(),
        });
    }
    if grid.n_nodes() > u32::MAX as usize {
        return Err(Error::invalid(
            "grid",
            "fewer than 2^32 nodes",
            grid.n_nodes(),
        ));
    }
    let st = family_stencil(m);
    let dx = grid.dx;
    let rows: Vec<Vec<Bond>> = (0..=grid.ny)
        .into_par_iter()
        .map(|j| {
            let mut out = Vec::new();
            for i in 0..=grid.nx {
                let a = grid.node(i, j);
                for e in &st {
                    let (ii, jj) = (i as i64 + e.di as i64, j as i64 + e.dj as i64);
                    if ii < 0 || jj < 0 || ii > grid.nx as i64 || jj > grid.ny as i64 {
                        continue;
                    }
                    let b = grid.node(ii as usize, jj as usize);
                    let keep = match (is_pd[a], is_pd[b]) {
                        (true, true) => a < b,
                        (true, false) => true,
                        _ => false,
                    };
                    if keep && exists(a, b) {
                        out.push(Bond {
                            i: a as u32,
                            j: b as u32,
                            xi: [e.di as f64 * dx, e.dj as f64 * dx],
                            beta: e.beta,
                        });
                    }
                }
            }
            out
        })
        .collect();
    Ok(rows.into_iter().flatten().collect())
}

/// Damage index (eq. 53) of every node listed in `nodes`: 1 - (intact family volume) / (family
/// volume), with volumes weighted by beta (the discrete form of the integrals of eq. 53).
pub fn damage(n_nodes: usize, bonds: &[Bond], broken: &[bool], nodes: &[usize]) -> Vec<f64> {
    let mut tot = vec![0.0; n_nodes];
    let mut brk = vec![0.0; n_nodes];
    for (b, &x) in bonds.iter().zip(broken) {
        for n in [b.i as usize, b.j as usize] {
            tot[n] += b.beta;
            if x {
                brk[n] += b.beta;
            }
        }
    }
    nodes
        .iter()
        .map(|&n| if tot[n] > 0.0 { brk[n] / tot[n] } else { 0.0 })
        .collect()
}
