//! Supports and loads on boundary regions of a structured mesh ([`crate::problem::Support`],
//! [`crate::problem::RegionLoad`]): the Dirichlet set, the consistent force vector, the node
//! set of each region and its responses (reaction, mean stress, displacement). Every value is
//! the reference load; the solution scales with one load factor.
//!
//! Node selection: an edge takes the nodes of its side (seam duplicates included), an edge part
//! those whose coordinate along the side lies in [from, to], a box those inside it (closed), a
//! point the nearest node, refused when it is farther than half the local element size. Nodes
//! removed by holes (`active` false) are never selected. A uniform traction on an edge (part)
//! gives the consistent nodal forces of linear edges, integrated exactly over the part of each
//! boundary segment inside [from, to]; segments whose midpoint lies in a hole carry none.

use crate::error::{Error, Result};
use crate::fe::dirichlet::Dirichlet;
use crate::fe::mesh::Mesh;
use crate::problem::regions::{outward_normal, traction_vector};
use crate::problem::{Domain, LoadKind, Region, RegionLoad, Side, Support};

/// The nodes of one support or load and what its responses need.
#[derive(Debug, Clone)]
pub struct RegionSet {
    /// scene name (`support[1]`, `load[0]`)
    pub name: String,
    pub nodes: Vec<usize>,
    /// edge regions: the loaded length and the outward normal (mean stress = F . n / (L h))
    pub edge: EdgeGeometry,
    /// the direction the region is driven in at the reference load (the applied force or the
    /// prescribed displacement; None when it is held at zero): responses are read along it
    pub drive: Option<[f64; 2]>,
    /// a support's prescribed components (u1, u2); a load's none
    pub fixed: [bool; 2],
    /// a load's resultant (its own nodal forces summed); a support's zero
    pub applied: [f64; 2],
}

/// Dirichlet set, force vector and region node sets of a scene's supports and loads.
#[derive(Debug, Clone)]
pub struct RegionConditions {
    pub bc: Dirichlet,
    pub f: Vec<f64>,
    /// supports first, then loads, in scene order
    pub sets: Vec<RegionSet>,
}

/// The responses of one region for a solution (u, reactions) at the reference load.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RegionResponse {
    /// the force the region receives from outside, over the thickness: a support's reaction
    /// (K u - f summed over its nodes in the components it prescribes, zero in the free ones,
    /// so no applied load's share), a load's resultant; every region's sum to zero
    pub force: [f64; 2],
    /// edge regions: the mean normal stress F . n / (L h)
    pub mean_stress: Option<f64>,
    /// mean displacement of the region's nodes
    pub displacement: [f64; 2],
}

impl RegionSet {
    /// The internal force K u = reactions + f summed over the region's nodes (the load path's
    /// response, which the SLA engines condense as rows of K u: `pd::splice::response`).
    fn internal_force(&self, reactions: &[f64], f: &[f64]) -> [f64; 2] {
        let mut force = [0.0; 2];
        for &n in &self.nodes {
            for c in 0..2 {
                force[c] += reactions[2 * n + c] + f[2 * n + c];
            }
        }
        force
    }

    /// The region's responses.
    pub fn response(&self, u: &[f64], reactions: &[f64], thickness: f64) -> RegionResponse {
        let mut force = [0.0; 2];
        let mut disp = [0.0; 2];
        for &n in &self.nodes {
            for c in 0..2 {
                if self.fixed[c] {
                    force[c] += reactions[2 * n + c];
                }
                disp[c] += u[2 * n + c];
            }
        }
        if self.fixed == [false, false] {
            force = self.applied;
        }
        let k = self.nodes.len().max(1) as f64;
        RegionResponse {
            force,
            mean_stress: self
                .edge
                .map(|(l, n)| (force[0] * n[0] + force[1] * n[1]) / (l * thickness)),
            displacement: [disp[0] / k, disp[1] / k],
        }
    }
}

/// The coordinate along a side (x1 on bottom/top, x2 on left/right).
fn along(side: Side) -> usize {
    match side {
        Side::Bottom | Side::Top => 0,
        Side::Left | Side::Right => 1,
    }
}

/// Local element size at a point: the larger spacing of the grid cell holding it.
fn local_size(mesh: &Mesh, p: [f64; 2]) -> f64 {
    let cell = |lines: &[f64], v: f64| {
        let k = lines.partition_point(|&l| l <= v).clamp(1, lines.len() - 1);
        lines[k] - lines[k - 1]
    };
    cell(&mesh.xs, p[0]).max(cell(&mesh.ys, p[1]))
}

