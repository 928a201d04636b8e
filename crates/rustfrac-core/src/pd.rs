//! Bond-based peridynamics on a uniform grid (paper section 2.2.1, eqs. 37-57).
//!
//! * Grid: nodes at the vertices of a uniform `dx` grid (the same nodes as the Q4 mesh of the
//!   coupled model); each node carries the volume of its `dx x dx` cell times the thickness.
//! * Horizon `delta = m dx` (eq. 57). The family of a node is every grid node whose cell overlaps
//!   the horizon disc; its partial-volume factor `beta` is the *exact* fraction of that cell inside
//!   the disc (circle / square intersection in closed form, [`cell_fraction`]). Cells whose centre
//!   lies outside the disc but which overlap it carry their (small) fraction too: this is the
//!   choice that reproduces the paper's gamma (DESIGN.md section 3).
//! * Neighbour search: cell binning with bins of one grid cell (one node per bin); the family is a
//!   fixed stencil of bin offsets computed once, so the search is O(N x family size).
//! * Bonds are stored once (32 bytes: two `u32` node ids, the bond vector and `beta`).
//! * Constants: gamma from the discretisation ([`gamma`]), micromodulus c (eq. 47), critical
//!   stretch s0 (eq. 48), linearised bond stiffness (eqs. 46, 55, 56), damage index (eq. 53).

use crate::error::{check_positive, Error, Result};
use crate::material::{Elastic, Plane};
use rayon::prelude::*;
use std::f64::consts::PI;

/// Area of {0 <= X <= x, 0 <= Y <= y} inside the disc of radius r centred at the origin (x, y >= 0).
fn corner_area(x: f64, y: f64, r: f64) -> f64 {
    let x = x.min(r);
    let y = y.min(r);
    if x <= 0.0 || y <= 0.0 {
        return 0.0;
    }
    if x * x + y * y <= r * r {
        return x * y;
    }
    // sqrt(r^2 - X^2) = y at X = xc; for X < xc the height is y, beyond it the arc
    let xc = (r * r - y * y).max(0.0).sqrt();
    let prim = |t: f64| 0.5 * (t * (r * r - t * t).max(0.0).sqrt() + r * r * (t / r).asin());
    y * xc + (prim(x) - prim(xc))
}

fn signed_corner(x: f64, y: f64, r: f64) -> f64 {
    x.signum() * y.signum() * corner_area(x.abs(), y.abs(), r)
}

/// Exact area of the rectangle [x0, x1] x [y0, y1] inside the disc of radius r centred at the
/// origin (inclusion-exclusion of signed corner areas, each in closed form).
pub fn rect_disc_area(x0: f64, x1: f64, y0: f64, y1: f64, r: f64) -> f64 {
    signed_corner(x1, y1, r) - signed_corner(x0, y1, r) - signed_corner(x1, y0, r)
        + signed_corner(x0, y0, r)
}

/// Exact fraction of the unit cell centred at (a, b) (grid units) inside the disc of radius m.
pub fn cell_fraction(a: f64, b: f64, m: f64) -> f64 {
    rect_disc_area(a - 0.5, a + 0.5, b - 0.5, b + 0.5, m).clamp(0.0, 1.0)
}

/// One stencil entry: grid offset (di, dj) and its partial-volume factor.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StencilEntry {
    pub di: i32,
    pub dj: i32,
    pub beta: f64,
}

/// The family stencil of horizon m (grid units): every offset != (0, 0) whose cell overlaps the
/// disc, with its exact partial-volume factor; sorted by (dj, di).
pub fn family_stencil(m: usize) -> Vec<StencilEntry> {
    let r = m as i32 + 1;
    let mut out = Vec::new();
    for dj in -r..=r {
        for di in -r..=r {
            if di == 0 && dj == 0 {
                continue;
            }
            let beta = cell_fraction(di as f64, dj as f64, m as f64);
            if beta > 0.0 {
                out.push(StencilEntry { di, dj, beta });
            }
        }
    }
    out
}

