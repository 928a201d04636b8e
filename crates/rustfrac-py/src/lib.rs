//! PyO3 bindings of rustfrac: the native module `rustfrac._core`.
//!
//! Bindings only. Each function takes plain numbers and strings (the Python package validates the
//! scene first), releases the GIL around the Rust call (`py.detach`), catches panics at the
//! boundary, and returns a dict of numpy arrays (moved, not copied, from Rust vectors) and
//! scalars. Core errors map to the exception classes of `rustfrac.errors`:
//!
//! | core error                         | Python exception                                 |
//! |------------------------------------|--------------------------------------------------|
//! | `InvalidInput` / `SizeMismatch`    | `InvalidParameterError` (a `ValueError`)         |
//! | `Singular` / `NotPositiveDefinite` | `SingularSystemError`                            |
//! | `Separated`                        | `SeparatedError` (a `SingularSystemError`)       |
//! | `Internal`, caught panic           | `InternalError`                                  |
//!
//! Progress: long runs take an optional Python callable `progress(done, total, message)`. It is
//! called from the worker thread at most every [`PROGRESS_INTERVAL_S`] seconds (plus once at the
//! end), and the GIL is acquired only for that call. If the callback raises (e.g.
//! `KeyboardInterrupt`), the run is asked to stop and the exception is re-raised afterwards.
//!
//! Adding a driver (CCM-PD; [`solve_xfem_plate`] is the worked example): a `#[pyfunction] solve_<method>(..., progress = None)` that
//! builds the core params, runs `detached(py, "<method>", || core::run(&params, |done, total|
//! prog.report(done, total, "<method>", false)))`, and returns a dict like [`solve_fem_plate`]
//! (history arrays as `history_<name>` keys); on the Python side one `_run_<method>` entry in
//! `rustfrac.runner._RUNNERS`.
//!
//! The solvers keep flat keyword signatures (PyO3 checks every name and type, and the `.pyi` stubs
//! mirror them one to one), so the plate, material and load keywords repeat across signatures by
//! design; turning them into core values happens once ([`material`], [`plate_load`]), and the
//! Python side builds them once (`rustfrac.runner._plate_kwargs`).

use numpy::ndarray::{Array2, Array3};
use numpy::{IntoPyArray, PyArray1};
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use rustfrac_core::error::Error as CoreError;
use rustfrac_core::fem::{Dirichlet, FemModel, LinearSystem};
use rustfrac_core::loading::{Grip, PlateLoad};
use rustfrac_core::material::{Elastic, Plane};
use rustfrac_core::mesh::Mesh;
use rustfrac_core::plate::{self, FemPlateParams};
use rustfrac_core::xfem::{self, GrowthParams, XfemParams};
use std::sync::Mutex;
use std::time::{Duration, Instant};

/// Minimum time between two progress callbacks.
pub const PROGRESS_INTERVAL_S: f64 = 0.1;

// ---------------------------------------------------------------------------------------------
// errors

/// Raises `rustfrac.errors.<name>(msg)`, falling back to a builtin if the package is missing.
fn py_error(py: Python<'_>, name: &str, msg: String) -> PyErr {
    let made = py
        .import("rustfrac.errors")
        .and_then(|m| m.getattr(name))
        .and_then(|cls| cls.call1((msg.clone(),)));
    match made {
        Ok(inst) => PyErr::from_value(inst),
        Err(_) if name == "InvalidParameterError" => PyValueError::new_err(msg),
        Err(_) => PyRuntimeError::new_err(msg),
    }
}

fn core_err(py: Python<'_>, e: CoreError) -> PyErr {
    let msg = e.to_string();
    let name = match e {
        CoreError::InvalidInput { .. } | CoreError::SizeMismatch { .. } => "InvalidParameterError",
        CoreError::Singular { .. } | CoreError::NotPositiveDefinite { .. } => "SingularSystemError",
        CoreError::Separated { .. } => "SeparatedError",
        CoreError::Internal { .. } => "InternalError",
        CoreError::Io { .. } => "CheckpointIOError",
    };
    py_error(py, name, msg)
}

/// Runs `f` without the GIL, turning a panic into `CoreError::Internal`.
fn detached<T: Send>(
    py: Python<'_>,
    what: &str,
    f: impl FnOnce() -> Result<T, CoreError> + Send,
) -> PyResult<T> {
    let r = py.detach(|| rustfrac_core::error::catch_panic(what, f));
    r.map_err(|e| core_err(py, e))
}

// ---------------------------------------------------------------------------------------------
// throttled progress

/// A progress sink usable from worker threads: forwards `(done, total, message)` to a Python
/// callable at most every [`PROGRESS_INTERVAL_S`] seconds, acquiring the GIL only then.
pub struct Progress {
    callback: Option<Py<PyAny>>,
    interval: Duration,
    state: Mutex<ProgressState>,
}

struct ProgressState {
    last: Option<Instant>,
    error: Option<PyErr>,
    calls: usize,
}

impl Progress {
    pub fn new(callback: Option<Py<PyAny>>) -> Self {
        Self {
            callback,
            interval: Duration::from_secs_f64(PROGRESS_INTERVAL_S),
            state: Mutex::new(ProgressState {
                last: None,
                error: None,
                calls: 0,
            }),
        }
    }

