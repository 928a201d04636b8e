//! The plate driver of the XFEM model: the parameters of the paper's benchmark plate (and
//! variants), their validation, and [`run`]: build the model, solve at the reference load, report
//! the SIFs, and optionally grow the cracks ([`crate::xfem::growth`]).

use super::enrichment::DEFAULT_AREA_THRESHOLD;
use super::growth::{grow, GrowthParams, GrowthStep, TipStep};
use super::interaction_integral::DomainSifs;
use super::model::{XfemModel, XfemOptions};
use super::patch::DeformedPatch;
use super::plate::{check_tip_clearance, PlateProblem, PlateSolve};
use crate::error::{check_finite, check_positive, Error, Result};
use crate::loading::{Grip, PlateEdges, PlateLoad};
use crate::material::Elastic;
use crate::mesh::Mesh;
use crate::solver::{condition_warning, ConditionEstimate};
use crate::warning::Warning;
use std::sync::Arc;

/// Everything the plate driver needs (the paper's benchmark: width 11, height 21, 44 x 83).
#[derive(Debug, Clone)]
pub struct XfemParams {
    /// plate width (x1) and height (x2); the plate is [0, width] x [0, height]
    pub width: f64,
    pub height: f64,
    /// elements along x1 and x2
    pub nx: usize,
    pub ny: usize,
    pub material: Elastic,
    /// crack polyline (the primary crack); an edge crack starts (or ends) on the boundary
    pub crack: Vec<[f64; 2]>,
    /// further cracks (polylines), for a plate with several cracks (empty: one crack)
    pub extra_cracks: Vec<Vec<[f64; 2]>>,
    /// reference load (u0 for displacement grips, traction for `Grip::Traction`)
    pub load: PlateLoad,
    pub nsub: usize,
    pub tip_nsub: usize,
    /// r_I in tip-element lengths (paper: 2.5)
    pub r_i_factor: f64,
    /// further radii (in element lengths) at which the SIFs are reported
    pub extra_radius_factors: Vec<f64>,
    pub fixed_area_radius: Option<f64>,
    pub area_threshold: f64,
    pub growth: Option<GrowthParams>,
    /// compute the condition estimate of every solve (2 extra solves each); without it
    /// `condition` is None, the history's is None, and only the free pivot-ratio bound guards
    /// against [`crate::solver::COND_SINGULAR`]
    pub condition: bool,
}

impl XfemParams {
    /// The paper's case (section 3; DESIGN.md section 2): E = 10000, nu = 0.25, plane strain,
    /// 11 x 21 plate, 44 x 83 elements, edge crack along x2 = 10.5 to a0 = 1.1, u0 = 0.01.
    pub fn paper(grip: Grip) -> Self {
        use crate::material::Plane;
        Self {
            width: 11.0,
            height: 21.0,
            nx: 44,
            ny: 83,
            material: Elastic {
                e: 10000.0,
                nu: 0.25,
                plane: Plane::Strain,
                thickness: 1.0,
            },
            crack: vec![[0.0, 10.5], [1.1, 10.5]],
            extra_cracks: Vec::new(),
            load: PlateLoad {
                grip,
                u0: 0.01,
                traction: 9.993,
            },
            nsub: 4,
            tip_nsub: 4,
            r_i_factor: 2.5,
            extra_radius_factors: vec![1.5, 2.0, 3.0, 3.5],
            fixed_area_radius: None,
            area_threshold: DEFAULT_AREA_THRESHOLD,
            growth: None,
            condition: true,
        }
    }
}

