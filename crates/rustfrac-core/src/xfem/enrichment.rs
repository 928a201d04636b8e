//! The enrichment (paper eqs. 2-3, 15-19): which nodes carry the shifted Heaviside function and
//! which the four shifted branch functions, and the branch functions themselves (eq. 2).
//!
//! * Tip elements: the elements whose closed rectangle contains a tip. Their nodes (plus, with
//!   `fixed_area_radius = Some(R)`, every node within R of the tip: Laborde et al. 2005) carry the
//!   four shifted branch functions N_I (F_j(x) - F_j(x_I)) of that tip (8 dofs per node and tip).
//! * Split elements: elements crossed by the crack (the polyline meets the closed rectangle) that
//!   are not tip elements and whose nodes do not all have the same H. Their nodes carry the shifted
//!   Heaviside function N_I (H(x) - H(x_I)) (2 dofs per node), except tip-enriched nodes.
//! * Small-area rule: a Heaviside node is dropped when min(A+, A-) / A < `area_threshold`, with A the
//!   area of its support (the elements containing it) and A+/A- the parts on either side of the
//!   crack (computed exactly by clipping each element of the support with the line of the crack
//!   segment that runs longest through it; exact for straight cracks, approximate where a kink lies
//!   inside an element). The same fraction is also measured with the quadrature weights of the
//!   rule each support element uses (sub-quads do not follow the crack, so a sliver without a
//!   Gauss point on one side would give a zero stiffness column), and the smaller of the two
//!   fractions is compared. Such a node's enrichment is nearly (or exactly, e.g. for a crack
//!   running along a grid line) linearly dependent on the standard functions and would make the
//!   matrix singular or badly conditioned. Default threshold: [`DEFAULT_AREA_THRESHOLD`] = 1e-4
//!   (Dolbow 1999; Moes et al. 1999 use the same order). With holes the areas are the support's
//!   material ([`crate::fe::fictitious`]): a cut element's material part measured by the rule the
//!   model integrates it with, on either side of the crack.
//! * Several cracks (module [`crate::xfem`], "Several cracks"): split elements, Heaviside
//!   candidates (tip nodes of the crack's own tips excluded) and the small-area rule are evaluated
//!   for each crack separately; every tip has its own branch functions (a node near two tips
//!   carries both sets). Tips of different cracks in one element are refused.
//!
//! The dof numbering of these sets and the enriched basis of each element are the model's
//! ([`crate::xfem::XfemModel`]).

use super::crack::{on_face, Crack, Tip};
use super::integration::{RuleKind, Rules};
use crate::error::{Error, Result};
use crate::fe::fictitious::{ElementKind, FictitiousDomain};
use crate::fe::mesh::Mesh;
use crate::geometry::{norm, positive_area, seg_box, sub};
use crate::problem::parse::crack_name;
use std::collections::HashMap;

/// Default small-area threshold (see the module documentation).
pub use crate::problem::schema::DEFAULT_AREA_THRESHOLD;

/// Branch functions of eq. (2) and their global gradients at `x` for a tip.
#[inline]
pub fn branch_functions(tip: &Tip, x: [f64; 2]) -> ([f64; 4], [[f64; 2]; 4]) {
    branch_functions_snapped(tip, x, 0.0)
}

/// [`branch_functions`] with the crack faces' side fixed the way [`Crack::heaviside`] fixes it:
/// a point behind the tip within `snap` of the tip's line lies on the H = -1 face (theta = -pi
/// for the last polyline point's tip, +pi for a tip at `points[0]`, whose frame is reversed).
/// Without this a node or a Gauss point lying on the crack (a crack through nodes, a sub-quad
/// point on an element diagonal) takes theta = +pi or -pi by the rounding of its coordinates,
/// i.e. the branch functions of the wrong face: K_I was off by 2.6 % and K_II by 7 % for a 45
/// degree crack through nodes (tests/suite/xfem_extremes.rs).
#[inline]
pub fn branch_functions_snapped(tip: &Tip, x: [f64; 2], snap: f64) -> ([f64; 4], [[f64; 2]; 4]) {
    let d = sub(x, tip.pos);
    let (c, s) = (tip.dir[0], tip.dir[1]);
    let [xl, yl] = on_face(tip, [c * d[0] + s * d[1], -s * d[0] + c * d[1]], snap);
    let r = xl.hypot(yl);
    let th = yl.atan2(xl);
    let sr = r.sqrt();
    let (s2, c2) = (0.5 * th).sin_cos();
    let (st, ct) = th.sin_cos();
    let f = [sr * s2, sr * c2, sr * s2 * st, sr * c2 * st];
    if r == 0.0 {
        return (f, [[0.0; 2]; 4]);
    }
    let (s32, c32) = (1.5 * th).sin_cos();
    let a = 0.5 / sr;
    let gl = [
        [-a * s2, a * c2],
        [a * c2, a * s2],
        [-a * s32 * st, a * (s2 + s32 * ct)],
        [-a * c32 * st, a * (c2 + c32 * ct)],
    ];
    let g = gl.map(|v| [v[0] * c - v[1] * s, v[0] * s + v[1] * c]);
    (f, g)
}