    /// Reports progress; `force` bypasses the throttle (first and last report). Returns `false`
    /// when the run should stop (the callback raised).
    pub fn report(&self, done: usize, total: usize, message: &str, force: bool) -> bool {
        let Some(cb) = &self.callback else {
            return true;
        };
        // a throttled report from one of several worker threads never waits for another's callback
        let mut st = if force {
            self.state.lock().unwrap_or_else(|p| p.into_inner())
        } else {
            match self.state.try_lock() {
                Ok(g) => g,
                Err(std::sync::TryLockError::Poisoned(p)) => p.into_inner(),
                Err(std::sync::TryLockError::WouldBlock) => return true,
            }
        };
        if st.error.is_some() {
            return false;
        }
        let now = Instant::now();
        if !force
            && st
                .last
                .is_some_and(|t| now.duration_since(t) < self.interval)
        {
            return true;
        }
        st.last = Some(now);
        st.calls += 1;
        let r = Python::attach(|py| cb.call1(py, (done, total, message)).map(|_| ()));
        match r {
            Ok(()) => true,
            Err(e) => {
                st.error = Some(e);
                false
            }
        }
    }

    /// Number of callbacks made so far.
    pub fn calls(&self) -> usize {
        self.state.lock().map(|s| s.calls).unwrap_or(0)
    }

    /// The exception the callback raised, if any (to re-raise once the GIL is held again).
    pub fn take_error(&self) -> Option<PyErr> {
        self.state
            .lock()
            .unwrap_or_else(|p| p.into_inner())
            .error
            .take()
    }
}

// ---------------------------------------------------------------------------------------------
// array helpers (moves, no copies, except index conversion to int64)

fn arr2<'py, const N: usize>(py: Python<'py>, v: Vec<[f64; N]>) -> Bound<'py, PyAny> {
    let n = v.len();
    let flat: Vec<f64> = v.into_flattened();
    Array2::from_shape_vec((n, N), flat)
        .expect("shape matches length")
        .into_pyarray(py)
        .into_any()
}

fn arr1<'py>(py: Python<'py>, v: Vec<f64>) -> Bound<'py, PyAny> {
    PyArray1::from_vec(py, v).into_any()
}

fn elements_i64<'py>(py: Python<'py>, e: &[[usize; 4]]) -> Bound<'py, PyAny> {
    let flat: Vec<i64> = e.iter().flatten().map(|&i| i as i64).collect();
    Array2::from_shape_vec((e.len(), 4), flat)
        .expect("shape matches length")
        .into_pyarray(py)
        .into_any()
}

fn index_i64<'py>(py: Python<'py>, v: &[usize]) -> Bound<'py, PyAny> {
    let v: Vec<i64> = v.iter().map(|&i| i as i64).collect();
    PyArray1::from_vec(py, v).into_any()
}

/// (c, 4, 2) array of quadrilateral cells (corner coordinates or corner displacements).
fn quads<'py>(py: Python<'py>, v: Vec<[[f64; 2]; 4]>) -> Bound<'py, PyAny> {
    let n = v.len();
    let flat: Vec<f64> = v.into_iter().flatten().flatten().collect();
    Array3::from_shape_vec((n, 4, 2), flat)
        .expect("shape matches length")
        .into_pyarray(py)
        .into_any()
}

/// A result's warnings as (kind name, message) pairs for Python.
fn warning_pairs(w: &[rustfrac_core::Warning]) -> Vec<(&'static str, String)> {
    w.iter()
        .map(|w| (w.kind.name(), w.message.clone()))
        .collect()
}

/// The load of the plate solvers' `bc`, `u0`, `traction` keywords.
fn plate_load(bc: &str, u0: f64, traction: f64) -> Result<PlateLoad, CoreError> {
    Ok(PlateLoad {
        grip: Grip::parse(bc)?,
        u0,
        traction,
    })
}

fn material(e: f64, nu: f64, plane: &str, thickness: f64) -> Result<Elastic, CoreError> {
    Elastic::new(e, nu, Plane::parse(plane)?, thickness)
}

// ---------------------------------------------------------------------------------------------
// functions

/// Solves the paper's plate with plain Q4 FEM: uncracked, or with a seam crack
/// `seam = (a0, crack_y)` (duplicated nodes from x1 = 0 to a0 on the grid line nearest crack_y).
///
/// Returns a dict: coords (n,2), elements (m,4) int64, u (2n,), reactions (2n,),
/// nodal_stress (n,3) [s11, s22, s12], gauss_points (g,2), gauss_stress (g,3); scalars sigma22,
/// cmod, energy, residual, n_dofs, anchor_node, seam_y (or None), wall_time_s, bc, condition
/// (dimensionless condition estimate of the solve, `rustfrac_core::solver::ConditionEstimate`),
/// condition_pivot_ratio (both None with `condition = False`: not computed, which saves the
/// estimate's 2 solves), warnings (list of (kind, message) pairs, kind in `WARNING_KINDS`: ill
/// conditioning, volumetric locking near nu = 0.5). A Dirichlet set leaving a rigid-body mode free
/// or a condition above `COND_SINGULAR` raises `SingularSystemError`.
#[pyfunction]
#[pyo3(signature = (*, width, height, nx, ny, e, nu, plane = "strain", thickness = 1.0,
                    bc = "free", u0 = 0.0, traction = 0.0, seam = None, gauss = 2,
                    condition = true, progress = None))]
