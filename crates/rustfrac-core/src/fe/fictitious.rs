//! Holes and notches as a fictitious domain on the structured Q4 grid: the mesh stays the
//! rectangle's, every element is classified against the domain's level set
//! ([`Domain::level_set`]) as *material* (no hole meets it: the element's own rule, bit for bit
//! as without holes), *void* (inside a hole: no stiffness) or *cut*, and a cut element is
//! integrated over its material part only.
//!
//! * The material part of a cut element is a list of convex polygons. Straight-edged holes
//!   ([`Shape::Rect`], [`Shape::Polygon`]: notches are rectangles poking out of the plate) are
//!   subtracted exactly: the hole is split into convex parts (a polygon by ear clipping,
//!   `crate::geometry::triangulate`) and each part is subtracted edge by edge
//!   (`crate::geometry::subtract_convex`).
//! * Circles are refined: the element is split by a quadtree, a cell the circle misses is kept,
//!   one inside it dropped, one it cuts split again down to leaves of size at most
//!   r / [`CIRCLE_LEAVES_PER_RADIUS`] (depth at most [`MAX_CIRCLE_DEPTH`]); a cut leaf keeps its
//!   part outside the *chord polygon* (the corners inside the circle and the exact crossings of
//!   the circle with the leaf's edges, a convex polygon inscribed in circle and leaf). The
//!   circle is then replaced by an inscribed polygon of chords of length c <= sqrt(2) s: the
//!   area error is about pi c^2 / 6, relatively c^2 / (6 r^2) <= 3.3e-4 of the hole's area;
//!   measured (tests below): 1.6e-4 relative (the hole slightly too small) on 16 .. 128
//!   elements per 4 r (the leaves are r / 32 on every grid).
//! * Quadrature on the pieces: fan triangles of each convex piece with the 3-point rule (degree 2:
//!   exact for the Q4 stiffness of a rectangle, whose integrand is of degree 2) or the 7-point
//!   rule (degree 5, for `gauss` >= 3 and for error norms), mapped back to the element's
//!   reference coordinates (xi, eta) with weights in the reference measure (they sum to 4 x the
//!   material fraction), so `w det J` is the physical weight as for every other rule.
//! * Nodes: a node's *support fraction* is the material area of the elements containing it over
//!   their area. Only a node with no material at all (every element containing it void) is
//!   *removed*: its dofs are prescribed to 0 and left out of the rigid-mode check
//!   ([`FictitiousDomain::constrain`]); a condition on such a node (a grip on a notched edge) is
//!   dropped. Such a node has no stiffness, so holding it at 0 holds no material: the reaction
//!   on every removed dof is exactly 0. A node keeping a sliver of material keeps its standard
//!   dofs: for plain Q4 the sliver costs no conditioning (the Jacobi-equilibrated condition
//!   estimate, what governs the Cholesky solve, does not grow as the sliver thins; measured at
//!   [`DEFAULT_MIN_SUPPORT_FRACTION`]), while holding it at 0 would make it a hidden support
//!   (it would carry a reaction the scene does not have). The small-cut-element treatment is
//!   therefore the element's own: an element whose material part is below round-off
//!   ([`WHOLE`] of its area) is void, every other one keeps its material part. What a sliver
//!   does make ill-conditioned is an *enrichment*: four branch functions (or a Heaviside
//!   function) on a sliver are nearly constant there, nearly dependent on the node's standard
//!   function, so below [`DEFAULT_MIN_SUPPORT_FRACTION`] a node's enriched dofs (XFEM) are
//!   prescribed to 0 ([`FictitiousDomain::drops_enrichment`]), which leaves the enrichment out
//!   of the space and holds no material (like the Heaviside small-area rule of
//!   [`crate::xfem::enrichment`]).
//! * Holes thinner than two elements: a node inside a hole whose support reaches material on
//!   both faces ties the faces together, so a slot narrower than about two elements is glued
//!   (measured, `tests/suite/hole_validation.rs`: an XFEM crack from the tip of a half-element slot
//!   gives K_I 14.78 instead of 27.12); draw the crack through such a slot from the plate's
//!   edge instead (its Heaviside enrichment separates the faces), or refine. Such holes are
//!   reported: a [`Warning`] names each one fewer than [`MIN_ELEMENTS_ACROSS`] elements across.
//! * Tractions on the plate's edges are not clipped by a notch: the forces on removed nodes are
//!   dropped ([`FictitiousDomain::constrain`]), the edge segments a notch cuts keep their full
//!   tributary length.