/// Grid lookups on the structured mesh with the geometric tolerance of the enrichment
/// (1e-10 x the smallest spacing).
struct Cells<'a> {
    mesh: &'a Mesh,
    nx: usize,
    tol: f64,
}

impl<'a> Cells<'a> {
    fn new(mesh: &'a Mesh) -> Self {
        Self {
            mesh,
            nx: mesh.nx(),
            tol: 1e-10 * mesh.min_spacing(),
        }
    }

    /// The closed rectangle [lo, hi] of element `e`.
    fn ebox(&self, e: usize) -> ([f64; 2], [f64; 2]) {
        let mesh = self.mesh;
        let (i, j) = (e % self.nx, e / self.nx);
        ([mesh.xs[i], mesh.ys[j]], [mesh.xs[i + 1], mesh.ys[j + 1]])
    }

    /// Index range of grid cells overlapping [lo, hi].
    fn range(&self, lines: &[f64], lo: f64, hi: f64) -> (usize, usize) {
        let tol = self.tol;
        let n = lines.len() - 1;
        let a = lines
            .partition_point(|&l| l < lo - tol)
            .saturating_sub(1)
            .min(n - 1);
        let b = lines.partition_point(|&l| l <= hi + tol).min(n);
        (a, b.max(a + 1))
    }
}

/// The elements containing node `n` (its support), in the order (i-1, j-1), (i, j-1), (i-1, j),
/// (i, j) of the grid indices (i, j) of the node.
pub(super) fn node_support(mesh: &Mesh, n: usize) -> impl Iterator<Item = usize> + '_ {
    let (nx, ny) = (mesh.nx(), mesh.ny());
    let (i, j) = (n % (nx + 1), n / (nx + 1));
    [j.wrapping_sub(1), j]
        .into_iter()
        .flat_map(move |jj| [i.wrapping_sub(1), i].into_iter().map(move |ii| (ii, jj)))
        .filter(move |&(ii, jj)| ii < nx && jj < ny)
        .map(move |(ii, jj)| mesh.element(ii, jj))
}

/// The enrichment sets of a model (see the module documentation), per crack and per tip.
#[derive(Debug)]
pub(super) struct EnrichmentSets {
    /// elements containing each tip
    pub(super) tip_elements: Vec<Vec<usize>>,
    /// branch-enriched nodes of each tip (sorted)
    pub(super) tip_nodes: Vec<Vec<usize>>,
    /// the tips enriching each branch-enriched node (increasing)
    pub(super) tips_of_node: HashMap<usize, Vec<usize>>,
    /// per crack: the elements it crosses (closure), with (segment, length) of the longest
    /// segment through each
    pub(super) crossed: Vec<HashMap<usize, (usize, f64)>>,
    /// split elements of each crack (crossed by it, not containing one of its tips)
    pub(super) split_elements: Vec<Vec<usize>>,
    /// Heaviside-enriched nodes of each crack (sorted)
    pub(super) heaviside_nodes: Vec<Vec<usize>>,
    /// nodes removed from each crack's Heaviside set by the small-area rule
    pub(super) dropped_nodes: Vec<Vec<usize>>,
}