#[allow(clippy::too_many_arguments)]
fn solve_fem_plate<'py>(
    py: Python<'py>,
    width: f64,
    height: f64,
    nx: usize,
    ny: usize,
    e: f64,
    nu: f64,
    plane: &str,
    thickness: f64,
    bc: &str,
    u0: f64,
    traction: f64,
    seam: Option<(f64, f64)>,
    gauss: usize,
    condition: bool,
    progress: Option<Py<PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let prog = Progress::new(progress);
    let params = (|| {
        Ok::<_, CoreError>(FemPlateParams {
            width,
            height,
            nx,
            ny,
            material: material(e, nu, plane, thickness)?,
            load: plate_load(bc, u0, traction)?,
            seam,
            gauss,
            condition,
        })
    })()
    .map_err(|err| core_err(py, err))?;
    let r = detached(py, "fem plate", || {
        prog.report(0, 1, "fem: assemble + factorise + solve", true);
        let r = plate::run(&params);
        prog.report(1, 1, "fem: done", true);
        r
    });
    if let Some(err) = prog.take_error() {
        return Err(err);
    }
    let r = r?;
    let d = PyDict::new(py);
    d.set_item("coords", arr2(py, r.coords))?;
    d.set_item("elements", elements_i64(py, &r.elements))?;
    d.set_item("u", arr1(py, r.u))?;
    d.set_item("reactions", arr1(py, r.reactions))?;
    d.set_item("nodal_stress", arr2(py, r.nodal_stress))?;
    d.set_item("gauss_points", arr2(py, r.gauss_points))?;
    d.set_item("gauss_stress", arr2(py, r.gauss_stress))?;
    d.set_item("sigma22", r.sigma22)?;
    d.set_item("cmod", r.cmod)?;
    d.set_item("energy", r.energy)?;
    d.set_item("residual", r.residual)?;
    d.set_item("n_dofs", r.n_dofs)?;
    d.set_item("anchor_node", r.anchor_node)?;
    d.set_item("seam_y", r.seam_y)?;
    d.set_item("wall_time_s", r.wall_time_s)?;
    d.set_item("condition", r.condition.map(|c| c.value()))?;
    d.set_item("condition_pivot_ratio", r.condition.map(|c| c.pivot_ratio))?;
    d.set_item("warnings", warning_pairs(&r.warnings))?;
    d.set_item("bc", params.load.grip.name())?;
    Ok(d)
}

/// Solves the plate with XFEM (Heaviside + branch enrichment, interaction-integral SIFs) and,
/// with `growth_steps > 0`, quasi-static LEFM crack growth (`rustfrac_core::xfem::run`).
///
/// `crack` is a polyline [(x1, x2), ...] with at least two points; an end on the plate boundary is
/// a mouth (edge crack), an end inside is a tip. `extra_cracks` are further polylines (several
/// cracks: they must neither cross nor touch, nor put tips of two cracks in one element; errors
/// name "cracks" or "cracks[k]"). Tips are numbered crack by crack (`crack` first). `tip_nsub = 0` means `nsub`; `r_i` and
/// `extra_radii` are in tip-element lengths; `fixed_area_radius = None` enriches the tip element
/// nodes only; growth needs `g0`; `da = None` grows one element length per step and
/// `a_stop = None` stops at 0.7 width.
///
/// Returns a dict: scalars K_I, K_II, J (from K, eq. 32), J_domain (eq. 33), r_i (absolute),
/// sigma22, cmod, n_dofs, n_std, n_heaviside_nodes, n_tip_nodes, n_dropped_nodes, anchor_node,
/// status, bc, wall_time_s, condition (dimensionless condition estimate of the initial solve;
/// None with `condition = False`), condition_pivot_ratio (likewise), warnings (list of (kind,
/// message) pairs, see `solve_fem_plate`); arrays coords (n,2), elements (m,4) int64, u (n_dofs,) (standard dofs
/// first: u[:n_std] are the nodal displacements), heaviside_nodes, tip_nodes (int64),
/// crack (k,2) (final polyline), crack_initial (k0,2), radii (r,5) [radius, K_I, K_II, J_from_K,
/// J_domain] sorted by radius, radii_factor (r,), tips (t,6) [x1, x2, K_I, K_II, J_from_K,
/// J_domain] for every tip, tip_crack (t,) int64 (the crack of each tip: 0 = `crack`, k =
/// extra_cracks[k-1]), cracks (P,2) with cracks_offsets (C+1,) int64 (final polylines of all
/// cracks, crack k = rows offsets[k]..offsets[k+1]), deformed_cells and deformed_disp (c,4,2)
/// (near the primary tip; plot
/// cells + scale * disp), snapshot_cells / snapshot_disp (C,4,2) with snapshot_offsets (s+1,)
/// (the patch around the growing tip at each critical state, displacements at the critical load;
/// snapshot k belongs to history row k + 1), and the growth history as history_<name> arrays (load_factor, sigma22,
/// cmod, u0, traction, a, K_I, K_II, kink_angle, tip_x, tip_y, condition (None instead of an
/// array with `condition = False`): the most critical tip;
/// empty without growth; history[0] is the unloaded origin) with every tip's state in tip_history_x,
/// tip_history_y, tip_history_K_I, tip_history_K_II, tip_history_kink_angle and
/// tip_history_grows (1.0 if the tip grew after that state) as (s, t) float64 arrays.
///
/// Progress: `progress(done, total, message)` after the first solve and after each growth step
/// (the core cannot be interrupted mid-run: an exception from the callback is re-raised when the
/// run returns).
#[pyfunction]
#[pyo3(signature = (*, width, height, nx, ny, e, nu, plane = "strain", thickness = 1.0,
                    bc = "free", u0 = 0.0, traction = 0.0, crack, extra_cracks = vec![],
                    nsub = 4, tip_nsub = 0,
                    r_i = 2.5, extra_radii = vec![1.5, 2.0, 3.0, 3.5], fixed_area_radius = None,
                    area_threshold = xfem::DEFAULT_AREA_THRESHOLD, growth_steps = 0, g0 = None,
                    da = None, a_stop = None, condition = true, progress = None))]
