//! Every result entry of every method: its group, name, kind (with the shape of an array),
//! unit and meaning, and when it is present. This table is the one place a result name lives:
//! the bindings export it (`rustfrac._core.result_schema()`), Python's `Result`, its files and
//! figures read names and units from it, and a test checks every record a run emits against it
//! (`output/tests.rs`). Adding a result key: one `t.add(..)` line in the method family's file
//! of `output/table/` and the line of the method's conversion (`output/{fem,xfem,pd}.rs`) that
//! sets it.
//!
//! Units are the scene's (consistent, chosen by the user; the paper's case N, mm, MPa) and are
//! named by dimension: "length", "stress", "force" (over the thickness), "energy",
//! "energy/area" (J, G), "stress sqrt(length)" (K), "1" (dimensionless), "rad", "s", "bytes";
//! "" for text, tables and indices. Names with a `<region>` or `<name>` part stand for one
//! entry per region (`support[0]`, `load[1]`) or probe of the scene.

pub use super::entry::{Dim, Entry, Kind, Methods, Presence};
use super::record::Group;
use std::sync::OnceLock;

/// Every result entry of every method.
pub fn schema() -> &'static [Entry] {
    static S: OnceLock<Vec<Entry>> = OnceLock::new();
    S.get_or_init(super::table::build)
}

/// The entries of `method`, in table order.
pub fn entries(method: &str) -> impl Iterator<Item = &'static Entry> + '_ {
    schema().iter().filter(move |e| e.methods.has(method))
}

/// The entry of `method` a key of group `g` is (None: not in the table).
pub fn entry(method: &str, g: Group, key: &str) -> Option<&'static Entry> {
    entries(method).find(|e| e.group == g && e.matches(key))
}