use crate::error::{Error, Result};
use crate::fe::dirichlet::Dirichlet;
use crate::fe::mesh::Mesh;
use crate::fe::quadrature::{triangle_rule, QPoint};
use crate::geometry::{clip_box, polygon_area, subtract_convex, triangulate};
use crate::problem::{Domain, Hole, Shape};
use crate::warning::{Warning, WarningKind};

/// Nodes whose support holds some material but less than this fraction keep their standard
/// dofs and lose their enrichment (module documentation). Measured
/// (`tests/suite/hole_validation.rs`, `small_fraction_rule_bounds_the_condition`): the
/// condition estimate of plain Q4 (of the Jacobi-equilibrated matrix, what governs the Cholesky
/// solve) does not grow as a sliver thins: 2.72e4 without a sliver, 2.88e4 at f = 1e-5 on a
/// 32 x 32 grid (only the unscaled matrix's condition grows like 1 / f), so the standard dofs
/// need no threshold; an enrichment on such a node is nearly dependent on its standard
/// function. 1e-3 is the Heaviside small-area rule's order (Dolbow 1999) for the whole support.
pub const DEFAULT_MIN_SUPPORT_FRACTION: f64 = 1e-3;

/// Quadtree leaves of a cut element are at most (smallest cut radius) / this: the chord polygon's
/// area error is then below 3.3e-4 of the hole's area (module documentation).
pub const CIRCLE_LEAVES_PER_RADIUS: f64 = 32.0;

/// Deepest quadtree of a circle-cut element (4^8 cells at most; reached only for a radius below
/// 1/8 element).
pub const MAX_CIRCLE_DEPTH: usize = 8;

/// Material fractions within this of 1 (0) make an element material (void): a hole touching an
/// element along an edge or at a point leaves it whole, a part below round-off is no material.
pub const WHOLE: f64 = 1e-12;

/// How an element meets the holes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ElementKind {
    /// no hole meets it
    Material,
    /// inside the holes
    Void,
    /// partly in a hole: integrated over its material part
    Cut,
}

/// The fictitious-domain data of a mesh and a domain with holes (module documentation).
#[derive(Debug, Clone)]
pub struct FictitiousDomain {
    /// the domain (its level set tells material points)
    pub domain: Domain,
    kind: Vec<ElementKind>,
    /// material area fraction of every element (1 material, 0 void)
    pub fraction: Vec<f64>,
    /// index into `pieces` of a cut element
    cut_index: Vec<u32>,
    /// the material part of each cut element: convex counter-clockwise polygons in the element's
    /// reference coordinates
    pieces: Vec<Vec<Vec<[f64; 2]>>>,
    /// the stiffness rule of each cut element (same order as `pieces`)
    rules: Vec<Vec<QPoint>>,
    /// material fraction of every node's support
    pub node_fraction: Vec<f64>,
    /// nodes removed (sorted): no material in their support
    pub removed_nodes: Vec<usize>,
    removed: Vec<bool>,
    /// nodes with material, but less than the threshold, in their support: their enrichment is
    /// dropped ([`FictitiousDomain::drops_enrichment`])
    sliver: Vec<bool>,
    /// holes and notches narrower than [`MIN_ELEMENTS_ACROSS`] elements (`narrow_holes`):
    /// their faces are tied, so the result is stiffer than the scene's
    pub warnings: Vec<Warning>,
}

/// The fewest elements across a hole or notch (its bounding box, within the plate, against the
/// largest element it overlaps along that direction) before its faces are tied: below it a node
/// inside the hole, or an element spanning it, couples material on both faces (measured,
/// `tests/suite/hole_validation.rs`: a half-element slot gives K_I 14.78 instead of 27.12).
pub const MIN_ELEMENTS_ACROSS: f64 = 2.0;

