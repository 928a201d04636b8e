//! Stress intensity factors by the domain form of the interaction integral (paper section 2.1.3,
//! eqs. 27-33 and 36), and of the J-integral.
//!
//! Everything here works in the crack-tip frame (x~1 along the crack, pointing ahead of the tip,
//! x~2 normal to it). At each quadrature point of the integration domain the model supplies the
//! tip-frame position, the tip-frame displacement gradient of the computed field and the
//! tip-frame gradient of the weight function q (eq. 29); [`DomainIntegral`] accumulates
//!
//! I = sum w [sigma_ij u^a_i,1 + sigma^a_ij u_i,1 - sigma^a_mn eps_mn delta_1j] q,j   (eqs. 27-28)
//! J = sum w [sigma_ij u_i,1 - 1/2 sigma_mn eps_mn delta_1j] q,j                     (eq. 33)
//!
//! and returns K_I = I(K^a = (1, 0)) E'/2, K_II = I(K^a = (0, 1)) E'/2 (eq. 31, with E' = E/(1-nu^2)
//! in plane strain and E in plane stress) and J from the SIFs (eq. 32). The auxiliary fields are
//! the Williams fields of [`crate::xfem::auxiliary`].
//!
//! The domain ([`XfemModel::sifs`]): the q-function of eq. (29) (q_I = 1 for nodes not farther
//! from the tip than r_I, with a relative tolerance of 1e-9); elements with mixed nodal q form the
//! domain and are integrated with their own rule (`nsub x nsub` sub-quads for standard elements).
//! The plate driver takes r_I = `r_i_factor` x the tip element's size sqrt(dx dy). Where the
//! domain reaches the plate boundary (a tip near an edge, or a short edge crack) it is clipped by
//! it, and the boundary term int_B F_j m_j q ds of the divergence theorem is added
//! ([`DomainIntegral::add_boundary`]), integrated along the boundary sides of the domain's
//! elements with a composite Gauss rule split at crack crossings and graded towards the tip.
//! Validated with the exact Williams field represented exactly by the enrichment: K to 2e-5 for
//! tips 0.01 .. 0.6 elements from an edge or a corner (0.28 .. 0.79 without the term), and on real
//! solutions against unclipped domains (0.7 %) and the energy release rate (1.7 %)
//! (tests/suite/xfem_extremes.rs).
//!
//! Holes and notches: a traction-free hole boundary inside the domain would add a boundary term
//! (the auxiliary traction is not zero there), so the domain keeps every hole out: [`XfemModel::sifs`]
//! refuses a radius a hole enters, [`XfemModel::sifs_clear_of_holes`] (the driver and growth)
//! shrinks it to [`XfemModel::hole_free_radius`], not below [`MIN_HOLE_FREE_RADIUS`] element
//! sizes. Measured (tests/suite/hole_validation.rs): a tip 0.6 from a hole of radius 0.5 on h = 0.25
//! (domain 1.67 elements) gives K_I within 0.80 % of a 4x finer mesh (its 2.5-element domain
//! clear of the hole; the 2x finer mesh is 0.37 % off it), and on one solution a domain shrunk
//! from 8 to 4.2 elements agrees with the 2.5-element one within 0.14 %.
//!
//! Several cracks: another crack entering the support of a tip's q-function would add face terms
//! the domain form lacks (the auxiliary field is traction-free on the tip's own crack only), so
//! such a radius is refused (`r_I`, [`XfemModel::other_crack_in_domain`]); growth stops with
//! status `cracks_meet` instead.

use super::auxiliary::williams_gradient;
use super::crack::{on_face, Crack, Tip};
use super::integration::RuleKind;
use super::model::{BasisBuf, EnrElement, XfemModel};
use crate::error::{check_positive, Error, Result};
use crate::fe::q4::stress;
use crate::geometry::{cross, norm, point_segment_distance, polyline_distance, seg_box, sub};
use crate::problem::parse::crack_name;
use crate::problem::Elastic;

