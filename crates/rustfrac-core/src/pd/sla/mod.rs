//! Sequentially linear analysis (SLA, Ni et al. 2019; paper section 3) of the CCM-PD (or pure PD)
//! plate on a model whose s0 calibration is made above it ([`run_calibrated`]; the entry point
//! that makes it, and that the Python bindings call, is [`crate::pd::analysis::run`]).
//!
//! Each step solves the current (linear) model once at the reference load, breaks the bond with
//! the smallest load factor lambda = s0 / s and records the response at that load. The run
//! (`run.rs`) builds the model and its solver (`choice.rs`), replays a checkpoint (`resume.rs`),
//! takes the steps (`steps.rs`, on the state `state.rs`; the critical bonds: `critical.rs`),
//! grows an adaptive region between them (`switch.rs`) and collects the result (`collect.rs`).
//! Two solvers behind one interface (`engine.rs`):
//! * **oracle** (`fast = false` or `pd.engine = "oracle"`, `oracle.rs`): reassemble the splice
//!   matrix and refactorise it (sparse LU, symbolic analysis reused) at every step.
//! * **fast** (default, `fast/`): condense once onto the PD unknowns (`fast/condensation.rs`);
//!   a broken bond is a rank-1 change of the condensed system, handled by Sherman-Morrison-
//!   Woodbury (`fast/smw.rs`) on a base condensed system S_0 kept in one of two forms
//!   (`fast/base.rs`): its dense LU (`pd.engine = "dense"`) or a sparse factor of it
//!   (`"sparse"`: K_PP plus a dense block on the FEM interface; sparse Cholesky for pure PD,
//!   for CCM-PD the Cholesky of K_PP bordered by the FEM coupling (Woodbury), or the sparse LU
//!   of S when K_PP is not symmetric positive definite); the columns of S_0^{-1} the breaks
//!   need are kept
//!   (`fast/columns.rs`). `"auto"` takes the form the cost model ([`crate::pd::cost`]: dense O(n_P^3) per
//!   condensation vs sparse factorisation + solves, for 500 steps) estimates cheaper; the choice
//!   and both estimates are in the result's `solver`. Periodic re-condensation
//!   ([`crate::pd::cost::auto_refactor_every`] dense, the cost model's interval sparse) bounds the stored update
//!   vectors, so a run of any length keeps its memory bounded: per step only the history row
//!   (about 100 bytes) is kept (`memory.rs`).
//!
//! **Detached nodes** (`grounding.rs`): a PD node whose intact bonds give no stiffness along some
//! direction is grounded there by a spring before the break that needs it; every grounding is
//! reported (`detached_nodes`, a warning). Only a true separation (a part of the body no longer
//! held: the Schur pivot vanishes, or the load path is cut) ends the run.
//!
//! **Checkpoints** ([`checkpoint`]): every `checkpoint_every` steps (and when cancelled) the
//! broken-bond sequence and the history are written; `resume_from` replays them and continues, bit
//! for bit the same as an uninterrupted run.
//!
//! Entry point: [`crate::pd::analysis::run`]`(&problem, &|step, max_steps| true)` (or
//! [`crate::pd::analysis::run_reporting`], whose callback reads an [`SlaProgress`]: the crack's
//! advance towards a crack-length stop) for a
//! [`crate::problem::Problem`] of method "pd" or "ccm_pd" (start from `Problem::paper("ccm_pd")`
//! and change what you need: `p.pd_mut().sla.max_steps = 100`; return `false` from the callback to
//! stop: status [`SlaStatus::Cancelled`]), then read [`CcmPdResult`]. Every rule of the problem is
//! checked first ([`crate::problem::validate`]; [`crate::Error::InvalidInput`] names the scene key
//! and its range); a separated body ends the run with [`SlaStatus::Separated`] (never NaN); faer
//! panics are caught inside the solver wrappers. [`run_model`] runs a model built by hand
//! ([`crate::pd::splice::SpliceModel::with_precrack`]).
//!
//! The records (`result.rs`: [`SlaStep`], [`SlaStatus`], [`CcmPdResult`]) are a leaf module, so
//! the checkpoint format depends on them and not on the run.

mod adaptive;
pub mod checkpoint;
mod choice;
mod collect;
mod critical;
mod engine;
mod fast;
mod grounding;
mod memory;
mod oracle;
mod progress;
mod result;
mod resume;
mod run;
mod state;
mod steps;
mod switch;

#[doc(hidden)]
pub use fast::{force_lu_form, force_screening};
pub use grounding::DEBRIS_LIMIT;
pub use memory::peak_memory_bytes;
pub use progress::SlaProgress;
pub use result::{
    CcmPdResult, Constants, FinalState, Geometry, ModelCounts, ReferenceState, RegionRecord,
    RegionSwitch, RunSummary, SlaStatus, SlaStep, SolverUsed, SolverWork, Timings,
};
pub use run::{run_calibrated, run_model};
pub use steps::stop_at_loaded_boundary;