/// An edge region's loaded length and outward normal.
type EdgeGeometry = Option<(f64, [f64; 2])>;

/// The nodes of a region (and its edge geometry), refusing a region with none.
fn nodes_of(
    mesh: &Mesh,
    domain: &Domain,
    active: &[bool],
    region: &Region,
    name: &str,
) -> Result<(Vec<usize>, EdgeGeometry)> {
    let on = |n: &usize| active.get(*n).copied().unwrap_or(true);
    let (w, h) = mesh.size();
    let tol = 1e-9 * w.max(h);
    let side_len = |s: Side| if along(s) == 0 { w } else { h };
    let nodes: Vec<usize>;
    let mut edge = None;
    match *region {
        Region::Edge(side) => {
            nodes = mesh.side_nodes(side).into_iter().filter(on).collect();
            edge = Some((side_len(side), outward_normal(side)));
        }
        Region::EdgePart { side, from, to } => {
            let a = along(side);
            nodes = mesh
                .side_nodes(side)
                .into_iter()
                .filter(on)
                .filter(|&n| (from - tol..=to + tol).contains(&mesh.coords[n][a]))
                .collect();
            edge = Some((to - from, outward_normal(side)));
            if nodes.is_empty() {
                return Err(Error::invalid(
                    &format!("{name}.from"),
                    "an edge part holding at least one node of the mesh (widen from..to or \
                     refine the mesh)",
                    format!("[{from}, {to}] on the {side:?} side"),
                ));
            }
        }
        Region::Box(b) => {
            nodes = (0..mesh.n_nodes())
                .filter(on)
                .filter(|&n| {
                    let p = mesh.coords[n];
                    p[0] >= b[0] - tol
                        && p[0] <= b[2] + tol
                        && p[1] >= b[1] - tol
                        && p[1] <= b[3] + tol
                })
                .collect();
            // a box in a hole holds only fictitious nodes (the plate would be held there)
            if !nodes
                .iter()
                .any(|&n| domain.level_set(mesh.coords[n]) > 0.0)
            {
                return Err(Error::invalid(
                    &format!("{name}.box"),
                    "a box holding at least one node of the mesh in the material (outside the \
                     holes and notches)",
                    format!("{b:?}"),
                ));
            }
        }
        Region::Point(p) => {
            let best = (0..mesh.n_nodes())
                .filter(on)
                .map(|n| {
                    (
                        n,
                        (mesh.coords[n][0] - p[0]).hypot(mesh.coords[n][1] - p[1]),
                    )
                })
                .min_by(|a, b| a.1.total_cmp(&b.1));
            let half = 0.5 * local_size(mesh, p);
            match best {
                Some((n, d)) if d <= half * (1.0 + 1e-9) => nodes = vec![n],
                _ => {
                    return Err(Error::invalid(
                        &format!("{name}.point"),
                        &format!(
                            "a point within half an element ({half:.4e}) of a node of the mesh"
                        ),
                        format!(
                            "{p:?} (nearest node {:.4e} away)",
                            best.map_or(f64::INFINITY, |b| b.1)
                        ),
                    ))
                }
            }
        }
    }
    if nodes.is_empty() {
        return Err(Error::invalid(
            &format!("{name}.side"),
            "an edge with at least one node left by the holes and notches",
            "none",
        ));
    }
    Ok((nodes, edge))
}

/// Consistent nodal forces of a uniform traction `t` on the part [from, to] of a side: for the
/// boundary segment [a, b] and the part [s, e] of it inside the interval, node a receives
/// t h int_s^e N_a dx and node b t h int_s^e N_b dx (exact for linear edges).
#[allow(clippy::too_many_arguments)]
fn edge_forces(
    mesh: &Mesh,
    domain: &Domain,
    side: Side,
    from: f64,
    to: f64,
    t: [f64; 2],
    thickness: f64,
    f: &mut [f64],
) -> f64 {
    let ax = along(side);
    let mut loaded = 0.0;
    for [a, b] in mesh.side_edges(side) {
        let (pa, pb) = (mesh.coords[a], mesh.coords[b]);
        let mid = [0.5 * (pa[0] + pb[0]), 0.5 * (pa[1] + pb[1])];
        if domain.level_set(mid) < 0.0 {
            continue;
        }
        let (xa, xb) = (pa[ax], pb[ax]);
        let (lo, hi) = (xa.min(xb), xa.max(xb));
        let (s, e) = (from.max(lo), to.min(hi));
        if e <= s {
            continue;
        }
        // N_a(x) = (x_b - x) / (x_b - x_a) on the segment (either orientation)
        let int_na = |x: f64| (x * xb - 0.5 * x * x) / (xb - xa);
        let wa = int_na(e) - int_na(s);
        let wb = (e - s) - wa;
        for (n, w) in [(a, wa), (b, wb)] {
            f[2 * n] += w * thickness * t[0];
            f[2 * n + 1] += w * thickness * t[1];
        }
        loaded += e - s;
    }
    loaded
}

