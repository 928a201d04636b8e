//! Sequentially linear analysis (SLA, Ni et al. 2019; paper section 3) of the CCM-PD (or pure PD)
//! plate, and the driver the Python bindings call ([`run`]).
//!
//! Each step solves the current (linear) model once at the reference load, breaks the bond with
//! the smallest load factor lambda = s0 / s and records the response at that load (`driver.rs`).
//! Two solvers behind one interface (`engine.rs`):
//! * **oracle** (`fast = false`, `oracle.rs`): reassemble the splice matrix and refactorise it
//!   (sparse LU, symbolic analysis reused) at every step.
//! * **fast** (default, `fast/`): condense once onto the PD unknowns (`fast/condensation.rs`);
//!   a broken bond is a rank-1 change of the condensed system, handled by Sherman-Morrison-
//!   Woodbury (`fast/smw.rs`); periodic re-condensation ([`auto_refactor_every`]) bounds the
//!   stored update vectors, so a run of any length keeps its memory at O(bonds + n_P^2): per step
//!   only the history row (about 100 bytes) is kept (`memory.rs`).
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
//! Entry point for the bindings: build [`CcmPdParams`] (start from [`CcmPdParams::paper`] and
//! override fields of its `model` ([`ModelSpec`]; `model.method` = [`Method::CcmPd`] or
//! [`Method::Pd`]) and `sla` ([`SlaParams`])), call [`run`]`(&params, &|step, max_steps| true)`
//! (return `false` to stop: status "cancelled"), read [`CcmPdResult`]. Every parameter is
//! validated ([`crate::Error::InvalidInput`] names it and its range): the SLA options by
//! [`SlaParams::validate`], the model when it is built ([`crate::pd::splice::SpliceModel::new`]);
//! a separated body ends the run with status "separated" (never NaN); faer panics are caught
//! inside the solver wrappers.
//!
//! The inputs (`params.rs`) and the records (`result.rs`: [`SlaStep`], [`CcmPdResult`]) are leaf
//! modules, so the checkpoint format depends on them and not on the driver.

pub mod checkpoint;
mod driver;
mod engine;
mod fast;
mod grounding;
mod memory;
mod oracle;
mod params;
mod result;

pub use crate::pd::splice::{Method, ModelSpec};
pub use driver::run;
pub use grounding::DEBRIS_LIMIT;
pub use memory::peak_memory_bytes;
pub use params::{auto_refactor_every, CcmPdParams, SlaParams};
pub use result::{CcmPdResult, SlaStep};
