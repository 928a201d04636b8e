//! [`SpliceModel::new`] in named phases: the grid and the PD constants, the node classes (PD
//! rectangles or pure PD), the pre-crack (`precrack.rs`), the hybrid elements, the bonds, the
//! blocks of the matrix pattern, the loading (`boundary.rs`), the crack-mouth nodes and the
//! node -> bonds incidence. Each phase validates its part of the spec, in this order.

use super::boundary::loading;
use super::precrack;
use super::{ModelSpec, SpliceModel};
use crate::error::{check_positive, Error, Result};
use crate::fe::q4::element_stiffness;
use crate::fe::quadrature::subquad_rule;
use crate::la::Pattern;
use crate::pd::{find_bonds, Bond, Grid, PdConstants};
use crate::warning::{Warning, WarningKind};

impl SpliceModel {
    /// Validates the spec and builds node classes, elements, bonds, pre-crack, pattern and loads.
    pub fn new(spec: &ModelSpec) -> Result<Self> {
        let (grid, pd) = grid_and_constants(spec)?;
        let (is_pd, pd_nodes, warnings) = node_classes(spec, &grid, &pd)?;
        let crack = precrack::in_grid_units(spec, &grid)?;
        let (ke, elements, n_removed) = hybrid_elements(spec, &grid, &is_pd, &crack);
        let bonds = find_bonds(&grid, spec.m, &is_pd)?;
        let precrack_broken = precrack::broken_bonds(&crack, &grid, &bonds);
        let (rows_of, cols_of, pattern) = blocks(&grid, &elements, &bonds, &is_pd)?;
        let lo = loading(spec, &grid)?;
        let cmod_nodes = precrack::mouth_nodes(&crack, &grid);
        let (node_bond_ptr, node_bonds) = incidence(grid.n_nodes(), &bonds);
        Ok(Self {
            node_bond_ptr,
            node_bonds,
            warnings,
            spec: spec.clone(),
            grid,
            pd,
            is_pd,
            pd_nodes,
            elements,
            n_removed_elements: n_removed,
            bonds,
            precrack_broken,
            ke,
            rows_of,
            cols_of,
            pattern,
            edges: lo.edges,
            bc: lo.bc,
            f: lo.f,
            anchor: lo.anchor,
            mask: lo.mask,
            prescribed: lo.prescribed,
            cmod_nodes,
        })
    }
}

pub(crate) fn grid_count(len: f64, dx: f64, name: &str) -> Result<usize> {
    let r = len / dx;
    let n = r.round();
    if !(1.0..=1e7).contains(&n) || (r - n).abs() > 1e-6 * n.max(1.0) {
        return Err(Error::invalid(
            name,
            "a multiple of dx (the grid must fit the plate exactly), at most 1e7 cells",
            format!("{len} / dx = {r}"),
        ));
    }
    Ok(n as usize)
}

/// The grid (W / dx and L / dx integers, the same spacing along both axes, at most
/// [`crate::fe::mesh::MAX_ELEMENTS`] nodes) and the PD constants on it.
fn grid_and_constants(spec: &ModelSpec) -> Result<(Grid, PdConstants)> {
    check_positive("width", spec.width)?;
    check_positive("height", spec.height)?;
    check_positive("dx", spec.dx)?;
    let nx = grid_count(spec.width, spec.dx, "width")?;
    let ny = grid_count(spec.height, spec.dx, "height")?;
    let dx = spec.width / nx as f64;
    if ((spec.height / ny as f64) - dx).abs() > 1e-9 * dx {
        return Err(Error::invalid(
            "dx",
            "the same spacing along x1 and x2",
            spec.dx,
        ));
    }
    // the same memory guard as the FEM meshes (a finer PD grid also makes each SLA step slow)
    if (nx + 1) * (ny + 1) > crate::fe::mesh::MAX_ELEMENTS {
        return Err(Error::invalid(
            "dx",
            &format!("at most {} grid nodes", crate::fe::mesh::MAX_ELEMENTS),
            (nx + 1) * (ny + 1),
        ));
    }
    let pd = PdConstants::new(&spec.material, spec.g0, dx, spec.m)?;
    let grid = Grid {
        nx,
        ny,
        dx,
        x0: 0.0,
        y0: 0.0,
    };
    Ok((grid, pd))
}

