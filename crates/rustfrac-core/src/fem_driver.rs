//! The FEM plate driver: the paper's edge-cracked plate (section 3) solved with plain Q4 FEM
//! (eqs. 4-14), uncracked or with a seam crack (duplicated nodes along a grid line) as an
//! independent reference for XFEM.
//!
//! It reads one [`Problem`] of method "fem": the domain, the material, the grips
//! ([`Boundary::plate_load`](crate::problem::Boundary::plate_load)), the seam (the first crack of
//! kind [`CrackKind::Seam`]; none: uncracked) and the [`FemMethod`] options.

use crate::error::{Error, Result};
use crate::fe::loading::{plate_conditions, sigma22, PlateEdges};
use crate::fe::mesh::Mesh;
use crate::fe::regions::{region_conditions, SceneResponses};
use crate::fe::{FemModel, LinearSystem};
use crate::la::{condition_warning, ConditionEstimate};
use crate::memory;
use crate::problem::parse::crack_name;
use crate::problem::{validate, CrackKind, FemMethod, Method, Problem};
use crate::warning::{Warning, WarningKind};
use std::time::Instant;

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
    /// node carrying the u1 = 0 anchor (free grips and traction; supports on regions: none)
    pub anchor_node: usize,
    /// supports, loads and probes (general scenes; the grips' top and bottom edges otherwise
    /// carry none)
    pub responses: SceneResponses,
    /// y of the seam actually used (grid line nearest to the requested one)
    pub seam_y: Option<f64>,
    /// length of the seam actually cut: from x1 = 0 to the first grid node at or beyond a0
    /// (a warning says so when it differs from a0)
    pub seam_length: Option<f64>,
    pub wall_time_s: f64,
    /// condition estimate of the solve (see [`ConditionEstimate`]); None when not computed
    /// ([`FemMethod::condition`] false: without it only the free pivot-ratio bound guards
    /// against [`crate::la::COND_SINGULAR`])
    pub condition: Option<ConditionEstimate>,
    /// numerical and accuracy warnings (a condition estimate above [`crate::la::COND_WARN`],
    /// volumetric locking near nu = 0.5, [`crate::problem::Elastic::locking_warning`])
    pub warnings: Vec<Warning>,
}

/// The plate's mesh, with the seam crack cut into it.
struct SeamedMesh {
    mesh: Mesh,
    /// the (lower, upper) node pair at the crack mouth
    mouth: Option<(usize, usize)>,
    /// y of the grid line the seam lies on
    seam_y: Option<f64>,
    /// the seam's real length and the warning when it is not the crack's a0
    seam_length: Option<f64>,
    warning: Option<Warning>,
}

/// Builds and solves the FEM plate of `p` (method "fem").
pub fn run(p: &Problem) -> Result<FemPlateResult> {
    let t0 = Instant::now();
    validate::problem(p)?;
    validate::reference_load(p)?;
    let Method::Fem(method) = &p.method else {
        return Err(Error::invalid(
            "method",
            "'fem' (the FEM plate driver)",
            format!("'{}'", p.method.name()),
        ));
    };
    let material = p.material.elastic;
    let n = 2 * (method.grid.nx + 1) * (method.grid.ny + 1);
    memory::check(
        &format!("the FEM plate of {n} unknowns"),
        n as f64 * memory::BYTES_PER_DOF,
    )?;
    let SeamedMesh {
        mesh,
        mouth,
        seam_y,
        seam_length,
        warning,
    } = seamed_mesh(p, method)?;
    let model = FemModel::with_domain(mesh, material, method.gauss, &p.domain)?;
    let edges = PlateEdges::of_mesh(&model.mesh);
    let active = model
        .fictitious
        .as_ref()
        .map_or_else(Vec::new, |fd| fd.active_nodes(model.mesh.n_nodes()));
    let t = material.thickness;
    let (bc, mut f, anchor, regions) = match p.boundary.grips() {
        Some(load) => {
            let (bc, f, anchor) = plate_conditions(&edges, &load, model.n_dofs(), t)?;
            (bc, f, anchor, None)
        }
        None => {
            let crate::problem::Boundary::Regions { supports, loads } = &p.boundary else {
                unreachable!("grips() is None only for regions")
            };
            let rc = region_conditions(
                &model.mesh,
                &p.domain,
                &active,
                supports,
                loads,
                model.n_dofs(),
                t,
            )?;
            (rc.bc.clone(), rc.f.clone(), usize::MAX, Some(rc))
        }
    };
    let bc = model.constrain(bc, &mut f)?;
    let sys = LinearSystem::with_positions(model.stiffness(), &bc, Some(&model.dof_positions()))?;
    let condition = sys.checked_condition("solve", method.condition)?;
    let sol = sys.solve(&f, 1.0)?;
    let (s22, mut responses) = match &regions {
        None => (
            sigma22(&edges, &sol.reactions, &f, p.domain.width, t),
            SceneResponses::default(),
        ),
        Some(rc) => (
            rc.primary_response(&sol.u, &sol.reactions, &f, t).0,
            rc.responses(&sol.u, &sol.reactions, t),
        ),
    };
    responses.probes = probes(p, &model.mesh, &sol.u, mouth)?;
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
        responses,
        seam_y,
        seam_length,
        wall_time_s: t0.elapsed().as_secs_f64(),
        condition,
        warnings: material
            .locking_warning()
            .into_iter()
            .chain(
                condition
                    .as_ref()
                    .and_then(|c| condition_warning("solve", c)),
            )
            .chain(warning)
            .chain(model.fictitious.iter().flat_map(|f| f.warnings.clone()))
            .collect(),
    })
}