/// The smallest q-radius, in tip-element sizes, that [`XfemModel::sifs_clear_of_holes`] shrinks
/// a SIF domain to so that no hole enters it. Measured on an edge crack (a = 1.1, h = 0.25;
/// tests/suite/hole_validation.rs, `xfem_sif_domain_radius_near_a_hole`), K_I against its value at the
/// default r_I = 2.5: +3.2 % at 1.0 and 1.25 element sizes (the domain is the ring of the tip
/// element's neighbours only), -31 % at 0.75, +0.94 % at 1.5, +0.14 % at 2, < 0.06 % at 3 and 4;
/// so a domain shrunk to 1.5 element sizes keeps K_I within 1 %.
pub const MIN_HOLE_FREE_RADIUS: f64 = 1.5;

/// SIFs and energy release rates from one integration domain.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DomainSifs {
    /// radius of the q-function domain
    pub radius: f64,
    pub k_i: f64,
    pub k_ii: f64,
    /// J from the SIFs, eq. (32)
    pub j_from_k: f64,
    /// J from its own domain integral, eq. (33)
    pub j_domain: f64,
}

/// Accumulator of the domain integrals over quadrature points (eq. 36).
pub struct DomainIntegral {
    mat: Elastic,
    d: [[f64; 3]; 3],
    i1: f64,
    i2: f64,
    j: f64,
}

#[inline]
fn stress_tensor(d: &[[f64; 3]; 3], g: &[[f64; 2]; 2]) -> [[f64; 2]; 2] {
    let eps = [g[0][0], g[1][1], g[0][1] + g[1][0]];
    let s = stress(d, &eps);
    [[s[0], s[2]], [s[2], s[1]]]
}

impl DomainIntegral {
    pub fn new(mat: &Elastic) -> Self {
        Self {
            mat: *mat,
            d: mat.d_matrix(),
            i1: 0.0,
            i2: 0.0,
            j: 0.0,
        }
    }

    /// The integrands of J and of the two interaction integrals at a point, as the vectors
    /// F_j = W delta_1j - sigma_ij u_i,1 (J, eq. 33) and
    /// F_j = W^int delta_1j - sigma_ij u^a_i,1 - sigma^a_ij u_i,1 (I with K^a = (1, 0) and
    /// (0, 1), eqs. 27-28), W^int = sigma^a_mn eps_mn, all in the tip frame.
    fn fluxes(&self, x: [f64; 2], g: &[[f64; 2]; 2]) -> [[f64; 2]; 3] {
        let s = stress_tensor(&self.d, g);
        let w_real = 0.5 * (s[0][0] * g[0][0] + s[1][1] * g[1][1] + s[0][1] * (g[0][1] + g[1][0]));
        let mut f = [[0.0; 2]; 3];
        for j in 0..2 {
            f[0][j] = -(s[0][j] * g[0][0] + s[1][j] * g[1][0]);
        }
        f[0][0] += w_real;
        for (mode, fm) in f[1..].iter_mut().enumerate() {
            let (k1, k2) = if mode == 0 { (1.0, 0.0) } else { (0.0, 1.0) };
            let ga = williams_gradient(&self.mat, k1, k2, x);
            let sa = stress_tensor(&self.d, &ga);
            // mixed energy sigma^a : eps (= sigma : eps^a)
            let w_int = sa[0][0] * g[0][0] + sa[1][1] * g[1][1] + sa[0][1] * (g[0][1] + g[1][0]);
            for j in 0..2 {
                fm[j] = -(s[0][j] * ga[0][0]
                    + s[1][j] * ga[1][0]
                    + sa[0][j] * g[0][0]
                    + sa[1][j] * g[1][0]);
            }
            fm[0] += w_int;
        }
        f
    }

    fn accumulate(&mut self, f: &[[f64; 2]; 3], v: [f64; 2], w: f64) {
        for (acc, fm) in [&mut self.j, &mut self.i1, &mut self.i2].into_iter().zip(f) {
            *acc += w * (fm[0] * v[0] + fm[1] * v[1]);
        }
    }

    /// Adds one area quadrature point: tip-frame position `x`, tip-frame displacement gradient
    /// `g[i][j] = du_i/dx_j`, tip-frame gradient of q, and weight `w` (Gauss weight x det J):
    /// the domain term -F_j q,j of eq. (36).
    pub fn add(&mut self, x: [f64; 2], g: &[[f64; 2]; 2], gq: [f64; 2], w: f64) {
        if gq[0] == 0.0 && gq[1] == 0.0 {
            return;
        }
        let f = self.fluxes(x, g);
        self.accumulate(&f, gq, -w);
    }

