//! Quasi-static LEFM crack growth (paper section 2.1.3): the growth loop of the plate driver
//! ([`crate::xfem::run`] with `growth = Some(..)`), by the maximum circumferential stress
//! criterion ([`super::criterion`]).
//!
//! Proportional loading; lambda is set by the most critical tip: for the current cracks solve
//! once at the reference load and take, at every tip, K_I and K_II at r_I (r_I_factor times that
//! tip's element size), the Erdogan-Sih kink angle theta_c and K_eq. The tip's critical load
//! factor is lambda_t = K_Ic / K_eq (K_Ic = sqrt(G0 E'); tips with K_eq <= 0 never become
//! critical) and the step's load factor is lambda = min_t lambda_t. The linear solution scaled by
//! lambda is the critical state, recorded as (lambda, lambda sigma22, lambda CMOD, lambda u0, a,
//! lambda K_I, lambda K_II, theta_c, tip) of the most critical tip (the first one in tip order on
//! ties), with every tip's state in `tip_history`. Every tip with lambda_t <= lambda (1 + tip_tie_tol) (scene key `xfem.tip_tie_tol`, 1e-6)
//! then advances (so symmetric tips grow together) by `da` (or its own tip element's chord) in
//! the direction theta_c from its current direction (`xfem.kink_rule = "hoop"`, the default; or
//! the predictor-corrector's direction, [`super::kink`]); the other tips stay. The run stops with
//! [`GrowthStatus`] `a_stop_reached` once the next length `a` of a crack would exceed `a_stop`,
//! `ligament_used_up` when a new tip would come closer to the plate boundary than
//! [`MIN_TIP_CLEARANCE`] element lengths (the mesh no longer resolves the remaining ligament),
//! `cracks_meet` when the grown cracks would cross or touch each other or put tips of two cracks
//! in one element, or another crack would enter a tip's SIF domain (coalescence is not
//! modelled), `max_steps_reached`, or `crack_closes` (K_eq <= 0).
//!
//! Holes and notches: where one would enter a tip's SIF domain, the q-radius is shrunk to the
//! largest one that excludes it ([`XfemModel::hole_free_radius`]; the domain form has no
//! hole-boundary term), recorded per step (`r_i` of [`GrowthStep`] and [`TipStep`]) with one
//! warning per run; growth stops with `ligament_used_up` once it would have to shrink below
//! [`MIN_HOLE_FREE_RADIUS`] element sizes (or a new tip comes closer to the hole than
//! [`MIN_TIP_CLEARANCE`] element lengths).

use super::condensed::CondensedSolver;
use super::crack::{Crack, CRACKS_APART};
use super::criterion::{k_equivalent, kink_angle};
use super::enrichment::TIPS_APART;
use super::growth_state::{GrowthState, KeptStates};
use super::interaction_integral::{DomainSifs, MIN_HOLE_FREE_RADIUS};
use super::kink::{corrected_angle, trial_angles};
use super::model::XfemModel;
use super::patch::DeformedPatch;
use super::plate::{PlateProblem, PlateSolve, MIN_TIP_CLEARANCE};
use crate::error::{Error, Result};
use crate::la::condition_warning;
use crate::problem::{Grip, Growth as GrowthOptions, KinkRule};
use crate::warning::Warning;