/// Node classes: every node PD (pure PD model, the plate at least two horizons wide and high), or
/// the nodes inside the PD rectangles. Returns the PD flags, the PD node ids (ascending) and the
/// discretisation warnings.
fn node_classes(
    spec: &ModelSpec,
    grid: &Grid,
    pd: &PdConstants,
) -> Result<(Vec<bool>, Vec<usize>, Vec<Warning>)> {
    let (dx, nn) = (grid.dx, grid.n_nodes());
    let mut is_pd = vec![spec.all_pd(); nn];
    if spec.all_pd() {
        let two_h = 2.0 * pd.delta;
        for (name, len) in [("width", spec.width), ("height", spec.height)] {
            if len < two_h - 1e-9 * dx {
                return Err(Error::invalid(
                    name,
                    &format!("at least two horizons (2 m dx = {two_h:.6}) for the pure PD model"),
                    len,
                ));
            }
        }
    }
    let warnings = horizon_warnings(spec);
    if !spec.all_pd() {
        mark_pd_regions(spec, grid, pd, &mut is_pd)?;
    }
    let pd_nodes: Vec<usize> = (0..nn).filter(|&n| is_pd[n]).collect();
    if pd_nodes.is_empty() {
        return Err(Error::invalid(
            "pd_regions",
            "rectangles containing at least one grid node",
            format!("{:?}", spec.pd_regions),
        ));
    }
    Ok((is_pd, pd_nodes, warnings))
}

/// The warning of a horizon factor m < 2 (too few bonds per node).
fn horizon_warnings(spec: &ModelSpec) -> Vec<Warning> {
    let mut warnings = Vec::new();
    if spec.m < 2 {
        warnings.push(Warning::new(
            WarningKind::Discretisation,
            format!(
                "horizon factor m = {}: a bulk node has only {} bonds (m = 2: {}, the paper's m = \
             4: {}); too few bonds for a peridynamic continuum, expect errors of several \
             percent in stiffness and fracture (use m >= 2, preferably 3-4)",
                spec.m,
                crate::pd::family_stencil(spec.m).len(),
                crate::pd::family_stencil(2).len(),
                crate::pd::family_stencil(4).len()
            ),
        ));
    }
    warnings
}

/// Validates the PD rectangles (finite, inside the plate, at least two horizons wide and high) and
/// flags the grid nodes inside them (closed, tolerance 1e-9 dx).
fn mark_pd_regions(
    spec: &ModelSpec,
    grid: &Grid,
    pd: &PdConstants,
    is_pd: &mut [bool],
) -> Result<()> {
    let dx = grid.dx;
    if spec.pd_regions.is_empty() {
        return Err(Error::invalid(
            "pd_regions",
            "at least one rectangle [x0, y0, x1, y1] (or the pure PD method)",
            "none",
        ));
    }
    let tol = 1e-9 * dx;
    for (k, r) in spec.pd_regions.iter().enumerate() {
        if r.iter().any(|v| !v.is_finite())
            || r[2] <= r[0]
            || r[3] <= r[1]
            || r[0] < -tol
            || r[1] < -tol
            || r[2] > spec.width + tol
            || r[3] > spec.height + tol
        {
            return Err(Error::invalid(
                &format!("pd_regions[{k}]"),
                "finite [x0, y0, x1, y1] with x0 < x1, y0 < y1 inside the plate",
                format!("{r:?}"),
            ));
        }
        // a region thinner than two horizons has no node with a full family: every node
        // is a boundary node of the PD region and the coupling dominates the solution
        let two_h = 2.0 * pd.delta;
        if r[2] - r[0] < two_h - tol || r[3] - r[1] < two_h - tol {
            return Err(Error::invalid(
                &format!("pd_regions[{k}]"),
                &format!(
                    "a rectangle at least two horizons wide and high (2 m dx = {two_h:.6} \
                     with m = {}, dx = {dx:.6}): x1 - x0 >= {two_h:.6} and \
                     y1 - y0 >= {two_h:.6}",
                    spec.m
                ),
                format!("{:.6} x {:.6}", r[2] - r[0], r[3] - r[1]),
            ));
        }
        for (n, flag) in is_pd.iter_mut().enumerate() {
            let p = grid.xy(n);
            if p[0] >= r[0] - tol && p[0] <= r[2] + tol && p[1] >= r[1] - tol && p[1] <= r[3] + tol
            {
                *flag = true;
            }
        }
    }
    Ok(())
}