    /// Adds one point of the plate boundary inside the q-domain (the domain clipped by the
    /// boundary): the boundary term + F_j m_j q of the divergence theorem, with `m` the outward
    /// unit normal of the plate in the tip frame, `q` the weight function there and `w` the line
    /// quadrature weight. The domain form of eq. (36) assumes q = 0 on the plate boundary; where
    /// the domain reaches it, J = -int_A F_j q,j dA + int_B F_j m_j q ds (the crack faces add
    /// nothing: both fields are traction-free there and m_1 = 0).
    pub fn add_boundary(&mut self, x: [f64; 2], g: &[[f64; 2]; 2], m: [f64; 2], q: f64, w: f64) {
        if q == 0.0 {
            return;
        }
        let f = self.fluxes(x, g);
        self.accumulate(&f, m, w * q);
    }

    /// K_I, K_II (eq. 31), J from K (eq. 32) and the domain J (eq. 33).
    pub fn finish(&self, radius: f64) -> DomainSifs {
        let ep = self.mat.e_prime();
        let k_i = 0.5 * ep * self.i1;
        let k_ii = 0.5 * ep * self.i2;
        DomainSifs {
            radius,
            k_i,
            k_ii,
            j_from_k: (k_i * k_i + k_ii * k_ii) / ep,
            j_domain: self.j,
        }
    }
}

/// 5-point Gauss-Legendre rule on [-1, 1] for the boundary term of the SIFs.
const GAUSS5: ([f64; 5], [f64; 5]) = (
    [
        -0.906_179_845_938_664,
        -0.538_469_310_105_683,
        0.0,
        0.538_469_310_105_683,
        0.906_179_845_938_664,
    ],
    [
        0.236_926_885_056_189_1,
        0.478_628_670_499_366_47,
        0.568_888_888_888_888_9,
        0.478_628_670_499_366_47,
        0.236_926_885_056_189_1,
    ],
);

/// Pieces [s0, s1] of the parameter s in [-1, 1] of the boundary side pa-pb (x = pa + (s + 1)/2
/// (pb - pa)) for the line quadrature of the SIF boundary term: split where a crack crosses the
/// side (the fields jump there) and halved until each piece is no longer than its distance to the
/// tip (the integrand grows like 1/r towards the tip: a graded composite rule).
fn boundary_pieces(cracks: &[Crack], tip: [f64; 2], pa: [f64; 2], pb: [f64; 2]) -> Vec<(f64, f64)> {
    let d = sub(pb, pa);
    let len = norm(d);
    let at = |s: f64| {
        [
            pa[0] + 0.5 * (s + 1.0) * d[0],
            pa[1] + 0.5 * (s + 1.0) * d[1],
        ]
    };
    let mut cuts = vec![-1.0, 1.0];
    for crack in cracks {
        for seg in crack.points.windows(2) {
            let e = sub(seg[1], seg[0]);
            let den = cross(d, e);
            if den == 0.0 {
                continue;
            }
            // pa + t d = seg0 + r e
            let w = sub(seg[0], pa);
            let (t, r) = (cross(w, e) / den, cross(w, d) / den);
            if (0.0..=1.0).contains(&r) && t > 0.0 && t < 1.0 {
                cuts.push(2.0 * t - 1.0);
            }
        }
    }
    cuts.sort_by(f64::total_cmp);
    let mut out = Vec::new();
    let mut stack: Vec<(f64, f64, u32)> = cuts.windows(2).map(|c| (c[0], c[1], 0)).collect();
    while let Some((s0, s1, depth)) = stack.pop() {
        if s1 <= s0 {
            continue;
        }
        let piece = 0.5 * (s1 - s0) * len;
        if depth < 40 && piece > point_segment_distance(tip, at(s0), at(s1)) {
            let sm = 0.5 * (s0 + s1);
            stack.push((s0, sm, depth + 1));
            stack.push((sm, s1, depth + 1));
        } else {
            out.push((s0, s1));
        }
    }
    out
}