impl EnrichmentSets {
    /// The sets for the given cracks and tips (global tip order, `tip_crack` the crack of each);
    /// `rules` are the model's quadrature rules (for the quadrature side of the small-area rule),
    /// `holes` the fictitious domain (the small-area rule then measures the material only).
    /// Refuses tips of different cracks in one element.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn new(
        mesh: &Mesh,
        cracks: &[Crack],
        tips: &[Tip],
        tip_crack: &[usize],
        fixed_area_radius: Option<f64>,
        area_threshold: f64,
        rules: &Rules,
        holes: Option<&FictitiousDomain>,
    ) -> Result<Self> {
        let cells = Cells::new(mesh);
        let (tip_elements, tip_nodes): (Vec<_>, Vec<_>) = tips
            .iter()
            .map(|tip| tip_sets(&cells, tip, fixed_area_radius))
            .unzip();
        check_tips_apart(tips, tip_crack, &tip_elements)?;
        let mut tips_of_node: HashMap<usize, Vec<usize>> = HashMap::new();
        for (t, nodes) in tip_nodes.iter().enumerate() {
            for &n in nodes {
                tips_of_node.entry(n).or_default().push(t);
            }
        }
        let crossed = cracks.iter().map(|c| crossed_elements(&cells, c)).collect();
        let n_cracks = cracks.len();
        let mut sets = Self {
            tip_elements,
            tip_nodes,
            tips_of_node,
            crossed,
            split_elements: Vec::with_capacity(n_cracks),
            heaviside_nodes: Vec::with_capacity(n_cracks),
            dropped_nodes: Vec::with_capacity(n_cracks),
        };
        for (c, crack) in cracks.iter().enumerate() {
            let own_tip = |t: usize| tip_crack[t] == c;
            let split = sets.split_elements_of(mesh, c, crack, &own_tip);
            let cand = sets.heaviside_candidates(mesh, &split, &own_tip);
            let (hn, dn) =
                sets.small_area_rule(&cells, (c, crack), &cand, area_threshold, rules, holes);
            sets.split_elements.push(split);
            sets.heaviside_nodes.push(hn);
            sets.dropped_nodes.push(dn);
        }
        Ok(sets)
    }

    /// Whether element `e` contains a tip (of any crack).
    pub(super) fn is_tip_element(&self, e: usize) -> bool {
        self.tip_elements
            .iter()
            .any(|v: &Vec<usize>| v.contains(&e))
    }

    /// The number of cracks crossing element `e`.
    pub(super) fn n_crossing(&self, e: usize) -> usize {
        self.crossed.iter().filter(|m| m.contains_key(&e)).count()
    }

    /// The sub-quad rule a crossed element will use.
    fn crossed_rule<'r>(&self, rules: &'r Rules, e: usize) -> &'r [crate::fe::quadrature::QPoint] {
        rules.get(self.crossed_kind(e))
    }

    /// The rule kind of a crossed element `e`.
    fn crossed_kind(&self, e: usize) -> RuleKind {
        RuleKind::select(self.is_tip_element(e), true, self.n_crossing(e) >= 2)
    }

    /// The split elements of crack `c`: crossed by it, not a tip element of its own tips, with
    /// nodes of both signs of H (increasing).
    fn split_elements_of(
        &self,
        mesh: &Mesh,
        c: usize,
        crack: &Crack,
        own_tip: &dyn Fn(usize) -> bool,
    ) -> Vec<usize> {
        let is_own_tip_elem = |e: usize| {
            (0..self.tip_elements.len()).any(|t| own_tip(t) && self.tip_elements[t].contains(&e))
        };
        let mut node_h: HashMap<usize, f64> = HashMap::new();
        let mut hval = |n: usize| -> f64 {
            *node_h
                .entry(n)
                .or_insert_with(|| crack.heaviside(mesh.coords[n]))
        };
        let mut split = Vec::new();
        let mut crossed_list: Vec<usize> = self.crossed[c].keys().copied().collect();
        crossed_list.sort_unstable();
        for &e in &crossed_list {
            if is_own_tip_elem(e) {
                continue;
            }
            let hs = mesh.elements[e].map(&mut hval);
            if hs.iter().any(|&h| h != hs[0]) {
                split.push(e);
            }
        }
        split
    }

    /// The Heaviside candidates of a crack: the nodes of its split elements that are not
    /// branch-enriched for one of its own tips (sorted, each once).
    fn heaviside_candidates(
        &self,
        mesh: &Mesh,
        split: &[usize],
        own_tip: &dyn Fn(usize) -> bool,
    ) -> Vec<usize> {
        let own_tip_node = |n: usize| {
            self.tips_of_node
                .get(&n)
                .is_some_and(|ts| ts.iter().any(|&t| own_tip(t)))
        };
        let mut cand: Vec<usize> = split
            .iter()
            .flat_map(|&e| mesh.elements[e])
            .filter(|&n| !own_tip_node(n))
            .collect();
        cand.sort_unstable();
        cand.dedup();
        cand
    }

    /// The small-area rule on the candidates of crack `c`: (kept Heaviside nodes, dropped nodes).
    /// With holes, a cut element's areas are those of its material part, both measures (the
    /// geometric and the quadrature one) taken with its material rule, the one the model
    /// integrates it with ([`crate::xfem::integration`]); a void element's are 0.
    fn small_area_rule(
        &self,
        cells: &Cells,
        (c, crack): (usize, &Crack),
        cand: &[usize],
        area_threshold: f64,
        rules: &Rules,
        holes: Option<&FictitiousDomain>,
    ) -> (Vec<usize>, Vec<usize>) {
        let mesh = cells.mesh;
        let crossed = &self.crossed[c];
        // per element: (geometric positive area, area, positive area seen by the quadrature
        // rule the element will use)
        let mut pos_area: HashMap<usize, (f64, f64, f64)> = HashMap::new();
        let mut elem_areas = |e: usize| -> (f64, f64, f64) {
            *pos_area.entry(e).or_insert_with(|| {
                let (lo, hi) = cells.ebox(e);
                let area = (hi[0] - lo[0]) * (hi[1] - lo[1]);
                if let Some(fd) = holes.filter(|fd| fd.kind(e) != ElementKind::Material) {
                    let kind = if crossed.contains_key(&e) {
                        self.crossed_kind(e)
                    } else {
                        RuleKind::Gauss
                    };
                    let rule = match kind {
                        RuleKind::Gauss => fd.rule(e, &[]).to_vec(),
                        k => fd.subcell_rule(e, rules.nsub(k)).unwrap_or_default(),
                    };
                    let (mut ap, mut at) = (0.0, 0.0);
                    for q in &rule {
                        let x = [
                            lo[0] + 0.5 * (q.xi + 1.0) * (hi[0] - lo[0]),
                            lo[1] + 0.5 * (q.eta + 1.0) * (hi[1] - lo[1]),
                        ];
                        let w = 0.25 * q.w * area;
                        at += w;
                        if crack.heaviside(x) > 0.0 {
                            ap += w;
                        }
                    }
                    return (ap, at, ap);
                }
                let Some(&(k, _)) = crossed.get(&e) else {
                    let c = [0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1])];
                    let ap = if crack.heaviside(c) > 0.0 { area } else { 0.0 };
                    return (ap, area, ap);
                };
                let poly = [lo, [hi[0], lo[1]], hi, [lo[0], hi[1]]];
                let ap = positive_area(&poly, crack.points[k], crack.points[k + 1]);
                let mut aq = 0.0;
                for q in self.crossed_rule(rules, e).iter() {
                    let x = [
                        lo[0] + 0.5 * (q.xi + 1.0) * (hi[0] - lo[0]),
                        lo[1] + 0.5 * (q.eta + 1.0) * (hi[1] - lo[1]),
                    ];
                    if crack.heaviside(x) > 0.0 {
                        aq += 0.25 * q.w * area;
                    }
                }
                (ap, area, aq)
            })
        };
        let mut hn = Vec::new();
        let mut dn = Vec::new();
        for &n in cand {
            let (mut ap, mut at, mut aq) = (0.0, 0.0, 0.0);
            for e in node_support(mesh, n) {
                let (a, t, q) = elem_areas(e);
                ap += a;
                at += t;
                aq += q;
            }
            // with holes `at` is the support's material area (0: no material, dropped)
            let frac = if at > 0.0 {
                (ap.min(at - ap) / at).min(aq.min(at - aq) / at)
            } else {
                0.0
            };
            if frac > area_threshold && frac > 1e-12 {
                hn.push(n);
            } else {
                dn.push(n);
            }
        }
        (hn, dn)
    }
}