impl XfemParams {
    /// All cracks: `crack` followed by `extra_cracks`.
    pub fn cracks(&self) -> Vec<Vec<[f64; 2]>> {
        std::iter::once(self.crack.clone())
            .chain(self.extra_cracks.iter().cloned())
            .collect()
    }
}

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
    /// displacements of the initial crack at the reference load (standard then enriched dofs)
    pub u: Vec<f64>,
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
    /// r_I (absolute)
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
    /// the node carrying the rigid-body anchor (bottom-right corner)
    pub anchor_node: usize,
    /// growth history: history[0] is the unloaded origin (lambda = 0, all loads zero, initial
    /// crack), so the initial loading branch from (0, 0) is part of the curve; then one critical
    /// state per crack length. Empty without growth.
    pub history: Vec<GrowthStep>,
    /// every tip's state at each point of `history`: `tip_history[k][t]` belongs to `history[k]`
    /// and global tip t (the origin row has zero SIFs); empty without growth
    pub tip_history: Vec<Vec<TipStep>>,
    /// why the run stopped: "single solve", "a_stop reached", "ligament used up",
    /// "max_steps reached", "cracks meet" or "crack closes (K_eq <= 0)"
    pub status: String,
    /// final polyline of the primary crack
    pub crack: Vec<[f64; 2]>,
    /// final polylines of all cracks (`cracks[0]` is `crack`)
    pub cracks: Vec<Vec<[f64; 2]>>,
    /// deformed-mesh cells near the primary tip of the initial crack (5 element lengths around it,
    /// 4 x 4 cells per element)
    pub deformed: DeformedPatch,
    /// growth runs: the deformed patch around the growing tip at every critical state
    /// (displacements at the critical load, i.e. scaled by lambda), for Fig. 8b
    pub snapshots: Vec<DeformedPatch>,
    /// condition estimate of the initial crack's solve (see [`ConditionEstimate`]); None when
    /// not computed ([`XfemParams::condition`] false)
    pub condition: Option<ConditionEstimate>,
    /// numerical and accuracy warnings (a condition estimate above
    /// [`crate::solver::COND_WARN`], volumetric locking near nu = 0.5, [`Elastic::locking_warning`])
    pub warnings: Vec<Warning>,
}

fn validate(p: &XfemParams) -> Result<()> {
    check_positive("width", p.width)?;
    check_positive("height", p.height)?;
    if p.nx < 2 {
        return Err(Error::invalid("nx", "an integer >= 2", p.nx));
    }
    if p.ny < 2 {
        return Err(Error::invalid("ny", "an integer >= 2", p.ny));
    }
    if p.nx.saturating_mul(p.ny) > 20_000_000 {
        return Err(Error::invalid(
            "nx * ny",
            "at most 2e7 elements",
            p.nx * p.ny,
        ));
    }
    Elastic::new(
        p.material.e,
        p.material.nu,
        p.material.plane,
        p.material.thickness,
    )?;
    check_finite("u0", p.load.u0)?;
    check_finite("traction", p.load.traction)?;
    match p.load.grip {
        Grip::Traction if p.load.traction == 0.0 => {
            return Err(Error::invalid(
                "traction",
                "a non-zero reference traction",
                0.0,
            ))
        }
        Grip::Free | Grip::Clamped if p.load.u0 == 0.0 => {
            return Err(Error::invalid(
                "u0",
                "a non-zero reference displacement",
                0.0,
            ))
        }
        _ => {}
    }
    if !(p.r_i_factor.is_finite() && p.r_i_factor >= 0.5 && p.r_i_factor <= 20.0) {
        return Err(Error::invalid(
            "r_i_factor",
            "0.5 <= r_i_factor <= 20 element lengths",
            p.r_i_factor,
        ));
    }
    for &f in &p.extra_radius_factors {
        if !(f.is_finite() && (0.5..=20.0).contains(&f)) {
            return Err(Error::invalid(
                "extra_radius_factors",
                "values in 0.5..=20 element lengths",
                f,
            ));
        }
    }
    if let Some(g) = &p.growth {
        check_positive("g0", g.g0)?;
        if let Some(da) = g.da {
            check_positive("da", da)?;
        }
        check_positive("a_stop", g.a_stop)?;
        if g.max_steps == 0 || g.max_steps > 100_000 {
            return Err(Error::invalid("max_steps", "1..=100000", g.max_steps));
        }
    }
    Ok(())
}

/// Runs the XFEM plate model: a single solve with SIFs at the reference load, and with
/// `growth = Some(..)` quasi-static LEFM growth (the criterion, the load factor of each step, the
/// extension of the critical tips and the stop statuses: [`crate::xfem::growth`]).
/// `progress(step, max_steps)` is called after each step.
///
/// Phases: `build` (validation, mesh, model), the initial solve, `initial_result` (SIFs at
/// every tip and radius, node sets, deformed patch), and the growth loop.
pub fn run(params: &XfemParams, progress: &(dyn Fn(usize, usize) + Sync)) -> Result<XfemResult> {
    let (model, plate) = build(params)?;
    let first = plate.solve(&model, "initial solve")?;
    let mut res = initial_result(params, &model, &first)?;
    let Some(g) = params.growth else {
        progress(1, 1);
        return Ok(res);
    };
    let growth = grow(model, first, &plate, &g, params.r_i_factor, progress)?;
    res.history = growth.history;
    res.tip_history = growth.tip_history;
    res.snapshots = growth.snapshots;
    res.warnings.extend(growth.warnings);
    if let Some(stop) = growth.status {
        res.status = stop.name().into();
    }
    res.crack = growth.cracks[0].clone();
    res.cracks = growth.cracks;
    Ok(res)
}