/// The q-function domain of one tip: evaluates the computed field in the tip frame and adds the
/// area and boundary terms of the elements to a [`DomainIntegral`].
struct QDomain<'a> {
    model: &'a XfemModel,
    u: &'a [f64],
    tip: Tip,
    snap: f64,
}

impl QDomain<'_> {
    /// To the tip frame: x~ = R (x - tip), R = [[c, s], [-s, c]].
    #[inline]
    fn rot(&self, v: [f64; 2]) -> [f64; 2] {
        let (c, s) = (self.tip.dir[0], self.tip.dir[1]);
        [c * v[0] + s * v[1], -s * v[0] + c * v[1]]
    }

    /// Tip-frame position (on the H = -1 face for points on the crack: the auxiliary fields are
    /// discontinuous across it too), tip-frame displacement gradient G~ = R G R^T, and the global
    /// basis gradients in `b` at (xi, eta) of element e; plus det J.
    fn field(
        &self,
        e: usize,
        en: Option<&EnrElement>,
        dofs: &[usize],
        xi: f64,
        eta: f64,
        b: &mut BasisBuf,
    ) -> ([f64; 2], [[f64; 2]; 2], f64) {
        let u = self.u;
        let (x, det) = self.model.basis(e, en, xi, eta, b);
        let mut g = [[0.0; 2]; 2];
        for (f, gf) in b.grads.iter().enumerate() {
            let (u1, u2) = (u[dofs[2 * f]], u[dofs[2 * f + 1]]);
            for jj in 0..2 {
                g[0][jj] += gf[jj] * u1;
                g[1][jj] += gf[jj] * u2;
            }
        }
        let rg = [self.rot([g[0][0], g[1][0]]), self.rot([g[0][1], g[1][1]])];
        let gl = [
            self.rot([rg[0][0], rg[1][0]]),
            self.rot([rg[0][1], rg[1][1]]),
        ];
        let tp = &self.tip;
        (on_face(tp, self.rot(sub(x, tp.pos)), self.snap), gl, det)
    }

    /// The domain term of element `e` with nodal q values `q` (mixed: the element is in the
    /// domain), with the element's own rule (`nsub x nsub` sub-quads for a standard element).
    fn add_area(
        &self,
        e: usize,
        en: Option<&EnrElement>,
        dofs: &[usize],
        q: [f64; 4],
        acc: &mut DomainIntegral,
        b: &mut BasisBuf,
    ) {
        let model = self.model;
        let rule = model.material_rule(e, en.map_or(RuleKind::Sub, |x| x.rule));
        for qp in rule.iter() {
            let (xl, gl, det) = self.field(e, en, dofs, qp.xi, qp.eta, b);
            let mut gq = [0.0; 2];
            for (gk, qk) in b.grads.iter().zip(q) {
                gq[0] += gk[0] * qk;
                gq[1] += gk[1] * qk;
            }
            acc.add(xl, &gl, self.rot(gq), qp.w * det);
        }
    }

    /// The boundary term along the sides of element `e` that lie on the plate boundary inside
    /// the domain.
    fn add_boundary(
        &self,
        e: usize,
        en: Option<&EnrElement>,
        dofs: &[usize],
        q: [f64; 4],
        acc: &mut DomainIntegral,
        b: &mut BasisBuf,
    ) {
        let mesh = &self.model.mesh;
        let (nx, ny) = (mesh.nx(), mesh.ny());
        let (i, j) = (e % nx, e / nx);
        let conn = mesh.elements[e];
        // sides of the element on the plate boundary inside the domain: (local nodes at
        // s = -1 and s = +1, the reference point of s, outward normal)
        let sides = [
            (j == 0, [0, 1], [[-1.0, -1.0], [1.0, -1.0]], [0.0, -1.0]),
            (i + 1 == nx, [1, 2], [[1.0, -1.0], [1.0, 1.0]], [1.0, 0.0]),
            (j + 1 == ny, [3, 2], [[-1.0, 1.0], [1.0, 1.0]], [0.0, 1.0]),
            (i == 0, [0, 3], [[-1.0, -1.0], [-1.0, 1.0]], [-1.0, 0.0]),
        ];
        for (on_b, [na, nb], [ra, rb], m) in sides {
            if !on_b || q[na] + q[nb] == 0.0 {
                continue;
            }
            let (pa, pb) = (mesh.coords[conn[na]], mesh.coords[conn[nb]]);
            let half = 0.5 * norm(sub(pb, pa));
            for (s0, s1) in boundary_pieces(&self.model.cracks, self.tip.pos, pa, pb) {
                for (gx, gw) in GAUSS5.0.iter().zip(GAUSS5.1) {
                    let t = 0.5 * (s0 + s1) + 0.5 * (s1 - s0) * gx;
                    let (xi, eta) = (
                        0.5 * (ra[0] + rb[0]) + 0.5 * (rb[0] - ra[0]) * t,
                        0.5 * (ra[1] + rb[1]) + 0.5 * (rb[1] - ra[1]) * t,
                    );
                    let (xl, gl, _) = self.field(e, en, dofs, xi, eta, b);
                    let qv = 0.5 * (1.0 - t) * q[na] + 0.5 * (1.0 + t) * q[nb];
                    acc.add_boundary(xl, &gl, self.rot(m), qv, gw * 0.5 * (s1 - s0) * half);
                }
            }
        }
    }
}

