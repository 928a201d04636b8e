//! The load responses of the SLA history as linear functionals of the displacements, and the
//! responses of a general scene (regions, probes) at the reference load.
//!
//! * Grips: sigma22 = (sum over the top edge nodes of (K u)_2) / (W h), and u0 = lambda u0_ref.
//! * Regions ([`RegionConditions::primary_response`], as XFEM): the primary region's response,
//!   sum over its nodes of c . (K u)_n / D (K u is the force a node receives from outside:
//!   reaction plus applied force) with c the outward normal and D = L h for an edge region (the
//!   mean normal stress), c the unit drive direction and D = 1 for a point or a box (the force
//!   along it); the `u0` column is the primary region's mean displacement along its drive.
//!   Both are linear in u, so the fast solver condenses them as it does sigma22.
//! * Probes: the displacement of the material node nearest the point; the opening of the
//!   pre-crack: the jump (normal, sliding) between the nodes nearest the point's foot on the
//!   crack on either side of it.

use super::precrack::nodes_across;
use super::SpliceModel;
use crate::error::{Error, Result};
use crate::fe::loading::PlateEdges;
use crate::fe::regions::{RegionConditions, SceneResponses};
use crate::problem::ProbeKind;

/// The primary response and the load displacement as functionals of u.
#[derive(Debug, Clone, PartialEq)]
pub struct Response {
    /// (dof, coefficient): the primary response is sum c (K u)_dof / divisor
    pub rows: Vec<(usize, f64)>,
    pub divisor: f64,
    /// (dof, weight) of the load displacement sum w u_dof (regions); None: the grips'
    /// lambda u0_ref
    pub displacement: Option<Vec<(usize, f64)>>,
    /// driven by a prescribed displacement (a cut load path then carries no load: separated)
    pub displacement_driven: bool,
}

impl Response {
    /// The grips': the top edge's x2 forces over W h.
    pub(super) fn grips(edges: &PlateEdges, width: f64, thickness: f64, driven: bool) -> Self {
        Self {
            rows: edges.top.iter().map(|&n| (2 * n + 1, 1.0)).collect(),
            divisor: width * thickness,
            displacement: None,
            displacement_driven: driven,
        }
    }

    /// The primary region's (none: zero).
    pub(super) fn regions(rc: &RegionConditions, n_supports: usize, thickness: f64) -> Self {
        let Some((k, s)) = rc.sets.iter().enumerate().find(|(_, s)| s.drive.is_some()) else {
            return Self {
                rows: Vec::new(),
                divisor: 1.0,
                displacement: Some(Vec::new()),
                displacement_driven: false,
            };
        };
        let d = s.drive.unwrap_or([0.0, 0.0]);
        let dn = d[0].hypot(d[1]);
        let dir = [d[0] / dn, d[1] / dn];
        let (c, divisor) = match s.edge {
            Some((l, n)) => (n, l * thickness),
            None => (dir, 1.0),
        };
        let nk = s.nodes.len().max(1) as f64;
        let pairs = |w: [f64; 2], scale: f64| -> Vec<(usize, f64)> {
            s.nodes
                .iter()
                .flat_map(|&n| (0..2).map(move |q| (2 * n + q, w[q] * scale)))
                .filter(|&(_, v)| v != 0.0)
                .collect()
        };
        Self {
            rows: pairs(c, 1.0),
            divisor,
            displacement: Some(pairs(dir, 1.0 / nk)),
            displacement_driven: k < n_supports,
        }
    }

    /// The coefficients on every dof (zero off the rows).
    pub(crate) fn dense_rows(&self, n_dofs: usize) -> Vec<f64> {
        let mut c = vec![0.0; n_dofs];
        for &(d, v) in &self.rows {
            c[d] += v;
        }
        c
    }

    /// The primary response of K u.
    pub(crate) fn value(&self, ku: &[f64]) -> f64 {
        let s: f64 = self.rows.iter().map(|&(d, c)| ku[d] * c).sum();
        s / self.divisor
    }

    /// The dofs the load displacement reads (none for the grips).
    pub(crate) fn load_dofs(&self) -> impl Iterator<Item = usize> + '_ {
        self.displacement.iter().flatten().map(|&(d, _)| d)
    }

    /// The load displacement of u (None: grips).
    pub(crate) fn load_displacement(&self, u: &[f64]) -> Option<f64> {
        self.displacement
            .as_ref()
            .map(|w| w.iter().map(|&(d, c)| u[d] * c).sum())
    }
}