/// The tip elements of a tip and its branch-enriched nodes (the tip elements' nodes, plus those
/// within the fixed-area radius; sorted, each once).
fn tip_sets(cells: &Cells, tip: &Tip, fixed_area_radius: Option<f64>) -> (Vec<usize>, Vec<usize>) {
    let (mesh, tol) = (cells.mesh, cells.tol);
    let (ia, ib) = cells.range(&mesh.xs, tip.pos[0], tip.pos[0]);
    let (ja, jb) = cells.range(&mesh.ys, tip.pos[1], tip.pos[1]);
    let mut els = Vec::new();
    for j in ja..jb {
        for i in ia..ib {
            let e = mesh.element(i, j);
            let (lo, hi) = cells.ebox(e);
            if tip.pos[0] >= lo[0] - tol
                && tip.pos[0] <= hi[0] + tol
                && tip.pos[1] >= lo[1] - tol
                && tip.pos[1] <= hi[1] + tol
            {
                els.push(e);
            }
        }
    }
    let mut nodes: Vec<usize> = els.iter().flat_map(|&e| mesh.elements[e]).collect();
    if let Some(r) = fixed_area_radius {
        let (ia, ib) = cells.range(&mesh.xs, tip.pos[0] - r, tip.pos[0] + r);
        let (ja, jb) = cells.range(&mesh.ys, tip.pos[1] - r, tip.pos[1] + r);
        for j in ja..=jb {
            for i in ia..=ib {
                let n = mesh.node(i, j);
                if norm(sub(mesh.coords[n], tip.pos)) <= r {
                    nodes.push(n);
                }
            }
        }
    }
    nodes.sort_unstable();
    nodes.dedup();
    (els, nodes)
}