/// A warning for each hole or notch fewer than [`MIN_ELEMENTS_ACROSS`] elements across (its
/// bounding box clipped to the plate, along x1 and along x2, against the largest element size
/// of the grid columns / rows it overlaps), naming it and the refinement that resolves it.
fn narrow_holes(mesh: &Mesh, domain: &Domain) -> Vec<Warning> {
    let largest = |lines: &[f64], lo: f64, hi: f64| {
        lines
            .windows(2)
            .filter(|w| w[1] > lo && w[0] < hi)
            .map(|w| w[1] - w[0])
            .fold(0.0f64, f64::max)
    };
    let mut out = Vec::new();
    for h in &domain.holes {
        let b = h.shape.bounding_box();
        let (x0, x1) = (b[0].max(mesh.xs[0]), b[2].min(mesh.xs[mesh.xs.len() - 1]));
        let (y0, y1) = (b[1].max(mesh.ys[0]), b[3].min(mesh.ys[mesh.ys.len() - 1]));
        let across = [
            ("x1", x1 - x0, largest(&mesh.xs, x0, x1)),
            ("x2", y1 - y0, largest(&mesh.ys, y0, y1)),
        ];
        let Some((axis, w, el)) = across
            .into_iter()
            .filter(|&(_, w, el)| el > 0.0 && w < MIN_ELEMENTS_ACROSS * el)
            .min_by(|a, b| (a.1 / a.2).total_cmp(&(b.1 / b.2)))
        else {
            continue;
        };
        out.push(Warning::new(
            WarningKind::Discretisation,
            format!(
                "{} is {:.3} elements across along {axis} (width {w:.4}, element size {el:.4}; \
                 fewer than {MIN_ELEMENTS_ACROSS}): the nodes and elements spanning it tie its \
                 faces, so the model is stiffer than the scene; refine there (mesh.refine box, \
                 or finer xs / ys), or draw a crack through a slot",
                h.name,
                w / el
            ),
        ));
    }
    out
}

/// The triangle-rule degree matching a Gauss rule of `gauss` points per direction.
fn degree_of(gauss: usize) -> usize {
    if gauss <= 2 {
        2
    } else {
        5
    }
}

impl FictitiousDomain {
    /// The data of `mesh` and the holes of `domain` (None without holes); `gauss` is the model's
    /// Gauss points per direction (the degree of the cut elements' rule), `min_fraction` the
    /// support fraction below which a node's enrichment is dropped (0 <= t < 1;
    /// [`DEFAULT_MIN_SUPPORT_FRACTION`]; no node with material is removed). Refuses holes of
    /// invalid shape (naming the hole, `hole[k].radius`, `notch[k]`, ...) and holes that leave
    /// no material.
    pub fn new(
        mesh: &Mesh,
        domain: &Domain,
        gauss: usize,
        min_fraction: f64,
    ) -> Result<Option<Self>> {
        if domain.holes.is_empty() {
            return Ok(None);
        }
        if !(0.0..1.0).contains(&min_fraction) {
            return Err(Error::invalid(
                "min_support_fraction",
                "a fraction 0 <= t < 1",
                min_fraction,
            ));
        }
        let holes = domain
            .holes
            .iter()
            .map(|h| {
                check_hole(h)?;
                convex_parts(h).map(|parts| (h, parts))
            })
            .collect::<Result<Vec<_>>>()?;
        let (nx, ne) = (mesh.nx(), mesh.n_elements());
        let degree = degree_of(gauss);
        let mut fd = Self {
            domain: domain.clone(),
            kind: Vec::with_capacity(ne),
            fraction: Vec::with_capacity(ne),
            cut_index: vec![u32::MAX; ne],
            pieces: Vec::new(),
            rules: Vec::new(),
            node_fraction: Vec::new(),
            removed_nodes: Vec::new(),
            removed: Vec::new(),
            sliver: Vec::new(),
            warnings: narrow_holes(mesh, domain),
        };
        for e in 0..ne {
            let (i, j) = (e % nx, e / nx);
            let bx = [mesh.xs[i], mesh.ys[j], mesh.xs[i + 1], mesh.ys[j + 1]];
            let (kind, frac, pieces) = classify(bx, &holes);
            fd.kind.push(kind);
            fd.fraction.push(frac);
            if kind == ElementKind::Cut {
                fd.cut_index[e] = fd.pieces.len() as u32;
                fd.rules.push(rule_on(&pieces, degree));
                fd.pieces.push(pieces);
            }
        }
        if fd.kind.iter().all(|&k| k == ElementKind::Void) {
            return Err(Error::invalid(
                &domain.holes[0].name,
                "holes and notches that leave material in the plate",
                "every element lies in a hole",
            ));
        }
        fd.node_support(mesh, min_fraction);
        Ok(Some(fd))
    }