/// The probes of a FEM run: displacements interpolated in the element holding the point; an
/// opening across the seam at the seam node pair nearest the point ([normal, sliding] jump,
/// upper minus lower face).
fn probes(
    p: &Problem,
    mesh: &Mesh,
    u: &[f64],
    mouth: Option<(usize, usize)>,
) -> Result<Vec<(String, [f64; 2])>> {
    use crate::problem::ProbeKind;
    p.probes
        .iter()
        .enumerate()
        .map(|(k, pr)| {
            let v = match pr.kind {
                ProbeKind::Displacement(q) => {
                    let (e, xi, eta) = mesh.locate(q[0], q[1]).ok_or_else(|| {
                        Error::invalid(
                            &format!("probe[{k}].point"),
                            "a point on the plate",
                            format!("{q:?}"),
                        )
                    })?;
                    let n = crate::fe::q4::shape(xi, eta);
                    let c = mesh.elements[e];
                    let at = |comp: usize| (0..4).map(|i| n[i] * u[2 * c[i] + comp]).sum::<f64>();
                    [at(0), at(1)]
                }
                ProbeKind::Opening { point, .. } => {
                    let Some(_) = mouth else {
                        return Err(Error::invalid(
                            &format!("probe[{k}].kind"),
                            "'displacement' (this FEM scene has no seam crack to open)",
                            "'opening'",
                        ));
                    };
                    let (lo, up) = mesh
                        .duplicate_of
                        .iter()
                        .map(|&(dup, orig)| (orig, dup))
                        .min_by(|a, b| {
                            let d = |n: usize| {
                                (mesh.coords[n][0] - point[0]).hypot(mesh.coords[n][1] - point[1])
                            };
                            d(a.0).total_cmp(&d(b.0))
                        })
                        .unwrap_or((0, 0));
                    // the seam runs along x1: the duplicate is the upper face
                    [u[2 * up + 1] - u[2 * lo + 1], u[2 * up] - u[2 * lo]]
                }
            };
            Ok((pr.name.clone(), v))
        })
        .collect()
}

/// The cracks as the FEM cuts them (a seam on the grid line nearest its y, from x1 = 0 to the
/// first grid node at or beyond a0; a problem without a seam: as asked).
pub fn cut_polylines(p: &Problem) -> Result<Vec<Vec<[f64; 2]>>> {
    let mut lines = p.crack_polylines();
    if let Method::Fem(method) = &p.method {
        let m = seamed_mesh(p, method)?;
        if let (Some(y), Some(len), Some(k)) = (
            m.seam_y,
            m.seam_length,
            p.cracks.iter().position(|c| c.kind == CrackKind::Seam),
        ) {
            lines[k] = vec![[0.0, y], [len, y]];
        }
    }
    Ok(lines)
}

/// The uniform grid over the plate; with a seam crack, its nodes duplicated along the grid line
/// nearest the crack's y, from x1 = 0 to a0. The refusals that need the grid name the crack's
/// scene keys.
fn seamed_mesh(p: &Problem, method: &FemMethod) -> Result<SeamedMesh> {
    let (d, grid) = (&p.domain, &method.grid);
    let mesh = Mesh::of_grid(grid, d)?;
    let Some((k, c)) = p
        .cracks
        .iter()
        .enumerate()
        .find(|(_, c)| c.kind == CrackKind::Seam)
    else {
        return Ok(SeamedMesh {
            mesh,
            mouth: None,
            seam_y: None,
            seam_length: None,
            warning: None,
        });
    };
    let (j, _) = Mesh::nearest_line(&mesh.ys, c.y);
    if j == 0 || j >= grid.ny {
        return Err(Error::invalid(
            &format!("{}.y", crack_name(k)),
            &format!(
                "a seam nearer an interior grid line than the bottom and top edges (mesh.ny = {})",
                grid.ny
            ),
            c.y,
        ));
    }
    let (m, pairs) = mesh.with_seam(j, c.a0).map_err(|e| match e {
        Error::InvalidInput { expected, got, .. } => Error::InvalidInput {
            param: format!("{}.a0", crack_name(k)),
            expected: format!("a seam crack of {expected}"),
            got,
        },
        e => e,
    })?;
    // the seam ends at the first grid node not duplicated: at or beyond a0
    let tip = pairs.len();
    let nx = grid.nx;
    if tip >= nx {
        return Err(Error::invalid(
            &format!("{}.a0", crack_name(k)),
            &format!(
                "a seam that leaves at least one element of ligament: a0 <= {:.6} (the last \
                 interior node of the seam's grid line, mesh.nx = {nx})",
                mesh.xs[nx - 1] - mesh.xs[0]
            ),
            c.a0,
        ));
    }
    let length = mesh.xs[tip] - mesh.xs[0];
    let y = mesh.ys[j];
    let moved = (y - c.y).abs() > 1e-9 * d.height;
    let mut warnings = Vec::new();
    if (length - c.a0).abs() > 1e-9 * d.width {
        warnings.push(format!(
            "the seam crack runs along grid lines from node to node: its real length is \
             {length:.6} (the first grid node at or beyond {}.a0 = {}); refine mesh.nx or \
             choose a0 on a node to cut exactly a0",
            crack_name(k),
            c.a0
        ));
    }
    if moved {
        warnings.push(format!(
            "the seam crack lies on a grid line: it is cut at x2 = {y:.6}, the grid line \
             nearest {}.y = {} (moved by {:.6}); refine mesh.ny or choose y on a grid line to \
             cut it where asked",
            crack_name(k),
            c.y,
            y - c.y
        ));
    }
    let warning = (!warnings.is_empty())
        .then(|| Warning::new(WarningKind::Discretisation, warnings.join("; ")));
    Ok(SeamedMesh {
        seam_y: Some(m.ys[j]),
        seam_length: Some(length),
        warning,
        mouth: Some(pairs[0]),
        mesh: m,
    })
}
