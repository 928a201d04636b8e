//! The XFEM model of one cracked plate (paper eqs. 3, 25-26): dof numbering, the enriched basis of
//! every element, element blocks and the global stiffness matrix.
//!
//! Built in named phases ([`XfemModel::new_multi`]): the cracks and their tips
//! ([`crate::xfem::crack`]), the enrichment sets ([`crate::xfem::enrichment`]), the dof numbering,
//! and the enriched elements (their basis functions, dofs and quadrature rule,
//! [`crate::xfem::integration`]).
//!
//! Numbering: standard dofs 2n, 2n+1 for node n (0 .. n_std), then 2 dofs per Heaviside node in
//! increasing node order (crack by crack), then for each tip 8 dofs per tip node in increasing
//! node order (branch function j of node I: dofs base + 2 j (u1) and base + 2 j + 1 (u2)).
//!
//! The enriched approximation (eq. 3) of an element is the list of its scalar basis functions:
//! the four standard N_k, then per node k the shifted Heaviside functions N_k (H_c(x) - H_c(x_k))
//! of each crack c that enriches it and the shifted branch functions N_k (F_j(x) - F_j(x_k)) of
//! each tip; every scalar function carries two dofs (u1, u2).

use super::crack::{build_cracks, global_tips, Crack, Tip};
use super::enrichment::{branch_functions_snapped, node_support, EnrichmentSets};
use super::integration::{RuleKind, Rules, StdBlocks};
use crate::error::{Error, Result};
use crate::fe::dirichlet::Dirichlet;
use crate::fe::fictitious::{ElementKind, FictitiousDomain, DEFAULT_MIN_SUPPORT_FRACTION};
use crate::fe::mesh::Mesh;
use crate::fe::q4::{add_btdb, geometry, shape};
use crate::fe::quadrature::QPoint;
use crate::la::{CscMatrix, Pattern};
pub use crate::problem::XfemOptions;
use crate::problem::{Domain, Elastic};
use std::borrow::Cow;
use std::collections::HashMap;
use std::sync::Arc;

/// One scalar basis function of an enriched element.
#[derive(Debug, Clone, Copy)]
pub(super) enum Func {
    Std(usize),
    /// shifted Heaviside function of the element's crack `slot` (index into `EnrElement::heav`)
    Heav {
        k: usize,
        slot: usize,
        hk: f64,
    },
    /// shifted branch function `j` of the element's tip `slot` (index into `EnrElement::tips`)
    Branch {
        k: usize,
        slot: usize,
        j: usize,
        fk: f64,
    },
}

/// An element carrying enriched functions: its basis functions, their dofs and its rule.
#[derive(Debug, Clone)]
pub(super) struct EnrElement {
    pub(super) funcs: Vec<Func>,
    pub(super) dofs: Vec<usize>,
    pub(super) rule: RuleKind,
    /// cracks whose Heaviside functions the element carries
    pub(super) heav: Vec<usize>,
    /// (global) tips whose branch functions the element carries
    pub(super) tips: Vec<usize>,
}

/// Scratch space of [`XfemModel::basis`]: basis values and gradients, and per quadrature point
/// the Heaviside values and branch functions of the element's cracks and tips.
#[derive(Default)]
pub(super) struct BasisBuf {
    pub(super) vals: Vec<f64>,
    pub(super) grads: Vec<[f64; 2]>,
    h: Vec<f64>,
    br: Vec<([f64; 4], [[f64; 2]; 4])>,
}