impl XfemModel {
    /// The first crack other than tip `tip`'s own that enters the support of its q-function
    /// (eq. 29) for q-radius `radius`: the elements with a node closer to the tip than `radius`.
    /// The domain form of the interaction integral assumes that the only crack faces inside the
    /// domain are those of the tip's own crack (the auxiliary Williams field is traction-free on
    /// those faces only); another crack there adds face terms the domain form lacks, so
    /// [`Self::sifs`] refuses such a radius.
    pub fn other_crack_in_domain(&self, tip: usize, radius: f64) -> Option<usize> {
        let mesh = &self.mesh;
        let tp = self.tips.get(tip)?.pos;
        let own = self.tip_crack[tip];
        let tol = 1e-10 * mesh.min_spacing();
        let nx = mesh.nx();
        let reach = radius
            + mesh.xs.windows(2).map(|v| v[1] - v[0]).fold(0.0, f64::max)
            + mesh.ys.windows(2).map(|v| v[1] - v[0]).fold(0.0, f64::max);
        for (c, crack) in self.cracks.iter().enumerate() {
            if c == own || polyline_distance(&crack.points, tp) > reach {
                continue;
            }
            for (e, conn) in mesh.elements.iter().enumerate() {
                let (i, j) = (e % nx, e / nx);
                let (lo, hi) = ([mesh.xs[i], mesh.ys[j]], [mesh.xs[i + 1], mesh.ys[j + 1]]);
                if lo[0] > tp[0] + reach
                    || hi[0] < tp[0] - reach
                    || lo[1] > tp[1] + reach
                    || hi[1] < tp[1] - reach
                    || !conn.iter().any(|&n| norm(sub(mesh.coords[n], tp)) < radius)
                {
                    continue;
                }
                if crack
                    .points
                    .windows(2)
                    .any(|s| seg_box(s[0], s[1], lo, hi, tol).is_some())
                {
                    return Some(c);
                }
            }
        }
        None
    }

    /// The hole or notch (its scene name) that enters the support of tip `tip`'s q-function for
    /// q-radius `radius` (an element with a node closer to the tip than `radius` that is not
    /// wholly material): the domain form assumes material throughout the domain, so
    /// [`Self::sifs`] refuses such a radius (a traction-free hole boundary inside the domain
    /// would add boundary terms, the auxiliary field not being traction-free there).
    pub fn hole_in_domain(&self, tip: usize, radius: f64) -> Option<String> {
        let fd = self.fictitious.as_ref()?;
        let tp = self.tips.get(tip)?.pos;
        let mesh = &self.mesh;
        for (e, conn) in mesh.elements.iter().enumerate() {
            if fd.kind(e) == crate::fe::ElementKind::Material
                || !conn.iter().any(|&n| norm(sub(mesh.coords[n], tp)) < radius)
            {
                continue;
            }
            let xy = mesh.element_coords(e);
            let c = [0.5 * (xy[0][0] + xy[2][0]), 0.5 * (xy[0][1] + xy[2][1])];
            return fd
                .domain
                .holes
                .iter()
                .min_by(|a, b| a.shape.level_set(c).total_cmp(&b.shape.level_set(c)))
                .map(|h| h.name.clone());
        }
        None
    }

