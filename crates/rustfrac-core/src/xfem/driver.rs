//! The plate driver of the XFEM model: [`run`] reads a [`Problem`] (domain, material, grips,
//! cracks and [`XfemMethod`]), builds the model, solves at the reference load, reports the SIFs,
//! and optionally grows the cracks ([`crate::xfem::growth`]).

use super::condensed::CondensedSolver;
use super::growth::{grow, shrunk_warning, GrowthStatus, GrowthStep, TipStep};
use super::growth_state::GrowthState;
use super::interaction_integral::DomainSifs;
use super::model::XfemModel;
use super::patch::CutCells;
use super::patch::DeformedPatch;
use super::plate::{check_tip_clearance, PlateProblem, PlateSolve};
use crate::error::{Error, Result};
use crate::fe::loading::PlateEdges;
use crate::fe::mesh::Mesh;
use crate::fe::regions::SceneResponses;
use crate::la::{condition_warning, ConditionEstimate};
use crate::problem::{validate, Method, Problem, XfemMethod};
use crate::warning::Warning;
use std::sync::Arc;

/// SIFs at one radius.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RadiusSifs {
    /// radius in tip-element lengths
    pub factor: f64,
    pub sifs: DomainSifs,
}

/// Result of [`run`].
#[derive(Debug, Clone)]
pub struct XfemResult {
    /// node coordinates of the mesh
    pub coords: Vec<[f64; 2]>,
    /// the mesh's Q4 elements (node indices, counter-clockwise)
    pub elements: Vec<[usize; 4]>,
    /// displacements of the initial crack at the reference load (standard then enriched dofs)
    pub u: Vec<f64>,
    /// nodal reactions K u - f of the standard dofs at the reference load, interleaved [r1, r2]
    pub reactions: Vec<f64>,
    pub n_dofs: usize,
    pub n_std: usize,
    /// Heaviside enrichments (nodes, summed over the cracks: a node enriched for two cracks
    /// counts twice)
    pub n_heaviside_nodes: usize,
    pub n_tip_nodes: usize,
    /// nodes dropped by the small-area rule, summed over the cracks
    pub n_dropped_nodes: usize,
    /// Heaviside-enriched nodes of any crack (sorted, each once)
    pub heaviside_nodes: Vec<usize>,
    pub tip_nodes: Vec<usize>,
    /// SIFs at r_I of the primary tip (the last polyline point if it is a tip) at the reference
    /// load
    pub k_i: f64,
    pub k_ii: f64,
    pub j_from_k: f64,
    pub j_domain: f64,
    /// r_I (absolute) of the primary tip's SIFs: `xfem.r_I` element sizes, or less where a hole
    /// would enter the domain ([`XfemModel::hole_free_radius`])
    pub r_i: f64,
    /// SIFs of the primary tip at r_I and at the extra radii, sorted by radius
    pub radii: Vec<RadiusSifs>,
    /// SIFs at r_I for every tip (global tip order, see [`XfemModel`]): (tip position, sifs)
    pub tips: Vec<([f64; 2], DomainSifs)>,
    /// the crack (index into `cracks`) of each entry of `tips`
    pub tip_crack: Vec<usize>,
    /// mean normal stress on the top edge from the reactions, at the reference load
    pub sigma22: f64,
    /// crack mouth opening (edge crack) or centre opening (interior crack) at the reference load
    pub cmod: f64,
    /// the grip condition that ran ("free", "clamped", "traction")
    pub grip: String,
    /// the node carrying the rigid-body anchor (bottom-right corner; none with supports on
    /// regions)
    pub anchor_node: usize,
    /// supports, loads and probes at the reference load (initial crack)
    pub responses: SceneResponses,
    /// growth runs: the responses at every point of `history` (scaled by its load factor)
    pub response_history: Vec<SceneResponses>,
    /// growth history: `history[0]` is the unloaded origin (lambda = 0, all loads zero, initial
    /// crack), so the initial loading branch from (0, 0) is part of the curve; then one critical
    /// state per crack length. Empty without growth.
    pub history: Vec<GrowthStep>,
    /// every tip's state at each point of `history`: `tip_history[k][t]` belongs to `history[k]`
    /// and global tip t (the origin row has zero SIFs); empty without growth
    pub tip_history: Vec<Vec<TipStep>>,
    /// why the run stopped ([`GrowthStatus::SingleSolve`] without growth)
    pub status: GrowthStatus,
    /// final polyline of the primary crack
    pub crack: Vec<[f64; 2]>,
    /// final polylines of all cracks (`cracks[0]` is `crack`)
    pub cracks: Vec<Vec<[f64; 2]>>,
    /// deformed-mesh cells near the primary tip of the initial crack (5 element lengths around it,
    /// 4 x 4 cells per element)
    pub deformed: DeformedPatch,
    /// the enriched elements of the initial crack as cells on each side of the crack with their
    /// own displacements at the reference load (files: [`XfemModel::cut_cells`], 2 x 2 cells per
    /// element)
    pub cut: CutCells,
    /// the enriched stresses at the 2 x 2 Gauss points of every element (initial crack,
    /// reference load): points and [s11, s22, s12]
    pub gauss_points: Vec<[f64; 2]>,
    pub gauss_stress: Vec<[f64; 3]>,
    /// growth runs: the deformed patch around the growing tip at every critical state
    /// (displacements at the critical load, i.e. scaled by lambda), for Fig. 8b
    pub snapshots: Vec<DeformedPatch>,
    /// growth runs: the whole plate at the kept critical states (`xfem.state_every`: every
    /// k-th step and the last), in history order; empty without growth
    pub states: Vec<GrowthState>,
    /// condition estimate of the initial crack's solve (see [`ConditionEstimate`]); None when
    /// not computed ([`XfemMethod::condition`] false)
    pub condition: Option<ConditionEstimate>,
    /// numerical and accuracy warnings (a condition estimate above [`crate::la::COND_WARN`],
    /// volumetric locking near nu = 0.5, [`crate::problem::Elastic::locking_warning`])
    pub warnings: Vec<Warning>,
}

