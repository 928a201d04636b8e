//! The plate problem of the XFEM driver: the loaded edges and the reference load of the
//! rectangular plate, one linear solve of a model at the reference load (reactions -> sigma22,
//! CMOD), and the smallest tip clearance the mesh resolves.

use super::model::XfemModel;
use crate::error::{Error, Result};
use crate::fe::loading::{plate_conditions, sigma22, PlateEdges};
use crate::fe::regions::{region_conditions, SceneResponses};
use crate::fe::LinearSystem;
use crate::la::ConditionEstimate;
use crate::problem::parse::crack_name;
use crate::problem::{Boundary, Domain, PlateLoad, Probe, ProbeKind};

/// The loaded plate [0, width] x [0, height] around a model (the cracks vary, the plate stays).
pub(super) struct PlateProblem {
    pub(super) edges: PlateEdges,
    /// reference load (u0 for displacement grips, traction for `Grip::Traction`)
    pub(super) load: PlateLoad,
    pub(super) width: f64,
    pub(super) height: f64,
    /// compute the condition estimate of every solve
    pub(super) condition: bool,
    /// the problem's conditions (grips: `load` and `edges`; or supports and loads on regions)
    pub(super) boundary: Boundary,
    /// the domain (holes)
    pub(super) domain: Domain,
    pub(super) probes: Vec<Probe>,
}

/// The conditions of one model at the reference load ([`PlateProblem::conditions`]).
pub(super) struct PlateConditions {
    /// Dirichlet conditions, holes' removed nodes included
    pub(super) bc: crate::fe::dirichlet::Dirichlet,
    /// forces at the reference load (all dofs)
    pub(super) f: Vec<f64>,
    pub(super) anchor: usize,
    pub(super) regions: Option<crate::fe::regions::RegionConditions>,
}

/// One solve of a plate model at the reference load.
pub(super) struct PlateSolve {
    pub(super) u: Vec<f64>,
    pub(super) sigma22: f64,
    pub(super) cmod: f64,
    pub(super) anchor: usize,
    pub(super) condition: Option<ConditionEstimate>,
    /// the nodal reactions K u - f of the standard dofs, interleaved [r1, r2]
    pub(super) reactions: Vec<f64>,
    /// supports, loads and probes at the reference load
    pub(super) responses: SceneResponses,
}

impl PlateProblem {
    /// One solve at the reference load: the rigid-mode check of the Dirichlet set (standard dofs;
    /// the enrichment has no rigid modes), factorisation, the condition check (with the estimate
    /// when `condition`; `what` names the solve) and the solve. The reference path of the growth
    /// ([`crate::xfem::condensed`] reuses one factorisation instead).
    pub(super) fn solve(&self, model: &XfemModel, what: &str) -> Result<PlateSolve> {
        let c = self.conditions(model)?;
        let sys =
            LinearSystem::with_positions(model.stiffness()?, &c.bc, Some(&model.dof_positions()))?;
        let condition = sys.checked_condition(what, self.condition)?;
        let sol = sys.solve(&c.f, 1.0)?;
        self.finish(model, &c, sol.u, &sol.reactions, condition)
    }

    /// The Dirichlet conditions (checked for rigid modes, holes' removed nodes prescribed) and
    /// the forces of `model` at the reference load.
    pub(super) fn conditions(&self, model: &XfemModel) -> Result<PlateConditions> {
        let (edges, load) = (&self.edges, &self.load);
        let t = model.material.thickness;
        let active = model
            .fictitious
            .as_ref()
            .map_or_else(Vec::new, |fd| fd.active_nodes(model.mesh.n_nodes()));
        let (bc, mut f, anchor, regions) = match &self.boundary {
            Boundary::Grips(_) => {
                let (bc, f, anchor) = plate_conditions(edges, load, model.n_dofs, t)?;
                (bc, f, anchor, None)
            }
            Boundary::Regions { supports, loads } => {
                let rc = region_conditions(
                    &model.mesh,
                    &self.domain,
                    &active,
                    supports,
                    loads,
                    model.n_dofs,
                    t,
                )?;
                (rc.bc.clone(), rc.f.clone(), usize::MAX, Some(rc))
            }
        };
        let bc = model.constrain(bc, &mut f)?;
        Ok(PlateConditions {
            bc,
            f,
            anchor,
            regions,
        })
    }

