//! The rows of the result schema's table, one file per method family; the units, shapes and
//! presence conditions they share are in `units.rs`. `super::schema` (`schema()`) puts them together.

mod common;
mod fem;
mod sla;
mod units;
mod xfem;

use super::entry::{Entry, Table};

/// Every entry, in table order.
pub(super) fn build() -> Vec<Entry> {
    let mut t = Table::new();
    common::rows(&mut t);
    fem::rows(&mut t);
    xfem::rows(&mut t);
    sla::rows(&mut t);
    t.v
}