/// One point of the load path: the critical state of one crack configuration (or the origin).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GrowthStep {
    /// load factor on the reference load (0 for the origin point)
    pub lambda: f64,
    pub sigma22: f64,
    pub cmod: f64,
    /// prescribed displacement lambda u0_ref (displacement grips), 0 under traction
    pub u0: f64,
    /// applied traction lambda t_ref (traction), 0 under displacement grips
    pub traction: f64,
    /// length (see [`Crack::a`]) of the crack of the most critical tip (the primary crack at
    /// the origin)
    pub a: f64,
    /// SIFs of the most critical tip at the critical load (every tip: `tip_history`)
    pub k_i: f64,
    pub k_ii: f64,
    /// kink angle of the most critical tip's extension (radians, tip frame)
    pub kink_angle: f64,
    /// position of the most critical tip (first in global tip order on ties)
    pub tip: [f64; 2],
    /// the q-radius (absolute) of that tip's SIFs: r_I, or less where a hole would enter the
    /// domain ([`XfemModel::hole_free_radius`]); 0 for the origin
    pub r_i: f64,
    /// condition estimate of this step's solve ([`crate::la::ConditionEstimate::value`]; 0 for the origin;
    /// None when not computed, [`crate::problem::XfemMethod::condition`])
    pub condition: Option<f64>,
}

/// The state of one tip at one point of the load path (see [`crate::xfem::XfemResult::tip_history`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TipStep {
    /// tip position at that critical state (before the extension that follows)
    pub pos: [f64; 2],
    /// SIFs at the critical load
    pub k_i: f64,
    pub k_ii: f64,
    /// kink angle (radians, tip frame) of the Erdogan-Sih criterion
    pub kink_angle: f64,
    /// the q-radius (absolute) of the SIFs (shrunk clear of holes, see [`GrowthStep::r_i`]);
    /// 0 for the origin
    pub r_i: f64,
    /// whether this tip was critical (within a relative `xfem.tip_tie_tol` of the step's load factor) and grew
    pub grows: bool,
}

/// Why a run stopped ([`crate::xfem::XfemResult::status`]; stable names, [`GrowthStatus::name`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GrowthStatus {
    /// no growth: one solve at the reference load
    SingleSolve,
    /// the next length `a` of a crack would exceed `a_stop`
    AStopReached,
    /// a new tip would come closer to the boundary, or to a hole or notch, than
    /// [`MIN_TIP_CLEARANCE`] element lengths, or a tip's SIF domain would have to shrink below
    /// [`MIN_HOLE_FREE_RADIUS`] element sizes to keep a hole out
    LigamentUsedUp,
    MaxStepsReached,
    /// the cracks would cross or touch, or another crack would enter a tip's SIF domain
    CracksMeet,
    /// no tip has K_eq > 0
    CrackCloses,
    /// the progress callback asked to stop (the steps so far are kept)
    Cancelled,
}

impl GrowthStatus {
    /// The stable snake_case name (the bindings' `meta["status"]`).
    pub fn name(&self) -> &'static str {
        match self {
            GrowthStatus::SingleSolve => "single_solve",
            GrowthStatus::AStopReached => "a_stop_reached",
            GrowthStatus::LigamentUsedUp => "ligament_used_up",
            GrowthStatus::MaxStepsReached => "max_steps_reached",
            GrowthStatus::CracksMeet => "cracks_meet",
            GrowthStatus::CrackCloses => "crack_closes",
            GrowthStatus::Cancelled => "cancelled",
        }
    }
}

