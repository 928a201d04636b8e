//! The PD surface correction (`pd.surface_correction = "energy"`): the energy method of Le &
//! Bobaru 2018 (Comput. Mech. 61, "Surface corrections for peridynamic models in
//! elasticity and fracture", section 3; Madenci & Oterkus 2014, "Peridynamic theory and its
//! applications", section 4.2).
//!
//! A node near a free surface (a hole, the pre-crack's faces; not the plate's outline, below)
//! misses part of its family, so it is softer than the bulk that c (eq. 47, with gamma) is calibrated on. For
//! each node i and direction k = 1, 2 the strain energy density under the uniform strain
//! eps_kk = eps (all other components zero) is, bond-based (eq. 46, s = eps n_k^2),
//!
//!   W_k(i) = 1/4 sum_j c s^2 |xi| beta_j V_j = (c eps^2 dx^3 t / 4) sum_j beta_j d_k^4 / |d|^3
//!
//! over the bonds j of its family that exist (d = xi / dx, the integer offset; the sum is
//! gamma's, [`super::gamma`]). Its node factors are g_k(i) = W_k(bulk) / W_k(i), W_k(bulk)
//! the same sum over the whole stencil (so a node with its full family gets 1 exactly: the
//! same terms in the same order). A bond i-j with unit vector n gets the factor (Madenci &
//! Oterkus eq. 4.16)
//!
//!   G_k = (g_k(i) + g_k(j)) / 2,   G = [ (n_1 / G_1)^2 + (n_2 / G_2)^2 ]^(-1/2)
//!
//! (G = G_1 when G_1 = G_2), and its stiffness c G ([`crate::pd::splice`] scales alpha), its
//! critical stretch s0 / sqrt(G) (below).
//!
//! * **The family counted.** A node's lattice family (offsets of [`super::family_stencil`] on
//!   the PD lattice x = i dx, y = j dx, inside the plate), without the bonds to removed nodes
//!   and through holes (the centre rule and the segment test of `splice/holes.rs`) and without
//!   those the pre-crack crosses (`splice/precrack.rs`, the same test in lattice units);
//!   partial volumes are the stencil's beta (the centre-rule volumes: `pd.hole_volumes =
//!   "exact"` scales the bonds, not the factors; the small-fraction rule by which FEM holes of
//!   CCM-PD remove FEM nodes is not the lattice's). Bonds to FEM nodes of the splice coupling
//!   count as present: the coupled model has them. The family is the lattice's, not the
//!   model's bond list, so a node's factor does not depend on which PD rectangle holds it:
//!   under the adaptive region (`pd/sla/adaptive.rs`) a node keeps its factors when the
//!   region grows over it, and a PD-FEM bond keeps its factor when it becomes PD-PD.
//!   (On a uniform grid the lattice family equals the model's bonds: tested.)
//! * **Once, on the initial model.** The factors are computed when the model is built, from
//!   the pre-cracked but unbroken bonds; bonds broken during the SLA do not change them (the
//!   damage is fracture, not a surface of the elastic model that c should be recalibrated on).
//! * **Where it fits, and the outline left alone.** The energy method assumes a node's cell
//!   ends at the surface. That holds at the pre-crack's faces (midway between node rows, as the
//!   paper's) and at holes by the centre rule, not at the plate's outline, whose nodes lie on it
//!   with full cells (the PD body is dx wider than the plate, which balances the missing bonds:
//!   a 2 x 4 pure PD plate at dx = 0.1 is within 0.5 % of the closed form uncorrected). There
//!   the correction would restore the bulk stiffness of that wider body and overcorrect (8 %
//!   too stiff, measured), so the family counts the lattice points beyond the outline as
//!   present: outline nodes are not corrected (`tests/suite/pd_surface_correction.rs`). The paper's
//!   CCM-PD rectangle reaches no plate edge.
//! * **A direction without bonds.** If W_k(i) = 0 (no existing bond with n_k != 0), the
//!   correction cannot restore it: g_k(i) = 1.
//! * **The bond's critical energy is kept, not s0.** A corrected bond breaks at the stretch
//!   s0_b = s0 / sqrt(G) ([`critical_stretch_scale`]), so its critical energy
//!   w_c = 1/2 G c s0_b^2 |xi| is the uncorrected bond's 1/2 c s0^2 |xi|, the energy eq. 48
//!   calibrates on G0. The bonds a growing crack cuts ahead of its tip are all present (the
//!   lattice count across the new crack is the bulk's), but their end nodes lie near the
//!   pre-crack's faces and carry factors G > 1 (up to 1.93 on the paper's grid); keeping s0
//!   would multiply their critical energy by G and inflate the fracture energy at the tip.
//!   Measured on the paper's case (`benches/RESULTS.md`, "Surface correction"): peak sigma22
//!   +7.6 % against XFEM with s0 kept, +4.3 % with w_c kept (+5.2 % uncorrected). Both
//!   engines read the critical stretch of a bond from here (`pd/sla/critical.rs`).

use crate::geometry::bond_crosses;
use crate::pd::{family_stencil, Bond, Grid};
use crate::problem::Domain;

