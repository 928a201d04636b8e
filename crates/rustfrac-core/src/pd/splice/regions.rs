//! Supports and loads on regions ([`crate::fe::regions`]) for the splice model.
//!
//! The region node sets, the consistent nodal forces of tractions and the checks (a part holding
//! nodes, a point near a node, one prescription per dof) are [`region_conditions`] on the PD grid
//! as a [`Mesh`] with the grid's lines (the same numbering: node (i, j) = j (nx + 1) + i), removed nodes
//! (holes, `holes.rs`) excluded. Then:
//!
//! * CCM-PD (`layers` = 1): unchanged, the edge node rows in the FEM part, as the grips.
//! * Pure PD (`layers` = m): volumetric boundary layers of thickness delta = m dx (at most half
//!   the grid across), so that a loaded edge node has a full family of loaded neighbours:
//!   - an edge or edge-part region takes, for each of its edge nodes, the m nodes of its column
//!     into the plate (the node and the m - 1 behind it, the grips' layers of `boundary.rs`);
//!   - a point region takes the material nodes within delta / 2 of the node nearest the point;
//!   - a box region is already volumetric and stays as it is.
//!
//!   A support prescribes its values on every node of its layer. A load acts as a body force on
//!   the layer: the consistent nodal force of the outer row ([`region_conditions`]: the traction
//!   t times the tributary length, times the thickness) is split equally over the material
//!   nodes of that node's column (a point force equally over the point's layer), i.e. a body
//!   force density t L / (layer area) for a uniform traction t on a length L. The resultant is
//!   the applied force exactly (up to round-off).

use crate::error::{Error, Result};
use crate::fe::regions::{region_conditions, RegionConditions};
use crate::fe::Dirichlet;
use crate::pd::Grid;
use crate::problem::{Domain, Region, RegionLoad, Side, Support};

/// The nodes behind edge node `n` of `side`, `layers` deep (n first), material ones only.
fn column(grid: &Grid, material: &[bool], n: usize, side: Side, layers: usize) -> Vec<usize> {
    let (i, j) = grid.ij(n);
    (0..layers)
        .filter_map(|k| {
            let (ii, jj) = match side {
                Side::Bottom => (i, j + k),
                Side::Top => (i, j.checked_sub(k)?),
                Side::Left => (i + k, j),
                Side::Right => (i.checked_sub(k)?, j),
            };
            (ii <= grid.nx && jj <= grid.ny).then(|| grid.node(ii, jj))
        })
        .filter(|&q| material[q])
        .collect()
}

/// The material nodes within `r` (grid units) of node `n`.
fn disc(grid: &Grid, material: &[bool], n: usize, r: f64) -> Vec<usize> {
    let (i, j) = grid.ij(n);
    let k = r.floor() as i64;
    let mut out = Vec::new();
    for dj in -k..=k {
        for di in -k..=k {
            let (ii, jj) = (i as i64 + di, j as i64 + dj);
            if ii < 0 || jj < 0 || ii > grid.nx as i64 || jj > grid.ny as i64 {
                continue;
            }
            if ((di * di + dj * dj) as f64).sqrt() <= r + 1e-12 {
                let q = grid.node(ii as usize, jj as usize);
                if material[q] {
                    out.push(q);
                }
            }
        }
    }
    out
}

/// The layer of each node of a region's outer set: (outer node, its layer).
fn layer_of(
    grid: &Grid,
    material: &[bool],
    region: &Region,
    outer: &[usize],
    layers: usize,
) -> Vec<(usize, Vec<usize>)> {
    outer
        .iter()
        .map(|&n| {
            let l = match *region {
                _ if layers <= 1 => vec![n],
                Region::Edge(side) | Region::EdgePart { side, .. } => {
                    let across = match side {
                        Side::Bottom | Side::Top => grid.ny,
                        Side::Left | Side::Right => grid.nx,
                    };
                    column(grid, material, n, side, layers.min(across / 2).max(1))
                }
                Region::Point(_) => disc(grid, material, n, 0.5 * layers as f64),
                Region::Box(_) => vec![n],
            };
            (n, l)
        })
        .collect()
}

/// The Dirichlet set, forces and (layer) node sets of `supports` and `loads` on the PD grid,
/// `layers` deep (1: CCM-PD edge rows; m: pure PD boundary layers). `material` flags the nodes
/// the holes leave.
pub(super) fn region_loading(
    grid: &Grid,
    domain: &Domain,
    material: &[bool],
    supports: &[Support],
    loads: &[RegionLoad],
    layers: usize,
    thickness: f64,
) -> Result<RegionConditions> {
    let mesh = super::graded::fe_mesh(grid)?;
    let ndof = 2 * grid.n_nodes();
    let mut rc = region_conditions(&mesh, domain, material, supports, loads, ndof, thickness)?;
    if layers <= 1 {
        return Ok(rc);
    }
    // supports: every node of the layer, one value per dof
    let mut bc = Dirichlet::default();
    let mut owner: std::collections::HashMap<usize, (&str, f64)> = Default::default();
    for (s, set) in supports.iter().zip(rc.sets.iter_mut()) {
        let nodes: Vec<usize> = layer_of(grid, material, &s.region, &set.nodes, layers)
            .into_iter()
            .flat_map(|(_, l)| l)
            .collect();
        let mut nodes_u = nodes.clone();
        nodes_u.sort_unstable();
        nodes_u.dedup();
        for (comp, v) in [(0, s.u1), (1, s.u2)] {
            let Some(v) = v else { continue };
            for &n in &nodes_u {
                if let Some((other, ov)) = owner.insert(2 * n + comp, (&s.name, v)) {
                    if other != s.name && ov != v {
                        return Err(Error::invalid(
                            &format!("{}.region", s.name),
                            "supports whose PD boundary layers (m node rows) prescribe each \
                             displacement component of a node once, or the same value",
                            format!(
                                "u{} of the node at {:?} is prescribed {ov} by {other} and {v} \
                                 by {}",
                                comp + 1,
                                grid.xy(n),
                                s.name
                            ),
                        ));
                    }
                }
            }
            bc.fix(&nodes_u, comp, v);
        }
        set.nodes = nodes_u;
    }
    rc.bc = bc;
    // loads: each load's outer nodal forces, split over the layers
    let mut f = vec![0.0; ndof];
    for (l, set) in loads.iter().zip(rc.sets.iter_mut().skip(supports.len())) {
        let one = region_conditions(
            &mesh,
            domain,
            material,
            &[],
            std::slice::from_ref(l),
            ndof,
            thickness,
        )?;
        // the loaded outer nodes (an edge part's forces reach the node just beyond its ends)
        let mut outer = set.nodes.clone();
        outer.extend(
            (0..grid.n_nodes()).filter(|&n| one.f[2 * n] != 0.0 || one.f[2 * n + 1] != 0.0),
        );
        outer.sort_unstable();
        outer.dedup();
        let mut nodes = Vec::new();
        for (n, layer) in layer_of(grid, material, &l.region, &outer, layers) {
            let k = layer.len() as f64;
            for &q in &layer {
                for c in 0..2 {
                    f[2 * q + c] += one.f[2 * n + c] / k;
                }
            }
            nodes.extend(layer);
        }
        nodes.sort_unstable();
        nodes.dedup();
        set.nodes = nodes;
    }
    rc.f = f;
    Ok(rc)
}