    /// The largest q-radius not above `radius` whose domain no hole or notch enters (see
    /// [`Self::hole_in_domain`]): `radius` itself when none does, else just below the distance
    /// from the tip to the nearest node of an element that is not wholly material (that node and
    /// every node farther away get q = 0, so the element carries no q-gradient). The standard
    /// treatment of voids near a tip in XFEM growth (Moes et al. 1999; Sukumar et al. 2001: a
    /// domain that excludes the hole instead of the hole-boundary term the auxiliary traction
    /// would need); [`XfemModel::sifs_clear_of_holes`] refuses a radius shrunk below
    /// [`MIN_HOLE_FREE_RADIUS`].
    pub fn hole_free_radius(&self, tip: usize, radius: f64) -> f64 {
        let (Some(fd), Some(tp)) = (self.fictitious.as_ref(), self.tips.get(tip)) else {
            return radius;
        };
        let mesh = &self.mesh;
        let nearest = mesh
            .elements
            .iter()
            .enumerate()
            .filter(|(e, _)| fd.kind(*e) != crate::fe::ElementKind::Material)
            .flat_map(|(_, conn)| conn.iter().map(|&n| norm(sub(mesh.coords[n], tp.pos))))
            .fold(f64::INFINITY, f64::min);
        // q = 1 for nodes within radius (1 + 1e-9): stay clear of that tolerance
        radius.min(nearest * (1.0 - 1e-6))
    }

    /// SIFs of tip `tip` with q-radius `radius`, shrunk by [`Self::hole_free_radius`] so that no
    /// hole or notch enters the domain (the radius used is [`DomainSifs::radius`]); refused
    /// ("r_I") when the shrunk radius would be smaller than [`MIN_HOLE_FREE_RADIUS`] tip-element
    /// sizes (the tip is then too close to the hole for the domain form on this mesh).
    pub fn sifs_clear_of_holes(&self, u: &[f64], tip: usize, radius: f64) -> Result<DomainSifs> {
        let r = self.hole_free_radius(tip, radius);
        if r < radius {
            let h_el = self.tip_element_size(tip);
            if r < MIN_HOLE_FREE_RADIUS * h_el {
                let name = self.hole_in_domain(tip, radius).unwrap_or_default();
                return Err(Error::invalid(
                    "r_I",
                    &format!(
                        "a q-domain clear of holes of at least {MIN_HOLE_FREE_RADIUS} element \
                         sizes ({name} leaves {:.3} element sizes to the tip at {:?}: refine the \
                         mesh or move the tip away from it)",
                        r / h_el,
                        self.tips[tip].pos
                    ),
                    radius,
                ));
            }
        }
        self.sifs(u, tip, r)
    }

    /// Whether the q-domain of tip `tip` for q-radius `radius` would reach (within 1.5 tip-element
    /// lengths) the other tip of the same crack (a centre crack shorter than the domain).
    pub fn other_tip_in_domain(&self, tip: usize, radius: f64) -> bool {
        let Some(tp) = self.tips.get(tip) else {
            return false;
        };
        let h_el = self.tip_element_size(tip);
        self.tips.iter().enumerate().any(|(t, other)| {
            t != tip
                && self.tip_crack[t] == self.tip_crack[tip]
                && norm(sub(other.pos, tp.pos)) < radius + 1.5 * h_el
        })
    }

