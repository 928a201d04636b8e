//! Loading of the paper's plate (eq. 61; docs/design.md, "Units and the paper's conventions"):
//! opposite displacements u0 on the top and bottom edges with u1 free (one anchor node removes
//! the rigid translation) or clamped (u1 = 0 on both edges), or a uniform traction on both
//! edges (three anchor constraints, which
//! carry no load because the applied forces are balanced).
//!
//! Shared by the FEM, XFEM and CCM-PD models; each says in its output which variant ran and which
//! node carries the anchor.

use crate::error::{check_finite, Error, Result};
use crate::fe::dirichlet::Dirichlet;
use crate::fe::mesh::Mesh;
use crate::problem::{Grip, PlateLoad, Side};

/// The loaded edges of a plate, in terms of node indices (dof = 2 n + comp).
#[derive(Debug, Clone)]
pub struct PlateEdges {
    /// nodes on the top edge, sorted by x
    pub top: Vec<usize>,
    /// nodes on the bottom edge, sorted by x
    pub bottom: Vec<usize>,
    /// tributary length of each top/bottom node (for consistent traction forces)
    pub top_len: Vec<f64>,
    pub bottom_len: Vec<f64>,
}

impl PlateEdges {
    /// The top and bottom edges of a structured mesh (seam duplicates included), with the
    /// tributary lengths of their nodes.
    pub fn of_mesh(m: &Mesh) -> Self {
        let top = m.side_nodes(Side::Top);
        let bottom = m.side_nodes(Side::Bottom);
        let xt: Vec<f64> = top.iter().map(|&n| m.coords[n][0]).collect();
        let xb: Vec<f64> = bottom.iter().map(|&n| m.coords[n][0]).collect();
        Self {
            top_len: tributary_lengths(&xt),
            bottom_len: tributary_lengths(&xb),
            top,
            bottom,
        }
    }
}

/// Dirichlet conditions, force vector and the anchor node for a plate load.
/// The anchor is the bottom-right corner (far from an edge crack at x = 0); for traction the
/// top-right corner additionally carries u1 = 0.
pub fn plate_conditions(
    edges: &PlateEdges,
    load: &PlateLoad,
    n_dofs: usize,
    thickness: f64,
) -> Result<(Dirichlet, Vec<f64>, usize)> {
    check_finite("u0", load.u0)?;
    check_finite("traction", load.traction)?;
    if edges.top.is_empty() || edges.bottom.is_empty() {
        return Err(Error::invalid(
            "plate edges",
            "non-empty top and bottom node sets",
            0,
        ));
    }
    let mut bc = Dirichlet::default();
    let mut f = vec![0.0; n_dofs];
    let anchor = *edges.bottom.last().unwrap();
    match load.grip {
        Grip::Free | Grip::Clamped => {
            bc.fix(&edges.top, 1, load.u0);
            bc.fix(&edges.bottom, 1, -load.u0);
            if load.grip == Grip::Clamped {
                bc.fix(&edges.top, 0, 0.0);
                bc.fix(&edges.bottom, 0, 0.0);
            } else {
                bc.fix(&[anchor], 0, 0.0);
            }
        }
        Grip::Traction => {
            for (&n, &l) in edges.top.iter().zip(&edges.top_len) {
                f[2 * n + 1] += load.traction * l * thickness;
            }
            for (&n, &l) in edges.bottom.iter().zip(&edges.bottom_len) {
                f[2 * n + 1] -= load.traction * l * thickness;
            }
            bc.fix(&[anchor], 0, 0.0);
            bc.fix(&[anchor], 1, 0.0);
            bc.fix(&[*edges.top.last().unwrap()], 0, 0.0);
        }
    }
    Ok((bc, f, anchor))
}

/// Tributary lengths of nodes on a line given their sorted coordinates (half of each adjacent
/// segment): the consistent load of a uniform traction on linear edges.
pub fn tributary_lengths(x: &[f64]) -> Vec<f64> {
    let n = x.len();
    let mut l = vec![0.0; n];
    for i in 0..n.saturating_sub(1) {
        let h = x[i + 1] - x[i];
        l[i] += 0.5 * h;
        l[i + 1] += 0.5 * h;
    }
    l
}

/// Mean normal stress on the top edge: total vertical force the top nodes receive from outside
/// (reaction + applied force) divided by the edge area (width x thickness).
pub fn sigma22(
    edges: &PlateEdges,
    reactions: &[f64],
    f: &[f64],
    width: f64,
    thickness: f64,
) -> f64 {
    let fy: f64 = edges
        .top
        .iter()
        .map(|&n| reactions[2 * n + 1] + f[2 * n + 1])
        .sum();
    fy / (width * thickness)
}