/// An XFEM model of one cracked plate: enrichment sets, dof numbering and integration rules.
///
/// A model holds any number of cracks (module documentation, "Several cracks"). Tips are
/// numbered globally: the tips of `cracks[0]` (in the order of [`Crack::tips`]), then those of
/// `cracks[1]`, ...; every per-tip field and method uses this index.
#[derive(Debug, Clone)]
pub struct XfemModel {
    pub mesh: Arc<Mesh>,
    pub material: Elastic,
    /// the cracks; `cracks[0]` is the primary crack (CMOD, growth history `a`)
    pub cracks: Vec<Crack>,
    /// every tip, by global tip index
    pub tips: Vec<Tip>,
    /// the crack of each tip (index into `cracks`)
    pub tip_crack: Vec<usize>,
    pub options: XfemOptions,
    /// number of standard dofs (2 per node)
    pub n_std: usize,
    /// total number of dofs (standard + enriched)
    pub n_dofs: usize,
    /// Heaviside-enriched nodes of each crack (sorted)
    pub heaviside_nodes: Vec<Vec<usize>>,
    /// nodes removed from each crack's Heaviside set by the small-area rule
    pub dropped_nodes: Vec<Vec<usize>>,
    /// branch-enriched nodes of each tip (sorted)
    pub tip_nodes: Vec<Vec<usize>>,
    /// elements containing each tip
    pub tip_elements: Vec<Vec<usize>>,
    /// split elements of each crack (crossed by it, not containing one of its tips)
    pub split_elements: Vec<Vec<usize>>,
    /// the holes' fictitious-domain data (None: no holes; [`XfemModel::new_in_domain`])
    pub fictitious: Option<Arc<FictitiousDomain>>,
    std: Arc<StdBlocks>,
    enr_index: Vec<u32>,
    enr: Vec<EnrElement>,
    pub(super) rules: Rules,
}

const NONE: u32 = u32::MAX;

/// XFEM models cracks by enrichment: a mesh with seam duplicates is refused.
fn check_no_seam(mesh: &Mesh) -> Result<()> {
    if !mesh.duplicate_of.is_empty() {
        return Err(Error::invalid(
            "mesh",
            "a structured mesh without seam duplicates",
            format!("{} duplicated nodes", mesh.duplicate_of.len()),
        ));
    }
    Ok(())
}

/// The dof numbering (see the module documentation): the first dof of every Heaviside node of
/// each crack and of every branch-enriched node of each tip.
struct DofNumbering {
    n_std: usize,
    n_dofs: usize,
    h_dof: Vec<HashMap<usize, usize>>,
    t_dof: Vec<HashMap<usize, usize>>,
}

impl DofNumbering {
    /// Standard, then the Heaviside nodes crack by crack, then the tip nodes tip by tip.
    fn new(n_nodes: usize, sets: &EnrichmentSets) -> Self {
        let n_std = 2 * n_nodes;
        let mut next = n_std;
        let mut h_dof: Vec<HashMap<usize, usize>> = Vec::with_capacity(sets.heaviside_nodes.len());
        for nodes in &sets.heaviside_nodes {
            let mut m = HashMap::new();
            for &n in nodes {
                m.insert(n, next);
                next += 2;
            }
            h_dof.push(m);
        }
        let mut t_dof: Vec<HashMap<usize, usize>> = Vec::new();
        for nodes in &sets.tip_nodes {
            let mut m = HashMap::new();
            for &n in nodes {
                m.insert(n, next);
                next += 8;
            }
            t_dof.push(m);
        }
        Self {
            n_std,
            n_dofs: next,
            h_dof,
            t_dof,
        }
    }
}

/// What the enriched elements are built from.
struct ElementEnrichment<'a> {
    mesh: &'a Mesh,
    cracks: &'a [Crack],
    tips: &'a [Tip],
    tip_crack: &'a [usize],
    sets: &'a EnrichmentSets,
    numbering: &'a DofNumbering,
}