    /// Refuses what the domain form cannot integrate: a wrong-sized `u`, an unknown tip, a
    /// non-positive radius, a tip on the plate boundary, a domain reaching the crack's other tip
    /// or entered by another crack.
    fn check_sif_domain(&self, u: &[f64], tip: usize, radius: f64) -> Result<()> {
        if u.len() != self.n_dofs {
            return Err(Error::SizeMismatch {
                what: "XFEM displacement vector".into(),
                expected: self.n_dofs,
                got: u.len(),
            });
        }
        if tip >= self.tips.len() {
            return Err(Error::invalid(
                "tip",
                &format!("< {}", self.tips.len()),
                tip,
            ));
        }
        check_positive("r_I", radius)?;
        let tp = self.tips[tip];
        let mesh = &self.mesh;
        let (w, h) = mesh.size();
        let dist_b = (tp.pos[0] - mesh.xs[0])
            .min(mesh.xs[0] + w - tp.pos[0])
            .min(tp.pos[1] - mesh.ys[0])
            .min(mesh.ys[0] + h - tp.pos[1]);
        // the q-domain may be clipped by the plate boundary (the boundary term of
        // DomainIntegral::add_boundary), but the tip must lie inside the plate
        if dist_b <= self.cracks[self.tip_crack[tip]].snap {
            return Err(Error::invalid(
                "crack",
                "crack tips inside the plate (not on its boundary)",
                format!("tip {:?} at {dist_b:e} from the boundary", tp.pos),
            ));
        }
        if self.other_tip_in_domain(tip, radius) {
            return Err(Error::invalid(
                "r_I",
                "a q-domain that does not reach the other crack tip",
                radius,
            ));
        }
        if let Some(name) = self.hole_in_domain(tip, radius) {
            return Err(Error::invalid(
                "r_I",
                &format!(
                    "a q-domain that no hole or notch enters ({name} enters the domain of the tip \
                     at {:?}: the interaction integral would miss the terms of its boundary)",
                    tp.pos
                ),
                radius,
            ));
        }
        if let Some(c) = self.other_crack_in_domain(tip, radius) {
            return Err(Error::invalid(
                "r_I",
                &format!(
                    "a q-domain that no other crack enters ({} passes through the domain of the \
                     tip at {:?}: the interaction integral would miss its face terms)",
                    crack_name(c),
                    tp.pos
                ),
                radius,
            ));
        }
        Ok(())
    }

    /// SIFs of tip `tip` from the domain interaction integral with q-radius `radius` (absolute).
    pub fn sifs(&self, u: &[f64], tip: usize, radius: f64) -> Result<DomainSifs> {
        self.check_sif_domain(u, tip, radius)?;
        let tp = self.tips[tip];
        let mesh = &self.mesh;
        let nx = mesh.nx();
        let span = radius
            + 2.0 * mesh.xs.windows(2).map(|v| v[1] - v[0]).fold(0.0, f64::max)
            + 2.0 * mesh.ys.windows(2).map(|v| v[1] - v[0]).fold(0.0, f64::max);
        let dom = QDomain {
            model: self,
            u,
            tip: tp,
            snap: self.cracks[self.tip_crack[tip]].snap,
        };
        let mut acc = DomainIntegral::new(&self.material);
        let mut b = BasisBuf::default();
        let mut n_dom = 0;
        for (e, conn) in mesh.elements.iter().enumerate() {
            let (i, j) = (e % nx, e / nx);
            if (mesh.xs[i] - tp.pos[0]).abs() > span || (mesh.ys[j] - tp.pos[1]).abs() > span {
                continue;
            }
            // closed disc with a relative tolerance: nodes at distance r (e.g. the two nodes of
            // an edge whose midpoint is the tip, r = h/2) get the same q whatever the rounding
            let q: [f64; 4] = conn.map(|n| {
                if norm(sub(mesh.coords[n], tp.pos)) <= radius * (1.0 + 1e-9) {
                    1.0
                } else {
                    0.0
                }
            });
            let qs: f64 = q.iter().sum();
            if qs == 0.0 {
                continue;
            }
            let en = self.enriched(e);
            let dofs = self.element_dofs(e);
            if qs < 4.0 {
                n_dom += 1;
                dom.add_area(e, en, &dofs, q, &mut acc, &mut b);
            }
            dom.add_boundary(e, en, &dofs, q, &mut acc, &mut b);
        }
        if n_dom == 0 {
            return Err(Error::invalid(
                "r_I",
                "a radius whose circle crosses at least one element",
                radius,
            ));
        }
        Ok(acc.finish(radius))
    }
}