/// The Dirichlet set, forces and node sets of `supports` and `loads` on `mesh` (n_dofs may exceed
/// 2 n_nodes: enrichment dofs carry no boundary condition). `active[n]` false: node n is removed
/// by a hole (an empty slice: every node is active).
pub fn region_conditions(
    mesh: &Mesh,
    domain: &Domain,
    active: &[bool],
    supports: &[Support],
    loads: &[RegionLoad],
    n_dofs: usize,
    thickness: f64,
) -> Result<RegionConditions> {
    let mut bc = Dirichlet::default();
    let mut f = vec![0.0; n_dofs];
    let mut sets = Vec::with_capacity(supports.len() + loads.len());
    let mut owner: std::collections::HashMap<usize, &str> = std::collections::HashMap::new();
    for s in supports {
        let (nodes, edge) = nodes_of(mesh, domain, active, &s.region, &s.name)?;
        for (comp, v) in [(0, s.u1), (1, s.u2)] {
            let Some(v) = v else { continue };
            for &n in &nodes {
                let d = 2 * n + comp;
                if let Some(other) = owner.insert(d, &s.name) {
                    if other != s.name {
                        return Err(Error::invalid(
                            &format!("{}.region", s.name),
                            "supports that prescribe each displacement component of a node \
                             once",
                            format!(
                                "u{} of the node at {:?} is prescribed by {other} and {}",
                                comp + 1,
                                mesh.coords[n],
                                s.name
                            ),
                        ));
                    }
                }
            }
            bc.fix(&nodes, comp, v);
        }
        let dv = [s.u1.unwrap_or(0.0), s.u2.unwrap_or(0.0)];
        sets.push(RegionSet {
            name: s.name.clone(),
            nodes,
            edge,
            drive: (dv != [0.0, 0.0]).then_some(dv),
            fixed: [s.u1.is_some(), s.u2.is_some()],
            applied: [0.0; 2],
        });
    }
    let total = |f: &[f64]| -> [f64; 2] {
        let mut t = [0.0; 2];
        for (d, v) in f.iter().enumerate().take(2 * mesh.n_nodes()) {
            t[d % 2] += v;
        }
        t
    };
    for l in loads {
        let (nodes, edge) = nodes_of(mesh, domain, active, &l.region, &l.name)?;
        let before = total(&f);
        let drive = match (l.kind, l.region) {
            (LoadKind::Force(fv), _) => {
                for c in 0..2 {
                    f[2 * nodes[0] + c] += fv[c];
                }
                fv
            }
            (
                LoadKind::Traction { normal, shear },
                Region::Edge(side) | Region::EdgePart { side, .. },
            ) => {
                let (from, to) = match l.region {
                    Region::EdgePart { from, to, .. } => (from, to),
                    _ => (f64::NEG_INFINITY, f64::INFINITY),
                };
                let t = traction_vector(side, normal, shear);
                let loaded = edge_forces(mesh, domain, side, from, to, t, thickness, &mut f);
                if loaded <= 0.0 {
                    return Err(Error::invalid(
                        &format!("{}.region", l.name),
                        "a load on material (the loaded edge lies in a hole or notch)",
                        format!("{:?}", l.region),
                    ));
                }
                t
            }
            (LoadKind::Traction { .. }, r) => {
                return Err(Error::invalid(
                    &format!("{}.region", l.name),
                    "'edge' or 'edge_part' for a traction ('point' for a force)",
                    r.name(),
                ))
            }
        };
        let after = total(&f);
        sets.push(RegionSet {
            name: l.name.clone(),
            nodes,
            edge,
            drive: (drive != [0.0, 0.0]).then_some(drive),
            fixed: [false; 2],
            applied: [after[0] - before[0], after[1] - before[1]],
        });
    }
    Ok(RegionConditions { bc, f, sets })
}

