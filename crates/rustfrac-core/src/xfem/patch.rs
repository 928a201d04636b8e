//! Deformed-mesh data for magnified plots near a crack tip (paper Fig. 8b): small cells of the
//! elements around the tip, each with the enriched displacement evaluated inside it, so that the
//! crack opening shows as a gap.

use super::model::{BasisBuf, XfemModel};
use crate::error::{Error, Result};
use crate::fe::q4::geometry;
use crate::geometry::{clip_left, point_segment_distance, polygon_area};

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

impl XfemModel {
    /// The enriched elements as cells for files (VTU): each element carrying an enrichment is
    /// split into m x m cells, and a cell that a crack segment crosses from side to side is
    /// split along the crack's line into its two parts (a cell holding a tip stays whole: the
    /// field is continuous beyond the tip). Each polygon's vertices carry the enriched
    /// displacement evaluated a hair inside that polygon, so each side of the crack shows its
    /// own face. Returns (polygons, displacements per vertex, element of each polygon).
    pub fn cut_cells(&self, u: &[f64], m: usize) -> Result<CutCells> {
        if m == 0 || m > 16 {
            return Err(Error::invalid("cells per element", "1..=16", m));
        }
        let mut out = CutCells::default();
        let d = self.material.d_matrix();
        let mut buf = BasisBuf::default();
        let segments: Vec<[[f64; 2]; 2]> = self
            .cracks
            .iter()
            .flat_map(|c| c.points.windows(2).map(|w| [w[0], w[1]]))
            .collect();
        for e in 0..self.mesh.n_elements() {
            let Some(en) = self.enriched(e) else { continue };
            let xy = self.mesh.element_coords(e);
            let dofs = self.element_dofs(e);
            let (x0, y0, hx, hy) = (
                xy[0][0],
                xy[0][1],
                (xy[1][0] - xy[0][0]) / m as f64,
                (xy[3][1] - xy[0][1]) / m as f64,
            );
            for b in 0..m {
                for a in 0..m {
                    let (cx0, cy0) = (x0 + a as f64 * hx, y0 + b as f64 * hy);
                    let cell = vec![
                        [cx0, cy0],
                        [cx0 + hx, cy0],
                        [cx0 + hx, cy0 + hy],
                        [cx0, cy0 + hy],
                    ];
                    let parts = split_by_crack(&cell, &segments);
                    for poly in parts {
                        if polygon_area(&poly).abs() <= 1e-14 * hx * hy {
                            continue;
                        }
                        let n = poly.len() as f64;
                        let c = poly
                            .iter()
                            .fold([0.0, 0.0], |s, p| [s[0] + p[0] / n, s[1] + p[1] / n]);
                        let disp = poly
                            .iter()
                            .map(|p| {
                                let q = [p[0] + 1e-7 * (c[0] - p[0]), p[1] + 1e-7 * (c[1] - p[1])];
                                let xi = 2.0 * (q[0] - xy[0][0]) / (xy[1][0] - xy[0][0]) - 1.0;
                                let eta = 2.0 * (q[1] - xy[0][1]) / (xy[3][1] - xy[0][1]) - 1.0;
                                self.basis(e, Some(en), xi, eta, &mut buf);
                                let mut d = [0.0; 2];
                                for (f, v) in buf.vals.iter().enumerate() {
                                    d[0] += v * u[dofs[2 * f]];
                                    d[1] += v * u[dofs[2 * f + 1]];
                                }
                                d
                            })
                            .collect();
                        let xi = 2.0 * (c[0] - xy[0][0]) / (xy[1][0] - xy[0][0]) - 1.0;
                        let eta = 2.0 * (c[1] - xy[0][1]) / (xy[3][1] - xy[0][1]) - 1.0;
                        out.stress.push(self.stress_at(
                            (e, Some(en), &dofs),
                            xi,
                            eta,
                            u,
                            &d,
                            &mut buf,
                        ));
                        out.polygons.push(poly);
                        out.disp.push(disp);
                        out.element.push(e);
                    }
                }
            }
        }
        Ok(out)
    }
}

