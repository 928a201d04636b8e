//! The plate problem of the XFEM driver: the loaded edges and the reference load of the
//! rectangular plate, one linear solve of a model at the reference load (reactions -> sigma22,
//! CMOD), and the smallest tip clearance the mesh resolves.

use super::model::XfemModel;
use crate::error::{Error, Result};
use crate::fe::loading::{plate_conditions, sigma22, PlateEdges, PlateLoad};
use crate::fe::LinearSystem;
use crate::la::ConditionEstimate;
use crate::problem::parse::crack_name;

/// The loaded plate [0, width] x [0, height] around a model (the cracks vary, the plate stays).
pub(super) struct PlateProblem {
    pub(super) edges: PlateEdges,
    /// reference load (u0 for displacement grips, traction for `Grip::Traction`)
    pub(super) load: PlateLoad,
    pub(super) width: f64,
    pub(super) height: f64,
    /// compute the condition estimate of every solve
    pub(super) condition: bool,
}

/// One solve of a plate model at the reference load.
pub(super) struct PlateSolve {
    pub(super) u: Vec<f64>,
    pub(super) sigma22: f64,
    pub(super) cmod: f64,
    pub(super) anchor: usize,
    pub(super) condition: Option<ConditionEstimate>,
}

impl PlateProblem {
    /// One solve at the reference load: the rigid-mode check of the Dirichlet set (standard dofs;
    /// the enrichment has no rigid modes), factorisation, the condition check (with the estimate
    /// when `condition`; `what` names the solve) and the solve.
    pub(super) fn solve(&self, model: &XfemModel, what: &str) -> Result<PlateSolve> {
        let (edges, load) = (&self.edges, &self.load);
        let t = model.material.thickness;
        let (bc, mut f, anchor) = plate_conditions(edges, load, model.n_dofs, t)?;
        let bc = model.constrain(bc, &mut f)?;
        let sys =
            LinearSystem::with_positions(model.stiffness()?, &bc, Some(&model.dof_positions()))?;
        let condition = sys.checked_condition(what, self.condition)?;
        let sol = sys.solve(&f, 1.0)?;
        let s22 = sigma22(edges, &sol.reactions, &f, self.width, t);
        let cmod = model.cmod(&sol.u)?;
        Ok(PlateSolve {
            u: sol.u,
            sigma22: s22,
            cmod,
            anchor,
            condition,
        })
    }
}

/// Smallest distance, in tip-element lengths, between a crack tip and the plate boundary that the
/// plate driver accepts: a shorter edge crack or a narrower ligament is not resolved by the mesh.
/// Measured on the tall strip against Tada (tests/xfem_extremes.rs, benches/RESULTS.md): an edge
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