impl std::fmt::Display for GrowthStatus {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// What a growth run produces (the growth fields of [`crate::xfem::XfemResult`]).
pub(super) struct Growth {
    pub(super) history: Vec<GrowthStep>,
    pub(super) tip_history: Vec<Vec<TipStep>>,
    pub(super) snapshots: Vec<DeformedPatch>,
    /// the whole plate at the kept critical states (`xfem.state_every`)
    pub(super) states: Vec<GrowthState>,
    /// warnings of the growth steps' solves
    pub(super) warnings: Vec<Warning>,
    /// None only if the loop ran out without a stop (it cannot: the last step stops with
    /// [`GrowthStatus::MaxStepsReached`])
    pub(super) status: Option<GrowthStatus>,
    /// final polylines of all cracks
    pub(super) cracks: Vec<Vec<[f64; 2]>>,
    /// the responses at every point of `history` (scaled by its load factor)
    pub(super) responses: Vec<crate::fe::regions::SceneResponses>,
}

/// The state of every tip of one crack configuration at the reference load: the tip element
/// sizes, the SIFs at r_I, the critical load factors and the kink angles.
struct TipStates {
    sizes: Vec<f64>,
    sifs: Vec<DomainSifs>,
    lams: Vec<f64>,
    kinks: Vec<f64>,
}

impl TipStates {
    /// `radii`: every tip's q-radius (r_I, shrunk clear of holes).
    fn new(model: &XfemModel, u: &[f64], sizes: Vec<f64>, radii: &[f64], kic: f64) -> Result<Self> {
        let n_tips = model.tips.len();
        let mut sifs = Vec::with_capacity(n_tips);
        let mut lams = Vec::with_capacity(n_tips);
        for (t, &r) in radii.iter().enumerate() {
            let s = model.sifs(u, t, r)?;
            let keq = k_equivalent(s.k_i, s.k_ii);
            lams.push(if keq > 0.0 { kic / keq } else { f64::INFINITY });
            sifs.push(s);
        }
        let kinks: Vec<f64> = sifs.iter().map(|s| kink_angle(s.k_i, s.k_ii)).collect();
        Ok(Self {
            sizes,
            sifs,
            lams,
            kinks,
        })
    }