/// What a refusal of two cracks' tips in one element expects (the growth loop stops on it:
/// `cracks_meet`).
pub(crate) const TIPS_APART: &str =
    "the tips of different cracks in different elements (one element cannot resolve two \
     crack-tip singularities, and the SIF domain of either tip would contain the other; refine \
     the mesh)";

/// Refuses two tips of different cracks in one element (documented limitation); the error names
/// the first of the two cracks by its scene key.
fn check_tips_apart(tips: &[Tip], tip_crack: &[usize], tip_elements: &[Vec<usize>]) -> Result<()> {
    for t1 in 0..tips.len() {
        for t2 in t1 + 1..tips.len() {
            if tip_crack[t1] == tip_crack[t2] {
                continue;
            }
            if let Some(e) = tip_elements[t1]
                .iter()
                .find(|e| tip_elements[t2].contains(e))
            {
                return Err(Error::invalid(
                    &crack_name(tip_crack[t1]),
                    TIPS_APART,
                    format!(
                        "tip {:?} of {} and tip {:?} of {} both in element {e}",
                        tips[t1].pos,
                        crack_name(tip_crack[t1]),
                        tips[t2].pos,
                        crack_name(tip_crack[t2])
                    ),
                ));
            }
        }
    }
    Ok(())
}

/// The elements a crack crosses (closure), each with (segment, length) of the longest segment
/// through it.
fn crossed_elements(cells: &Cells, crack: &Crack) -> HashMap<usize, (usize, f64)> {
    let mesh = cells.mesh;
    let mut crossed: HashMap<usize, (usize, f64)> = HashMap::new();
    for (k, s) in crack.points.windows(2).enumerate() {
        let (ia, ib) = cells.range(&mesh.xs, s[0][0].min(s[1][0]), s[0][0].max(s[1][0]));
        let (ja, jb) = cells.range(&mesh.ys, s[0][1].min(s[1][1]), s[0][1].max(s[1][1]));
        let len = norm(sub(s[1], s[0]));
        for j in ja..jb {
            for i in ia..ib {
                let e = mesh.element(i, j);
                let (lo, hi) = cells.ebox(e);
                if let Some((t0, t1)) = seg_box(s[0], s[1], lo, hi, cells.tol) {
                    let l = (t1 - t0) * len;
                    let ent = crossed.entry(e).or_insert((k, -1.0));
                    if l > ent.1 {
                        *ent = (k, l);
                    }
                }
            }
        }
    }
    crossed
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::unit;

    #[test]
    fn branch_gradients_match_finite_differences() {
        let tip = Tip {
            pos: [0.3, -0.2],
            dir: unit([0.8, 0.6]),
            at_start: false,
        };
        for &x in &[[0.5, 0.1], [0.0, -0.5], [0.35, 0.4], [-0.3, -0.3]] {
            let (_, g) = branch_functions(&tip, x);
            for j in 0..2 {
                let h = 1e-7;
                let (mut xp, mut xm) = (x, x);
                xp[j] += h;
                xm[j] -= h;
                let (fp, _) = branch_functions(&tip, xp);
                let (fm, _) = branch_functions(&tip, xm);
                for k in 0..4 {
                    let fd = (fp[k] - fm[k]) / (2.0 * h);
                    assert!(
                        (fd - g[k][j]).abs() < 1e-6,
                        "F{k} d{j}: {fd} vs {}",
                        g[k][j]
                    );
                }
            }
        }
    }
}
