//! Holes and notches of the PD model: the *centre rule* and bonds through holes.
//!
//! * A grid node is material iff its cell centre (the node itself: each node carries the
//!   dx x dx cell around it) is, `Domain::level_set(x) >= 0`. A cut cell is all material or all
//!   void, so the boundary of the hole moves by up to dx / 2 and the volume of the material by
//!   O(dx) per unit length of the hole's boundary: the error of the rule is O(dx) (the default,
//!   `pd.hole_volumes = "centre"`).
//! * `pd.hole_volumes = "exact"` ([`HoleVolumes::Exact`]) keeps the centre rule for which nodes
//!   exist but gives a material node whose cell a hole cuts the volume of the cell's material
//!   part, f_i dx^2 t ([`cell_material_fractions`]: exact for a circle or an axis-aligned
//!   rectangle, sub-sampled on 64 x 64 points for polygons and cells that several holes cut).
//!   A bond's stiffness c beta V_i V_j / |xi| (eq. 46) then takes f_i f_j (its `beta` is scaled
//!   by it; PD holes only: FEM holes of CCM-PD are the fictitious domain's); loads on regions keep
//!   the full cell volume. Measured on Kirsch's plate
//!   (tests/suite/pd_general.rs, `pd_hole_volumes_centre_vs_exact_against_kirsch`; w = 6, a = 0.5,
//!   m = 3) at dx = 0.1 / 0.05 / 0.025: displacement differences across the hole, centre
//!   3.38 / 2.91 / 2.66 %, exact 4.02 / 3.23 / 2.80 %; hoop strain at the hole's top (the node
//!   row through it, whose cells the hole cuts), centre -24.0 / -22.4 / -19.2 %, exact
//!   +1.8 / +6.2 / +6.8 %; at r = 1.2 a, centre -0.3 / +0.3 / +2.6 %, exact +12.8 / +8.2 /
//!   +5.1 %. The exact volumes fix the strain of the cut cells but soften the ring around them:
//!   the centre rule's volume errors cancel on average (cut cells whose centre is material carry
//!   void, those whose centre is void carry material), the exact rule drops the material of the
//!   removed cut cells. Neither is better everywhere; the default stays `centre`.
//! * A removed node keeps its place in the numbering (node (i, j) = j (nx + 1) + i) but has no
//!   bonds, no element, no load and no region; both its dofs are fixed to zero, so it takes no
//!   part in any equation, response or damage index (it is left out of `pd_nodes`).
//! * A bond whose segment passes through a hole ([`crate::problem::Shape::cuts_segment`]: for a
//!   circle, the segment's distance to the centre below the radius; rectangles and polygons, the
//!   segment crossing the interior) does not exist, even between two material nodes: the hole
//!   screens the interaction, as a pre-crack does.
//!
//! Holes in the FEM part of CCM-PD (a hole whose bounding box lies in no PD rectangle, a *FEM
//! hole*) are a fictitious domain on the grid's Q4 elements, the rule of FEM and XFEM
//! ([`FictitiousDomain`], `fe/fictitious.rs`): an element with FEM nodes only is integrated over
//! its material part (cut), dropped (void) or kept whole; a FEM node is removed when its support
//! holds no material ([`FictitiousDomain::is_removed`]), not by the centre rule.
//! A FEM hole cutting a hybrid element (PD and FEM nodes: the band at a PD rectangle's boundary)
//! is refused: its PD rows would need partial volumes, its FEM rows a cut element of mixed
//! nodes. Holes inside a PD rectangle keep the centre rule (bit for bit as before).

use crate::error::{Error, Result};
use crate::fe::fictitious::{ElementKind, FictitiousDomain, DEFAULT_MIN_SUPPORT_FRACTION};
use crate::pd::{rect_disc_area, Bond, Grid};
use crate::problem::{Domain, Hole, HoleVolumes, Shape};

/// Is the hole's bounding box inside one of the PD rectangles (a PD hole, the centre rule)?
pub(crate) fn in_pd_rectangle(h: &Hole, regions: &[[f64; 4]]) -> bool {
    let b = h.shape.bounding_box();
    regions
        .iter()
        .any(|r| r[0] <= b[0] && b[2] <= r[2] && r[1] <= b[1] && b[3] <= r[3])
}

/// The FEM part's holes as a fictitious domain on the grid's elements (None without FEM holes:
/// pure PD, or every hole in a PD rectangle). Element e = j nx + i and node numbering are the
/// grid's.
pub(super) fn fem_domain(
    d: &Domain,
    grid: &Grid,
    regions: &[[f64; 4]],
    all_pd: bool,
) -> Result<Option<FictitiousDomain>> {
    let holes: Vec<Hole> = d
        .holes
        .iter()
        .filter(|h| !all_pd && !in_pd_rectangle(h, regions))
        .cloned()
        .collect();
    if holes.is_empty() {
        return Ok(None);
    }
    let mesh = super::graded::fe_mesh(grid)?;
    let fem = Domain {
        width: d.width,
        height: d.height,
        holes,
    };
    FictitiousDomain::new(&mesh, &fem, 2, DEFAULT_MIN_SUPPORT_FRACTION)
}