    /// Support fractions, the removed nodes (no material) and the sliver nodes (below
    /// `min_fraction`).
    fn node_support(&mut self, mesh: &Mesh, min_fraction: f64) {
        let n = mesh.n_nodes();
        let (mut mat, mut all) = (vec![0.0; n], vec![0.0; n]);
        for (e, conn) in mesh.elements.iter().enumerate() {
            let xy = mesh.element_coords(e);
            let area = (xy[1][0] - xy[0][0]) * (xy[3][1] - xy[0][1]);
            for &node in conn {
                mat[node] += self.fraction[e] * area;
                all[node] += area;
            }
        }
        self.node_fraction = mat
            .iter()
            .zip(&all)
            .map(|(m, a)| if *a > 0.0 { m / a } else { 0.0 })
            .collect();
        self.removed = self.node_fraction.iter().map(|&f| f <= 0.0).collect();
        self.sliver = self
            .node_fraction
            .iter()
            .map(|&f| f > 0.0 && f < min_fraction)
            .collect();
        self.removed_nodes = (0..n).filter(|&k| self.removed[k]).collect();
    }

    /// Whether `p` lies in the material (outside every hole: a positive level set).
    pub fn in_material(&self, p: [f64; 2]) -> bool {
        self.domain.level_set(p) > 0.0
    }

    /// How element `e` meets the holes.
    pub fn kind(&self, e: usize) -> ElementKind {
        self.kind[e]
    }

    /// Per node of `n_nodes`: true unless removed (boundary regions select active nodes only).
    pub fn active_nodes(&self, n_nodes: usize) -> Vec<bool> {
        (0..n_nodes).map(|n| !self.is_removed(n)).collect()
    }

    /// Whether node `n` is removed (no material: its dofs prescribed to 0).
    pub fn is_removed(&self, n: usize) -> bool {
        self.removed[n]
    }

    /// Whether node `n`'s enriched dofs are prescribed to 0: removed, or a sliver (some material
    /// but less than the threshold in its support; its standard dofs stay free).
    pub fn drops_enrichment(&self, n: usize) -> bool {
        self.removed[n] || self.sliver[n]
    }

    /// The stiffness rule of element `e`: `full` (its own rule) for a material element, empty
    /// for a void one, the material part's rule for a cut one.
    pub fn rule<'a>(&'a self, e: usize, full: &'a [QPoint]) -> &'a [QPoint] {
        match self.kind[e] {
            ElementKind::Material => full,
            ElementKind::Void => &[],
            ElementKind::Cut => &self.rules[self.cut_index[e] as usize],
        }
    }

    /// A rule of degree `degree` (2 or 5, [`triangle_rule`]) on the material part of a cut
    /// element (None for material and void elements).
    pub fn cut_rule(&self, e: usize, degree: usize) -> Option<Vec<QPoint>> {
        (self.kind[e] == ElementKind::Cut)
            .then(|| rule_on(&self.pieces[self.cut_index[e] as usize], degree))
    }

    /// The material part of a cut element intersected with the `nsub x nsub` sub-squares of the
    /// XFEM sub-quad rule (eq. 35), the 3-point rule on the triangles of every piece (None for
    /// material and void elements): the sub-quads' sampling of the enrichment, restricted to the
    /// material.
    pub fn subcell_rule(&self, e: usize, nsub: usize) -> Option<Vec<QPoint>> {
        if self.kind[e] != ElementKind::Cut {
            return None;
        }
        let h = 2.0 / nsub as f64;
        let pieces = &self.pieces[self.cut_index[e] as usize];
        let mut parts = Vec::new();
        for sj in 0..nsub {
            for si in 0..nsub {
                let lo = [-1.0 + si as f64 * h, -1.0 + sj as f64 * h];
                let hi = [lo[0] + h, lo[1] + h];
                for p in pieces {
                    let c = clip_box(p, lo, hi);
                    if c.len() >= 3 && polygon_area(&c) > WHOLE * h * h {
                        parts.push(c);
                    }
                }
            }
        }
        Some(rule_on(&parts, 2))
    }

    /// The Dirichlet conditions of a model with these holes: the conditions `bc` less those on
    /// removed nodes, checked for the rigid-body modes ([`Dirichlet::check_rigid_modes`] on the
    /// node positions `node_xy`), then every dof of a removed node prescribed to 0: its standard
    /// dofs and the further dofs `extra(node)` gives (XFEM enrichment), and the further dofs of
    /// every other node that [drops its enrichment](Self::drops_enrichment). The forces `f` on
    /// those dofs are zeroed.
    pub fn constrain(
        &self,
        bc: Dirichlet,
        f: &mut [f64],
        node_xy: &[[f64; 2]],
        extra: impl Fn(usize) -> Vec<usize>,
    ) -> Result<Dirichlet> {
        let removed_dof = |d: usize| d / 2 < self.removed.len() && self.removed[d / 2];
        let mut kept = Dirichlet {
            dofs: bc
                .dofs
                .into_iter()
                .filter(|&(d, _)| !removed_dof(d))
                .collect(),
        };
        kept.check_rigid_modes(node_xy)?;
        let mut hold = |d: usize| {
            kept.dofs.push((d, 0.0));
            if let Some(v) = f.get_mut(d) {
                *v = 0.0;
            }
        };
        for n in 0..self.removed.len() {
            if self.removed[n] {
                [2 * n, 2 * n + 1].into_iter().for_each(&mut hold);
            }
            if self.drops_enrichment(n) {
                extra(n).into_iter().for_each(&mut hold);
            }
        }
        Ok(kept)
    }
}

