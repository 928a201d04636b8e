//! The pre-crack of the splice model (docs/design.md, "The splice coupling").
//!
//! A polyline: a bond is broken when its end nodes lie strictly on opposite sides of a
//! crack segment and the crossing point lies on the *closed* segment (the tip counts), decided in
//! grid units with tolerance 1e-9 x bond length; the pre-crack must not pass through a grid node
//! (refused). In the FEM part the crack is a real discontinuity by *removed elements*: every element
//! whose interior the crack cuts is dropped. On the paper's grid the crack x2 = 10.5 lies midway
//! between node rows, so this removes one row of elements (a slit one cell high), which is exactly
//! the set of material the broken PD bonds disconnect: nodes on rows x2 = 10.467 and 10.533 are
//! coupled neither by bonds nor by elements across the crack. (Duplicated nodes would need the
//! crack on a grid line, i.e. a different grid than the paper's.)
//!
//! On a graded grid (`graded.rs`) grid units are piecewise linear in the position: a pre-crack
//! segment must be horizontal, vertical or inside the uniform part (refused otherwise), so its
//! image in grid units is the straight segment the tests below use.
//!
//! Here: the validation of the polyline (in grid units), the cells it cuts, the bonds it breaks,
//! and the crack-mouth nodes of the CMOD.

use crate::error::{check_finite, Error, Result};
use crate::geometry::{bond_crosses, clipped_length};
use crate::pd::{Bond, Grid};
use crate::problem::validate::precrack_off_nodes;
use crate::problem::Domain;

/// The pre-crack polyline in grid units, validated: none or at least 2 points, every point inside
/// the plate, segments of positive length, no grid node on a segment.
pub(super) fn in_grid_units(
    precrack: &[[f64; 2]],
    d: &Domain,
    grid: &Grid,
) -> Result<Vec<[f64; 2]>> {
    let (nx, ny, dx) = (grid.nx, grid.ny, grid.dx);
    let crack: Vec<[f64; 2]> = precrack.iter().map(|&p| grid.to_units(p)).collect();
    if precrack.len() == 1 {
        return Err(Error::invalid(
            "precrack",
            "a polyline of at least 2 points (or none)",
            1,
        ));
    }
    for (k, p) in precrack.iter().enumerate() {
        check_finite(&format!("precrack[{k}][0]"), p[0])?;
        check_finite(&format!("precrack[{k}][1]"), p[1])?;
        let tol = 1e-9 * dx;
        if p[0] < -tol || p[0] > d.width + tol || p[1] < -tol || p[1] > d.height + tol {
            return Err(Error::invalid(
                &format!("precrack[{k}]"),
                "a point inside the plate",
                format!("{p:?}"),
            ));
        }
    }
    if !grid.is_uniform() {
        straight_in_grid_units(precrack, grid)?;
    }
    for s in crack.windows(2) {
        let (a, b) = (s[0], s[1]);
        let l = ((b[0] - a[0]).powi(2) + (b[1] - a[1]).powi(2)).sqrt();
        if l < 1e-9 {
            return Err(Error::invalid(
                "precrack",
                "segments of positive length",
                format!("{a:?}"),
            ));
        }
    }
    let xy = |i: usize, j: usize| grid.xy(grid.node(i, j));
    let culprit = |k: usize| ("precrack".to_string(), format!("segment {k}"));
    precrack_off_nodes(&crack, [nx, ny], &xy, &culprit)?;
    Ok(crack)
}

