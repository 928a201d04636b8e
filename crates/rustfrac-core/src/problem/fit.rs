//! What a scene asks that it may not mean, said before the run ([`scene_warnings`]): a default
//! sized for the paper's plate on another plate (the uniform grid's element shape, the paper's
//! crack), and the work a scene asks for, estimated before anything is built and warned past
//! [`COST_BUDGET_S`]. Sizes no machine holds are refused by the schema's ranges and
//! [`super::MAX_ELEMENTS`]; these are the ones that run, but not as the user may think.

use super::schema;
use super::{CrackKind, FeGrid, KinkRule, Method, Problem, SlaEngine};
use crate::warning::{Warning, WarningKind};

/// Largest element aspect ratio (longer over shorter side) of a uniform grid without a warning:
/// the paper's 44 x 83 grid on its 11 x 21 plate has 1.01; at 3.8 (the same grid on a 20 x 10
/// plate) K_I is 5 % low.
pub const MAX_ASPECT: f64 = 2.0;

/// The estimated run time (seconds) past which a scene warns with its estimate.
pub const COST_BUDGET_S: f64 = 60.0;

/// Seconds of one sparse factorisation and solve of `n` unknowns of a Q4 grid: c n^1.5 (nested
/// dissection in 2D), c from 25 s for 2e6 unknowns on a 2-core machine ([`super::grid`]).
fn factorisation_s(n: f64) -> f64 {
    25.0 * (n / 2e6).powf(1.5)
}

impl Problem {
    /// The warnings of the scene, made before the run ([`scene_warnings`]).
    pub fn scene_warnings(&self) -> Vec<Warning> {
        scene_warnings(self)
    }
}

/// Every warning of the scene, made before anything is built.
pub fn scene_warnings(p: &Problem) -> Vec<Warning> {
    let mut out = Vec::new();
    if let Some(g) = p.fe_grid() {
        out.extend(aspect(p, g));
    }
    out.extend(paper_crack(p));
    out.extend(cost(p));
    out
}

fn discretisation(message: String) -> Warning {
    Warning::new(WarningKind::Discretisation, message)
}

/// A uniform grid of elements far from square.
fn aspect(p: &Problem, g: &FeGrid) -> Option<Warning> {
    if !(g.xs.is_empty() && g.ys.is_empty()) || g.nx == 0 || g.ny == 0 {
        return None;
    }
    let (w, h) = (p.domain.width, p.domain.height);
    let (hx, hy) = (w / g.nx as f64, h / g.ny as f64);
    let a = (hx / hy).max(hy / hx);
    let default = |key: &str| schema::spec("mesh", key).map_or(0, |s| s.default.i());
    let was_default = g.nx as i64 == default("nx") && g.ny as i64 == default("ny");
    (a > MAX_ASPECT).then(|| {
        discretisation(format!(
            "mesh: the uniform grid {} x {} on the plate {w} x {h} has elements of aspect {a:.2} \
             ({hx:.4} x {hy:.4}; more than {MAX_ASPECT}): K_I and the opening lose accuracy{}; \
             set mesh.nx, mesh.ny for near-square elements (e.g. {} x {})",
            g.nx,
            g.ny,
            if was_default {
                " (the default grid, sized for the paper's 11 x 21 plate)"
            } else {
                ""
            },
            g.nx,
            ((h / hx).round() as usize).max(1),
        ))
    })
}

/// The paper's crack (the defaults of `[crack]`) on another plate.
fn paper_crack(p: &Problem) -> Option<Warning> {
    let c = p.cracks.first()?;
    let default = |key: &str| schema::spec("crack", key).map_or(f64::NAN, |s| s.default.f());
    let plate = |key: &str| schema::spec("plate", key).map_or(f64::NAN, |s| s.default.f());
    let paper_plate = p.domain.width == plate("width") && p.domain.height == plate("height");
    let paper_crack = c.kind != CrackKind::Center
        && c.a0 == default("a0")
        && c.y == default("y")
        && c.angle == 0.0
        && c.side == super::Side::Left;
    (paper_crack && !paper_plate).then(|| {
        discretisation(format!(
            "crack: the paper's crack (the defaults of [crack]: '{}' from x1 = 0 at x2 = \
             crack.y = {}, length crack.a0 = {}) on the plate {} x {}, not the paper's {} x {}; \
             set [crack] to place it",
            c.kind.name(),
            c.y,
            c.a0,
            p.domain.width,
            p.domain.height,
            plate("width"),
            plate("height")
        ))
    })
}

/// The run's estimated time: solves of the FEM/XFEM system (one, or per growth step) and
/// factorisations of the PD / CCM-PD system (per SLA step for the oracle engine, per
/// `pd.refactor_every` breaks otherwise), warned past [`COST_BUDGET_S`].
fn cost(p: &Problem) -> Option<Warning> {
    let (w, h) = (p.domain.width, p.domain.height);
    let (what, count, one_s) = match &p.method {
        Method::Fem(_) | Method::Xfem(_) => {
            let g = p.fe_grid()?;
            let n = 2.0 * (g.nx as f64 + 1.0) * (g.ny as f64 + 1.0);
            let steps = match &p.method {
                Method::Xfem(x) => x.growth.as_ref().map_or(1.0, |gr| {
                    let a0 = p.cracks.iter().map(|c| c.a0).fold(0.0, f64::max);
                    let da = gr.da.unwrap_or(w / g.nx.max(1) as f64);
                    let by_length = ((gr.a_stop - a0) / da).ceil().max(1.0);
                    let per = if gr.kink_rule == KinkRule::PredictorCorrector {
                        2.0
                    } else {
                        1.0
                    };
                    per * (gr.max_steps as f64).min(by_length)
                }),
                _ => 1.0,
            };
            ("solves", steps, factorisation_s(n))
        }
        Method::Pd(pd) | Method::CcmPd(pd) => {
            let n = 2.0 * (w / pd.dx + 1.0) * (h / pd.dx + 1.0);
            // a PD row couples the pi m^2 nodes of a horizon, a Q4 row 9
            let bonds = (std::f64::consts::PI * (pd.m * pd.m) as f64 / 9.0).max(1.0);
            let pd_share = if pd.regions.is_empty() {
                1.0
            } else {
                let area: f64 = pd
                    .regions
                    .iter()
                    .map(|r| (r[2] - r[0]) * (r[3] - r[1]))
                    .sum();
                (area / (w * h)).min(1.0)
            };
            let steps = pd.sla.max_steps as f64;
            let count = match (pd.sla.engine, pd.sla.refactor_every) {
                (SlaEngine::Oracle, _) => 1.0 + steps,
                (_, 0) => 1.0,
                (_, k) => 1.0 + steps / k as f64,
            };
            (
                "factorisations",
                count,
                factorisation_s(n) * (1.0 + pd_share * (bonds - 1.0)),
            )
        }
    };
    let total = count * one_s;
    (total > COST_BUDGET_S).then(|| {
        discretisation(format!(
            "cost: about {total:.3e} s estimated before the run ({count:.0} {what} of about \
                 {one_s:.2e} s each; more than the budget of {COST_BUDGET_S} s): reduce \
                 xfem.growth_steps / raise xfem.da, pd.sla_steps, raise pd.refactor_every or \
                 coarsen the grid if this is not meant"
        ))
    })
}