/// Refuses a hole shape that is not finite or has no area (naming the hole).
fn check_hole(h: &Hole) -> Result<()> {
    let finite = |p: &[f64; 2]| p[0].is_finite() && p[1].is_finite();
    match &h.shape {
        Shape::Circle { center, radius } => {
            if !finite(center) {
                return Err(Error::invalid(
                    &format!("{}.center", h.name),
                    "finite coordinates",
                    format!("{center:?}"),
                ));
            }
            if !(radius.is_finite() && *radius > 0.0) {
                return Err(Error::invalid(
                    &format!("{}.radius", h.name),
                    "a positive radius",
                    radius,
                ));
            }
        }
        Shape::Rect { min, max } => {
            if !(finite(min) && finite(max) && max[0] > min[0] && max[1] > min[1]) {
                return Err(Error::invalid(
                    &h.name,
                    "a rectangle of finite corners and positive width and height",
                    format!("{min:?} .. {max:?}"),
                ));
            }
        }
        Shape::Polygon(v) => {
            let area = polygon_area(v).abs();
            let (w, ht) = {
                let b = h.shape.bounding_box();
                (b[2] - b[0], b[3] - b[1])
            };
            if v.len() < 3 || !v.iter().all(finite) || area.is_nan() || area <= 1e-12 * w * ht {
                return Err(Error::invalid(
                    &format!("{}.points", h.name),
                    "a simple polygon of at least 3 finite vertices and positive area",
                    format!("{} vertices, area {area:e}", v.len()),
                ));
            }
        }
    }
    Ok(())
}

/// The convex parts of a straight-edged hole (a rectangle itself, a polygon's ear-clipping
/// triangles; none for a circle). Refuses a polygon that is not simple (its triangles do not
/// cover its area), naming `hole[k].points`.
fn convex_parts(h: &Hole) -> Result<Vec<Vec<[f64; 2]>>> {
    match &h.shape {
        Shape::Circle { .. } => Ok(Vec::new()),
        Shape::Rect { min, max } => Ok(vec![box_polygon([min[0], min[1], max[0], max[1]])]),
        Shape::Polygon(v) => {
            let tris = triangulate(v);
            let (a, t) = (
                polygon_area(v).abs(),
                tris.iter().map(|t| polygon_area(t)).sum::<f64>(),
            );
            if (t - a).abs() > 1e-9 * a {
                return Err(Error::invalid(
                    &format!("{}.points", h.name),
                    "a simple polygon (no crossing edges)",
                    format!(
                        "{} vertices whose triangulation covers {t:e} of area {a:e}",
                        v.len()
                    ),
                ));
            }
            Ok(tris.into_iter().map(|t| t.to_vec()).collect())
        }
    }
}

/// The counter-clockwise polygon of a box [x0, y0, x1, y1].
fn box_polygon(bx: [f64; 4]) -> Vec<[f64; 2]> {
    vec![
        [bx[0], bx[1]],
        [bx[2], bx[1]],
        [bx[2], bx[3]],
        [bx[0], bx[3]],
    ]
}

/// Centre and half diagonal of a box.
fn centre_half(bx: [f64; 4]) -> ([f64; 2], f64) {
    let c = [0.5 * (bx[0] + bx[2]), 0.5 * (bx[1] + bx[3])];
    (c, 0.5 * (bx[2] - bx[0]).hypot(bx[3] - bx[1]))
}