/// On a graded grid the map to grid units is piecewise linear, so a segment stays straight in
/// grid units only if it is axis-aligned or lies where the lines are uniform (the cells of
/// spacing dx around the PD rectangles): other segments are refused.
fn straight_in_grid_units(precrack: &[[f64; 2]], grid: &Grid) -> Result<()> {
    let tol = 1e-9 * grid.dx;
    // the uniform run of lines around the PD part, per axis
    let uniform_run = |lines: &[f64]| -> [f64; 2] {
        let h: Vec<f64> = lines.windows(2).map(|w| w[1] - w[0]).collect();
        let ok = |k: usize| (h[k] - grid.dx).abs() <= tol;
        let k0 = (0..h.len()).find(|&k| ok(k)).unwrap_or(0);
        let mut k1 = k0;
        while k1 < h.len() && ok(k1) {
            k1 += 1;
        }
        [lines[k0], lines[k1]]
    };
    let (rx, ry) = (uniform_run(&grid.xs), uniform_run(&grid.ys));
    let inside = |p: [f64; 2]| {
        p[0] >= rx[0] - tol && p[0] <= rx[1] + tol && p[1] >= ry[0] - tol && p[1] <= ry[1] + tol
    };
    for (k, s) in precrack.windows(2).enumerate() {
        let axis_aligned = (s[0][0] - s[1][0]).abs() <= tol || (s[0][1] - s[1][1]).abs() <= tol;
        let in_uniform_part = inside(s[0]) && inside(s[1]);
        if !(axis_aligned || in_uniform_part) {
            return Err(Error::invalid(
                "precrack",
                &format!(
                    "with pd.fem_grading > 1, segments that are horizontal or vertical or lie in                      the uniform part of the grid around the PD rectangles (x1 in [{:.6},                      {:.6}], x2 in [{:.6}, {:.6}]); or pd.fem_grading = 1",
                    rx[0], rx[1], ry[0], ry[1]
                ),
                format!("segment {k}: {:?} -> {:?}", s[0], s[1]),
            ));
        }
    }
    Ok(())
}

/// Does the pre-crack cut the interior of grid cell (i, j) (the element there is removed)?
pub(super) fn cuts_cell(crack: &[[f64; 2]], i: usize, j: usize) -> bool {
    let bx = [i as f64, j as f64, i as f64 + 1.0, j as f64 + 1.0];
    crack
        .windows(2)
        .any(|s| clipped_length(s[0], s[1], bx) > 1e-9)
}

/// The bonds the pre-crack breaks (crossing test in grid units, [`bond_crosses`]).
pub(super) fn broken_bonds(crack: &[[f64; 2]], grid: &Grid, bonds: &[Bond]) -> Vec<bool> {
    bonds
        .iter()
        .map(|b| {
            let (pi, pj) = (grid.ij(b.i as usize), grid.ij(b.j as usize));
            let p = [pi.0 as f64, pi.1 as f64];
            let q = [pj.0 as f64, pj.1 as f64];
            crack.windows(2).any(|s| bond_crosses(p, q, s[0], s[1]))
        })
        .collect()
}

/// (node below, node above, unit normal) at the crack mouth (vertex `at` of the polyline: the
/// first point of an edge crack, the centre of a centre crack), [`nodes_across`] the segment
/// starting there, for the CMOD; None without a pre-crack.
pub(super) fn mouth_nodes(
    crack: &[[f64; 2]],
    at: usize,
    grid: &Grid,
) -> Option<(usize, usize, [f64; 2])> {
    if crack.len() >= at + 2 {
        nodes_across(crack[at], crack[at + 1], crack[at], grid)
    } else {
        None
    }
}

/// (node below, node above, unit normal n) across the crack segment a-b at its point `x` (grid
/// units): the grid node nearest x on each side of the segment's line (within 2 cells), n the
/// left normal of a -> b ("above" is its side).
pub(super) fn nodes_across(
    a: [f64; 2],
    b: [f64; 2],
    x: [f64; 2],
    grid: &Grid,
) -> Option<(usize, usize, [f64; 2])> {
    let (nx, ny) = (grid.nx, grid.ny);
    let l = ((b[0] - a[0]).powi(2) + (b[1] - a[1]).powi(2)).sqrt();
    let nrm = [-(b[1] - a[1]) / l, (b[0] - a[0]) / l];
    let mut best = [(f64::INFINITY, usize::MAX); 2];
    let (ic, jc) = (x[0].round() as i64, x[1].round() as i64);
    for j in (jc - 2).max(0)..=(jc + 2).min(ny as i64) {
        for i in (ic - 2).max(0)..=(ic + 2).min(nx as i64) {
            let p = [i as f64, j as f64];
            let side = (p[0] - a[0]) * nrm[0] + (p[1] - a[1]) * nrm[1];
            let d = (p[0] - x[0]).powi(2) + (p[1] - x[1]).powi(2);
            let k = usize::from(side > 0.0);
            if d < best[k].0 {
                best[k] = (d, grid.node(i as usize, j as usize));
            }
        }
    }
    if best[0].1 != usize::MAX && best[1].1 != usize::MAX {
        Some((best[0].1, best[1].1, nrm))
    } else {
        None
    }
}