/// The material flags with FEM holes: a FEM node is material iff its support holds material and no PD hole holds it by the centre rule; PD nodes keep the centre rule (`material`).
pub(super) fn fem_material(
    d: &Domain,
    grid: &Grid,
    fd: &FictitiousDomain,
    is_pd: &[bool],
    regions: &[[f64; 4]],
    material: &mut [bool],
) {
    for (n, m) in material.iter_mut().enumerate() {
        if is_pd[n] {
            continue;
        }
        let q = grid.xy(n);
        *m = !fd.is_removed(n)
            && d.holes
                .iter()
                .filter(|h| in_pd_rectangle(h, regions))
                .all(|h| h.shape.level_set(q) >= 0.0);
    }
}

/// How FEM holes meet a hybrid element `e` (nodes `nodes`): Ok when they leave it whole
/// (then the centre rule of the PD holes decides, as before), refused naming the hole otherwise.
pub(super) fn check_hybrid(
    fd: &FictitiousDomain,
    grid: &Grid,
    e: usize,
    nodes: &[usize; 4],
) -> Result<()> {
    if fd.kind(e) == ElementKind::Material {
        return Ok(());
    }
    let (lo, hi) = (grid.xy(nodes[0]), grid.xy(nodes[2]));
    let c = [0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1])];
    let hd = 0.5 * (hi[0] - lo[0]).hypot(hi[1] - lo[1]);
    let name = fd
        .domain
        .holes
        .iter()
        .find(|h| h.shape.level_set(c) < hd)
        .map_or("hole", |h| h.name.as_str());
    Err(Error::invalid(
        name,
        "for method 'ccm_pd' a hole or notch in the FEM part that cuts no hybrid element (the \
         elements with PD and FEM nodes at a PD rectangle's boundary), or one inside a PD \
         rectangle; move the hole or enlarge the PD rectangle around it",
        format!("it cuts the hybrid element [{:?}, {:?}]", lo, hi),
    ))
}

/// Sub-samples per side of a cell for the material fraction of cells without a closed form.
const SUBSAMPLES: usize = 64;

/// The material fraction of every node's cell [x - dx/2, x + dx/2]^2 (1 for cells no hole cuts;
/// the plate's outline does not count: edge nodes keep their full cell, as without holes).
pub(super) fn cell_material_fractions(d: &Domain, grid: &Grid) -> Vec<f64> {
    let h = 0.5 * grid.dx;
    (0..grid.n_nodes())
        .map(|n| {
            let [x, y] = grid.xy(n);
            let (lo, hi) = ([x - h, y - h], [x + h, y + h]);
            // holes that may overlap the cell (bounding-circle test)
            let near: Vec<&Shape> = d
                .holes
                .iter()
                .map(|hl| &hl.shape)
                .filter(|sh| sh.level_set([x, y]) < h * std::f64::consts::SQRT_2)
                .collect();
            let area = grid.dx * grid.dx;
            match near.as_slice() {
                [] => 1.0,
                [Shape::Circle { center, radius }] => {
                    let c = *center;
                    let inside = rect_disc_area(
                        lo[0] - c[0],
                        hi[0] - c[0],
                        lo[1] - c[1],
                        hi[1] - c[1],
                        *radius,
                    );
                    (1.0 - inside / area).clamp(0.0, 1.0)
                }
                [Shape::Rect { min, max }] => {
                    let ox = (hi[0].min(max[0]) - lo[0].max(min[0])).max(0.0);
                    let oy = (hi[1].min(max[1]) - lo[1].max(min[1])).max(0.0);
                    (1.0 - ox * oy / area).clamp(0.0, 1.0)
                }
                shapes => {
                    let k = SUBSAMPLES;
                    let mut inside = 0usize;
                    for a in 0..k {
                        for b in 0..k {
                            let p = [
                                lo[0] + (a as f64 + 0.5) / k as f64 * grid.dx,
                                lo[1] + (b as f64 + 0.5) / k as f64 * grid.dx,
                            ];
                            if shapes.iter().any(|sh| sh.level_set(p) < 0.0) {
                                inside += 1;
                            }
                        }
                    }
                    1.0 - inside as f64 / (k * k) as f64
                }
            }
        })
        .collect()
}

/// Scales every bond's `beta` by the material fractions f_i f_j of its nodes' cells
/// ([`HoleVolumes::Exact`]; nothing for [`HoleVolumes::Centre`] or without PD holes: FEM holes
/// of CCM-PD are the fictitious domain's, see [`fem_domain`]). A material node's fraction is
/// kept above 1 / SUBSAMPLES^2 (its centre is material).
pub(super) fn apply_hole_volumes(
    d: &Domain,
    grid: &Grid,
    (rule, regions, all_pd): (HoleVolumes, &[[f64; 4]], bool),
    bonds: &mut [Bond],
) {
    let pd_holes = Domain {
        width: d.width,
        height: d.height,
        holes: d
            .holes
            .iter()
            .filter(|h| all_pd || in_pd_rectangle(h, regions))
            .cloned()
            .collect(),
    };
    if rule == HoleVolumes::Centre || pd_holes.holes.is_empty() {
        return;
    }
    let floor = 1.0 / (SUBSAMPLES * SUBSAMPLES) as f64;
    let f: Vec<f64> = cell_material_fractions(&pd_holes, grid)
        .into_iter()
        .map(|v| v.max(floor))
        .collect();
    for b in bonds {
        b.beta *= f[b.i as usize] * f[b.j as usize];
    }
}

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
