//! What the table's rows share: units, shapes, presence conditions and the names they are
//! written with.

pub(super) use super::super::entry::Dim::{Fixed, PlusOne, Twice, Var};
pub(super) use super::super::entry::Kind::{
    Float, FloatList, Floats, Int, Ints, Str, StrList, TableList,
};
pub(super) use super::super::entry::{Dim, Kind, Methods, Table};
pub(super) use super::super::record::Group::{Fields, Headline, History, Meta, Scalars};

pub(super) const LENGTH: &str = "length";
pub(super) const STRESS: &str = "stress";
pub(super) const FORCE: &str = "force";
pub(super) const ENERGY: &str = "energy";
pub(super) const G_UNIT: &str = "energy/area";
pub(super) const K_UNIT: &str = "stress sqrt(length)";
pub(super) const ONE: &str = "1";
pub(super) const RAD: &str = "rad";
pub(super) const SECONDS: &str = "s";
pub(super) const BYTES: &str = "bytes";
pub(super) const TEXT: &str = "";

pub(super) const ROWS: &[Dim] = &[Var("n_rows")];
pub(super) const XY: &[Dim] = &[Var("n_nodes"), Fixed(2)];
pub(super) const NODE_DOFS: &[Dim] = &[Twice("n_nodes")];
pub(super) const PAIR: &[Dim] = &[Fixed(2)];
pub(super) const PAIRS: &[Dim] = &[Var("n_points"), Fixed(2)];
pub(super) const BOXES: &[Dim] = &[Var("n_boxes"), Fixed(4)];
pub(super) const QUADS: &[Dim] = &[Var("n_patch_cells"), Fixed(4), Fixed(2)];
pub(super) const SNAP_QUADS: &[Dim] = &[Var("n_snapshot_cells"), Fixed(4), Fixed(2)];
pub(super) const TIP_ROWS: &[Dim] = &[Var("n_tip_rows"), Var("n_tips")];
pub(super) const GAUSS_XY: &[Dim] = &[Var("n_gauss"), Fixed(2)];
pub(super) const GAUSS_S: &[Dim] = &[Var("n_gauss"), Fixed(3)];

pub(super) const REGIONS: &str =
    "the scene has supports or loads on regions ([[support]], [[load]])";
pub(super) const PROBES: &str = "the scene has probes ([[probe]])";
pub(super) const EDGE_REGIONS: &str = "an edge region of the scene (a support or load on an edge)";
pub(super) const GROWTH: &str = "a growth run (xfem.growth)";
