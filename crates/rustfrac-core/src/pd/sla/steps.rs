//! The SLA steps of a run (section 3): each step solves the current (linear) model once at the
//! reference load, takes the critical bond(s) (`critical.rs`), records (lambda, sigma22, CMOD,
//! u0 = lambda u0_ref) at that load, and breaks them. Before a bond breaks, its end nodes are
//! grounded where they need it (`grounding.rs`).

use super::critical::critical_bonds;
use super::engine::{timing, Engine, Update};
use super::grounding::Grounding;
use super::progress::SlaProgress;
use super::result::{SlaStatus, SlaStep};
use super::state::RunState;
use crate::error::{Error, Result};
use crate::pd::splice::{ProbeFunctional, SpliceModel};
use crate::problem::SlaParams;
use std::time::Instant;

impl RunState {
    /// The SLA steps after the replayed ones, up to `max_steps` or until the run ends (separated,
    /// no bond in tension, cancelled, crack length reached) or the adaptive region must grow
    /// (then the midpoints of the bonds that grow it; the step is not taken). `sigma0` is the
    /// reference sigma22 of the intact model.
    pub(super) fn steps(
        &mut self,
        sla: &SlaParams,
        model: &SpliceModel,
        engine: &mut dyn Engine,
        fp: u64,
        sigma0: f64,
        progress: &(dyn Fn(&SlaProgress) -> bool + Sync),
    ) -> Result<Option<Vec<[f64; 2]>>> {
        let s0 = model.pd.s0;
        let load = model.problem.boundary.plate_load();
        let max_steps = sla.max_steps;
        let mut lam = vec![f64::INFINITY; model.bonds.len()];
        let first_step = self.history.len() + 1;
        let mut crack_len = crack_length(model, &self.broken);
        // a0: the pre-crack's length, where the crack length starts
        let (a0, extent) = crack_extent(model);
        for step in first_step..=max_steps {
            if self.status != SlaStatus::Completed {
                break;
            }
            let st = match engine.state() {
                Ok(s) => s,
                Err(Error::Separated { .. }) => {
                    self.status = SlaStatus::Separated;
                    break;
                }
                Err(e) => return Err(e),
            };
            // under displacement grips a cut load path leaves both parts held by their own grip:
            // the system stays regular but carries no load any more
            if model.response.displacement_driven && st.sigma22.abs() <= 1e-9 * sigma0.abs() {
                self.status = SlaStatus::Separated;
                break;
            }
            let tie_tol = sla.tie_tol;
            let Some((lmin, sel)) =
                critical_bonds(model, &self.broken, engine, s0, tie_tol, &mut lam)
            else {
                self.status = SlaStatus::NoBondInTension;
                break;
            };
            if let Some(centres) = self.growth(model, &sel) {
                return Ok(Some(centres));
            }
            if STOP_AT_HELD.with(|f| f.get()) && sel.iter().any(|&b| held_end(model, b)) {
                self.status = SlaStatus::LoadedBoundaryReached;
                break;
            }
            self.note_interface(model, &sel);
            // the load displacement at the reference load (before the break changes u)
            let u0_ref = model
                .response
                .load_displacement(engine.u())
                .unwrap_or(load.u0);
            let first = sel[0];
            let (detached, sep) =
                advance(model, engine, &mut self.broken, &mut self.grounding, &sel)?;
            self.detached_nodes
                .extend(detached.iter().map(|&n| (step, n)));
            // the crack length, updated from this step's bonds (O(bonds) only once a model)
            let cl =
                (sel.iter().filter(|&&b| self.broken[b])).fold(crack_len, |l, &b| l.max(extent(b)));
            crack_len = cl;
            let bf = &model.bonds[first];
            let row = SlaStep {
                step,
                lambda: lmin,
                sigma22: lmin * st.sigma22,
                cmod: lmin * st.cmod,
                u0: lmin * u0_ref,
                bonds: sel,
                nodes: [bf.i as usize, bf.j as usize],
                detached,
                crack_length: cl,
                probes: st_probes(&self.probes, engine.u(), lmin),
            };
            self.record(model, sla, row);
            let every = sla.checkpoint_every;
            if every > 0 && step % every == 0 {
                self.checkpoint(sla, fp)?;
            }
            let go_on = progress(&SlaProgress {
                step,
                max_steps,
                crack_length: cl,
                initial_crack_length: a0,
                stop_crack_length: sla.stop_crack_length,
            });
            if sep {
                self.status = SlaStatus::Separated;
                break;
            }
            if !go_on {
                self.status = SlaStatus::Cancelled;
                self.checkpoint(sla, fp)?;
                break;
            }
            if let Some(l) = sla.stop_crack_length {
                if cl >= l {
                    self.status = SlaStatus::CrackLengthReached;
                    break;
                }
            }
        }
        Ok(None)
    }
}

