//! Grounding springs of detached PD nodes (the model side; docs/design.md, "Detached nodes").
//!
//! A PD node's rows hold only its bonds. When its intact bonds give no stiffness along some
//! direction of its free dofs (all broken, or the remaining ones parallel), the splice matrix is
//! singular although the body has not separated. Such a node is grounded along that direction by a
//! [`Spring`] k p p^T: with no external force it carries none there, so no other result changes.
//! Here: the spring stiffness, the null directions of a node, whether a node is held, and the
//! assembly with springs; when the SLA grounds which node is [`crate::pd::sla`]'s grounding.

use super::SpliceModel;
use crate::la::CscMatrix;

/// A grounding spring k p p^T on the free dofs of one PD node, along the unit direction `p`: it
/// removes a direction in which the node's intact bonds give no stiffness (all bonds broken, or
/// all remaining bonds parallel), see [`SpliceModel::null_directions`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Spring {
    pub node: usize,
    pub p: [f64; 2],
}

impl SpliceModel {
    /// Stiffness of the grounding springs: the force constant c V^2 / dx of a full
    /// nearest-neighbour bond (eq. 46 with beta = 1), so the spring is of the size of the node's
    /// other matrix entries. Its value never changes a result: it acts only along directions in
    /// which the node has no other stiffness, where the node carries no force.
    pub(crate) fn spring_stiffness(&self) -> f64 {
        self.pd.c * self.pd.volume * self.pd.volume / self.pd.dx
    }

    /// The unit directions (0, 1 or 2, orthonormal) of the free dofs of PD node `n` in which its
    /// intact bonds give no stiffness (the null space of sum n n^T over its intact bonds, restricted
    /// to its free dofs), decided exactly on integer grid offsets. Empty for FEM nodes (their
    /// element rows never change) and for fully prescribed nodes. A PD node's rows hold only its
    /// bonds, so such a direction makes the system singular: the SLA grounds it with a
    /// [`Spring`] (the node is *detached* along it; with no external force it carries none).
    pub(crate) fn null_directions(&self, n: usize, broken: &[bool]) -> Vec<[f64; 2]> {
        if !self.is_pd[n] {
            return Vec::new();
        }
        let (fx, fy) = (!self.mask[2 * n], !self.mask[2 * n + 1]);
        if !fx && !fy {
            return Vec::new();
        }
        // first intact offset, and whether another one is not parallel to it
        let mut first: Option<(i64, i64)> = None;
        let mut rank2 = false;
        let (mut any_x, mut any_y) = (false, false);
        for &b in self.bonds_of(n) {
            if broken[b as usize] {
                continue;
            }
            let xi = self.bonds[b as usize].xi;
            let o = (
                (xi[0] / self.grid.dx).round() as i64,
                (xi[1] / self.grid.dx).round() as i64,
            );
            any_x |= o.0 != 0;
            any_y |= o.1 != 0;
            match first {
                None => first = Some(o),
                Some(f) => rank2 |= f.0 * o.1 - f.1 * o.0 != 0,
            }
        }
        match (fx, fy) {
            (true, true) => match first {
                None => vec![[1.0, 0.0], [0.0, 1.0]],
                Some(_) if rank2 => Vec::new(),
                Some((a, b)) => {
                    let l = ((a * a + b * b) as f64).sqrt();
                    vec![[-(b as f64) / l, a as f64 / l]]
                }
            },
            (true, false) if !any_x => vec![[1.0, 0.0]],
            (false, true) if !any_y => vec![[0.0, 1.0]],
            _ => Vec::new(),
        }
    }

    /// Is node `n` *held*: a FEM node (its element rows tie it to the mesh), or a node with a
    /// prescribed dof or an applied force? A fragment of PD nodes connected to no held node floats
    /// freely and carries no load (debris, see [`crate::pd::sla`]).
    pub(crate) fn is_held(&self, n: usize) -> bool {
        !self.is_pd[n]
            || self.mask[2 * n]
            || self.mask[2 * n + 1]
            || self.f[2 * n] != 0.0
            || self.f[2 * n + 1] != 0.0
    }

    /// The grounding springs a state needs from scratch: for every PD node, its null directions
    /// under `broken` (see [`SpliceModel::null_directions`]).
    pub(crate) fn springs_for(&self, broken: &[bool]) -> Vec<Spring> {
        self.pd_nodes
            .iter()
            .flat_map(|&n| {
                self.null_directions(n, broken)
                    .into_iter()
                    .map(move |p| Spring { node: n, p })
            })
            .collect()
    }

    /// [`SpliceModel::assemble`] plus the grounding `springs` (k p p^T on each node's 2 x 2 block,
    /// which the bond blocks always put in the pattern).
    pub(crate) fn assemble_with(&self, broken: &[bool], springs: &[Spring]) -> CscMatrix {
        let mut k = self.assemble(broken);
        let ks = self.spring_stiffness();
        for s in springs {
            for (a, &pa) in s.p.iter().enumerate() {
                for (b, &pb) in s.p.iter().enumerate() {
                    let (r, c) = (2 * s.node + a, 2 * s.node + b);
                    let v = ks * pa * pb;
                    if v == 0.0 || self.mask[r] || self.mask[c] {
                        continue;
                    }
                    let rows = &k.row_idx[k.col_ptr[c]..k.col_ptr[c + 1]];
                    if let Some(pos) = rows.iter().position(|&x| x == r) {
                        k.val[k.col_ptr[c] + pos] += v;
                    }
                }
            }
        }
        k
    }
}
