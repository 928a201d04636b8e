//! The output side of the core, the twin of [`crate::problem`]: every run's result becomes a
//! [`Record`] (named values in five groups: headline, fields, history, scalars, meta), and
//! [`schema`] is the table of every name a record may hold, per method, with its kind, shape,
//! unit, meaning and when it is present; [`status`] lists each method's statuses. The
//! conversions live here, one file per method (`fem.rs`, `xfem.rs`, `pd.rs`, the shared parts
//! in `common.rs`); the bindings turn a record into Python without knowing a name.
//!
//! Adding a result key: one line of [`schema`] and the line of the method's conversion that
//! sets it; the test of `output/tests.rs` fails when the two disagree.

pub mod check;
mod common;
pub mod entry;
mod fem;
mod pd;
pub mod record;
pub mod schema;
pub mod status;
mod table;
#[cfg(test)]
mod tests;
mod xfem;

pub use record::{Entries, Group, Record, Value};
pub use schema::{Dim, Entry, Kind, Methods, Presence};
pub use status::Status;
