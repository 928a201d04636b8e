//! Loading of the splice model: the plate's top and bottom edges
//! ([`crate::fe::loading::plate_conditions`]). In the coupled model those are the edge node rows; in
//! the pure PD model the displacement conditions act on volumetric boundary layers of m node rows
//! (thickness m dx = delta) at the top and bottom, the usual choice that gives edge nodes a full
//! family of prescribed neighbours. The u1 anchor of the "free" grip is the bottom-right corner
//! node (reported). Supports and loads on regions: `regions.rs`. Nodes removed by holes
//! (`holes.rs`) are fixed to zero (both dofs) in either case.

use super::regions::region_loading;
use super::response::Response;
use crate::error::Result;
use crate::fe::loading::{plate_conditions, tributary_lengths, PlateEdges};
use crate::fe::regions::RegionConditions;
use crate::fe::Dirichlet;
use crate::pd::Grid;
use crate::problem::{Boundary, Grip, Problem};

/// The loading of a model: the loaded node rows, the displacement conditions, the external forces
/// (traction grip), the anchor node and the constrained dofs with their reference values.
pub(super) struct Loading {
    pub(super) edges: PlateEdges,
    pub(super) bc: Dirichlet,
    pub(super) f: Vec<f64>,
    pub(super) anchor: usize,
    pub(super) mask: Vec<bool>,
    pub(super) prescribed: Vec<f64>,
    /// supports and loads on regions (None: the grips)
    pub(super) regions: Option<RegionConditions>,
    /// the history's load responses
    pub(super) response: Response,
}

/// The loading of `p` on `grid` ([`crate::fe::loading::plate_conditions`] on [`edges`] of
/// `layers` node rows: 1 for the coupled model, m for pure PD).
pub(super) fn loading(
    p: &Problem,
    layers: usize,
    grid: &Grid,
    material: &[bool],
) -> Result<Loading> {
    let ndof = 2 * grid.n_nodes();
    let thickness = p.material.elastic.thickness;
    let (edges, bc, f, anchor, regions, response) = match &p.boundary {
        Boundary::Grips(_) => {
            let edges = edges(layers, grid);
            let load = p.boundary.plate_load();
            let (bc, f, anchor) = plate_conditions(&edges, &load, ndof, thickness)?;
            let driven = load.grip != Grip::Traction;
            let response = Response::grips(&edges, p.domain.width, thickness, driven);
            (edges, bc, f, anchor, None, response)
        }
        Boundary::Regions { supports, loads } => {
            let rc = region_loading(
                grid, &p.domain, material, supports, loads, layers, thickness,
            )?;
            let response = Response::regions(&rc, supports.len(), thickness);
            let edges = PlateEdges {
                top: Vec::new(),
                bottom: Vec::new(),
                top_len: Vec::new(),
                bottom_len: Vec::new(),
            };
            (edges, rc.bc.clone(), rc.f.clone(), 0, Some(rc), response)
        }
    };
    let (mut mask, mut prescribed) = bc.to_mask(ndof)?;
    let mut f = f;
    // removed nodes take part in no equation: held at 0 (a grip on a notched edge too: a cut
    // FEM element keeps their columns), no force
    for (n, _) in material.iter().enumerate().filter(|(_, &m)| !m) {
        for d in [2 * n, 2 * n + 1] {
            mask[d] = true;
            prescribed[d] = 0.0;
            f[d] = 0.0;
        }
    }
    Ok(Loading {
        edges,
        bc,
        f,
        anchor,
        mask,
        prescribed,
        regions,
        response,
    })
}

/// The loaded node rows with their tributary lengths: the edge rows (coupled), or volumetric layers
/// of m rows (pure PD, at most half the grid; only the outer row carries a traction length).
fn edges(layers: usize, grid: &Grid) -> PlateEdges {
    let ny = grid.ny;
    let layers = layers.min(ny / 2).max(1);
    let mut top = Vec::new();
    let mut bottom = Vec::new();
    let mut top_len = Vec::new();
    let mut bottom_len = Vec::new();
    let trib = tributary_lengths(&grid.xs);
    for j in (ny + 1 - layers)..=ny {
        for (i, &t) in trib.iter().enumerate() {
            top.push(grid.node(i, j));
            top_len.push(if j == ny { t } else { 0.0 });
        }
    }
    for j in (0..layers).rev() {
        for (i, &t) in trib.iter().enumerate() {
            bottom.push(grid.node(i, j));
            bottom_len.push(if j == 0 { t } else { 0.0 });
        }
    }
    PlateEdges {
        top,
        bottom,
        top_len,
        bottom_len,
    }
}