#[allow(clippy::too_many_arguments)]
fn solve_xfem_plate<'py>(
    py: Python<'py>,
    width: f64,
    height: f64,
    nx: usize,
    ny: usize,
    e: f64,
    nu: f64,
    plane: &str,
    thickness: f64,
    bc: &str,
    u0: f64,
    traction: f64,
    crack: Vec<[f64; 2]>,
    extra_cracks: Vec<Vec<[f64; 2]>>,
    nsub: usize,
    tip_nsub: usize,
    r_i: f64,
    extra_radii: Vec<f64>,
    fixed_area_radius: Option<f64>,
    area_threshold: f64,
    growth_steps: usize,
    g0: Option<f64>,
    da: Option<f64>,
    a_stop: Option<f64>,
    condition: bool,
    progress: Option<Py<PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let prog = Progress::new(progress);
    let params = (|| {
        let growth = if growth_steps == 0 {
            None
        } else {
            let Some(g0) = g0 else {
                return Err(CoreError::invalid(
                    "g0",
                    "a fracture energy > 0 (needed when growth_steps > 0)",
                    "None",
                ));
            };
            Some(GrowthParams {
                g0,
                da,
                a_stop: a_stop.unwrap_or(0.7 * width),
                max_steps: growth_steps,
            })
        };
        Ok::<_, CoreError>(XfemParams {
            width,
            height,
            nx,
            ny,
            material: material(e, nu, plane, thickness)?,
            crack,
            extra_cracks,
            load: plate_load(bc, u0, traction)?,
            nsub,
            tip_nsub: if tip_nsub == 0 { nsub } else { tip_nsub },
            r_i_factor: r_i,
            extra_radius_factors: extra_radii,
            fixed_area_radius,
            area_threshold,
            growth,
            condition,
        })
    })()
    .map_err(|err| core_err(py, err))?;
    let total = growth_steps.max(1);
    let t0 = Instant::now();
    let r = detached(py, "xfem plate", || {
        prog.report(0, total, "xfem: enrich + assemble + solve", true);
        let r = xfem::run(&params, &|done, tot| {
            if params.growth.is_some() {
                let msg = format!("xfem: growth step {done}/{tot}");
                prog.report(done, tot.max(1), &msg, false);
            }
        });
        prog.report(total, total, "xfem: done", true);
        let mesh = Mesh::uniform(0.0, 0.0, width, height, nx, ny)?;
        r.map(|r| (r, mesh))
    });
    let wall = t0.elapsed().as_secs_f64();
    if let Some(err) = prog.take_error() {
        return Err(err);
    }
    let (r, mesh) = r?;
    let d = PyDict::new(py);
    d.set_item("coords", arr2(py, mesh.coords))?;
    d.set_item("elements", elements_i64(py, &mesh.elements))?;
    d.set_item("u", arr1(py, r.u))?;
    d.set_item("heaviside_nodes", index_i64(py, &r.heaviside_nodes))?;
    d.set_item("tip_nodes", index_i64(py, &r.tip_nodes))?;
    d.set_item("crack", arr2(py, r.crack))?;
    d.set_item("crack_initial", arr2(py, params.crack.clone()))?;
    let radii: Vec<[f64; 5]> = r
        .radii
        .iter()
        .map(|x| {
            let s = x.sifs;
            [s.radius, s.k_i, s.k_ii, s.j_from_k, s.j_domain]
        })
        .collect();
    let factors: Vec<f64> = r.radii.iter().map(|x| x.factor).collect();
    d.set_item("radii", arr2(py, radii))?;
    d.set_item("radii_factor", arr1(py, factors))?;
    let tips: Vec<[f64; 6]> = r
        .tips
        .iter()
        .map(|(p, s)| [p[0], p[1], s.k_i, s.k_ii, s.j_from_k, s.j_domain])
        .collect();
    d.set_item("tips", arr2(py, tips))?;
    d.set_item("tip_crack", index_i64(py, &r.tip_crack))?;
    let mut offsets: Vec<i64> = vec![0];
    let mut pts: Vec<[f64; 2]> = Vec::new();
    for c in &r.cracks {
        pts.extend_from_slice(c);
        offsets.push(pts.len() as i64);
    }
    d.set_item("cracks", arr2(py, pts))?;
    d.set_item("cracks_offsets", PyArray1::from_vec(py, offsets))?;
    let n_tips = r.tips.len();
    let tip_col = |f: fn(&xfem::TipStep) -> f64| {
        let flat: Vec<f64> = r.tip_history.iter().flatten().map(f).collect();
        Array2::from_shape_vec((r.tip_history.len(), n_tips), flat)
            .expect("one entry per tip and state")
            .into_pyarray(py)
            .into_any()
    };
    d.set_item("tip_history_x", tip_col(|s| s.pos[0]))?;
    d.set_item("tip_history_y", tip_col(|s| s.pos[1]))?;
    d.set_item("tip_history_K_I", tip_col(|s| s.k_i))?;
    d.set_item("tip_history_K_II", tip_col(|s| s.k_ii))?;
    d.set_item("tip_history_kink_angle", tip_col(|s| s.kink_angle))?;
    d.set_item(
        "tip_history_grows",
        tip_col(|s| f64::from(u8::from(s.grows))),
    )?;
    d.set_item("deformed_cells", quads(py, r.deformed.cells))?;
    d.set_item("deformed_disp", quads(py, r.deformed.disp))?;
    // growth snapshots: concatenated cells, snapshot k = rows offsets[k]..offsets[k+1]
    let mut offsets: Vec<i64> = vec![0];
    let (mut s_cells, mut s_disp) = (Vec::new(), Vec::new());
    for snap in r.snapshots {
        s_cells.extend(snap.cells);
        s_disp.extend(snap.disp);
        offsets.push(s_cells.len() as i64);
    }
    d.set_item("snapshot_cells", quads(py, s_cells))?;
    d.set_item("snapshot_disp", quads(py, s_disp))?;
    d.set_item("snapshot_offsets", PyArray1::from_vec(py, offsets))?;
    let h = &r.history;
    let col = |f: fn(&xfem::GrowthStep) -> f64| -> Vec<f64> { h.iter().map(f).collect() };
    d.set_item("history_load_factor", arr1(py, col(|s| s.lambda)))?;
    d.set_item("history_sigma22", arr1(py, col(|s| s.sigma22)))?;
    d.set_item("history_cmod", arr1(py, col(|s| s.cmod)))?;
    d.set_item("history_u0", arr1(py, col(|s| s.u0)))?;
    d.set_item("history_traction", arr1(py, col(|s| s.traction)))?;
    d.set_item("history_a", arr1(py, col(|s| s.a)))?;
    d.set_item("history_K_I", arr1(py, col(|s| s.k_i)))?;
    d.set_item("history_K_II", arr1(py, col(|s| s.k_ii)))?;
    d.set_item("history_kink_angle", arr1(py, col(|s| s.kink_angle)))?;
    d.set_item("history_tip_x", arr1(py, col(|s| s.tip[0])))?;
    d.set_item("history_tip_y", arr1(py, col(|s| s.tip[1])))?;
    if params.condition {
        d.set_item(
            "history_condition",
            arr1(py, col(|s| s.condition.unwrap_or(0.0))),
        )?;
    } else {
        d.set_item("history_condition", py.None())?;
    }
    d.set_item("condition", r.condition.map(|c| c.value()))?;
    d.set_item("condition_pivot_ratio", r.condition.map(|c| c.pivot_ratio))?;
    d.set_item("K_I", r.k_i)?;
    d.set_item("K_II", r.k_ii)?;
    d.set_item("J", r.j_from_k)?;
    d.set_item("J_domain", r.j_domain)?;
    d.set_item("r_i", r.r_i)?;
    d.set_item("sigma22", r.sigma22)?;
    d.set_item("cmod", r.cmod)?;
    d.set_item("n_dofs", r.n_dofs)?;
    d.set_item("n_std", r.n_std)?;
    d.set_item("n_heaviside_nodes", r.n_heaviside_nodes)?;
    d.set_item("n_tip_nodes", r.n_tip_nodes)?;
    d.set_item("n_dropped_nodes", r.n_dropped_nodes)?;
    d.set_item("anchor_node", r.anchor_node)?;
    d.set_item("status", r.status)?;
    d.set_item("bc", r.grip)?;
    d.set_item("wall_time_s", wall)?;
    d.set_item("warnings", warning_pairs(&r.warnings))?;
    Ok(d)
}