impl ElementEnrichment<'_> {
    /// Every element touching an enriched node, as (element -> index into the list or NONE, the
    /// list in increasing element order).
    fn elements(&self) -> (Vec<u32>, Vec<EnrElement>) {
        let mesh = self.mesh;
        let mut enr_elems: Vec<usize> = Vec::new();
        let enriched_nodes = self
            .sets
            .heaviside_nodes
            .iter()
            .flatten()
            .chain(self.sets.tip_nodes.iter().flatten())
            .copied();
        for n in enriched_nodes {
            enr_elems.extend(node_support(mesh, n));
        }
        enr_elems.sort_unstable();
        enr_elems.dedup();
        let mut enr_index = vec![NONE; mesh.n_elements()];
        let mut enr = Vec::with_capacity(enr_elems.len());
        for &e in &enr_elems {
            enr_index[e] = enr.len() as u32;
            enr.push(self.element(e));
        }
        (enr_index, enr)
    }

    /// The basis functions, dofs and rule of element `e`.
    fn element(&self, e: usize) -> EnrElement {
        let (mesh, cracks, tips) = (self.mesh, self.cracks, self.tips);
        let slot_of = |list: &mut Vec<usize>, v: usize| match list.iter().position(|&x| x == v) {
            Some(s) => s,
            None => {
                list.push(v);
                list.len() - 1
            }
        };
        let conn = mesh.elements[e];
        let mut funcs: Vec<Func> = (0..4).map(Func::Std).collect();
        let mut dofs: Vec<usize> = conn.iter().flat_map(|&n| [2 * n, 2 * n + 1]).collect();
        let (mut heav, mut etips) = (Vec::new(), Vec::new());
        for (k, &n) in conn.iter().enumerate() {
            for (c, crack) in cracks.iter().enumerate() {
                if let Some(&base) = self.numbering.h_dof[c].get(&n) {
                    funcs.push(Func::Heav {
                        k,
                        slot: slot_of(&mut heav, c),
                        hk: crack.heaviside(mesh.coords[n]),
                    });
                    dofs.extend([base, base + 1]);
                }
            }
            let tips_of_node = &self.sets.tips_of_node;
            for &t in tips_of_node.get(&n).map_or(&[][..], |v| v.as_slice()) {
                let base = self.numbering.t_dof[t][&n];
                let slot = slot_of(&mut etips, t);
                let (fk, _) = branch_functions_snapped(
                    &tips[t],
                    mesh.coords[n],
                    cracks[self.tip_crack[t]].snap,
                );
                for (j, &f) in fk.iter().enumerate() {
                    funcs.push(Func::Branch { k, slot, j, fk: f });
                    dofs.extend([base + 2 * j, base + 2 * j + 1]);
                }
            }
        }
        let sub_quads =
            !etips.is_empty() || heav.iter().any(|&c| self.sets.crossed[c].contains_key(&e));
        let rule = RuleKind::select(
            self.sets.is_tip_element(e),
            sub_quads,
            self.sets.n_crossing(e) >= 2,
        );
        EnrElement {
            funcs,
            dofs,
            rule,
            heav,
            tips: etips,
        }
    }
}

impl XfemModel {
    /// Builds the model of a plate with one crack: validates the options and the crack, computes
    /// the enrichment. Errors name the crack "crack".
    pub fn new(
        mesh: Arc<Mesh>,
        material: Elastic,
        crack: Vec<[f64; 2]>,
        options: XfemOptions,
    ) -> Result<Self> {
        Self::new_multi(mesh, material, vec![crack], options)
    }

    /// Builds the model of a plate with several cracks (one polyline each; module documentation,
    /// "Several cracks"). Errors name a crack "cracks\[k\]" (or "crack" when there is only one);
    /// cracks that cross or touch, and tips of different cracks in one element, are refused
    /// with parameter "cracks".
    pub fn new_multi(
        mesh: Arc<Mesh>,
        material: Elastic,
        cracks: Vec<Vec<[f64; 2]>>,
        options: XfemOptions,
    ) -> Result<Self> {
        check_no_seam(&mesh)?;
        let std = Arc::new(StdBlocks::new(&mesh, &material));
        Self::with_blocks(mesh, material, cracks, options, std, None)
    }

    /// [`XfemModel::new_multi`] on the material of `domain`: with holes, cut elements are
    /// integrated over their material part ([`crate::xfem::integration`]), nodes without
    /// material are prescribed to 0, sliver nodes lose their enrichment ([`XfemModel::constrain`]) and a crack end on a hole is a
    /// mouth ([`Crack::named_in`]). Without holes, the plain model.
    pub fn new_in_domain(
        mesh: Arc<Mesh>,
        material: Elastic,
        cracks: Vec<Vec<[f64; 2]>>,
        options: XfemOptions,
        domain: &Domain,
    ) -> Result<Self> {
        let fd = FictitiousDomain::new(&mesh, domain, 2, DEFAULT_MIN_SUPPORT_FRACTION)?;
        let Some(fd) = fd else {
            return Self::new_multi(mesh, material, cracks, options);
        };
        check_no_seam(&mesh)?;
        let std = Arc::new(StdBlocks::new(&mesh, &material));
        Self::with_blocks(mesh, material, cracks, options, std, Some(Arc::new(fd)))
    }