/// A probe as two linear functionals of u: component c is sum w u_dof over `comps[c]` (the
/// displacement (u1, u2) of a node, or the (normal, sliding) jump across the pre-crack).
#[derive(Debug, Clone, PartialEq)]
pub struct ProbeFunctional {
    pub name: String,
    pub comps: [Vec<(usize, f64)>; 2],
}

impl ProbeFunctional {
    /// Its value for the displacements u.
    pub fn value(&self, u: &[f64]) -> [f64; 2] {
        self.comps
            .each_ref()
            .map(|c| c.iter().map(|&(d, w)| w * u[d]).sum())
    }

    /// Every dof it reads.
    pub fn dofs(&self) -> impl Iterator<Item = usize> + '_ {
        self.comps.iter().flatten().map(|&(d, _)| d)
    }
}

impl SpliceModel {
    /// The responses of the scene's regions and probes for the solution (u, reactions) at the
    /// reference load (empty for the grips).
    pub fn scene_responses(&self, u: &[f64], reactions: &[f64]) -> Result<SceneResponses> {
        let mut r = match &self.regions {
            Some(rc) => rc.responses(u, reactions, self.problem.material.elastic.thickness),
            None => SceneResponses::default(),
        };
        for pf in self.probe_functionals()? {
            r.probes.push((pf.name.clone(), pf.value(u)));
        }
        Ok(r)
    }

    /// The scene's probes as functionals of u (the SLA history records them at every step).
    pub fn probe_functionals(&self) -> Result<Vec<ProbeFunctional>> {
        let g = &self.grid;
        let mut out = Vec::with_capacity(self.problem.probes.len());
        for (k, pr) in self.problem.probes.iter().enumerate() {
            let q = pr.point();
            let comps = match pr.kind {
                ProbeKind::Displacement(_) => {
                    let n = (0..g.n_nodes())
                        .filter(|&n| self.material[n])
                        .min_by(|&a, &b| {
                            let d = |n: usize| {
                                let x = g.xy(n);
                                (x[0] - q[0]).hypot(x[1] - q[1])
                            };
                            d(a).total_cmp(&d(b))
                        })
                        .unwrap_or(0);
                    [vec![(2 * n, 1.0)], vec![(2 * n + 1, 1.0)]]
                }
                ProbeKind::Opening { .. } => {
                    let c: Vec<[f64; 2]> = self.precrack.iter().map(|&p| g.to_units(p)).collect();
                    let qg = g.to_units(q);
                    let seg = c
                        .windows(2)
                        .min_by(|a, b| {
                            let d = |s: &[[f64; 2]]| {
                                crate::geometry::point_segment_distance(qg, s[0], s[1])
                            };
                            d(a).total_cmp(&d(b))
                        })
                        .ok_or_else(|| {
                            Error::invalid(
                                &format!("probe[{k}].crack"),
                                "a scene with a pre-crack",
                                "none",
                            )
                        })?;
                    let (a, b) = (seg[0], seg[1]);
                    let t = [b[0] - a[0], b[1] - a[1]];
                    let l2 = t[0] * t[0] + t[1] * t[1];
                    let s = (((qg[0] - a[0]) * t[0] + (qg[1] - a[1]) * t[1]) / l2).clamp(0.0, 1.0);
                    let foot = [a[0] + s * t[0], a[1] + s * t[1]];
                    let Some((lo, hi, n)) = nodes_across(a, b, foot, g) else {
                        return Err(Error::invalid(
                            &format!("probe[{k}].point"),
                            "a point whose foot on the crack has grid nodes on both sides",
                            format!("{q:?}"),
                        ));
                    };
                    // du = u_hi - u_lo; normal du . n, sliding du . (n2, -n1)
                    let jump = |w: [f64; 2]| -> Vec<(usize, f64)> {
                        [
                            (2 * hi, w[0]),
                            (2 * hi + 1, w[1]),
                            (2 * lo, -w[0]),
                            (2 * lo + 1, -w[1]),
                        ]
                        .into_iter()
                        .filter(|&(_, v)| v != 0.0)
                        .collect()
                    };
                    [jump([n[0], n[1]]), jump([n[1], -n[0]])]
                }
            };
            out.push(ProbeFunctional {
                name: pr.name.clone(),
                comps,
            });
        }
        Ok(out)
    }
}
