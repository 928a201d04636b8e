//! The paper's edge-cracked plate (section 3) with the plain FEM model: uncracked, or with a seam
//! crack (duplicated nodes along a grid line) as an independent reference for XFEM.

use crate::error::{check_positive, Error, Result};
use crate::fem::{FemModel, LinearSystem};
use crate::loading::{plate_conditions, sigma22, PlateEdges, PlateLoad};
use crate::material::Elastic;
use crate::mesh::Mesh;
use crate::solver::{condition_warning, ConditionEstimate};
use crate::warning::Warning;
use std::time::Instant;

/// Parameters of a FEM plate run.
#[derive(Debug, Clone)]
pub struct FemPlateParams {
    /// plate width W along x1 and height L along x2
    pub width: f64,
    pub height: f64,
    /// elements along x1 and x2
    pub nx: usize,
    pub ny: usize,
    pub material: Elastic,
    pub load: PlateLoad,
    /// seam crack from x1 = 0 to `a` along the grid line nearest to `crack_y` (None: uncracked)
    pub seam: Option<(f64, f64)>,
    /// Gauss points per direction (2 is exact for rectangles)
    pub gauss: usize,
    /// compute the condition estimate (2 extra solves: +15-20 % of the run at 1e5-1e6 unknowns,
    /// benches/RESULTS.md); without it `condition` is None and only the free pivot-ratio bound
    /// guards against [`crate::solver::COND_SINGULAR`]
    pub condition: bool,
}

/// Results of a FEM plate run.
#[derive(Debug, Clone)]
pub struct FemPlateResult {
    pub coords: Vec<[f64; 2]>,
    pub elements: Vec<[usize; 4]>,
    pub u: Vec<f64>,
    pub reactions: Vec<f64>,
    pub nodal_stress: Vec<[f64; 3]>,
    pub gauss_points: Vec<[f64; 2]>,
    pub gauss_stress: Vec<[f64; 3]>,
    pub sigma22: f64,
    /// crack mouth opening (upper minus lower u2 at x1 = 0); 0 when uncracked
    pub cmod: f64,
    pub energy: f64,
    pub residual: f64,
    pub n_dofs: usize,
    /// node carrying the u1 = 0 anchor (free grips and traction)
    pub anchor_node: usize,
    /// y of the seam actually used (grid line nearest to the requested one)
    pub seam_y: Option<f64>,
    pub wall_time_s: f64,
    /// condition estimate of the solve (see [`ConditionEstimate`]); None when not computed
    /// ([`FemPlateParams::condition`] false)
    pub condition: Option<ConditionEstimate>,
    /// numerical and accuracy warnings (a condition estimate above [`crate::solver::COND_WARN`],
    /// volumetric locking near nu = 0.5, [`Elastic::locking_warning`])
    pub warnings: Vec<Warning>,
}

/// Builds and solves the FEM plate.
pub fn run(p: &FemPlateParams) -> Result<FemPlateResult> {
    let t0 = Instant::now();
    check_positive("width", p.width)?;
    check_positive("height", p.height)?;
    p.material.validate()?;
    let mut mesh = Mesh::uniform(0.0, 0.0, p.width, p.height, p.nx, p.ny)?;
    let mut mouth = None;
    let mut seam_y = None;
    if let Some((a, y)) = p.seam {
        if !(a.is_finite() && a > 0.0 && a < p.width) {
            return Err(Error::invalid(
                "a0",
                &format!("0 < a0 < width = {}", p.width),
                a,
            ));
        }
        if !(y.is_finite() && y > 0.0 && y < p.height) {
            return Err(Error::invalid(
                "crack_y",
                &format!("0 < crack_y < height = {}", p.height),
                y,
            ));
        }
        let (j, _) = Mesh::nearest_line(&mesh.ys, y);
        let (m, pairs) = mesh.with_seam(j, a)?;
        seam_y = Some(m.ys[j]);
        mouth = Some(pairs[0]);
        mesh = m;
    }
    let model = FemModel::new(mesh, p.material, p.gauss)?;
    let edges = PlateEdges::of_mesh(&model.mesh);
    let (bc, f, anchor) = plate_conditions(&edges, &p.load, model.n_dofs(), p.material.thickness)?;
    bc.check_rigid_modes(&model.mesh.coords)?;
    let sys = LinearSystem::with_positions(model.stiffness(), &bc, Some(&model.dof_positions()))?;
    let condition = sys.checked_condition("solve", p.condition)?;
    let sol = sys.solve(&f, 1.0)?;
    let s22 = sigma22(&edges, &sol.reactions, &f, p.width, p.material.thickness);
    let cmod = mouth.map_or(0.0, |(lo, up)| sol.u[2 * up + 1] - sol.u[2 * lo + 1]);
    let (gauss_points, gauss_stress) = model.gauss_stresses(&sol.u);
    let nodal_stress = model.nodal_stresses(&sol.u);
    Ok(FemPlateResult {
        coords: model.mesh.coords.clone(),
        elements: model.mesh.elements.clone(),
        n_dofs: model.n_dofs(),
        nodal_stress,
        gauss_points,
        gauss_stress,
        sigma22: s22,
        cmod,
        energy: sol.energy,
        residual: sol.residual,
        u: sol.u,
        reactions: sol.reactions,
        anchor_node: anchor,
        seam_y,
        wall_time_s: t0.elapsed().as_secs_f64(),
        condition,
        warnings: p
            .material
            .locking_warning()
            .into_iter()
            .chain(
                condition
                    .as_ref()
                    .and_then(|c| condition_warning("solve", c)),
            )
            .collect(),
    })
}