thread_local! {
    /// Stop at a bond ending at a held node ([`held_end`]); off only in tests.
    static STOP_AT_HELD: std::cell::Cell<bool> = const { std::cell::Cell::new(true) };
}

/// Stops (`on`, the rule) or not runs on this thread at a bond that ends at a node carrying the
/// boundary conditions ([`SlaStatus::LoadedBoundaryReached`]): for tests, which follow a run
/// past such a bond to check what comes after it (the fast engine's accuracy check).
#[doc(hidden)]
pub fn stop_at_loaded_boundary(on: bool) {
    STOP_AT_HELD.with(|f| f.set(on));
}

/// Whether bond `b` ends at a node carrying an applied force of the scene (a loaded edge, a
/// traction grip, a point load). Breaking it would be a crack the load made (the edge's nodes
/// miss half their neighbours and carry the concentrated nodal forces): the step stops the run
/// ([`SlaStatus::LoadedBoundaryReached`]). Prescribed displacements act on volumetric boundary
/// layers in pure PD (full families at the edge) and are not counted.
fn held_end(model: &SpliceModel, b: usize) -> bool {
    let bond = &model.bonds[b];
    [bond.i as usize, bond.j as usize].into_iter().any(|n| {
        [2 * n, 2 * n + 1]
            .iter()
            .any(|&d| model.f.get(d).is_some_and(|&v| v != 0.0))
    })
}

/// Breaks the bonds `sel` of one step: for each bond in order, the grounding springs its end
/// nodes need once it is gone, then the bond. Returns the detached nodes and whether the body
/// separated (the remaining updates are then skipped). Used by the live run and by the replay of
/// a checkpoint, so both apply exactly the same updates in the same order.
pub(super) fn advance(
    model: &SpliceModel,
    engine: &mut dyn Engine,
    broken: &mut [bool],
    grounding: &mut Grounding,
    sel: &[usize],
) -> Result<(Vec<usize>, bool)> {
    let mut detached = Vec::new();
    for &b in sel {
        broken[b] = true;
        let bond = &model.bonds[b];
        let mut ups = Vec::new();
        for n in [bond.i as usize, bond.j as usize] {
            for (m, sp) in grounding.springs(model, n, broken) {
                if !detached.contains(&m) {
                    detached.push(m);
                }
                ups.push(Update::Ground(sp));
            }
        }
        ups.push(Update::Break(b));
        for u in ups {
            match engine.apply(u) {
                Ok(()) => {}
                Err(Error::Separated { detail }) => {
                    timing(&detail, Instant::now());
                    return Ok((detached, true));
                }
                Err(e) => return Err(e),
            }
        }
    }
    Ok((detached, false))
}

/// The crack length of the broken bonds: the pre-crack's length, or the farthest projection on
/// its direction of a broken bond's midpoint (pre-crack bonds aside), whichever is larger.
fn crack_length(model: &SpliceModel, broken: &[bool]) -> f64 {
    let (b, extent) = crack_extent(model);
    (0..model.bonds.len())
        .filter(|&i| broken[i])
        .fold(b, |len, i| len.max(extent(i)))
}

/// The pre-crack's length and the crack length a broken bond reaches ([`crack_length`]: the
/// length is the max of both over the broken bonds, so a step updates it from its own bonds).
fn crack_extent(model: &SpliceModel) -> (f64, impl Fn(usize) -> f64 + '_) {
    let pc = &model.precrack;
    let (p0, t, l0) = if pc.len() >= 2 {
        let d = [pc[1][0] - pc[0][0], pc[1][1] - pc[0][1]];
        let l = (d[0] * d[0] + d[1] * d[1]).sqrt();
        let l0: f64 = pc
            .windows(2)
            .map(|s| ((s[1][0] - s[0][0]).powi(2) + (s[1][1] - s[0][1]).powi(2)).sqrt())
            .sum();
        (pc[0], [d[0] / l, d[1] / l], l0)
    } else {
        ([0.0, 0.0], [1.0, 0.0], 0.0)
    };
    let extent = move |b: usize| {
        if model.precrack_broken[b] {
            return f64::NEG_INFINITY;
        }
        let bond = &model.bonds[b];
        let xi = model.grid.xy(bond.i as usize);
        let mid = [xi[0] + 0.5 * bond.xi[0], xi[1] + 0.5 * bond.xi[1]];
        (mid[0] - p0[0]) * t[0] + (mid[1] - p0[1]) * t[1]
    };
    (l0, extent)
}

/// The probes at the step's load lambda (the engine's u is at the reference load; it holds every
/// probe dof, [`Fast`](super::fast::Fast) keeps them in its ring).
fn st_probes(probes: &[ProbeFunctional], u: &[f64], lambda: f64) -> Vec<[f64; 2]> {
    probes
        .iter()
        .map(|p| p.value(u).map(|v| lambda * v))
        .collect()
}