    /// The most critical tip (first on ties) and the load factor it sets, or None when no tip
    /// can become critical (K_eq <= 0 everywhere); with the tips that grow.
    fn critical(&self, tie: f64) -> Option<Critical> {
        let lams = &self.lams;
        let t = (0..lams.len()).fold(0, |b, t| if lams[t] < lams[b] { t } else { b });
        let lam = lams[t];
        if !lam.is_finite() {
            return None;
        }
        let grows: Vec<bool> = lams.iter().map(|&l| l <= lam * (1.0 + tie)).collect();
        Some(Critical { t, lam, grows })
    }
}

/// The critical state of one step: the most critical tip `t`, the load factor `lam` it sets and
/// the tips that grow (lambda_t <= lambda (1 + tip_tie_tol)).
struct Critical {
    t: usize,
    lam: f64,
    grows: Vec<bool>,
}

/// The cracks after one extension of the critical tips.
struct Extension {
    polylines: Vec<Vec<[f64; 2]>>,
    /// the next length `a` of every crack
    next_a: Vec<f64>,
    /// a new tip comes too close to the plate boundary or to a hole
    ligament: bool,
}

/// Extends every tip with `grows` by `da` (or its tip element's chord) at the angle `kinks[t]`
/// from its current direction.
fn extend_tips(
    model: &XfemModel,
    st: &TipStates,
    kinks: &[f64],
    grows: &[bool],
    da: Option<f64>,
    plate: &PlateProblem,
) -> Extension {
    let (x_max, y_max) = (plate.width, plate.height);
    let mut polylines: Vec<Vec<[f64; 2]>> = model.cracks.iter().map(|c| c.points.clone()).collect();
    let mut next_a: Vec<f64> = model.cracks.iter().map(Crack::a).collect();
    let mut ligament = false;
    for (k, tip) in model.tips.iter().enumerate() {
        if !grows[k] {
            continue;
        }
        let c = model.tip_crack[k];
        let da = da.unwrap_or_else(|| model.tip_element_length(k));
        let (cs, sn) = (kinks[k].cos(), kinks[k].sin());
        let d = [
            tip.dir[0] * cs - tip.dir[1] * sn,
            tip.dir[0] * sn + tip.dir[1] * cs,
        ];
        let p = [tip.pos[0] + da * d[0], tip.pos[1] + da * d[1]];
        // the next tip must stay resolvable (the q-domain may be clipped by the boundary)
        let margin = MIN_TIP_CLEARANCE * st.sizes[k];
        if p[0] < margin || p[0] > x_max - margin || p[1] < margin || p[1] > y_max - margin {
            ligament = true;
        }
        // a hole or notch is a boundary of the material too
        if model
            .fictitious
            .as_ref()
            .is_some_and(|fd| fd.domain.level_set(p) < margin)
        {
            ligament = true;
        }
        if tip.at_start {
            polylines[c].insert(0, p);
        } else {
            polylines[c].push(p);
        }
        next_a[c] += if model.cracks[c].mouth { da } else { 0.5 * da };
    }
    Extension {
        polylines,
        next_a,
        ligament,
    }
}

/// The extension angles of the growing tips under `xfem.kink_rule = "predictor_corrector"`
/// ([`super::kink`]): the criterion's angles `st.kinks` (predictor) and their extension `trial`,
/// one solve of the plate with the trial cracks (the growth loop's solve: the condensed one when the run has it, else [`PlateProblem::solve`]; `step` names it in
/// warnings), the criterion at the trial tips and [`corrected_angle`]. Where the trial cannot
/// be built (a trial tip leaves the ligament, cracks meet) or a trial tip's SIFs cannot be
/// evaluated, the predictor's angle stays (the loop's own checks then stop the run as under
/// `hoop`).
#[allow(clippy::too_many_arguments)]
fn corrected_kinks(
    model: &XfemModel,
    st: &TipStates,
    trial: Extension,
    grows: &[bool],
    r_i_factor: f64,
    plate: &PlateProblem,
    condensed: Option<&mut CondensedSolver>,
    step: usize,
    warnings: &mut Vec<Warning>,
) -> Result<Vec<f64>> {
    if trial.ligament {
        return Ok(st.kinks.clone());
    }
    let Ok(trial_model) = model.with_cracks(trial.polylines) else {
        return Ok(st.kinks.clone());
    };
    let what = format!("growth step {} (corrector trial)", step + 1);
    let sol = match condensed {
        Some(c) => c.solve(plate, &trial_model, &what)?,
        None => plate.solve(&trial_model, &what)?,
    };
    warnings.extend(
        sol.condition
            .as_ref()
            .and_then(|c| condition_warning(&what, c)),
    );
    let at_trial = trial_angles(&trial_model, &sol.u, grows, r_i_factor);
    Ok(st
        .kinks
        .iter()
        .zip(at_trial)
        .map(|(&k0, k1)| k1.map_or(k0, |k1| corrected_angle(k0, k1)))
        .collect())
}

impl Growth {
    /// A run at its origin: history[0] is the unloaded initial crack (lambda = 0, all loads
    /// zero), so the initial loading branch from (0, 0) is part of the curve.
    fn origin(model: &XfemModel, first: &PlateSolve) -> Self {
        let history = vec![GrowthStep {
            lambda: 0.0,
            sigma22: 0.0,
            cmod: 0.0,
            u0: 0.0,
            traction: 0.0,
            a: model.cracks[0].a(),
            k_i: 0.0,
            k_ii: 0.0,
            kink_angle: 0.0,
            tip: model.tips[0].pos,
            // nothing computed at the unloaded origin: NaN says so
            r_i: f64::NAN,
            condition: first.condition.map(|_| f64::NAN),
        }];
        let tip_history = vec![model
            .tips
            .iter()
            .map(|t| TipStep {
                pos: t.pos,
                k_i: 0.0,
                k_ii: 0.0,
                kink_angle: 0.0,
                r_i: f64::NAN,
                grows: false,
            })
            .collect()];
        Self {
            history,
            tip_history,
            snapshots: Vec::new(),
            states: Vec::new(),
            warnings: Vec::new(),
            status: None,
            cracks: Vec::new(),
            responses: vec![first.responses.scaled(0.0)],
        }
    }

