//! A Q4 plane-elasticity model on a structured mesh (paper section 2.1.1): parallel assembly of
//! the global stiffness on a pattern built once, consistent nodal forces of tractions and body
//! forces, Gauss-point and nodal stresses, and error norms against an exact field.
//!
//! The standard dofs of node n are 2n (u1) and 2n + 1 (u2).
//!
//! With holes ([`FemModel::with_domain`]) every integral runs over the material only
//! ([`crate::fe::fictitious`]): cut elements use their material part's rule, void elements add
//! nothing, and the nodes without material are prescribed to 0 ([`FemModel::constrain`]).
//! Without holes nothing changes, bit for bit.

use crate::error::{Error, Result};
use crate::fe::dirichlet::Dirichlet;
use crate::fe::fictitious::{ElementKind, FictitiousDomain, DEFAULT_MIN_SUPPORT_FRACTION};
use crate::fe::mesh::Mesh;
use crate::fe::q4::{element_stiffness, geometry, shape, strain, stress};
use crate::fe::quadrature::{subquad_rule, QPoint};
use crate::la::{CscMatrix, Pattern};
use crate::problem::{Domain, Elastic, Side};

/// A Q4 plane-elasticity model on a mesh: standard dofs only.
pub struct FemModel {
    pub mesh: Mesh,
    pub material: Elastic,
    /// element quadrature (2 x 2 Gauss by default: exact for rectangles)
    pub rule: Vec<QPoint>,
    /// the holes' fictitious-domain data (None: no holes)
    pub fictitious: Option<FictitiousDomain>,
    blocks: Vec<Vec<usize>>,
    pattern: Pattern,
}

impl FemModel {
    /// Builds the model and its sparsity pattern (once). `gauss` is the points per direction.
    pub fn new(mesh: Mesh, material: Elastic, gauss: usize) -> Result<Self> {
        // one point per direction leaves the hourglass modes of Q4 elasticity (rank 3 of 5
        // deformation modes): refused, not stabilised
        if !(2..=5).contains(&gauss) {
            return Err(Error::invalid(
                "mesh.gauss",
                "2..=5 points per direction (1 leaves the hourglass modes)",
                gauss,
            ));
        }
        let blocks: Vec<Vec<usize>> = mesh
            .elements
            .iter()
            .map(|e| e.iter().flat_map(|&n| [2 * n, 2 * n + 1]).collect())
            .collect();
        let pattern = Pattern::symmetric(2 * mesh.n_nodes(), &blocks)?;
        Ok(Self {
            mesh,
            material,
            rule: subquad_rule(1, gauss),
            fictitious: None,
            blocks,
            pattern,
        })
    }

    /// [`FemModel::new`] on the material of `domain`: with holes, the fictitious-domain data
    /// ([`FictitiousDomain::new`], the default node removal threshold
    /// [`DEFAULT_MIN_SUPPORT_FRACTION`]); without, the plain model.
    pub fn with_domain(
        mesh: Mesh,
        material: Elastic,
        gauss: usize,
        domain: &Domain,
    ) -> Result<Self> {
        let mut m = Self::new(mesh, material, gauss)?;
        m.fictitious = FictitiousDomain::new(&m.mesh, domain, gauss, DEFAULT_MIN_SUPPORT_FRACTION)?;
        Ok(m)
    }

    /// The Dirichlet conditions `bc` of this model checked for rigid-body modes; with holes, the
    /// removed nodes' conditions dropped, their dofs prescribed to 0 and their forces in `f`
    /// zeroed ([`FictitiousDomain::constrain`]).
    pub fn constrain(&self, bc: Dirichlet, f: &mut [f64]) -> Result<Dirichlet> {
        match &self.fictitious {
            Some(fd) => fd.constrain(bc, f, &self.mesh.coords, |_| Vec::new()),
            None => {
                bc.check_rigid_modes(&self.mesh.coords)?;
                Ok(bc)
            }
        }
    }