/// Solves a uniform rectangular Q4 grid (origin 0, size width x height, nx x ny elements) with
/// explicit Dirichlet conditions `fixed_dofs` -> `fixed_values` (dof = 2 node + component) and
/// nodal forces `forces` (length 2 (nx+1) (ny+1), or empty for none). Nodes are numbered row by
/// row from the bottom-left corner. Too few conditions (a free rigid-body mode, named) or a
/// numerically singular system (pivot-ratio bound above `COND_SINGULAR`) raise
/// `SingularSystemError`.
///
/// Returns a dict: coords, elements, u, reactions, nodal_stress, energy, residual, n_dofs.
#[pyfunction]
#[pyo3(signature = (*, width, height, nx, ny, e, nu, plane = "strain", thickness = 1.0,
                    fixed_dofs, fixed_values, forces = Vec::new()))]
#[allow(clippy::too_many_arguments)]
fn solve_fem_grid<'py>(
    py: Python<'py>,
    width: f64,
    height: f64,
    nx: usize,
    ny: usize,
    e: f64,
    nu: f64,
    plane: &str,
    thickness: f64,
    fixed_dofs: Vec<usize>,
    fixed_values: Vec<f64>,
    forces: Vec<f64>,
) -> PyResult<Bound<'py, PyDict>> {
    let (model, sol) = detached(py, "fem grid", || {
        if fixed_dofs.len() != fixed_values.len() {
            return Err(CoreError::SizeMismatch {
                what: "fixed_values".into(),
                expected: fixed_dofs.len(),
                got: fixed_values.len(),
            });
        }
        let mat = material(e, nu, plane, thickness)?;
        let mesh = Mesh::uniform(0.0, 0.0, width, height, nx, ny)?;
        let model = FemModel::new(mesh, mat, 2)?;
        let n = model.n_dofs();
        let f = if forces.is_empty() {
            vec![0.0; n]
        } else if forces.len() == n {
            forces
        } else {
            return Err(CoreError::SizeMismatch {
                what: "forces".into(),
                expected: n,
                got: forces.len(),
            });
        };
        let bc = Dirichlet {
            dofs: fixed_dofs.into_iter().zip(fixed_values).collect(),
        };
        bc.check_rigid_modes(&model.mesh.coords)?;
        let sys = LinearSystem::new(model.stiffness(), &bc)?;
        sys.checked_condition("solve", false)?;
        let sol = sys.solve(&f, 1.0)?;
        Ok((model, sol))
    })?;
    let nodal = model.nodal_stresses(&sol.u);
    let d = PyDict::new(py);
    d.set_item("coords", arr2(py, model.mesh.coords.clone()))?;
    d.set_item("elements", elements_i64(py, &model.mesh.elements))?;
    d.set_item("n_dofs", model.n_dofs())?;
    d.set_item("u", arr1(py, sol.u))?;
    d.set_item("reactions", arr1(py, sol.reactions))?;
    d.set_item("nodal_stress", arr2(py, nodal))?;
    d.set_item("energy", sol.energy)?;
    d.set_item("residual", sol.residual)?;
    Ok(d)
}