/// The element box `bx` against the holes (each with its convex parts, [`convex_parts`]): its
/// kind, material fraction and (cut) material pieces in reference coordinates.
fn classify(
    bx: [f64; 4],
    holes: &[(&Hole, Vec<Vec<[f64; 2]>>)],
) -> (ElementKind, f64, Vec<Vec<[f64; 2]>>) {
    let (c, hd) = centre_half(bx);
    let area = (bx[2] - bx[0]) * (bx[3] - bx[1]);
    let min_area = WHOLE * area;
    // the level set is a signed distance: |phi(centre)| >= half diagonal decides the box
    let mut near: Vec<&(&Hole, Vec<Vec<[f64; 2]>>)> = Vec::new();
    for hp in holes {
        let h = hp.0;
        let phi = h.shape.level_set(c);
        if phi <= -hd {
            return (ElementKind::Void, 0.0, Vec::new());
        }
        if phi < hd {
            near.push(hp);
        }
    }
    if near.is_empty() {
        return (ElementKind::Material, 1.0, Vec::new());
    }
    // polygon operations in coordinates relative to the box's corner (round-off relative to the
    // element's size, not to its distance from the origin)
    let o = [bx[0], bx[1]];
    let local = |p: &[f64; 2]| [p[0] - o[0], p[1] - o[1]];
    let lbx = [0.0, 0.0, bx[2] - bx[0], bx[3] - bx[1]];
    let circles: Vec<([f64; 2], f64)> = near
        .iter()
        .filter_map(|h| match h.0.shape {
            Shape::Circle { center, radius } => Some((local(&center), radius)),
            _ => None,
        })
        .collect();
    let mut pieces = if circles.is_empty() {
        vec![box_polygon(lbx)]
    } else {
        let r_min = circles.iter().map(|c| c.1).fold(f64::INFINITY, f64::min);
        let size = lbx[2].max(lbx[3]);
        let depth = (size * CIRCLE_LEAVES_PER_RADIUS / r_min)
            .log2()
            .ceil()
            .clamp(0.0, MAX_CIRCLE_DEPTH as f64) as usize;
        let mut out = Vec::new();
        circle_cells(lbx, &circles, depth, min_area, &mut out);
        out
    };
    for (_, parts) in &near {
        for part in parts {
            let lp: Vec<[f64; 2]> = part.iter().map(local).collect();
            pieces = subtract_convex(pieces, &lp, min_area);
        }
    }
    let to_ref = |p: &[f64; 2]| [2.0 * p[0] / lbx[2] - 1.0, 2.0 * p[1] / lbx[3] - 1.0];
    let reference: Vec<Vec<[f64; 2]>> = pieces
        .iter()
        .map(|p| p.iter().map(to_ref).collect())
        .collect();
    let frac = reference.iter().map(|p| polygon_area(p)).sum::<f64>() / 4.0;
    if frac >= 1.0 - WHOLE {
        return (ElementKind::Material, 1.0, Vec::new());
    }
    if frac <= WHOLE {
        return (ElementKind::Void, 0.0, Vec::new());
    }
    (ElementKind::Cut, frac, reference)
}

/// The quadtree of a circle-cut cell (module documentation): the material pieces of `bx` outside
/// the `circles` (centre, radius), appended to `out`.
fn circle_cells(
    bx: [f64; 4],
    circles: &[([f64; 2], f64)],
    depth: usize,
    min_area: f64,
    out: &mut Vec<Vec<[f64; 2]>>,
) {
    let (c, hd) = centre_half(bx);
    let mut cut = Vec::with_capacity(circles.len());
    for &(o, r) in circles {
        let phi = (c[0] - o[0]).hypot(c[1] - o[1]) - r;
        if phi <= -hd {
            return;
        }
        if phi < hd {
            cut.push((o, r));
        }
    }
    if cut.is_empty() {
        out.push(box_polygon(bx));
        return;
    }
    if depth > 0 {
        let (xm, ym) = (c[0], c[1]);
        for q in [
            [bx[0], bx[1], xm, ym],
            [xm, bx[1], bx[2], ym],
            [bx[0], ym, xm, bx[3]],
            [xm, ym, bx[2], bx[3]],
        ] {
            circle_cells(q, &cut, depth - 1, min_area, out);
        }
        return;
    }
    let mut pieces = vec![box_polygon(bx)];
    for (o, r) in cut {
        let chord = chord_polygon(bx, o, r);
        if chord.len() >= 3 {
            pieces = subtract_convex(pieces, &chord, min_area);
        }
    }
    out.extend(pieces);
}

