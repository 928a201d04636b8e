//! Deformed-mesh data for magnified plots near a crack tip (paper Fig. 8b): small cells of the
//! elements around the tip, each with the enriched displacement evaluated inside it, so that the
//! crack opening shows as a gap.

use super::model::{BasisBuf, XfemModel};
use crate::error::{Error, Result};
use crate::fe::q4::geometry;

impl XfemModel {
    /// Deformed-mesh data near a tip: every element whose centre lies within `half_width` of the
    /// tip (in x and y) is split into m x m cells; each cell's corners are returned with the
    /// enriched displacement evaluated inside that cell (so the crack opening shows as a gap).
    pub fn deformed_near_tip(
        &self,
        u: &[f64],
        tip: usize,
        half_width: f64,
        m: usize,
    ) -> Result<DeformedPatch> {
        if tip >= self.tips.len() {
            return Err(Error::invalid("tip", "an existing tip index", tip));
        }
        if m == 0 || m > 16 {
            return Err(Error::invalid("cells per element", "1..=16", m));
        }
        let tp = self.tips[tip].pos;
        let mut patch = DeformedPatch::default();
        let mut buf = BasisBuf::default();
        for e in 0..self.mesh.n_elements() {
            let xy = self.mesh.element_coords(e);
            let c = [
                0.25 * (xy[0][0] + xy[1][0] + xy[2][0] + xy[3][0]),
                0.25 * (xy[0][1] + xy[1][1] + xy[2][1] + xy[3][1]),
            ];
            if (c[0] - tp[0]).abs() > half_width || (c[1] - tp[1]).abs() > half_width {
                continue;
            }
            let en = self.enriched(e);
            let dofs = self.element_dofs(e);
            let hcell = 2.0 / m as f64;
            for b in 0..m {
                for a in 0..m {
                    let (x0, y0) = (-1.0 + a as f64 * hcell, -1.0 + b as f64 * hcell);
                    let corners = [
                        (x0, y0),
                        (x0 + hcell, y0),
                        (x0 + hcell, y0 + hcell),
                        (x0, y0 + hcell),
                    ];
                    let (cx, cy) = (x0 + 0.5 * hcell, y0 + 0.5 * hcell);
                    let mut cell = [[0.0; 2]; 4];
                    let mut disp = [[0.0; 2]; 4];
                    for (k, &(xi, eta)) in corners.iter().enumerate() {
                        // evaluate a hair inside the cell so each cell sees its own crack side
                        let (xe, ee) = (xi + 1e-7 * (cx - xi), eta + 1e-7 * (cy - eta));
                        self.basis(e, en, xe, ee, &mut buf);
                        let (xp, _, _) = geometry(&xy, xi, eta);
                        cell[k] = xp;
                        for (f, v) in buf.vals.iter().enumerate() {
                            disp[k][0] += v * u[dofs[2 * f]];
                            disp[k][1] += v * u[dofs[2 * f + 1]];
                        }
                    }
                    patch.cells.push(cell);
                    patch.disp.push(disp);
                }
            }
        }
        Ok(patch)
    }
}

/// Deformed-mesh data for a magnified plot near a tip (Fig. 8b): reference corners of small cells
/// and the displacement at each corner (plot `cells + scale * disp`).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct DeformedPatch {
    pub cells: Vec<[[f64; 2]; 4]>,
    pub disp: Vec<[[f64; 2]; 4]>,
}