/// Exercises the progress mechanism: `steps` steps of `step_s` seconds each without the GIL,
/// reporting every step through the throttle. Returns the number of callbacks made.
#[pyfunction]
#[pyo3(signature = (steps, step_s, progress = None))]
fn _progress_demo(
    py: Python<'_>,
    steps: usize,
    step_s: f64,
    progress: Option<Py<PyAny>>,
) -> PyResult<usize> {
    let prog = Progress::new(progress);
    let dt = Duration::from_secs_f64(step_s.max(0.0));
    detached(py, "progress demo", || {
        for i in 0..steps {
            std::thread::sleep(dt);
            if !prog.report(i + 1, steps, "demo", i + 1 == steps) {
                break;
            }
        }
        Ok(())
    })?;
    if let Some(err) = prog.take_error() {
        return Err(err);
    }
    Ok(prog.calls())
}

/// Raises a Rust panic inside the detached region (tests that it reaches Python as
/// `InternalError`, not as a crash).
#[pyfunction]
fn _panic_demo(py: Python<'_>) -> PyResult<()> {
    detached(py, "panic demo", || -> Result<(), CoreError> {
        panic!("deliberate panic for testing")
    })
}

fn hist_i64<'py>(py: Python<'py>, v: impl Iterator<Item = usize>) -> Bound<'py, PyAny> {
    PyArray1::from_vec(py, v.map(|i| i as i64).collect()).into_any()
}