/// Runs the XFEM plate model of `problem` (method [`Method::Xfem`]): a single solve with SIFs at
/// the reference load, and with `growth = Some(..)` quasi-static LEFM growth (the criterion, the
/// load factor of each step, the extension of the critical tips and the stop statuses:
/// [`crate::xfem::growth`]). `progress(step, max_steps)` is called after each step; returning
/// `false` stops the growth with the steps so far (status `cancelled`).
///
/// Phases: `build` (validation, mesh, model), the initial solve, `initial_result` (SIFs at
/// every tip and radius, node sets, deformed patch), and the growth loop. Errors name the scene
/// key to change ("mesh.nx", "crack.a0", "xfem.r_I", ...).
pub fn run(
    problem: &Problem,
    progress: &(dyn Fn(usize, usize) -> bool + Sync),
) -> Result<XfemResult> {
    run_with(problem, progress, false)
}

/// [`run`] with the growth's reference solves: the initial solve and every growth step assemble
/// and factorise the whole system instead of condensing onto the enriched dofs
/// ([`crate::xfem::condensed`]); the oracle of the condensed growth (tests, benchmarks). Without
/// growth, the same as [`run`] (a single solve is never condensed).
pub fn run_reference(
    problem: &Problem,
    progress: &(dyn Fn(usize, usize) -> bool + Sync),
) -> Result<XfemResult> {
    run_with(problem, progress, true)
}