/// A convex cell split along the line of the first crack segment that crosses it from side to
/// side (both crossings on the segment); the cell itself otherwise.
fn split_by_crack(cell: &[[f64; 2]], segments: &[[[f64; 2]; 2]]) -> Vec<Vec<[f64; 2]>> {
    for &[a, b] in segments {
        let left = clip_left(cell, a, b);
        let right = clip_left(cell, b, a);
        if left.len() < 3 || right.len() < 3 {
            continue;
        }
        // the crossing points are the vertices both parts share; they must lie on the segment
        let on_segment = left
            .iter()
            .filter(|p| right.iter().any(|q| q == *p))
            .all(|&p| point_segment_distance(p, a, b) <= 1e-12 * (1.0 + p[0].abs() + p[1].abs()));
        if on_segment {
            return vec![left, right];
        }
    }
    vec![cell.to_vec()]
}

/// The enriched elements as cells with their own displacements ([`XfemModel::cut_cells`]).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct CutCells {
    pub polygons: Vec<Vec<[f64; 2]>>,
    pub disp: Vec<Vec<[f64; 2]>>,
    pub element: Vec<usize>,
    /// the enriched stress [s11, s22, s12] at each polygon's vertex centroid
    pub stress: Vec<[f64; 3]>,
}

impl XfemModel {
    /// The stress [s11, s22, s12] of the enriched field at (xi, eta) of element `e` (eq. 3
    /// differentiated: the gradients of every standard, Heaviside and branch function).
    /// `dofs` are the element's ([`XfemModel::element_dofs`]), `d` the material matrix: both
    /// computed once per element (or model) by the callers.
    fn stress_at(
        &self,
        (e, en, dofs): (usize, Option<&super::model::EnrElement>, &[usize]),
        xi: f64,
        eta: f64,
        u: &[f64],
        d: &[[f64; 3]; 3],
        buf: &mut BasisBuf,
    ) -> [f64; 3] {
        self.basis(e, en, xi, eta, buf);
        let mut eps = [0.0; 3];
        for (f, g) in buf.grads.iter().enumerate() {
            let (u1, u2) = (u[dofs[2 * f]], u[dofs[2 * f + 1]]);
            eps[0] += g[0] * u1;
            eps[1] += g[1] * u2;
            eps[2] += g[1] * u1 + g[0] * u2;
        }
        crate::fe::q4::stress(d, &eps)
    }

    /// The enriched stresses at the 2 x 2 Gauss points of every element (points, stresses; the
    /// layout of [`crate::fe::FemModel::gauss_stresses`]). In an element the crack crosses, a
    /// point's stress is its own side's.
    pub fn gauss_stresses(&self, u: &[f64]) -> (Vec<[f64; 2]>, Vec<[f64; 3]>) {
        let rule = crate::fe::quadrature::subquad_rule(1, 2);
        let mut buf = BasisBuf::default();
        let n = self.mesh.n_elements();
        let (mut pts, mut sig) = (Vec::with_capacity(4 * n), Vec::with_capacity(4 * n));
        let d = self.material.d_matrix();
        for e in 0..n {
            let en = self.enriched(e);
            let xy = self.mesh.element_coords(e);
            let dofs = self.element_dofs(e);
            for q in &rule {
                pts.push(geometry(&xy, q.xi, q.eta).0);
                sig.push(self.stress_at((e, en, &dofs), q.xi, q.eta, u, &d, &mut buf));
            }
        }
        (pts, sig)
    }
}

/// Deformed-mesh data for a magnified plot near a tip (Fig. 8b): reference corners of small cells
/// and the displacement at each corner (plot `cells + scale * disp`).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct DeformedPatch {
    pub cells: Vec<[[f64; 2]; 4]>,
    pub disp: Vec<[[f64; 2]; 4]>,
}