/// The convex polygon of the corners of `bx` inside the circle (o, r) and the crossings of the
/// circle with its edges, counter-clockwise along the box's boundary.
fn chord_polygon(bx: [f64; 4], o: [f64; 2], r: f64) -> Vec<[f64; 2]> {
    let corners = box_polygon(bx);
    let mut poly = Vec::with_capacity(8);
    for k in 0..4 {
        let (p, q) = (corners[k], corners[(k + 1) % 4]);
        let (px, py) = (p[0] - o[0], p[1] - o[1]);
        if px.hypot(py) <= r {
            poly.push(p);
        }
        // |p + t (q - p) - o|^2 = r^2, roots strictly inside the edge in increasing t
        let d = [q[0] - p[0], q[1] - p[1]];
        let a = d[0] * d[0] + d[1] * d[1];
        let b = d[0] * px + d[1] * py;
        let cc = px * px + py * py - r * r;
        let disc = b * b - a * cc;
        if disc > 0.0 {
            let s = disc.sqrt();
            for t in [(-b - s) / a, (-b + s) / a] {
                if t > 0.0 && t < 1.0 {
                    poly.push([p[0] + t * d[0], p[1] + t * d[1]]);
                }
            }
        }
    }
    poly
}

/// The rule of degree `degree` on convex counter-clockwise polygons (fan triangles).
fn rule_on(pieces: &[Vec<[f64; 2]>], degree: usize) -> Vec<QPoint> {
    let tri = triangle_rule(degree);
    let mut pts = Vec::new();
    for p in pieces {
        for k in 1..p.len().saturating_sub(1) {
            let (a, b, c) = (p[0], p[k], p[k + 1]);
            let area = polygon_area(&[a, b, c]);
            if area <= 0.0 {
                continue;
            }
            for &(l, w) in &tri {
                let l3 = 1.0 - l[0] - l[1];
                pts.push(QPoint {
                    xi: l[0] * a[0] + l[1] * b[0] + l3 * c[0],
                    eta: l[0] * a[1] + l[1] * b[1] + l3 * c[1],
                    w: w * area,
                });
            }
        }
    }
    pts
}

#[cfg(test)]
mod tests {
    use super::*;

    fn hole(name: &str, shape: Shape) -> Hole {
        Hole {
            name: name.into(),
            shape,
        }
    }

    fn material_area(mesh: &Mesh, fd: &FictitiousDomain) -> f64 {
        (0..mesh.n_elements())
            .map(|e| {
                let xy = mesh.element_coords(e);
                let a = (xy[1][0] - xy[0][0]) * (xy[3][1] - xy[0][1]);
                match fd.kind(e) {
                    ElementKind::Material => a,
                    ElementKind::Void => 0.0,
                    // the rule's weights are in the reference measure (area 4)
                    ElementKind::Cut => {
                        let w: f64 = fd.rule(e, &[]).iter().map(|q| q.w).sum();
                        assert!((w / 4.0 - fd.fraction[e]).abs() < 1e-13);
                        a * w / 4.0
                    }
                }
            })
            .sum()
    }

    #[test]
    fn circle_area_error_is_small() {
        // a unit circle in [0, 4]^2; the chord polygon's area error, relative to pi
        for n in [16, 32, 64, 128] {
            let mesh = Mesh::uniform(0.0, 0.0, 4.0, 4.0, n, n).unwrap();
            let mut d = Domain::rect(4.0, 4.0);
            d.holes.push(hole(
                "hole[0]",
                Shape::Circle {
                    center: [2.0, 2.0],
                    radius: 1.0,
                },
            ));
            let fd = FictitiousDomain::new(&mesh, &d, 2, DEFAULT_MIN_SUPPORT_FRACTION)
                .unwrap()
                .unwrap();
            let hole_area = 16.0 - material_area(&mesh, &fd);
            let rel = (hole_area - std::f64::consts::PI) / std::f64::consts::PI;
            eprintln!("n = {n}: relative hole-area error {rel:.3e}");
            assert!(rel.abs() < 3.3e-4 && rel < 0.0, "{rel}");
        }
    }