/// Runs a bond-based peridynamics model (`method = "pd"`: PD everywhere) or the splice CCM-PD
/// coupling (`"ccm_pd"`: PD in the rectangles `pd_regions` = [(x0, y0, x1, y1), ...], FEM
/// elsewhere) of the plate, then the sequentially linear analysis (`sla_steps` bond breaks at
/// most). `precrack` is a polyline (first point at the crack mouth; empty = uncracked).
///
/// Returns a dict. Scalars: sigma22, cmod (reference load, before any break), gamma, c, s0,
/// delta, n_dofs, n_nodes, n_pd_nodes, n_bonds, n_precrack_bonds, n_removed_elements,
/// bytes_per_bond, anchor_node, status, solver, n_refactorisations, max_update_rank,
/// refactor_interval, resumed_steps, n_checkpoints, setup_seconds, sla_seconds,
/// peak_memory_bytes (or None), wall_time_s, bc, method; warnings (list of (kind, message)
/// pairs: discretisation warnings, e.g. m < 2 or detached nodes). Checkpoints: `checkpoint_every` steps to
/// `checkpoint_path` (atomic), `resume_from` a checkpoint of the same model (replayed bit for
/// bit). Arrays: detached_nodes (d,2) int64 (step, node; step 0 = by the pre-crack), node_xy (n,2), u (2n,),
/// u_final (2n,; empty when the body separated), pd_nodes (p,) int64, pd_node_xy (p,2),
/// damage (p,), broken (b,) bool, bond_nodes (b,2) int64, out_of_balance (2,), anchor_xy (2,),
/// history_step, history_load_factor, history_sigma22, history_cmod, history_u0,
/// history_crack_length, history_bond (the critical bond of the step), history_n_broken,
/// history_node_i, history_node_j, history_n_detached (one entry per SLA step), damage_at_steps (k,) int64 and
/// damage_at (k,p).
#[pyfunction]
#[pyo3(signature = (*, method, width, height, dx, m, e, nu, plane = "strain", thickness = 1.0,
                    g0, bc = "free", u0 = 0.0, traction = 0.0, pd_regions = Vec::new(),
                    precrack = Vec::new(), sla_steps = 500, stop_crack_length = None,
                    tie_tol = 0.0, refactor_every = 0, fast = true, damage_at_steps = Vec::new(),
                    checkpoint_every = 0, checkpoint_path = None, resume_from = None,
                    progress = None))]
