//! Holes and notches of the PD model (issue 12): the *centre rule* and bonds through holes.
//!
//! * A grid node is material iff its cell centre (the node itself: each node carries the
//!   dx x dx cell around it) is, `Domain::level_set(x) >= 0`. A cut cell is all material or all
//!   void, so the boundary of the hole moves by up to dx / 2 and the volume of the material by
//!   O(dx) per unit length of the hole's boundary: the error of the rule is O(dx) (partial
//!   volumes of cut cells are not computed).
//! * A removed node keeps its place in the numbering (node (i, j) = j (nx + 1) + i) but has no
//!   bonds, no element, no load and no region; both its dofs are fixed to zero, so it takes no
//!   part in any equation, response or damage index (it is left out of `pd_nodes`).
//! * A bond whose segment passes through a hole ([`crate::problem::Shape::cuts_segment`]: for a
//!   circle, the segment's distance to the centre below the radius; rectangles and polygons, the
//!   segment crossing the interior) does not exist, even between two material nodes: the hole
//!   screens the interaction, as a pre-crack does.

use crate::pd::Grid;
use crate::problem::Domain;

/// `material[n]`: is node n material by the centre rule (all true without holes)?
pub(super) fn material_nodes(d: &Domain, grid: &Grid) -> Vec<bool> {
    (0..grid.n_nodes())
        .map(|n| d.holes.is_empty() || d.level_set(grid.xy(n)) >= 0.0)
        .collect()
}

/// Does the bond between material nodes a and b exist: both material and its segment through no
/// hole?
pub(super) fn bond_exists(d: &Domain, grid: &Grid, material: &[bool], a: usize, b: usize) -> bool {
    if !material[a] || !material[b] {
        return false;
    }
    let (pa, pb) = (grid.xy(a), grid.xy(b));
    !d.holes.iter().any(|h| h.shape.cuts_segment(pa, pb))
}