    #[test]
    fn straight_holes_are_exact() {
        let mesh = Mesh::uniform(0.0, 0.0, 2.0, 1.0, 8, 4).unwrap();
        let mut d = Domain::rect(2.0, 1.0);
        // a notch from the left edge (poking out) and a triangle
        d.holes.push(hole(
            "notch[0]",
            Shape::Rect {
                min: [-1.0, 0.4],
                max: [0.33, 0.47],
            },
        ));
        d.holes.push(hole(
            "hole[0]",
            Shape::Polygon(vec![[1.1, 0.2], [1.7, 0.3], [1.3, 0.8]]),
        ));
        let fd = FictitiousDomain::new(&mesh, &d, 2, 0.0).unwrap().unwrap();
        let tri = 0.5 * ((0.6f64 * 0.6) - (0.1 * 0.2));
        let exact = 2.0 - 0.33 * 0.07 - tri;
        assert!((material_area(&mesh, &fd) - exact).abs() < 1e-14);
        // the second moment int x^2 of the material (2 x 2 Gauss on whole elements, the
        // degree-5 rule on cut ones): exact too
        let full = crate::fe::quadrature::subquad_rule(1, 2);
        let m2: f64 = (0..mesh.n_elements())
            .map(|e| {
                let xy = mesh.element_coords(e);
                let (dx, dy) = (xy[1][0] - xy[0][0], xy[3][1] - xy[0][1]);
                let rule = match fd.kind(e) {
                    ElementKind::Material => full.clone(),
                    ElementKind::Void => Vec::new(),
                    ElementKind::Cut => fd.cut_rule(e, 5).unwrap(),
                };
                rule.iter()
                    .map(|q| {
                        let x = xy[0][0] + 0.5 * (q.xi + 1.0) * dx;
                        0.25 * q.w * dx * dy * x * x
                    })
                    .sum::<f64>()
            })
            .sum();
        let t = [[1.1, 0.2], [1.7, 0.3], [1.3, 0.8]];
        let tri_m2 = tri / 6.0
            * (t[0][0] * t[0][0]
                + t[1][0] * t[1][0]
                + t[2][0] * t[2][0]
                + t[0][0] * t[1][0]
                + t[1][0] * t[2][0]
                + t[2][0] * t[0][0]);
        let exact_m2 = 8.0 / 3.0 - 0.33f64.powi(3) / 3.0 * 0.07 - tri_m2;
        assert!((m2 - exact_m2).abs() < 1e-13, "{m2} vs {exact_m2}");
    }

    #[test]
    fn nodes_without_material_are_removed() {
        let mesh = Mesh::uniform(0.0, 0.0, 4.0, 4.0, 4, 4).unwrap();
        let mut d = Domain::rect(4.0, 4.0);
        d.holes.push(hole(
            "hole[0]",
            Shape::Rect {
                min: [1.0, 1.0],
                max: [3.0, 3.0],
            },
        ));
        let fd = FictitiousDomain::new(&mesh, &d, 2, DEFAULT_MIN_SUPPORT_FRACTION)
            .unwrap()
            .unwrap();
        // the 4 elements inside are void, the centre node has no material
        assert_eq!(fd.removed_nodes, vec![mesh.node(2, 2)]);
        assert_eq!(
            (0..16).filter(|&e| fd.kind(e) == ElementKind::Void).count(),
            4
        );
        assert!((fd.node_fraction[mesh.node(1, 1)] - 0.75).abs() < 1e-15);
    }

    #[test]
    fn bad_holes_are_refused_by_name() {
        let mesh = Mesh::uniform(0.0, 0.0, 1.0, 1.0, 2, 2).unwrap();
        let mut d = Domain::rect(1.0, 1.0);
        d.holes.push(hole(
            "hole[3]",
            Shape::Circle {
                center: [0.5, 0.5],
                radius: -1.0,
            },
        ));
        let e = FictitiousDomain::new(&mesh, &d, 2, 1e-3).unwrap_err();
        assert!(e.to_string().contains("hole[3].radius"), "{e}");
        d.holes[0].shape = Shape::Rect {
            min: [-1.0, -1.0],
            max: [2.0, 2.0],
        };
        d.holes[0].name = "notch[1]".into();
        let e = FictitiousDomain::new(&mesh, &d, 2, 1e-3).unwrap_err();
        assert!(e.to_string().contains("notch[1]"), "{e}");
        d.holes[0].shape = Shape::Polygon(vec![[0.0, 0.0], [1.0, 1.0], [f64::NAN, 0.0]]);
        let e = FictitiousDomain::new(&mesh, &d, 2, 1e-3).unwrap_err();
        assert!(e.to_string().contains("notch[1].points"), "{e}");
        // crossing edges, non-zero signed area
        d.holes[0].shape = Shape::Polygon(vec![
            [0.1, 0.1],
            [0.9, 0.1],
            [0.9, 0.9],
            [0.5, 0.0],
            [0.1, 0.9],
        ]);
        let e = FictitiousDomain::new(&mesh, &d, 2, 1e-3).unwrap_err();
        assert!(e.to_string().contains("no crossing edges"), "{e}");
        assert!(
            FictitiousDomain::new(&mesh, &Domain::rect(1.0, 1.0), 2, 1e-3)
                .unwrap()
                .is_none()
        );
    }
}