    /// The kind of element `e` (material without holes).
    fn kind(&self, e: usize) -> ElementKind {
        self.fictitious
            .as_ref()
            .map_or(ElementKind::Material, |fd| fd.kind(e))
    }

    /// A rule on the material part of element `e`: `full` for a material element, empty for a
    /// void one, the degree-5 rule of the material part for a cut one.
    fn material_rule(&self, e: usize, full: &[QPoint]) -> Vec<QPoint> {
        match (&self.fictitious, self.kind(e)) {
            (Some(fd), ElementKind::Cut) => fd.cut_rule(e, 5).unwrap_or_default(),
            (_, ElementKind::Void) => Vec::new(),
            _ => full.to_vec(),
        }
    }

    pub fn n_dofs(&self) -> usize {
        2 * self.mesh.n_nodes()
    }

    /// Position of every dof (its node's coordinates), for the nested-dissection ordering.
    pub fn dof_positions(&self) -> Vec<[f64; 2]> {
        self.mesh.coords.iter().flat_map(|&c| [c, c]).collect()
    }

    /// Global stiffness (full symmetric storage), assembled in parallel.
    pub fn stiffness(&self) -> CscMatrix {
        if let Some(fd) = &self.fictitious {
            return self.pattern.assemble(&self.blocks, &self.blocks, |e, out| {
                element_stiffness(
                    &self.mesh.element_coords(e),
                    &self.material,
                    fd.rule(e, &self.rule),
                    out,
                )
            });
        }
        self.pattern.assemble(&self.blocks, &self.blocks, |e, out| {
            element_stiffness(
                &self.mesh.element_coords(e),
                &self.material,
                &self.rule,
                out,
            )
        })
    }

    /// Consistent nodal forces of a uniform traction `t` (force per area) on one side.
    pub fn traction_forces(&self, side: Side, t: [f64; 2], f: &mut [f64]) {
        edge_traction(&self.mesh, side, t, self.material.thickness, f)
    }

    /// Consistent nodal forces of a body force b(x) (force per volume), 3 x 3 Gauss per element
    /// (over the material only).
    pub fn body_forces(&self, b: impl Fn(f64, f64) -> [f64; 2]) -> Vec<f64> {
        let mut f = vec![0.0; self.n_dofs()];
        let full = subquad_rule(1, 3);
        for (e, conn) in self.mesh.elements.iter().enumerate() {
            let xy = self.mesh.element_coords(e);
            let rule = self.material_rule(e, &full);
            for q in &rule {
                let (x, _, det) = geometry(&xy, q.xi, q.eta);
                let n = shape(q.xi, q.eta);
                let bv = b(x[0], x[1]);
                let w = q.w * det * self.material.thickness;
                for k in 0..4 {
                    f[2 * conn[k]] += w * n[k] * bv[0];
                    f[2 * conn[k] + 1] += w * n[k] * bv[1];
                }
            }
        }
        f
    }

    /// Element displacement vector.
    pub fn element_u(&self, e: usize, u: &[f64]) -> [f64; 8] {
        let c = self.mesh.elements[e];
        std::array::from_fn(|i| u[2 * c[i / 2] + i % 2])
    }

    /// Stresses at the 2 x 2 Gauss points of every element: (n_elements * 4) x 3, plus the points.
    /// With holes, only the points in the material (of material and cut elements).
    pub fn gauss_stresses(&self, u: &[f64]) -> (Vec<[f64; 2]>, Vec<[f64; 3]>) {
        let d = self.material.d_matrix();
        let rule = subquad_rule(1, 2);
        let mut pts = Vec::with_capacity(4 * self.mesh.n_elements());
        let mut sig = Vec::with_capacity(4 * self.mesh.n_elements());
        for e in 0..self.mesh.n_elements() {
            let xy = self.mesh.element_coords(e);
            let ue = self.element_u(e, u);
            for q in &rule {
                let (x, g, _) = geometry(&xy, q.xi, q.eta);
                if let Some(fd) = &self.fictitious {
                    if !fd.in_material(x) {
                        continue;
                    }
                }
                pts.push(x);
                sig.push(stress(&d, &strain(&g, &ue)));
            }
        }
        (pts, sig)
    }