#[allow(clippy::too_many_arguments)]
fn solve_pd_plate<'py>(
    py: Python<'py>,
    method: &str,
    width: f64,
    height: f64,
    dx: f64,
    m: usize,
    e: f64,
    nu: f64,
    plane: &str,
    thickness: f64,
    g0: f64,
    bc: &str,
    u0: f64,
    traction: f64,
    pd_regions: Vec<(f64, f64, f64, f64)>,
    precrack: Vec<(f64, f64)>,
    sla_steps: usize,
    stop_crack_length: Option<f64>,
    tie_tol: f64,
    refactor_every: usize,
    fast: bool,
    damage_at_steps: Vec<usize>,
    checkpoint_every: usize,
    checkpoint_path: Option<std::path::PathBuf>,
    resume_from: Option<std::path::PathBuf>,
    progress: Option<Py<PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    use rustfrac_core::pd::sla::{self, CcmPdParams, Method, SlaParams};
    use rustfrac_core::pd::splice::ModelSpec;
    let prog = Progress::new(progress);
    let params = (|| {
        Ok::<_, CoreError>(CcmPdParams {
            model: ModelSpec {
                method: Method::parse(method)?,
                width,
                height,
                dx,
                m,
                material: material(e, nu, plane, thickness)?,
                g0,
                pd_regions: pd_regions
                    .iter()
                    .map(|&(x0, y0, x1, y1)| [x0, y0, x1, y1])
                    .collect(),
                precrack: precrack.iter().map(|&(x, y)| [x, y]).collect(),
                load: plate_load(bc, u0, traction)?,
            },
            sla: SlaParams {
                max_steps: sla_steps,
                stop_crack_length,
                tie_tol,
                refactor_every,
                fast,
                damage_at_steps,
                checkpoint_every,
                checkpoint_path,
                resume_from,
            },
        })
    })()
    .map_err(|err| core_err(py, err))?;
    let name = params.model.method.name();
    let t0 = Instant::now();
    let r = detached(py, name, || {
        let total = sla_steps.max(1);
        if !prog.report(0, total, &format!("{name}: building the model"), true) {
            return Err(CoreError::Internal {
                detail: "cancelled".into(),
            });
        }
        // a raising callback stops the run (status "cancelled", a checkpoint is written when
        // configured); its exception is re-raised below
        let report = |step: usize, steps: usize| {
            prog.report(step, steps, &format!("sla: step {step}/{steps}"), false)
        };
        let r = sla::run(&params, &report)?;
        let msg = format!("sla: {} after {} steps", r.status, r.history.len());
        prog.report(total, total, &msg, true);
        Ok(r)
    });
    let wall = t0.elapsed().as_secs_f64();
    if let Some(err) = prog.take_error() {
        return Err(err);
    }
    let r = r?;
    let d = PyDict::new(py);
    let h = &r.history;
    d.set_item("history_step", hist_i64(py, h.iter().map(|s| s.step)))?;
    d.set_item(
        "history_load_factor",
        arr1(py, h.iter().map(|s| s.lambda).collect()),
    )?;
    d.set_item(
        "history_sigma22",
        arr1(py, h.iter().map(|s| s.sigma22).collect()),
    )?;
    d.set_item("history_cmod", arr1(py, h.iter().map(|s| s.cmod).collect()))?;
    d.set_item("history_u0", arr1(py, h.iter().map(|s| s.u0).collect()))?;
    d.set_item(
        "history_crack_length",
        arr1(py, h.iter().map(|s| s.crack_length).collect()),
    )?;
    d.set_item("history_bond", hist_i64(py, h.iter().map(|s| s.bonds[0])))?;
    d.set_item(
        "history_n_broken",
        hist_i64(py, h.iter().map(|s| s.bonds.len())),
    )?;
    d.set_item("history_node_i", hist_i64(py, h.iter().map(|s| s.nodes[0])))?;
    d.set_item("history_node_j", hist_i64(py, h.iter().map(|s| s.nodes[1])))?;
    d.set_item(
        "history_n_detached",
        hist_i64(py, h.iter().map(|s| s.detached.len())),
    )?;
    let p = r.damage.len();
    d.set_item(
        "damage_at_steps",
        hist_i64(py, r.damage_at.iter().map(|(k, _)| *k)),
    )?;
    let k = r.damage_at.len();
    let snaps: Vec<f64> = r.damage_at.into_iter().flat_map(|(_, v)| v).collect();
    d.set_item(
        "damage_at",
        Array2::from_shape_vec((k, p), snaps)
            .map_err(|err| py_error(py, "InternalError", format!("damage_at: {err}")))?
            .into_pyarray(py),
    )?;
    d.set_item("node_xy", arr2(py, r.node_xy))?;
    d.set_item("u", arr1(py, r.u))?;
    d.set_item("u_final", arr1(py, r.u_final))?;
    d.set_item("pd_nodes", hist_i64(py, r.pd_nodes.into_iter()))?;
    d.set_item("pd_node_xy", arr2(py, r.pd_node_xy))?;
    d.set_item("damage", arr1(py, r.damage))?;
    d.set_item("broken", PyArray1::from_vec(py, r.broken))?;
    let nb = r.bond_nodes.len();
    let flat: Vec<i64> = r.bond_nodes.iter().flatten().map(|&i| i as i64).collect();
    d.set_item(
        "bond_nodes",
        Array2::from_shape_vec((nb, 2), flat)
            .expect("shape matches length")
            .into_pyarray(py),
    )?;
    d.set_item("out_of_balance", arr1(py, r.out_of_balance.to_vec()))?;
    d.set_item("anchor_xy", arr1(py, r.anchor_xy.to_vec()))?;
    d.set_item("sigma22", r.sigma22)?;
    d.set_item("cmod", r.cmod)?;
    d.set_item("gamma", r.gamma)?;
    d.set_item("c", r.c)?;
    d.set_item("s0", r.s0)?;
    d.set_item("delta", r.delta)?;
    d.set_item("n_dofs", r.n_dofs)?;
    d.set_item("n_nodes", r.n_nodes)?;
    d.set_item("n_pd_nodes", r.n_pd_nodes)?;
    d.set_item("n_bonds", r.n_bonds)?;
    d.set_item("n_precrack_bonds", r.n_precrack_bonds)?;
    d.set_item("n_removed_elements", r.n_removed_elements)?;
    d.set_item("bytes_per_bond", r.bytes_per_bond)?;
    d.set_item("anchor_node", r.anchor_node)?;
    d.set_item("status", r.status)?;
    d.set_item("solver", r.solver)?;
    d.set_item("n_refactorisations", r.n_refactorisations)?;
    d.set_item("max_update_rank", r.max_update_rank)?;
    d.set_item("refactor_interval", r.refactor_interval)?;
    d.set_item("resumed_steps", r.resumed_steps)?;
    d.set_item("n_checkpoints", r.n_checkpoints)?;
    d.set_item("warnings", warning_pairs(&r.warnings))?;
    let nd = r.detached_nodes.len();
    let flat: Vec<i64> = r
        .detached_nodes
        .iter()
        .flat_map(|&(s, n)| [s as i64, n as i64])
        .collect();
    d.set_item(
        "detached_nodes",
        Array2::from_shape_vec((nd, 2), flat)
            .map_err(|err| py_error(py, "InternalError", format!("detached_nodes: {err}")))?
            .into_pyarray(py),
    )?;
    d.set_item("setup_seconds", r.setup_seconds)?;
    d.set_item("sla_seconds", r.sla_seconds)?;
    d.set_item("peak_memory_bytes", r.peak_memory_bytes)?;
    d.set_item("wall_time_s", wall)?;
    d.set_item("bc", r.grip)?;
    d.set_item("method", r.method)?;
    Ok(d)
}

#[pymodule]
fn _core(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add("PROGRESS_INTERVAL_S", PROGRESS_INTERVAL_S)?;
    m.add("COND_WARN", rustfrac_core::solver::COND_WARN)?;
    m.add("COND_SINGULAR", rustfrac_core::solver::COND_SINGULAR)?;
    m.add(
        "WARNING_KINDS",
        rustfrac_core::WarningKind::ALL
            .iter()
            .map(|k| k.name())
            .collect::<Vec<_>>(),
    )?;
    m.add_function(wrap_pyfunction!(solve_fem_plate, m)?)?;
    m.add_function(wrap_pyfunction!(solve_fem_grid, m)?)?;
    m.add_function(wrap_pyfunction!(solve_xfem_plate, m)?)?;
    m.add_function(wrap_pyfunction!(_progress_demo, m)?)?;
    m.add_function(wrap_pyfunction!(_panic_demo, m)?)?;
    m.add_function(wrap_pyfunction!(solve_pd_plate, m)?)?;
    Ok(())
}