    /// A model of the same plate with another (single) crack, reusing the mesh and the standard
    /// blocks.
    pub fn with_crack(&self, crack: Vec<[f64; 2]>) -> Result<Self> {
        self.with_cracks(vec![crack])
    }

    /// A model of the same plate with other cracks, reusing the mesh and the standard blocks.
    pub fn with_cracks(&self, cracks: Vec<Vec<[f64; 2]>>) -> Result<Self> {
        Self::with_blocks(
            self.mesh.clone(),
            self.material,
            cracks,
            self.options,
            self.std.clone(),
            self.fictitious.clone(),
        )
    }

    /// Tip `tip` (global index).
    pub fn tip(&self, tip: usize) -> &Tip {
        &self.tips[tip]
    }

    /// The phases of a model: options, cracks and tips, enrichment sets, dof numbering, enriched
    /// elements.
    fn with_blocks(
        mesh: Arc<Mesh>,
        material: Elastic,
        polylines: Vec<Vec<[f64; 2]>>,
        options: XfemOptions,
        std: Arc<StdBlocks>,
        fictitious: Option<Arc<FictitiousDomain>>,
    ) -> Result<Self> {
        options.validate()?;
        let cracks = build_cracks(polylines, &mesh, fictitious.as_deref().map(|f| &f.domain))?;
        let (tips, tip_crack) = global_tips(&cracks);
        let rules = Rules::new(options.nsub, options.tip_nsub);
        let sets = EnrichmentSets::new(
            &mesh,
            &cracks,
            &tips,
            &tip_crack,
            options.fixed_area_radius,
            options.area_threshold,
            &rules,
            fictitious.as_deref(),
        )?;
        let numbering = DofNumbering::new(mesh.n_nodes(), &sets);
        let (enr_index, enr) = ElementEnrichment {
            mesh: &mesh,
            cracks: &cracks,
            tips: &tips,
            tip_crack: &tip_crack,
            sets: &sets,
            numbering: &numbering,
        }
        .elements();
        let EnrichmentSets {
            tip_elements,
            tip_nodes,
            split_elements,
            heaviside_nodes,
            dropped_nodes,
            ..
        } = sets;
        Ok(Self {
            mesh,
            material,
            cracks,
            tips,
            tip_crack,
            options,
            n_std: numbering.n_std,
            n_dofs: numbering.n_dofs,
            heaviside_nodes,
            dropped_nodes,
            tip_nodes,
            tip_elements,
            split_elements,
            fictitious,
            std,
            enr_index,
            enr,
            rules,
        })
    }

    /// Position of every dof (its node's coordinates; enriched dofs take their node's position),
    /// e.g. for a geometric nested-dissection ordering of the solver.
    pub fn dof_positions(&self) -> Vec<[f64; 2]> {
        let mut xy: Vec<[f64; 2]> = self.mesh.coords.iter().flat_map(|&c| [c, c]).collect();
        xy.resize(self.n_dofs, [0.0; 2]);
        let mut next = self.n_std;
        for &n in self.heaviside_nodes.iter().flatten() {
            xy[next] = self.mesh.coords[n];
            xy[next + 1] = self.mesh.coords[n];
            next += 2;
        }
        for nodes in &self.tip_nodes {
            for &n in nodes {
                for k in 0..8 {
                    xy[next + k] = self.mesh.coords[n];
                }
                next += 8;
            }
        }
        xy
    }

    /// Number of elements carrying enriched functions.
    pub fn n_enriched_elements(&self) -> usize {
        self.enr.len()
    }

