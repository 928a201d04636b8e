//! The graded FEM grid of a CCM-PD model (`pd.fem_grading` > 1).
//!
//! The grid lines are uniform, spacing dx, over the bounding box of the PD rectangles plus a
//! band of m + 1 elements around it (clipped to the plate), and grow geometrically beyond it
//! (ratio `pd.fem_grading`, element sizes capped at `pd.fem_coarse` dx) with
//! [`crate::problem::grading::graded_lines`], the FEM/XFEM graded grids' rule. So every PD node, its
//! whole family (|xi| <= m dx) and every hybrid element see the uniform PD spacing: bonds, node
//! volumes, partial volumes and the shared element matrix are those of the uniform model, and
//! only whole FEM elements away from the PD part differ (their own matrices,
//! [`super::ElementStiffness`]). The splice coupling needs nothing else: a FEM node far from the
//! PD part is an ordinary node of a graded Q4 mesh.
//!
//! [`check_families`] verifies the property on the built model (every bond's vector equals its
//! end nodes' positions' difference).

use crate::error::{Error, Result};
use crate::pd::{Bond, Grid};
use crate::problem::grading::graded_lines;
use crate::problem::PdMethod;

/// The grid of a CCM-PD model with grading: uniform `dx` (nx x ny cells on the plate) near the
/// PD rectangles, graded beyond. `pm.fem_grading == 1` gives the uniform grid.
pub(super) fn grid(pm: &PdMethod, nx: usize, ny: usize, dx: f64) -> Grid {
    if pm.fem_grading == 1.0 || pm.regions.is_empty() {
        return Grid::uniform(nx, ny, dx, 0.0, 0.0);
    }
    let band = (pm.m + 1) as f64;
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for r in &pm.regions {
        for a in 0..2 {
            lo[a] = lo[a].min(r[a]);
            hi[a] = hi[a].max(r[2 + a]);
        }
    }
    let lines = |a: usize, n: usize| -> Vec<f64> {
        // the box in whole cells of the uniform grid, widened by the band
        let i_lo = ((lo[a] / dx + 1e-9).floor() - band).max(0.0) as usize;
        let i_hi = (((hi[a] / dx - 1e-9).ceil() + band) as usize).min(n);
        let len = n as f64 * dx;
        let at = |i: usize| if i == n { len } else { i as f64 * dx };
        graded_lines(
            len,
            at(i_lo),
            at(i_hi),
            dx,
            pm.fem_grading,
            pm.fem_coarse * dx,
        )
    };
    Grid::graded(lines(0, nx), lines(1, ny), dx)
}

/// Every bond's vector is its end nodes' distance (the PD families lie on the uniform part of
/// the grid), within 1e-9 dx: else the grid is refused (an internal rule of [`grid`]).
pub(super) fn check_families(grid: &Grid, bonds: &[Bond]) -> Result<()> {
    if grid.is_uniform() {
        return Ok(());
    }
    let tol = 1e-9 * grid.dx;
    for b in bonds {
        let (p, q) = (grid.xy(b.i as usize), grid.xy(b.j as usize));
        if (q[0] - p[0] - b.xi[0]).abs() > tol || (q[1] - p[1] - b.xi[1]).abs() > tol {
            return Err(Error::invalid(
                "pd.fem_grading",
                "a graded grid whose lines are uniform (dx) over every PD family",
                format!("the bond from {p:?} to {q:?} spans graded cells"),
            ));
        }
    }
    Ok(())
}

/// Does cell (i, j) differ from the dx x dx square (by more than 1e-9 dx)?
pub(super) fn is_graded_cell(grid: &Grid, i: usize, j: usize) -> bool {
    if grid.is_uniform() {
        return false;
    }
    let [hx, hy] = grid.cell_size(i, j);
    let tol = 1e-9 * grid.dx;
    (hx - grid.dx).abs() > tol || (hy - grid.dx).abs() > tol
}

/// The grid as a FEM mesh (the same nodes and elements; holes' fictitious domain and regions'
/// node sets are built on it).
pub(super) fn fe_mesh(grid: &Grid) -> Result<crate::fe::mesh::Mesh> {
    use crate::fe::mesh::Mesh;
    if grid.is_uniform() {
        let (w, h) = (grid.nx as f64 * grid.dx, grid.ny as f64 * grid.dx);
        Mesh::uniform(grid.x0, grid.y0, w, h, grid.nx, grid.ny)
    } else {
        Mesh::from_lines(grid.xs.clone(), grid.ys.clone())
    }
}
