//! Bonds on the PD grid: the grid, the bond list, the neighbour search and the damage index
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

/// A tensor grid of (nx + 1) x (ny + 1) nodes, node (i, j) = j (nx + 1) + i, at (`xs[i]`, `ys[j]`).
/// Uniform ([`Grid::uniform`]): `xs[i]` = x0 + i dx. Graded ([`Grid::graded`], the FEM part of a
/// CCM-PD model, `pd::splice`): the lines are spaced `dx` wherever PD nodes and their families
/// lie and grow away from them; everything that is only about the PD part (bonds, volumes, the
/// family stencil) keeps the uniform spacing `dx`.
#[derive(Debug, Clone, PartialEq)]
pub struct Grid {
    pub nx: usize,
    pub ny: usize,
    /// the PD spacing (the lines' spacing everywhere on a uniform grid)
    pub dx: f64,
    pub x0: f64,
    pub y0: f64,
    /// the vertical grid lines (nx + 1)
    pub xs: Vec<f64>,
    /// the horizontal grid lines (ny + 1)
    pub ys: Vec<f64>,
    /// the lines are x0 + i dx, y0 + j dx
    uniform: bool,
}

impl Grid {
    /// The uniform grid of nx x ny cells of size dx from (x0, y0).
    pub fn uniform(nx: usize, ny: usize, dx: f64, x0: f64, y0: f64) -> Self {
        Self {
            nx,
            ny,
            dx,
            x0,
            y0,
            xs: (0..=nx).map(|i| x0 + i as f64 * dx).collect(),
            ys: (0..=ny).map(|j| y0 + j as f64 * dx).collect(),
            uniform: true,
        }
    }

    /// The tensor grid with lines `xs`, `ys` (strictly increasing, at least 2 each) and PD
    /// spacing `dx`.
    pub fn graded(xs: Vec<f64>, ys: Vec<f64>, dx: f64) -> Self {
        Self {
            nx: xs.len() - 1,
            ny: ys.len() - 1,
            dx,
            x0: xs[0],
            y0: ys[0],
            xs,
            ys,
            uniform: false,
        }
    }

    /// Are the lines x0 + i dx, y0 + j dx?
    pub fn is_uniform(&self) -> bool {
        self.uniform
    }
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
        [self.xs[i], self.ys[j]]
    }
    /// The place (i, j) of node `n` on the PD lattice x = i dx, y = j dx (the PD nodes of every
    /// grid lie on it, graded FEM grids included).
    pub fn lattice_key(&self, n: usize) -> [i64; 2] {
        let [x, y] = self.xy(n);
        [(x / self.dx).round() as i64, (y / self.dx).round() as i64]
    }
    /// The size (hx, hy) of cell (i, j).
    pub fn cell_size(&self, i: usize, j: usize) -> [f64; 2] {
        [self.xs[i + 1] - self.xs[i], self.ys[j + 1] - self.ys[j]]
    }
    /// A point in grid units: (x - x0) / dx on a uniform grid; on a graded grid the cell index
    /// plus the fraction within the cell (piecewise linear in each coordinate; outside the
    /// lines extrapolated with the end cells).
    pub fn to_units(&self, p: [f64; 2]) -> [f64; 2] {
        if self.uniform {
            return [(p[0] - self.x0) / self.dx, (p[1] - self.y0) / self.dx];
        }
        let unit = |lines: &[f64], x: f64| -> f64 {
            let n = lines.len() - 1;
            let k = lines.partition_point(|&l| l <= x).clamp(1, n) - 1;
            k as f64 + (x - lines[k]) / (lines[k + 1] - lines[k])
        };
        [unit(&self.xs, p[0]), unit(&self.ys, p[1])]
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

/// The bonds of every node, both ends (CSR over nodes: pointers, bond ids).
pub fn incidence(nn: usize, bonds: &[Bond]) -> (Vec<usize>, Vec<u32>) {
    let mut node_bond_ptr = vec![0usize; nn + 1];
    for b in bonds {
        node_bond_ptr[b.i as usize + 1] += 1;
        node_bond_ptr[b.j as usize + 1] += 1;
    }
    for n in 0..nn {
        node_bond_ptr[n + 1] += node_bond_ptr[n];
    }
    let mut fill = node_bond_ptr.clone();
    let mut node_bonds = vec![0u32; node_bond_ptr[nn]];
    for (k, b) in bonds.iter().enumerate() {
        for n in [b.i as usize, b.j as usize] {
            node_bonds[fill[n]] = k as u32;
            fill[n] += 1;
        }
    }
    (node_bond_ptr, node_bonds)
}