fn run_with(
    problem: &Problem,
    progress: &(dyn Fn(usize, usize) -> bool + Sync),
    reference: bool,
) -> Result<XfemResult> {
    let (x, model, plate) = build(problem)?;
    // a growth run condenses every solve onto the enriched dofs, the initial one included
    let mut condensed = (x.growth.is_some() && !reference).then(CondensedSolver::default);
    let first = match condensed.as_mut() {
        Some(c) => c.solve(&plate, &model, "initial solve")?,
        None => plate.solve(&model, "initial solve")?,
    };
    let mut res = initial_result(problem, x, &model, &first)?;
    let Some(g) = x.growth else {
        let _ = progress(1, 1);
        return Ok(res);
    };
    let g0 = problem.material.g0;
    let growth = grow(
        model,
        first,
        &plate,
        (&g, g0),
        (x.r_i, x.tip_tie_tol),
        progress,
        condensed,
    )?;
    res.history = growth.history;
    res.response_history = growth.responses;
    res.tip_history = growth.tip_history;
    res.snapshots = growth.snapshots;
    res.states = growth.states;
    res.warnings.extend(growth.warnings);
    if let Some(stop) = growth.status {
        res.status = stop;
    }
    res.crack = growth.cracks[0].clone();
    res.cracks = growth.cracks;
    Ok(res)
}

/// The XFEM options of `p`, after the problem's rules ([`validate::problem`],
/// [`validate::reference_load`]) and the driver's own: at least 2 elements each way.
fn checked(p: &Problem) -> Result<&XfemMethod> {
    validate::problem(p)?;
    validate::reference_load(p)?;
    let Method::Xfem(x) = &p.method else {
        return Err(Error::invalid(
            "method",
            "'xfem' (the XFEM driver)",
            p.method.name(),
        ));
    };
    for (n, key) in [(x.grid.nx, "mesh.nx"), (x.grid.ny, "mesh.ny")] {
        if n < 2 {
            return Err(Error::invalid(key, "an integer >= 2 (XFEM)", n));
        }
    }
    Ok(x)
}

/// Validates the problem and builds the mesh, the model of the initial cracks (refusing tips
/// closer to the boundary than [`crate::xfem::MIN_TIP_CLEARANCE`]) and the plate problem.
fn build(p: &Problem) -> Result<(&XfemMethod, XfemModel, PlateProblem)> {
    let x = checked(p)?;
    let d = &p.domain;
    let n = 2 * (x.grid.nx + 1) * (x.grid.ny + 1);
    crate::memory::check(
        &format!("the XFEM plate of {n} standard unknowns"),
        n as f64 * crate::memory::BYTES_PER_DOF,
    )?;
    let mesh = Arc::new(Mesh::of_grid(&x.grid, d)?);
    let edges = PlateEdges::of_mesh(&mesh);
    let model = XfemModel::new_in_domain(
        mesh.clone(),
        p.material.elastic,
        p.crack_polylines(),
        x.options,
        d,
    )?;
    check_tip_clearance(&model)?;
    let plate = PlateProblem {
        edges,
        load: p.boundary.plate_load(),
        width: d.width,
        height: d.height,
        condition: x.condition,
        boundary: p.boundary.clone(),
        domain: d.clone(),
        probes: p.probes.clone(),
    };
    Ok((x, model, plate))
}

/// An error of the model's SIF domain check ("r_I", an absolute radius) named by the scene key
/// `key` of the radius factor.
fn radius_key(e: Error, key: &str) -> Error {
    match e {
        Error::InvalidInput {
            param,
            expected,
            got,
        } if param == "r_I" => Error::InvalidInput {
            param: key.to_string(),
            expected,
            got,
        },
        e => e,
    }
}

/// The SIFs of the initial solve `u`: r_I of the primary tip, (position, SIFs at r_I) of every
/// tip, and the primary tip's SIFs at r_I and at those extra radii whose q-domain neither the
/// other tip of its crack nor another crack nor a hole enters (the others are dropped), sorted by
/// radius. Where a hole would enter a tip's r_I domain, it is shrunk clear of it
/// ([`XfemModel::sifs_clear_of_holes`], the radius used is that tip's [`DomainSifs::radius`]).
#[allow(clippy::type_complexity)]
fn initial_sifs(
    x: &XfemMethod,
    model: &XfemModel,
    u: &[f64],
) -> Result<(f64, Vec<([f64; 2], DomainSifs)>, Vec<RadiusSifs>)> {
    let h_tip = model.tip_element_size(0);
    let mut tips = Vec::new();
    for t in 0..model.tips.len() {
        let r = x.r_i * model.tip_element_size(t);
        let s = model
            .sifs_clear_of_holes(u, t, r)
            .map_err(|e| radius_key(e, "xfem.r_I"))?;
        tips.push((model.tips[t].pos, s));
    }
    let main = tips[0].1;
    let r_i = main.radius;
    let mut radii = vec![RadiusSifs {
        factor: x.r_i,
        sifs: main,
    }];
    for &f in &x.extra_radii {
        let r = f * h_tip;
        if model.other_tip_in_domain(0, r)
            || model.other_crack_in_domain(0, r).is_some()
            || model.hole_in_domain(0, r).is_some()
        {
            continue;
        }
        radii.push(RadiusSifs {
            factor: f,
            sifs: model
                .sifs(u, 0, r)
                .map_err(|e| radius_key(e, "xfem.extra_radii"))?,
        });
    }
    radii.sort_by(|a, b| a.factor.total_cmp(&b.factor));
    Ok((r_i, tips, radii))
}