    pub(super) fn enriched(&self, e: usize) -> Option<&EnrElement> {
        let k = self.enr_index[e];
        (k != NONE).then(|| &self.enr[k as usize])
    }

    /// Dofs of element `e` (2 per scalar basis function: u1, u2).
    pub fn element_dofs(&self, e: usize) -> Vec<usize> {
        match self.enriched(e) {
            Some(en) => en.dofs.clone(),
            None => self.mesh.elements[e]
                .iter()
                .flat_map(|&n| [2 * n, 2 * n + 1])
                .collect(),
        }
    }

    /// Rule `kind` of element `e` restricted to the material ([`crate::xfem::integration`]):
    /// the rule itself without holes or in a material element, nothing in a void one, and in a
    /// cut one the material part's rule (`Gauss`) or its pieces clipped by the sub-quads.
    pub(super) fn material_rule(&self, e: usize, kind: RuleKind) -> Cow<'_, [QPoint]> {
        let full = self.rules.get(kind);
        let Some(fd) = &self.fictitious else {
            return Cow::Borrowed(full);
        };
        match (fd.kind(e), kind) {
            (ElementKind::Material, _) => Cow::Borrowed(full),
            (ElementKind::Void, _) => Cow::Borrowed(&[]),
            (ElementKind::Cut, RuleKind::Gauss) => Cow::Borrowed(fd.rule(e, full)),
            (ElementKind::Cut, k) => {
                Cow::Owned(fd.subcell_rule(e, self.rules.nsub(k)).unwrap_or_default())
            }
        }
    }

    /// The Dirichlet conditions `bc` checked for rigid-body modes; with holes, the removed
    /// nodes' conditions dropped and all their dofs (standard and enriched) prescribed to 0, the
    /// enriched dofs of sliver nodes too ([`FictitiousDomain::drops_enrichment`]), their forces
    /// in `f` zeroed ([`FictitiousDomain::constrain`]).
    pub fn constrain(&self, bc: Dirichlet, f: &mut [f64]) -> Result<Dirichlet> {
        let Some(fd) = &self.fictitious else {
            bc.check_rigid_modes(&self.mesh.coords)?;
            return Ok(bc);
        };
        let mut enriched: HashMap<usize, Vec<usize>> = HashMap::new();
        for (e, conn) in self.mesh.elements.iter().enumerate() {
            let Some(en) = self.enriched(e) else { continue };
            for (k, func) in en.funcs.iter().enumerate() {
                if let Func::Heav { k: node, .. } | Func::Branch { k: node, .. } = *func {
                    if fd.drops_enrichment(conn[node]) {
                        let v = enriched.entry(conn[node]).or_default();
                        v.extend([en.dofs[2 * k], en.dofs[2 * k + 1]]);
                    }
                }
            }
        }
        for v in enriched.values_mut() {
            v.sort_unstable();
            v.dedup();
        }
        fd.constrain(bc, f, &self.mesh.coords, |n| {
            enriched.get(&n).cloned().unwrap_or_default()
        })
    }

    /// Values and global gradients of the scalar basis functions of element `e` at (xi, eta), in
    /// the order of [`Self::element_dofs`]. Returns the physical point and det J.
    pub(super) fn basis(
        &self,
        e: usize,
        en: Option<&EnrElement>,
        xi: f64,
        eta: f64,
        b: &mut BasisBuf,
    ) -> ([f64; 2], f64) {
        let xy = self.mesh.element_coords(e);
        let (x, g, det) = geometry(&xy, xi, eta);
        let n = shape(xi, eta);
        b.vals.clear();
        b.grads.clear();
        let Some(en) = en else {
            b.vals.extend_from_slice(&n);
            b.grads.extend((0..4).map(|k| [g[0][k], g[1][k]]));
            return (x, det);
        };
        b.h.clear();
        b.h.extend(en.heav.iter().map(|&c| self.cracks[c].heaviside(x)));
        b.br.clear();
        b.br.extend(en.tips.iter().map(|&t| {
            branch_functions_snapped(&self.tips[t], x, self.cracks[self.tip_crack[t]].snap)
        }));
        for f in &en.funcs {
            match *f {
                Func::Std(k) => {
                    b.vals.push(n[k]);
                    b.grads.push([g[0][k], g[1][k]]);
                }
                Func::Heav { k, slot, hk } => {
                    let s = b.h[slot] - hk;
                    b.vals.push(n[k] * s);
                    b.grads.push([g[0][k] * s, g[1][k] * s]);
                }
                Func::Branch { k, slot, j, fk } => {
                    let (fv, fg) = &b.br[slot];
                    let s = fv[j] - fk;
                    b.vals.push(n[k] * s);
                    b.grads
                        .push([g[0][k] * s + n[k] * fg[j][0], g[1][k] * s + n[k] * fg[j][1]]);
                }
            }
        }
        (x, det)
    }

    /// Element stiffness block (row-major, dofs of [`Self::element_dofs`]), eqs. (25)-(26), (34).
    pub fn element_block(&self, e: usize, out: &mut Vec<f64>) {
        self.block_of(e, self.enriched(e), out);
    }

    /// The standard block of element `e` as if it carried no enrichment (its 8 standard dofs):
    /// the block of the uncracked plate, equal to the standard-standard part of an enriched
    /// element's block up to round-off (the same polynomial integrand, integrated exactly by
    /// either rule, [`crate::xfem::integration`]).
    pub(super) fn plain_block(&self, e: usize, out: &mut Vec<f64>) {
        self.block_of(e, None, out);
    }

    /// The elements carrying enriched functions (increasing element order) with their basis.
    pub(super) fn enriched_elements(&self) -> impl Iterator<Item = (usize, &EnrElement)> {
        self.enr_index
            .iter()
            .enumerate()
            .filter(|(_, &k)| k != NONE)
            .map(|(e, &k)| (e, &self.enr[k as usize]))
    }

    /// The block of element `e` with the enrichment `en` (None: the plain block).
    fn block_of(&self, e: usize, en: Option<&EnrElement>, out: &mut Vec<f64>) {
        out.clear();
        let kind = self.fictitious.as_ref().map(|fd| fd.kind(e));
        if en.is_none() && kind.is_none_or(|k| k == ElementKind::Material) {
            out.extend_from_slice(self.std.of(e));
            return;
        }
        let nd = en.map_or(8, |x| x.dofs.len());
        out.resize(nd * nd, 0.0);
        let d = self.material.d_matrix();
        let mut b = BasisBuf::default();
        let rule = self.material_rule(e, en.map_or(RuleKind::Gauss, |x| x.rule));
        for q in rule.iter() {
            let (_, det) = self.basis(e, en, q.xi, q.eta, &mut b);
            add_btdb(out, &b.grads, &d, q.w * det * self.material.thickness);
        }
    }

    /// Global stiffness matrix (pattern built for this enrichment, parallel assembly).
    pub fn stiffness(&self) -> Result<CscMatrix> {
        let blocks: Vec<Vec<usize>> = (0..self.mesh.n_elements())
            .map(|e| self.element_dofs(e))
            .collect();
        let pattern = Pattern::symmetric(self.n_dofs, &blocks)?;
        Ok(pattern.into_matrix(&blocks, &blocks, |e, out| self.element_block(e, out)))
    }

    /// The dofs (u1, u2) of the four branch functions (eq. 2, in the order of
    /// [`crate::xfem::branch_functions`]) of tip `tip` at each of its branch-enriched nodes, as
    /// (node, [[u1, u2]; 4]), sorted by node: for imposing or reading near-tip fields.
    pub fn branch_dofs(&self, tip: usize) -> Vec<(usize, [[usize; 2]; 4])> {
        let mut out: HashMap<usize, [[usize; 2]; 4]> = HashMap::new();
        for e in self.enr_elements_of(tip) {
            let Some(en) = self.enriched(e) else { continue };
            let conn = self.mesh.elements[e];
            for (f, func) in en.funcs.iter().enumerate() {
                if let Func::Branch { k, slot, j, .. } = *func {
                    if en.tips[slot] == tip {
                        out.entry(conn[k]).or_default()[j] = [en.dofs[2 * f], en.dofs[2 * f + 1]];
                    }
                }
            }
        }
        let mut v: Vec<_> = out.into_iter().collect();
        v.sort_unstable_by_key(|x| x.0);
        v
    }

    /// Elements carrying tip `tip`'s branch functions.
    fn enr_elements_of(&self, tip: usize) -> Vec<usize> {
        (0..self.mesh.n_elements())
            .filter(|&e| self.enriched(e).is_some_and(|en| en.tips.contains(&tip)))
            .collect()
    }

    /// Size of the (first) element containing tip `tip`: sqrt(dx dy).
    pub fn tip_element_size(&self, tip: usize) -> f64 {
        let e = self.tip_elements[tip][0];
        let xy = self.mesh.element_coords(e);
        ((xy[1][0] - xy[0][0]) * (xy[3][1] - xy[0][1])).sqrt()
    }

    /// Length of the chord of the (first) tip element along the crack direction at tip `tip`:
    /// the default growth increment ("one element length").
    pub fn tip_element_length(&self, tip: usize) -> f64 {
        let e = self.tip_elements[tip][0];
        let xy = self.mesh.element_coords(e);
        let (dx, dy) = (xy[1][0] - xy[0][0], xy[3][1] - xy[0][1]);
        let d = self.tips[tip].dir;
        let lx = if d[0].abs() > 1e-12 {
            dx / d[0].abs()
        } else {
            f64::INFINITY
        };
        let ly = if d[1].abs() > 1e-12 {
            dy / d[1].abs()
        } else {
            f64::INFINITY
        };
        lx.min(ly)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::problem::Plane;

    #[test]
    fn level_set_and_enrichment_sets() {
        let mesh = Arc::new(Mesh::uniform(0.0, 0.0, 4.0, 3.0, 8, 7).unwrap());
        let mat = Elastic::new(1.0, 0.3, Plane::Strain, 1.0).unwrap();
        let m = XfemModel::new(
            mesh.clone(),
            mat,
            vec![[0.0, 1.5], [1.75, 1.5]],
            XfemOptions::default(),
        )
        .unwrap();
        assert!(m.cracks[0].mouth);
        assert_eq!(m.cracks[0].tips.len(), 1);
        assert!(m.cracks[0].level_set([1.0, 2.0]) > 0.0 && m.cracks[0].level_set([1.0, 1.0]) < 0.0);
        // tip at x = 1.75 (mid element 3), split elements 0..=2 in row 3
        assert_eq!(m.tip_elements[0], vec![mesh.element(3, 3)]);
        assert_eq!(m.split_elements[0].len(), 3);
        assert_eq!(m.tip_nodes[0].len(), 4);
        assert_eq!(m.heaviside_nodes[0].len(), 6); // x = 0, 0.5, 1.0 on two rows
        assert_eq!(m.n_dofs, m.n_std + 6 * 2 + 4 * 8);
        // reversed polyline is re-oriented so the mouth comes first
        let r = Crack::new(vec![[1.75, 1.5], [0.0, 1.5]], &mesh).unwrap();
        assert_eq!(r.points[0], [0.0, 1.5]);
        assert!(Crack::new(vec![[0.0, 1.5], [4.0, 1.5]], &mesh).is_err());
        assert!(Crack::new(vec![[0.0, 1.5]], &mesh).is_err());
        assert!(Crack::new(vec![[0.0, 1.5], [5.0, 1.5]], &mesh).is_err());
        // crack along a grid line: the off-line nodes are dropped by the area rule
        let g = XfemModel::new(
            mesh.clone(),
            mat,
            vec![[0.0, 1.5 + 3.0 / 14.0], [1.75, 1.5 + 3.0 / 14.0]],
            XfemOptions::default(),
        )
        .unwrap();
        assert!(!g.dropped_nodes[0].is_empty());
        for &n in &g.heaviside_nodes[0] {
            assert!((mesh.coords[n][1] - (1.5 + 3.0 / 14.0)).abs() < 1e-12);
        }
    }
}