/// The FEM elements: every Q4 element with at least one FEM node (hybrid elements included) whose
/// interior the pre-crack does not cut, and the element stiffness of the dx x dx square (exact
/// 2 x 2 Gauss, row-major 8 x 8). Returns (stiffness, elements, number removed by the pre-crack).
fn hybrid_elements(
    spec: &ModelSpec,
    grid: &Grid,
    is_pd: &[bool],
    crack: &[[f64; 2]],
) -> (Vec<f64>, Vec<[usize; 4]>, usize) {
    let (nx, ny, dx) = (grid.nx, grid.ny, grid.dx);
    let mut ke = Vec::new();
    let sq = [[0.0, 0.0], [dx, 0.0], [dx, dx], [0.0, dx]];
    element_stiffness(&sq, &spec.material, &subquad_rule(1, 2), &mut ke);
    let mut elements = Vec::new();
    let mut n_removed = 0;
    for j in 0..ny {
        for i in 0..nx {
            let n0 = grid.node(i, j);
            let e = [n0, n0 + 1, n0 + nx + 2, n0 + nx + 1];
            if e.iter().all(|&n| is_pd[n]) {
                continue;
            }
            if precrack::cuts_cell(crack, i, j) {
                n_removed += 1;
                continue;
            }
            elements.push(e);
        }
    }
    (ke, elements, n_removed)
}

/// The blocks of the splice matrix and their pattern: an element writes the rows of its FEM nodes
/// (all 8 columns), a bond the rows of its PD end(s) (4 columns).
#[allow(clippy::type_complexity)]
fn blocks(
    grid: &Grid,
    elements: &[[usize; 4]],
    bonds: &[Bond],
    is_pd: &[bool],
) -> Result<(Vec<Vec<usize>>, Vec<Vec<usize>>, Pattern)> {
    let mut rows_of = Vec::with_capacity(elements.len() + bonds.len());
    let mut cols_of = Vec::with_capacity(elements.len() + bonds.len());
    for e in elements {
        let mut r = Vec::with_capacity(8);
        let mut c = Vec::with_capacity(8);
        for &n in e {
            if !is_pd[n] {
                r.extend([2 * n, 2 * n + 1]);
            }
            c.extend([2 * n, 2 * n + 1]);
        }
        rows_of.push(r);
        cols_of.push(c);
    }
    for b in bonds {
        let (i, j) = (b.i as usize, b.j as usize);
        let mut r = vec![2 * i, 2 * i + 1];
        if is_pd[j] {
            r.extend([2 * j, 2 * j + 1]);
        }
        rows_of.push(r);
        cols_of.push(vec![2 * i, 2 * i + 1, 2 * j, 2 * j + 1]);
    }
    let ndof = 2 * grid.n_nodes();
    let pattern = Pattern::new(ndof, &rows_of, &cols_of)?;
    Ok((rows_of, cols_of, pattern))
}

/// The bonds of every node, both ends (CSR over nodes: pointers, bond ids).
fn incidence(nn: usize, bonds: &[Bond]) -> (Vec<usize>, Vec<u32>) {
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