/// The factors of a model's bonds and what the run reports of them.
#[derive(Debug, Clone, PartialEq)]
pub struct SurfaceFactors {
    /// per bond of the model: the stiffness factor G (1 for a bond of two full families)
    pub bond: Vec<f64>,
    /// per bond: the factor of its critical stretch, s0_b = s0 x this ([`critical_stretch_scale`])
    pub s0_scale: Vec<f64>,
    /// per grid node: the node factors (g_1, g_2) (1 for a full family, and for the nodes no
    /// bond touches)
    pub node: Vec<[f64; 2]>,
    /// what the run reports ([`SurfaceSummary`])
    pub summary: SurfaceSummary,
}

/// The correction's numbers for the result's meta.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct SurfaceSummary {
    /// PD nodes with a node factor g_1 or g_2 other than 1
    pub n_nodes_corrected: usize,
    /// PD nodes
    pub n_pd_nodes: usize,
    /// smallest and largest node factor over the PD nodes and both directions
    pub node_factor_range: [f64; 2],
    /// smallest and largest bond factor over the bonds the pre-crack leaves
    pub bond_factor_range: [f64; 2],
}

/// The node factors (g_1, g_2) of every node of the PD lattice that `bonds` touch, and the
/// bond factors G ([module docs](self)). `precrack` is the pre-crack polyline in plate
/// coordinates, `precrack_broken` the model's bonds it crosses (left out of the summary's bond
/// range), `pd_nodes` the model's PD nodes (the summary's node counts).
pub fn energy_factors(
    domain: &Domain,
    grid: &Grid,
    m: usize,
    precrack: &[[f64; 2]],
    bonds: &[Bond],
    precrack_broken: &[bool],
    pd_nodes: &[usize],
) -> SurfaceFactors {
    let lattice = Lattice::new(domain, grid, m, precrack);
    let mut g = vec![[f64::NAN; 2]; grid.n_nodes()];
    for b in bonds {
        for n in [b.i as usize, b.j as usize] {
            if g[n][0].is_nan() {
                g[n] = lattice.node_factors(grid.lattice_key(n));
            }
        }
    }
    let bond: Vec<f64> = bonds
        .iter()
        .map(|b| {
            let (gi, gj) = (g[b.i as usize], g[b.j as usize]);
            bond_factor([0.5 * (gi[0] + gj[0]), 0.5 * (gi[1] + gj[1])], b.xi)
        })
        .collect();
    let mut s = SurfaceSummary {
        n_pd_nodes: pd_nodes.len(),
        node_factor_range: [f64::INFINITY, f64::NEG_INFINITY],
        bond_factor_range: [f64::INFINITY, f64::NEG_INFINITY],
        ..Default::default()
    };
    for f in g.iter_mut().filter(|f| f[0].is_nan()) {
        *f = [1.0; 2];
    }
    for &n in pd_nodes {
        let f = g[n];
        if f != [1.0; 2] {
            s.n_nodes_corrected += 1;
        }
        for v in f {
            s.node_factor_range = [s.node_factor_range[0].min(v), s.node_factor_range[1].max(v)];
        }
    }
    for (&v, &cut) in bond.iter().zip(precrack_broken) {
        if !cut {
            s.bond_factor_range = [s.bond_factor_range[0].min(v), s.bond_factor_range[1].max(v)];
        }
    }
    for r in [&mut s.node_factor_range, &mut s.bond_factor_range] {
        if r[0] > r[1] {
            *r = [1.0; 2];
        }
    }
    SurfaceFactors {
        s0_scale: bond.iter().map(|&v| critical_stretch_scale(v)).collect(),
        bond,
        node: g,
        summary: s,
    }
}

/// The factor of s0 for a bond of stiffness factor `g`: 1 / sqrt(g), which keeps the bond's
/// critical energy 1/2 g c (s0 / sqrt(g))^2 |xi| ([module docs](self)); exactly 1 for g = 1.
pub fn critical_stretch_scale(g: f64) -> f64 {
    1.0 / g.sqrt()
}

/// The bond factor G = [(n_1 / G_1)^2 + (n_2 / G_2)^2]^(-1/2) of a bond with vector `xi` and
/// directional factors `gk` = (G_1, G_2) (Madenci & Oterkus eq. 4.16); G_1 when both are equal
/// (exactly 1 for two full families).
pub fn bond_factor(gk: [f64; 2], xi: [f64; 2]) -> f64 {
    if gk[0] == gk[1] {
        return gk[0];
    }
    let l = (xi[0] * xi[0] + xi[1] * xi[1]).sqrt();
    let (n1, n2) = (xi[0] / l, xi[1] / l);
    1.0 / ((n1 / gk[0]).powi(2) + (n2 / gk[1]).powi(2)).sqrt()
}

/// The PD lattice of a plate: which lattice bonds exist.
struct Lattice<'a> {
    domain: &'a Domain,
    dx: f64,
    stencil: Vec<crate::pd::StencilEntry>,
    /// the pre-crack in lattice units
    crack: Vec<[f64; 2]>,
    /// sum_j beta_j d_k^4 / |d|^3 over the whole stencil, k = 1, 2
    bulk: [f64; 2],
}