/// The result of the initial solve (status single_solve; the growth fields empty).
fn initial_result(
    p: &Problem,
    x: &XfemMethod,
    model: &XfemModel,
    first: &PlateSolve,
) -> Result<XfemResult> {
    let (r_i, tips, radii) = initial_sifs(x, model, &first.u)?;
    let shrunk: Vec<(usize, usize, f64)> = tips
        .iter()
        .enumerate()
        .filter(|(t, (_, s))| s.radius < x.r_i * model.tip_element_size(*t))
        .map(|(t, (_, s))| (0, t, s.radius / model.tip_element_size(t)))
        .collect();
    let main = tips[0].1;
    let h_tip = model.tip_element_size(0);
    let deformed = model.deformed_near_tip(&first.u, 0, 5.0 * h_tip, 4)?;
    let (gauss_points, gauss_stress) = model.gauss_stresses(&first.u);
    let mut tip_nodes: Vec<usize> = model.tip_nodes.iter().flatten().copied().collect();
    tip_nodes.sort_unstable();
    tip_nodes.dedup();
    let mut heaviside_nodes: Vec<usize> = model.heaviside_nodes.iter().flatten().copied().collect();
    heaviside_nodes.sort_unstable();
    heaviside_nodes.dedup();
    Ok(XfemResult {
        coords: model.mesh.coords.clone(),
        elements: model.mesh.elements.clone(),
        u: first.u.clone(),
        reactions: first.reactions.clone(),
        n_dofs: model.n_dofs,
        n_std: model.n_std,
        n_heaviside_nodes: model.heaviside_nodes.iter().map(Vec::len).sum(),
        n_tip_nodes: tip_nodes.len(),
        n_dropped_nodes: model.dropped_nodes.iter().map(Vec::len).sum(),
        heaviside_nodes,
        tip_nodes,
        k_i: main.k_i,
        k_ii: main.k_ii,
        j_from_k: main.j_from_k,
        j_domain: main.j_domain,
        r_i,
        radii,
        tips,
        tip_crack: model.tip_crack.clone(),
        sigma22: first.sigma22,
        cmod: first.cmod,
        grip: p.boundary.name().to_string(),
        anchor_node: first.anchor,
        responses: first.responses.clone(),
        response_history: Vec::new(),
        history: Vec::new(),
        tip_history: Vec::new(),
        status: GrowthStatus::SingleSolve,
        crack: model.cracks[0].points.clone(),
        cracks: model.cracks.iter().map(|c| c.points.clone()).collect(),
        deformed,
        cut: model.cut_cells(&first.u, 2)?,
        gauss_points,
        gauss_stress,
        snapshots: Vec::new(),
        states: Vec::new(),
        condition: first.condition,
        warnings: p
            .material
            .elastic
            .locking_warning()
            .into_iter()
            .chain(
                first
                    .condition
                    .as_ref()
                    .and_then(|c| condition_warning("initial solve", c)),
            )
            .chain(model.fictitious.iter().flat_map(|f| f.warnings.clone()))
            .chain(shrunk_warning(&shrunk, x.r_i, "initial crack"))
            .collect(),
    })
}