    /// Nodal stresses: element corner values averaged over the elements sharing a node (with
    /// holes: the elements holding material; 0 at a node without any).
    pub fn nodal_stresses(&self, u: &[f64]) -> Vec<[f64; 3]> {
        let d = self.material.d_matrix();
        let mut acc = vec![[0.0; 3]; self.mesh.n_nodes()];
        let mut cnt = vec![0usize; self.mesh.n_nodes()];
        let corners = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)];
        for (e, conn) in self.mesh.elements.iter().enumerate() {
            if self.kind(e) == ElementKind::Void {
                continue;
            }
            let xy = self.mesh.element_coords(e);
            let ue = self.element_u(e, u);
            for (k, &(xi, eta)) in corners.iter().enumerate() {
                let (_, g, _) = geometry(&xy, xi, eta);
                let s = stress(&d, &strain(&g, &ue));
                for c in 0..3 {
                    acc[conn[k]][c] += s[c];
                }
                cnt[conn[k]] += 1;
            }
        }
        acc.iter()
            .zip(&cnt)
            .map(|(a, &c)| a.map(|v| v / c.max(1) as f64))
            .collect()
    }

    /// L2 norm of the displacement error and energy norm of the error against an exact field
    /// `exact(x, y) -> (u, grad u)` with grad u = [[du1/dx1, du1/dx2], [du2/dx1, du2/dx2]],
    /// integrated with 4 x 4 Gauss points per element (with holes: over the material only, the
    /// degree-5 rule on the material part of a cut element).
    pub fn error_norms(
        &self,
        u: &[f64],
        exact: impl Fn(f64, f64) -> ([f64; 2], [[f64; 2]; 2]),
    ) -> (f64, f64) {
        let d = self.material.d_matrix();
        let full = subquad_rule(1, 4);
        let (mut l2, mut en) = (0.0, 0.0);
        for e in 0..self.mesh.n_elements() {
            let xy = self.mesh.element_coords(e);
            let ue = self.element_u(e, u);
            let rule = self.material_rule(e, &full);
            for q in &rule {
                let (x, g, det) = geometry(&xy, q.xi, q.eta);
                let n = shape(q.xi, q.eta);
                let (ux, gx) = exact(x[0], x[1]);
                let uh = [
                    (0..4).map(|k| n[k] * ue[2 * k]).sum::<f64>(),
                    (0..4).map(|k| n[k] * ue[2 * k + 1]).sum::<f64>(),
                ];
                let eh = strain(&g, &ue);
                let ex = [gx[0][0], gx[1][1], gx[0][1] + gx[1][0]];
                let de = [eh[0] - ex[0], eh[1] - ex[1], eh[2] - ex[2]];
                let sd = stress(&d, &de);
                let w = q.w * det * self.material.thickness;
                l2 += w * ((uh[0] - ux[0]).powi(2) + (uh[1] - ux[1]).powi(2));
                en += w * (de[0] * sd[0] + de[1] * sd[1] + de[2] * sd[2]);
            }
        }
        (l2.sqrt(), en.sqrt())
    }
}

/// Consistent nodal forces of a uniform traction on one side of a structured mesh (linear edges:
/// half the edge force to each end node).
pub fn edge_traction(mesh: &Mesh, side: Side, t: [f64; 2], thickness: f64, f: &mut [f64]) {
    for [a, b] in mesh.side_edges(side) {
        let (pa, pb) = (mesh.coords[a], mesh.coords[b]);
        let len = ((pb[0] - pa[0]).powi(2) + (pb[1] - pa[1]).powi(2)).sqrt();
        for n in [a, b] {
            f[2 * n] += 0.5 * len * thickness * t[0];
            f[2 * n + 1] += 0.5 * len * thickness * t[1];
        }
    }
}