impl<'a> Lattice<'a> {
    fn new(domain: &'a Domain, grid: &Grid, m: usize, precrack: &[[f64; 2]]) -> Self {
        let dx = grid.dx;
        let stencil = family_stencil(m);
        let mut bulk = [0.0; 2];
        for e in &stencil {
            let w = energy_terms(e.di, e.dj, e.beta);
            bulk = [bulk[0] + w[0], bulk[1] + w[1]];
        }
        Self {
            domain,
            dx,
            stencil,
            crack: precrack.iter().map(|p| [p[0] / dx, p[1] / dx]).collect(),
            bulk,
        }
    }

    /// The position of lattice point (i, j): as the uniform grid places its nodes.
    fn xy(&self, k: [i64; 2]) -> [f64; 2] {
        [0.0 + k[0] as f64 * self.dx, 0.0 + k[1] as f64 * self.dx]
    }

    /// Does lattice point k count as material: not in a hole (the centre rule)? Points beyond
    /// the plate's outline count too: the outline is not a surface this correction fits
    /// ([module docs](self)), so its nodes keep their bonds' stiffness.
    fn material(&self, k: [i64; 2]) -> bool {
        self.domain.holes.is_empty() || self.domain.level_set(self.xy(k)) >= 0.0
    }

    /// Does the lattice bond p-q exist: q material, through no hole, across no pre-crack?
    fn bond_exists(&self, p: [i64; 2], q: [i64; 2]) -> bool {
        if !self.material(q) {
            return false;
        }
        let (xp, xq) = (self.xy(p), self.xy(q));
        if self
            .domain
            .holes
            .iter()
            .any(|h| h.shape.cuts_segment(xp, xq))
        {
            return false;
        }
        let (pu, qu) = ([p[0] as f64, p[1] as f64], [q[0] as f64, q[1] as f64]);
        !self
            .crack
            .windows(2)
            .any(|s| bond_crosses(pu, qu, s[0], s[1]))
    }

    /// (g_1, g_2) of the node at lattice point p: the bulk's energy sums over its own.
    fn node_factors(&self, p: [i64; 2]) -> [f64; 2] {
        let mut own = [0.0; 2];
        for e in &self.stencil {
            let q = [p[0] + e.di as i64, p[1] + e.dj as i64];
            if self.bond_exists(p, q) {
                let w = energy_terms(e.di, e.dj, e.beta);
                own = [own[0] + w[0], own[1] + w[1]];
            }
        }
        let g = |k: usize| {
            if own[k] > 0.0 {
                self.bulk[k] / own[k]
            } else {
                1.0
            }
        };
        [g(0), g(1)]
    }
}

/// beta d_k^4 / |d|^3, k = 1, 2, of the stencil offset d = (di, dj): the bond's share of the
/// strain energy density under uniform uniaxial strain along x_k, up to c eps^2 dx^3 t / 4.
fn energy_terms(di: i32, dj: i32, beta: f64) -> [f64; 2] {
    let (a, b) = (di as f64, dj as f64);
    let r3 = (a * a + b * b).sqrt().powi(3);
    [beta * a.powi(4) / r3, beta * b.powi(4) / r3]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bond_factor_limits() {
        // equal directional factors: that factor, whatever the direction
        assert_eq!(bond_factor([1.0, 1.0], [0.3, 0.7]), 1.0);
        assert_eq!(bond_factor([1.3, 1.3], [0.3, 0.7]), 1.3);
        // along an axis: that axis's factor
        assert!((bond_factor([2.0, 1.0], [1.0, 0.0]) - 2.0).abs() < 1e-15);
        assert!((bond_factor([2.0, 1.0], [0.0, 1.0]) - 1.0).abs() < 1e-15);
        // at 45 degrees: the ellipse's radius, between the two
        let g = bond_factor([2.0, 1.0], [1.0, 1.0]);
        assert!((g - 1.0 / (0.5f64 / 4.0 + 0.5).sqrt()).abs() < 1e-15 && g > 1.0 && g < 2.0);
    }

    #[test]
    fn critical_energy_is_kept() {
        assert_eq!(critical_stretch_scale(1.0), 1.0);
        for g in [1.1, 1.5, 1.93, 2.83] {
            // G c (s0 k)^2 = c s0^2
            let k = critical_stretch_scale(g);
            assert!((g * k * k - 1.0).abs() < 1e-15, "{g}");
        }
    }

    #[test]
    fn bulk_sums_are_gammas() {
        // the energy sum along x1 over the stencil is gamma's denominator (pi m^3 / 4 / gamma)
        for m in 1..=6 {
            let st = family_stencil(m);
            let s: f64 = st.iter().map(|e| energy_terms(e.di, e.dj, e.beta)[0]).sum();
            let gamma = crate::pd::gamma(m).unwrap();
            let want = std::f64::consts::PI * (m as f64).powi(3) / 4.0 / gamma;
            assert!((s - want).abs() < 1e-12 * want, "m = {m}: {s} vs {want}");
        }
    }
}