    /// Records the critical state `crit` of one step (the solution `sol` scaled by its load
    /// factor; `refs` = (u0, traction) of the reference load), its deformed patch and, when
    /// `states` keeps any, the whole plate's state ([`GrowthState`]) of growth step `step`.
    #[allow(clippy::too_many_arguments)]
    fn record(
        &mut self,
        model: &XfemModel,
        sol: &PlateSolve,
        st: &TipStates,
        crit: &Critical,
        (u0_ref, t_ref): (f64, f64),
        (step, states): (usize, &mut KeptStates),
    ) -> Result<()> {
        let (t, lam, grows) = (crit.t, crit.lam, &crit.grows);
        let s = st.sifs[t];
        self.responses.push(sol.responses.scaled(lam));
        self.history.push(GrowthStep {
            lambda: lam,
            sigma22: lam * sol.sigma22,
            cmod: lam * sol.cmod,
            u0: lam * u0_ref,
            traction: lam * t_ref,
            a: model.cracks[model.tip_crack[t]].a(),
            k_i: lam * s.k_i,
            k_ii: lam * s.k_ii,
            kink_angle: st.kinks[t],
            tip: model.tips[t].pos,
            r_i: s.radius,
            condition: sol.condition.map(|c| c.value()),
        });
        self.tip_history.push(
            (0..model.tips.len())
                .map(|k| TipStep {
                    pos: model.tips[k].pos,
                    k_i: lam * st.sifs[k].k_i,
                    k_ii: lam * st.sifs[k].k_ii,
                    kink_angle: st.kinks[k],
                    r_i: st.sifs[k].radius,
                    grows: grows[k],
                })
                .collect(),
        );
        let mut snap = model.deformed_near_tip(&sol.u, t, 5.0 * st.sizes[t], 4)?;
        for d in snap.disp.iter_mut().flatten().flatten() {
            *d *= lam;
        }
        self.snapshots.push(snap);
        if states.any() {
            let row = self.history.len() - 1;
            states.push(step, GrowthState::new(model, &sol.u, lam, row)?);
        }
        Ok(())
    }
}

/// One warning for the SIF domains shrunk clear of holes during `what` (history row, tip,
/// radius in element sizes), or None when none was.
pub(super) fn shrunk_warning(
    shrunk: &[(usize, usize, f64)],
    r_i_factor: f64,
    what: &str,
) -> Option<Warning> {
    let (first, last) = (shrunk.first()?, shrunk.last()?);
    let min = shrunk.iter().map(|s| s.2).fold(f64::INFINITY, f64::min);
    Some(Warning::new(
        crate::warning::WarningKind::Discretisation,
        format!(
            "xfem.r_I: {what}: the SIF domain was shrunk from {r_i_factor} to as little as \
             {min:.3} element sizes so that no hole or notch enters it ({} tip states, history \
             rows {} .. {}; K_I stays within about 1 % down to {MIN_HOLE_FREE_RADIUS}, \
             see the r_I history column)",
            shrunk.len(),
            first.0,
            last.0
        ),
    ))
}

/// The growth loop (see the module documentation) from the initial model and its solve `first`
/// at the reference load of `plate`, with the fracture energy `g0` (K_Ic = sqrt(G0 E'));
/// `progress(step, max_steps)` is called after each step; `false` stops the growth
/// ([`GrowthStatus::Cancelled`]). Each step's solve condenses onto the enriched dofs with one
/// factorisation for the whole growth (`condensed`, [`crate::xfem::condensed`], which solved
/// `first`), or without it factorises the whole system ([`PlateProblem::solve`], the oracle).
pub(super) fn grow(
    mut model: XfemModel,
    first: PlateSolve,
    plate: &PlateProblem,
    (g, g0): (&GrowthOptions, f64),
    (r_i_factor, tie): (f64, f64),
    progress: &(dyn Fn(usize, usize) -> bool + Sync),
    mut condensed: Option<CondensedSolver>,
) -> Result<Growth> {
    let kic = (g0 * model.material.e_prime()).sqrt();
    // the history's u0 and traction columns: the grips' reference values, or (regions) the
    // load-point displacement of each solve and no traction column
    let refs = |sol: &PlateSolve| match (&plate.boundary, plate.load.grip) {
        (crate::problem::Boundary::Regions { .. }, _) => (sol.responses.load_displacement, 0.0),
        (_, Grip::Traction) => (0.0, plate.load.traction),
        _ => (plate.load.u0, 0.0),
    };
    let mut out = Growth::origin(&model, &first);
    let mut states = KeptStates::new(g.state_every);
    let mut sol = first;
    // (history row, tip, radius in element sizes) of every domain shrunk clear of a hole
    let mut shrunk: Vec<(usize, usize, f64)> = Vec::new();
    for step in 0..g.max_steps {
        if step > 0 {
            let what = format!("growth step {step}");
            sol = match condensed.as_mut() {
                Some(c) => c.solve(plate, &model, &what)?,
                None => plate.solve(&model, &what)?,
            };
            out.warnings.extend(
                sol.condition
                    .as_ref()
                    .and_then(|c| condition_warning(&what, c)),
            );
        }
        let n_tips = model.tips.len();
        let sizes: Vec<f64> = (0..n_tips).map(|t| model.tip_element_size(t)).collect();
        // r_I, shrunk where a hole would enter the domain (not below MIN_HOLE_FREE_RADIUS)
        let radii: Vec<f64> = (0..n_tips)
            .map(|t| model.hole_free_radius(t, r_i_factor * sizes[t]))
            .collect();
        if (0..n_tips).any(|t| model.other_crack_in_domain(t, radii[t]).is_some()) {
            out.status = Some(GrowthStatus::CracksMeet);
            break;
        }
        if (0..n_tips).any(|t| radii[t] < MIN_HOLE_FREE_RADIUS * sizes[t]) {
            out.status = Some(GrowthStatus::LigamentUsedUp);
            break;
        }
        for (t, &r) in radii.iter().enumerate() {
            if r < r_i_factor * sizes[t] {
                shrunk.push((step + 1, t, r / sizes[t]));
            }
        }
        let st = TipStates::new(&model, &sol.u, sizes, &radii, kic)?;
        let Some(crit) = st.critical(tie) else {
            out.status = Some(GrowthStatus::CrackCloses);
            break;
        };
        out.record(&model, &sol, &st, &crit, refs(&sol), (step, &mut states))?;
        if !progress(step + 1, g.max_steps) {
            out.status = Some(GrowthStatus::Cancelled);
            break;
        }
        let hoop = extend_tips(&model, &st, &st.kinks, &crit.grows, g.da, plate);
        // the lengths do not depend on the direction: no trial where the run stops anyway
        let last =
            hoop.next_a.iter().any(|&a| a > g.a_stop * (1.0 + 1e-12)) || step + 1 == g.max_steps;
        let ext = match g.kink_rule {
            KinkRule::PredictorCorrector if !last => {
                let kinks = corrected_kinks(
                    &model,
                    &st,
                    hoop,
                    &crit.grows,
                    r_i_factor,
                    plate,
                    condensed.as_mut(),
                    step,
                    &mut out.warnings,
                )?;
                extend_tips(&model, &st, &kinks, &crit.grows, g.da, plate)
            }
            _ => hoop,
        };
        if ext.ligament {
            out.status = Some(GrowthStatus::LigamentUsedUp);
            break;
        }
        if ext.next_a.iter().any(|&a| a > g.a_stop * (1.0 + 1e-12)) {
            out.status = Some(GrowthStatus::AStopReached);
            break;
        }
        if step + 1 == g.max_steps {
            out.status = Some(GrowthStatus::MaxStepsReached);
            break;
        }
        model = match model.with_cracks(ext.polylines) {
            Err(Error::InvalidInput { expected, .. })
                if expected == CRACKS_APART || expected == TIPS_APART =>
            {
                out.status = Some(GrowthStatus::CracksMeet);
                break;
            }
            m => m?,
        };
    }
    out.cracks = model.cracks.iter().map(|c| c.points.clone()).collect();
    out.states = states.finish();
    out.warnings
        .extend(shrunk_warning(&shrunk, r_i_factor, "growth"));
    Ok(out)
}