impl RegionConditions {
    /// The region whose response is the run's primary load response: the first load, else the
    /// first support with a non-zero prescribed displacement.
    pub fn primary(&self) -> Option<&RegionSet> {
        self.sets.iter().find(|s| s.drive.is_some())
    }

    /// The primary response (edges: the mean traction along the drive direction, F . d / (L h),
    /// so the applied stress for a normal or a shear traction; points and boxes: the force along
    /// the drive direction) and the primary displacement (the region's mean displacement along
    /// the drive direction).
    pub fn primary_response(
        &self,
        u: &[f64],
        reactions: &[f64],
        f: &[f64],
        thickness: f64,
    ) -> (f64, f64) {
        let Some(s) = self.primary() else {
            return (0.0, 0.0);
        };
        let r = s.response(u, reactions, thickness);
        let force = s.internal_force(reactions, f);
        let d = s.drive.unwrap_or([0.0, 0.0]);
        let dn = d[0].hypot(d[1]).max(f64::MIN_POSITIVE);
        let along = |v: [f64; 2]| (v[0] * d[0] + v[1] * d[1]) / dn;
        let resp = match s.edge {
            Some((l, _)) => along(force) / (l * thickness),
            None => along(force),
        };
        (resp, along(r.displacement))
    }
}

/// The responses of a scene at the reference load, in scene order: every support and load
/// (reaction, mean stress, mean displacement) and every probe (a displacement [u1, u2], or an
/// opening [normal jump, sliding jump] across a crack); results scale them by the load factor.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SceneResponses {
    pub regions: Vec<(String, RegionResponse)>,
    pub probes: Vec<(String, [f64; 2])>,
    /// the primary region's mean displacement along its drive direction (the load-point
    /// displacement; the grips' u0 for the paper's plate)
    pub load_displacement: f64,
}

impl SceneResponses {
    /// The same responses at `lam` times the reference load.
    pub fn scaled(&self, lam: f64) -> Self {
        let sc = |v: [f64; 2]| [lam * v[0], lam * v[1]];
        Self {
            regions: self
                .regions
                .iter()
                .map(|(n, r)| {
                    (
                        n.clone(),
                        RegionResponse {
                            force: sc(r.force),
                            mean_stress: r.mean_stress.map(|s| lam * s),
                            displacement: sc(r.displacement),
                        },
                    )
                })
                .collect(),
            probes: self
                .probes
                .iter()
                .map(|(n, v)| (n.clone(), sc(*v)))
                .collect(),
            load_displacement: lam * self.load_displacement,
        }
    }
}

impl RegionConditions {
    /// Every region's response and the load displacement (probes are the driver's).
    pub fn responses(&self, u: &[f64], reactions: &[f64], thickness: f64) -> SceneResponses {
        let f = &self.f;
        SceneResponses {
            regions: self
                .sets
                .iter()
                .map(|s| (s.name.clone(), s.response(u, reactions, thickness)))
                .collect(),
            probes: Vec::new(),
            load_displacement: self.primary_response(u, reactions, f, thickness).1,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn partial_traction_is_exact_and_conservative() {
        let mesh = Mesh::uniform(0.0, 0.0, 2.0, 1.0, 4, 2).unwrap();
        let d = Domain::rect(2.0, 1.0);
        let mut f = vec![0.0; 2 * mesh.n_nodes()];
        // [0.3, 1.1] straddles three segments of length 0.5
        let l = edge_forces(&mesh, &d, Side::Top, 0.3, 1.1, [0.0, 2.0], 1.5, &mut f);
        assert!((l - 0.8).abs() < 1e-14);
        let total: f64 = (0..mesh.n_nodes()).map(|n| f[2 * n + 1]).sum();
        assert!((total - 2.0 * 0.8 * 1.5).abs() < 1e-13);
        // moment about x = 0 equals the traction's: int_0.3^1.1 x dx * t h
        let moment: f64 = (0..mesh.n_nodes())
            .map(|n| f[2 * n + 1] * mesh.coords[n][0])
            .sum();
        let exact = 0.5 * (1.1f64.powi(2) - 0.3f64.powi(2)) * 2.0 * 1.5;
        assert!((moment - exact).abs() < 1e-13);
    }
}