/// Validates the parameters and builds the mesh, the model of the initial cracks (refusing tips
/// closer to the boundary than [`crate::xfem::MIN_TIP_CLEARANCE`]) and the plate problem.
fn build(params: &XfemParams) -> Result<(XfemModel, PlateProblem)> {
    validate(params)?;
    let mesh = Arc::new(Mesh::uniform(
        0.0,
        0.0,
        params.width,
        params.height,
        params.nx,
        params.ny,
    )?);
    let opts = XfemOptions {
        nsub: params.nsub,
        tip_nsub: params.tip_nsub,
        fixed_area_radius: params.fixed_area_radius,
        area_threshold: params.area_threshold,
    };
    let edges = PlateEdges::of_mesh(&mesh);
    let model = XfemModel::new_multi(mesh.clone(), params.material, params.cracks(), opts)?;
    check_tip_clearance(&model)?;
    let plate = PlateProblem {
        edges,
        load: params.load,
        width: params.width,
        height: params.height,
        condition: params.condition,
    };
    Ok((model, plate))
}

/// The SIFs of the initial solve `u`: r_I of the primary tip, (position, SIFs at r_I) of every
/// tip, and the primary tip's SIFs at r_I and the extra radii, sorted by radius.
#[allow(clippy::type_complexity)]
fn initial_sifs(
    params: &XfemParams,
    model: &XfemModel,
    u: &[f64],
) -> Result<(f64, Vec<([f64; 2], DomainSifs)>, Vec<RadiusSifs>)> {
    let h_tip = model.tip_element_size(0);
    let r_i = params.r_i_factor * h_tip;
    let mut tips = Vec::new();
    for t in 0..model.tips.len() {
        let r = params.r_i_factor * model.tip_element_size(t);
        tips.push((model.tips[t].pos, model.sifs(u, t, r)?));
    }
    let main = tips[0].1;
    let mut radii = vec![RadiusSifs {
        factor: params.r_i_factor,
        sifs: main,
    }];
    for &f in &params.extra_radius_factors {
        radii.push(RadiusSifs {
            factor: f,
            sifs: model.sifs(u, 0, f * h_tip)?,
        });
    }
    radii.sort_by(|a, b| a.factor.total_cmp(&b.factor));
    Ok((r_i, tips, radii))
}

/// The result of the initial solve (status "single solve"; the growth fields empty).
fn initial_result(
    params: &XfemParams,
    model: &XfemModel,
    first: &PlateSolve,
) -> Result<XfemResult> {
    let (r_i, tips, radii) = initial_sifs(params, model, &first.u)?;
    let main = tips[0].1;
    let h_tip = model.tip_element_size(0);
    let deformed = model.deformed_near_tip(&first.u, 0, 5.0 * h_tip, 4)?;
    let mut tip_nodes: Vec<usize> = model.tip_nodes.iter().flatten().copied().collect();
    tip_nodes.sort_unstable();
    tip_nodes.dedup();
    let mut heaviside_nodes: Vec<usize> = model.heaviside_nodes.iter().flatten().copied().collect();
    heaviside_nodes.sort_unstable();
    heaviside_nodes.dedup();
    Ok(XfemResult {
        u: first.u.clone(),
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
        grip: params.load.grip.name().to_string(),
        anchor_node: first.anchor,
        history: Vec::new(),
        tip_history: Vec::new(),
        status: "single solve".into(),
        crack: model.cracks[0].points.clone(),
        cracks: model.cracks.iter().map(|c| c.points.clone()).collect(),
        deformed,
        snapshots: Vec::new(),
        condition: first.condition,
        warnings: params
            .material
            .locking_warning()
            .into_iter()
            .chain(
                first
                    .condition
                    .as_ref()
                    .and_then(|c| condition_warning("initial solve", c)),
            )
            .collect(),
    })
}