    /// The solve's responses from the displacements `u` and reactions K u - f (sigma22, supports,
    /// loads, probes, CMOD).
    pub(super) fn finish(
        &self,
        model: &XfemModel,
        c: &PlateConditions,
        u: Vec<f64>,
        reactions: &[f64],
        condition: Option<ConditionEstimate>,
    ) -> Result<PlateSolve> {
        let t = model.material.thickness;
        let (s22, mut responses) = match &c.regions {
            None => (
                sigma22(&self.edges, reactions, &c.f, self.width, t),
                SceneResponses {
                    load_displacement: self.load.u0,
                    ..SceneResponses::default()
                },
            ),
            Some(rc) => (
                rc.primary_response(&u, reactions, &c.f, t).0,
                rc.responses(&u, reactions, t),
            ),
        };
        responses.probes = self.probe_values(model, &u)?;
        let cmod = model.cmod(&u)?;
        Ok(PlateSolve {
            reactions: reactions[..model.n_std.min(reactions.len())].to_vec(),
            u,
            sigma22: s22,
            cmod,
            anchor: c.anchor,
            condition,
            responses,
        })
    }

    /// The probes: the enriched displacement at a point, or the jump across a crack at the crack
    /// point nearest the probe's point ([`XfemModel::jump_at`]).
    fn probe_values(&self, model: &XfemModel, u: &[f64]) -> Result<Vec<(String, [f64; 2])>> {
        self.probes
            .iter()
            .enumerate()
            .map(|(k, pr)| {
                let v = match pr.kind {
                    ProbeKind::Displacement(q) => model.displacement_at(u, q).ok_or_else(|| {
                        Error::invalid(
                            &format!("probe[{k}].point"),
                            "a point on the plate",
                            format!("{q:?}"),
                        )
                    })?,
                    ProbeKind::Opening { point, crack } => model.jump_at(u, crack, point)?,
                };
                Ok((pr.name.clone(), v))
            })
            .collect()
    }
}

/// Smallest distance, in tip-element lengths, between a crack tip and the plate boundary that the
/// plate driver accepts: a shorter edge crack or a narrower ligament is not resolved by the mesh.
/// Measured on the tall strip against Tada (tests/suite/xfem_extremes.rs, benches/RESULTS.md): an edge
/// crack 0.8 elements long gives K_I 24 % low; a ligament of 2, 4, 8, 16 elements gives K_I 17, 8.4,
/// 3.6, 1.7 % low (error ~ 0.3 h / ligament); a tip 0.5 elements from the edge, 49 % low even though
/// its (clipped) SIF domains are right for the computed field. It is a mesh limit, not a SIF one:
/// the q-domain may be clipped by the boundary.
pub const MIN_TIP_CLEARANCE: f64 = 2.0;

/// Refuses crack tips closer than [`MIN_TIP_CLEARANCE`] element lengths to the plate boundary or
/// to a hole or notch, and tips inside a hole (naming the crack's length, "crack.a0" or
/// "crack[k].a0").
pub(super) fn check_tip_clearance(model: &XfemModel) -> Result<()> {
    let mesh = &model.mesh;
    let (w, h) = mesh.size();
    let (x0, y0) = (mesh.xs[0], mesh.ys[0]);
    for (t, tip) in model.tips.iter().enumerate() {
        let p = tip.pos;
        let d = (p[0] - x0)
            .min(x0 + w - p[0])
            .min(p[1] - y0)
            .min(y0 + h - p[1]);
        let h_el = model.tip_element_size(t);
        if let Some(fd) = &model.fictitious {
            let hole = fd
                .domain
                .holes
                .iter()
                .min_by(|a, b| a.shape.level_set(p).total_cmp(&b.shape.level_set(p)));
            if let Some(hole) = hole {
                let dh = hole.shape.level_set(p);
                if dh < MIN_TIP_CLEARANCE * h_el * (1.0 - 1e-9) {
                    let what = if dh <= 0.0 { "inside" } else { "near" };
                    return Err(Error::invalid(
                        &format!("{}.a0", crack_name(model.tip_crack[t])),
                        &format!(
                            "crack tips in the material, at least {MIN_TIP_CLEARANCE} element \
                             lengths from every hole and notch (refine the mesh or change the \
                             crack)"
                        ),
                        format!(
                            "tip {p:?} {what} {} (level set {dh:.4e} = {:.2} element lengths)",
                            hole.name,
                            dh / h_el
                        ),
                    ));
                }
            }
        }
        if d < MIN_TIP_CLEARANCE * h_el * (1.0 - 1e-9) {
            return Err(Error::invalid(
                &format!("{}.a0", crack_name(model.tip_crack[t])),
                &format!(
                    "crack tips at least {MIN_TIP_CLEARANCE} element lengths from the plate \
                     boundary: the mesh cannot resolve a crack or a ligament shorter than that \
                     (refine the mesh)"
                ),
                format!(
                    "tip {:?} at {d:.4e} = {:.2} element lengths ({h_el:.4e}) from the boundary",
                    p,
                    d / h_el
                ),
            ));
        }
    }
    Ok(())
}