/// gamma = [integral over the disc of xi1^4/|xi|^3 dA] / [sum_j xi1^4/|xi|^3 beta_j dx^2]
/// (Ongaro et al. 2021, DESIGN.md section 3), computed on the grid stencil of horizon m dx. It is
/// independent of dx. The continuum integral is pi delta^3 / 4.
pub fn gamma(m: usize) -> Result<f64> {
    if m == 0 || m > 64 {
        return Err(Error::invalid("m", "an integer horizon ratio 1..=64", m));
    }
    let st = family_stencil(m);
    let mut sum = 0.0;
    for e in &st {
        let (a, b) = (e.di as f64, e.dj as f64);
        let r = (a * a + b * b).sqrt();
        sum += a.powi(4) / r.powi(3) * e.beta;
    }
    let md = m as f64;
    Ok(PI * md.powi(3) / 4.0 / sum)
}

/// The PD constants of a bond-based plane model.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PdConstants {
    pub dx: f64,
    pub m: usize,
    /// horizon delta = m dx (eq. 57)
    pub delta: f64,
    /// correction factor from the discretisation
    pub gamma: f64,
    /// micromodulus c = 48 E gamma / (5 pi h delta^3) (eq. 47)
    pub c: f64,
    /// critical stretch s0 = sqrt(5 pi G0 / (12 E delta)) (eq. 48)
    pub s0: f64,
    /// node volume dx^2 h
    pub volume: f64,
}

/// Checks that bond-based PD can represent the material: plane strain needs nu = 1/4 (plane stress
/// would need 1/3, whose constants eqs. 47-48 do not cover: refused too).
pub fn check_material(mat: &Elastic) -> Result<()> {
    mat.validate()?;
    match mat.plane {
        Plane::Strain => {
            if (mat.nu - 0.25).abs() > 1e-12 {
                return Err(Error::invalid(
                    "nu",
                    "nu = 0.25: bond-based (pairwise) peridynamics in plane strain has a fixed \
                     Poisson's ratio of 1/4 (paper section 2.2.1); use XFEM/FEM for other values",
                    mat.nu,
                ));
            }
            Ok(())
        }
        Plane::Stress => Err(Error::invalid(
            "plane",
            "plane strain: bond-based PD in plane stress fixes nu = 1/3 and needs different \
             constants than eqs. 47-48, which are implemented for plane strain only",
            "stress",
        )),
    }
}

impl PdConstants {
    /// Validates the inputs and computes gamma, c, s0.
    pub fn new(mat: &Elastic, g0: f64, dx: f64, m: usize) -> Result<Self> {
        check_material(mat)?;
        check_positive("G0", g0)?;
        check_positive("dx", dx)?;
        if !(1..=12).contains(&m) {
            return Err(Error::invalid("m", "an integer horizon ratio 1..=12", m));
        }
        let delta = m as f64 * dx;
        let gamma = gamma(m)?;
        let h = mat.thickness;
        let c = 48.0 * mat.e * gamma / (5.0 * PI * h * delta.powi(3));
        let s0 = (5.0 * PI * g0 / (12.0 * mat.e * delta)).sqrt();
        Ok(Self {
            dx,
            m,
            delta,
            gamma,
            c,
            s0,
            volume: dx * dx * h,
        })
    }

    /// Linearised bond stiffness (eqs. 46, 55, 56) with both node volumes (rows scaled by the
    /// node volume, DESIGN.md section 3): the force on node i is alpha n n^T (u_j - u_i) with
    /// alpha = c beta V_i V_j / |xi| and n = xi / |xi|. Returns alpha.
    pub fn bond_alpha(&self, bond: &Bond) -> f64 {
        let l = (bond.xi[0] * bond.xi[0] + bond.xi[1] * bond.xi[1]).sqrt();
        self.c * bond.beta * self.volume * self.volume / l
    }
}

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
                    if keep {
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exact_areas() {
        // whole disc
        let a = rect_disc_area(-2.0, 2.0, -2.0, 2.0, 1.0);
        assert!((a - PI).abs() < 1e-14);
        // quarter disc
        assert!((rect_disc_area(0.0, 1.0, 0.0, 1.0, 1.0) - PI / 4.0).abs() < 1e-14);
        // half disc
        assert!((rect_disc_area(-1.0, 1.0, 0.0, 3.0, 1.0) - PI / 2.0).abs() < 1e-14);
        // sum of cell fractions = disc area
        let m = 4usize;
        let s: f64 = family_stencil(m).iter().map(|e| e.beta).sum::<f64>()
            + cell_fraction(0.0, 0.0, m as f64);
        assert!((s - PI * 16.0).abs() < 1e-11, "{s}");
    }
}
