//! Every scene key: its section, kind, default, valid range and meaning. This table is the one
//! place where a scene rule lives; the Python package reads it (`rustfrac._core.scene_schema()`)
//! to build its section classes, so a new parameter is one entry here plus the line of
//! [`super::parse`] that reads it into the [`super::Problem`].
//!
//! Units are consistent and up to the user; the paper's case uses N, mm and MPa (E = 10000).

use super::grid::MAX_ELEMENTS;
use super::value::Value;
use crate::error::{MAG_MAX, MAG_MIN};
use std::sync::OnceLock;

/// Default of the small-area rule's threshold (`xfem.area_threshold`; see
/// [`crate::xfem::enrichment`]).
pub const DEFAULT_AREA_THRESHOLD: f64 = 1e-4;
/// Largest SLA step count, re-condensation period and damage-snapshot step.
pub const MAX_STEPS: usize = 1_000_000;
/// XFEM growth's default stop length as a fraction of the plate width (`xfem.a_stop = 0`: the
/// paper's Fig. 7 runs to 0.7 W).
pub const DEFAULT_A_STOP_FRACTION: f64 = 0.7;
/// Most damage snapshots a run stores (each holds one value per PD node).
pub const MAX_SNAPSHOTS: usize = 10_000;
/// Largest number of XFEM growth steps.
pub const MAX_GROWTH_STEPS: usize = 100_000;
/// Largest PD horizon factor m = delta / dx (bonds per node grow as m^2).
pub const MAX_HORIZON_FACTOR: usize = 12;
/// Plane-strain Poisson's ratio of bond-based peridynamics (fixed by the model).
pub const PD_NU: f64 = 0.25;
/// Radii (tip-element lengths) at which the SIFs are reported besides r_I, where they fit.
pub const XFEM_EXTRA_RADII: [f64; 4] = [1.5, 2.0, 3.0, 3.5];
/// The methods, in the order the docs list them.
pub const METHODS: [&str; 4] = ["fem", "xfem", "pd", "ccm_pd"];
/// The grip variants of the plate's loading (eq. 61).
pub const BCS: [&str; 3] = ["free", "clamped", "traction"];
/// Crack kinds accepted by each method.
pub fn crack_kinds(method: &str) -> &'static [&'static str] {
    match method {
        "fem" => &["none", "seam"],
        "xfem" => &["edge", "center"],
        _ => &["none", "edge", "center"],
    }
}
/// The crack kind of a scene without a `[crack]` section: the paper's crack, as a seam for FEM.
pub fn default_crack_kind(method: &str) -> &'static str {
    if method == "fem" {
        "seam"
    } else {
        "edge"
    }
}
/// Sections each method reads (the others must not appear in its scenes).
pub fn method_sections(method: &str) -> &'static [&'static str] {
    match method {
        "fem" => &["plate", "material", "load", "crack", "mesh"],
        "xfem" => &["plate", "material", "load", "crack", "mesh", "xfem"],
        _ => &["plate", "material", "load", "crack", "pd"],
    }
}
/// Every section, in the order of the docs.
pub const SECTIONS: [&str; 12] = [
    "plate",
    "material",
    "load",
    "crack",
    "mesh",
    "xfem",
    "pd",
    "hole",
    "notch",
    "support",
    "region_load",
    "probe",
];
/// The general scene's lists of tables (`[[hole]]`, ...), every method reads them: (scene key,
/// schema section of its entries). `[[load]]` entries are the section `region_load` (a `[load]`
/// table is the paper's grips).
pub const LIST_SECTIONS: [(&str, &str); 5] = [
    ("hole", "hole"),
    ("notch", "notch"),
    ("support", "support"),
    ("load", "region_load"),
    ("probe", "probe"),
];
/// Hole shapes.
pub const SHAPES: [&str; 3] = ["circle", "rect", "polygon"];
/// `pd.hole_volumes`: the volume of a PD node whose cell a hole cuts ([`super::HoleVolumes`]).
pub const HOLE_VOLUMES: [&str; 2] = ["centre", "exact"];
/// `xfem.kink_rule`: the direction rule of XFEM growth ([`super::KinkRule`]).
pub const KINK_RULES: [&str; 2] = ["hoop", "predictor_corrector"];
/// `pd.engine`: the SLA solver ([`super::SlaEngine`]).
pub const SLA_ENGINES: [&str; 4] = ["auto", "dense", "sparse", "oracle"];
/// `pd.region`: the CCM-PD region fixed (`pd.center`, `pd.size`) or adaptive
/// ([`super::pd_region`]).
pub const PD_REGIONS: [&str; 2] = ["fixed", "adaptive"];
// --- pd.surface_correction ---
/// `pd.surface_correction`: the PD surface correction ([`super::SurfaceCorrection`],
/// `crate::pd::surface_correction`).
pub const SURFACE_CORRECTIONS: [&str; 2] = ["none", "energy"];
// --- end pd.surface_correction ---
/// `pd.s0_calibration`: the critical stretch's rule ([`crate::pd::calibration`]).
pub const S0_CALIBRATIONS: [&str; 3] = ["continuum", "grid", "sla"];
/// Largest `pd.adapt_margin` and `pd.adapt_size` (horizons).
pub const MAX_ADAPT_HORIZONS: f64 = 50.0;
/// Regions of supports (loads: all but "box").
pub const REGIONS: [&str; 4] = ["edge", "edge_part", "point", "box"];
/// Probe kinds.
pub const PROBES: [&str; 2] = ["displacement", "opening"];
/// Largest ratio of neighbouring element sizes of a graded grid (`mesh.grading`).
pub const MAX_GRADING: f64 = 2.0;
/// Largest FEM element of a graded CCM-PD grid, in units of dx (`pd.fem_coarse`).
pub const MAX_FEM_COARSE: f64 = 1000.0;
/// Most vertices of a polygon hole.
pub const MAX_POLYGON_VERTICES: usize = 10_000;

/// The kind of a key's value.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    Float,
    Int,
    Str,
    Bool,
    /// two floats
    Pair,
    /// a list of integers
    IntList,
    /// a list of numbers
    FloatList,
    /// a list of pairs of numbers
    PairList,
}

impl Kind {
    /// Stable name (the Python side maps it to a type).
    pub fn name(&self) -> &'static str {
        match self {
            Kind::Float => "float",
            Kind::Int => "int",
            Kind::Str => "str",
            Kind::Bool => "bool",
            Kind::Pair => "pair",
            Kind::IntList => "intlist",
            Kind::FloatList => "floatlist",
            Kind::PairList => "pairlist",
        }
    }
    /// How messages say "a value of this kind".
    pub fn phrase(&self) -> &'static str {
        match self {
            Kind::Float => "a number",
            Kind::Int => "an integer",
            Kind::Str => "a string",
            Kind::Bool => "true or false",
            Kind::Pair => "a pair of numbers",
            Kind::IntList => "a list of integers",
            Kind::FloatList => "a list of numbers",
            Kind::PairList => "a list of pairs of numbers",
        }
    }
}

/// A key's value after its kind was checked.
#[derive(Debug, Clone, PartialEq)]
pub enum Val {
    Float(f64),
    Int(i64),
    Str(String),
    Bool(bool),
    Pair([f64; 2]),
    IntList(Vec<i64>),
    FloatList(Vec<f64>),
    PairList(Vec<[f64; 2]>),
}

impl Val {
    pub fn f(&self) -> f64 {
        match self {
            Val::Float(v) => *v,
            Val::Int(v) => *v as f64,
            _ => f64::NAN,
        }
    }
    pub fn i(&self) -> i64 {
        match self {
            Val::Int(v) => *v,
            _ => 0,
        }
    }
    pub fn s(&self) -> &str {
        match self {
            Val::Str(v) => v,
            _ => "",
        }
    }
    pub fn b(&self) -> bool {
        matches!(self, Val::Bool(true))
    }
    pub fn pair(&self) -> [f64; 2] {
        match self {
            Val::Pair(v) => *v,
            _ => [f64::NAN; 2],
        }
    }
    pub fn ints(&self) -> &[i64] {
        match self {
            Val::IntList(v) => v,
            _ => &[],
        }
    }
    pub fn floats(&self) -> &[f64] {
        match self {
            Val::FloatList(v) => v,
            _ => &[],
        }
    }
    pub fn pairs(&self) -> &[[f64; 2]] {
        match self {
            Val::PairList(v) => v,
            _ => &[],
        }
    }
    /// Back to the tree (defaults and normalised values for Python).
    pub fn to_value(&self) -> Value {
        match self {
            Val::Float(v) => Value::Float(*v),
            Val::Int(v) => Value::Int(*v),
            Val::Str(v) => Value::Str(v.clone()),
            Val::Bool(v) => Value::Bool(*v),
            Val::Pair(v) => Value::List(v.iter().map(|&x| Value::Float(x)).collect()),
            Val::IntList(v) => Value::List(v.iter().map(|&x| Value::Int(x)).collect()),
            Val::FloatList(v) => Value::List(v.iter().map(|&x| Value::Float(x)).collect()),
            Val::PairList(v) => Value::List(
                v.iter()
                    .map(|p| Value::List(p.iter().map(|&x| Value::Float(x)).collect()))
                    .collect(),
            ),
        }
    }
    /// Python-style repr for messages.
    pub fn repr(&self) -> String {
        self.to_value().repr()
    }
}

/// One scene key.
pub struct KeySpec {
    pub section: &'static str,
    pub key: &'static str,
    pub kind: Kind,
    pub default: Val,
    /// the valid range in words (messages and docs)
    pub valid: String,
    /// what the key means, with units
    pub doc: &'static str,
    /// the range check of a value of the right kind
    pub ok: fn(&Val) -> bool,
}

impl KeySpec {
    /// `section.key`, the name errors carry.
    pub fn param(&self) -> String {
        format!("{}.{}", self.section, self.key)
    }
}

fn finite(v: f64) -> bool {
    v.is_finite() && v.abs() <= MAG_MAX
}
fn positive(v: f64) -> bool {
    v.is_finite() && (MAG_MIN..=MAG_MAX).contains(&v)
}
fn nonneg(v: f64) -> bool {
    v == 0.0 || positive(v)
}

const POS: &str = "a finite number in [1e-30, 1e30]";
const FINITE: &str = "a finite number with |value| <= 1e30";

/// "one of 'a', 'b'": the valid range in words of a key whose value is one of `opts`.
pub fn choice(opts: &[&str]) -> String {
    let q: Vec<String> = opts.iter().map(|o| format!("'{o}'")).collect();
    format!("one of {}", q.join(", "))
}

#[allow(clippy::too_many_lines)]
fn build() -> Vec<KeySpec> {
    use Kind::*;
    let k = |section, key, kind, default, valid: &str, doc, ok: fn(&Val) -> bool| KeySpec {
        section,
        key,
        kind,
        default,
        valid: valid.to_string(),
        doc,
        ok,
    };
    let pos = |v: &Val| positive(v.f());
    let fin = |v: &Val| finite(v.f());
    let mut v = vec![
        k("plate", "width", Float, Val::Float(11.0), POS,
          "plate width W along x1 (length); the plate is [0, W] x [0, L]", pos),
        k("plate", "height", Float, Val::Float(21.0), POS,
          "plate height L along x2 (length)", pos),
        k("material", "E", Float, Val::Float(10000.0), POS,
          "Young's modulus (stress)", pos),
        k("material", "nu", Float, Val::Float(0.25), "-1 < nu < 0.5",
          "Poisson's ratio (bond-based PD fixes 0.25)",
          |v| v.f().is_finite() && v.f() > -1.0 && v.f() < 0.5),
        k("material", "plane", Str, Val::Str("strain".into()), &choice(&["strain", "stress"]),
          "plane strain or plane stress", |v| matches!(v.s(), "strain" | "stress")),
        k("material", "thickness", Float, Val::Float(1.0), POS,
          "out-of-plane thickness h (length)", pos),
        k("material", "G0", Float, Val::Float(0.367), POS,
          "critical energy release rate (force / length): LEFM growth and PD bond strength", pos),
        k("load", "bc", Str, Val::Str("free".into()), &choice(&BCS),
          "grips on the top and bottom edges (eq. 61): 'free' (u2 = +-u0, u1 free, one anchor \
           node), 'clamped' (u2 = +-u0, u1 = 0) or 'traction' (uniform normal stress)",
          |v| BCS.contains(&v.s())),
        k("load", "u0", Float, Val::Float(0.01), FINITE,
          "reference grip displacement (length), non-zero under displacement grips", fin),
        k("load", "traction", Float, Val::Float(9.993), FINITE,
          "reference traction (stress) of bc = 'traction', non-zero there", fin),
        k("crack", "kind", Str, Val::Str("seam".into()),
          &choice(&["none", "seam", "edge", "center"]),
          "'none', 'seam' (FEM: duplicated nodes on the grid line nearest y), 'edge' (XFEM level \
           set / PD pre-broken bonds) or 'center' (XFEM interior crack); without a [crack] \
           section: 'seam' for FEM, else 'edge'",
          |v| matches!(v.s(), "none" | "seam" | "edge" | "center")),
        k("crack", "a0", Float, Val::Float(1.1), POS,
          "crack length (length); the half-length of a 'center' crack", pos),
        k("crack", "y", Float, Val::Float(10.5), POS,
          "x2 of the crack mouth (left/right edge cracks) or centre", pos),
        k("crack", "angle", Float, Val::Float(0.0), "-180 <= angle <= 180 degrees",
          "degrees counter-clockwise from x1 ('center'), or from the side's inward normal \
           (edge cracks); XFEM only, 0 elsewhere",
          |v| v.f().is_finite() && v.f().abs() <= 180.0),
        k("crack", "x", Float, Val::Float(5.5), POS,
          "x1 of a 'center' crack's centre, or of the mouth of a bottom/top edge crack", pos),
        k("crack", "side", Str, Val::Str("left".into()),
          &choice(&["left", "right", "bottom", "top"]),
          "the edge an XFEM edge crack starts from (other methods: 'left')",
          |v| matches!(v.s(), "left" | "right" | "bottom" | "top")),
        k("mesh", "nx", Int, Val::Int(44), "an integer >= 1",
          "Q4 elements along x1 (FEM, XFEM)", |v| v.i() >= 1),
        k("mesh", "ny", Int, Val::Int(83), "an integer >= 1",
          "Q4 elements along x2 (FEM, XFEM)", |v| v.i() >= 1),
        k("mesh", "gauss", Int, Val::Int(2),
          "an integer in 2..5 (1 point per direction leaves the Q4 element's hourglass modes: \
           the stiffness is rank deficient)",
          "Gauss points per direction of the standard elements (2 is exact for rectangles)",
          |v| (2..=5).contains(&v.i())),
        k("mesh", "xs", FloatList, Val::FloatList(Vec::new()),
          "empty (uniform) or strictly increasing x1 grid lines from 0 to plate.width",
          "the vertical grid lines of a tensor grid (then mesh.nx is their count - 1)",
          |v| v.floats().iter().all(|&x| finite(x))),
        k("mesh", "ys", FloatList, Val::FloatList(Vec::new()),
          "empty (uniform) or strictly increasing x2 grid lines from 0 to plate.height",
          "the horizontal grid lines of a tensor grid (then mesh.ny is their count - 1)",
          |v| v.floats().iter().all(|&x| finite(x))),
        k("mesh", "refine", FloatList, Val::FloatList(Vec::new()),
          "empty (off) or a box [x0, y0, x1, y1] with x0 < x1, y0 < y1",
          "graded grid: elements of size mesh.refine_h in this box, growing by mesh.grading \
           per element away from it up to the uniform grid's size (plate / mesh.nx, mesh.ny)",
          |v| v.floats().is_empty() || (v.floats().len() == 4 && v.floats().iter().all(|&x| finite(x))
              && v.floats()[0] < v.floats()[2] && v.floats()[1] < v.floats()[3])),
        k("mesh", "refine_h", Float, Val::Float(0.0), "0 (off) or a length in [1e-30, 1e30]",
          "element size in the refinement box", |v| nonneg(v.f())),
        k("mesh", "grading", Float, Val::Float(1.2),
          &format!("1 <= grading <= {MAX_GRADING}"),
          "ratio of neighbouring element sizes outside the refinement box",
          |v| v.f() >= 1.0 && v.f() <= MAX_GRADING),
        k("xfem", "nsub", Int, Val::Int(4), "an integer in 1..32",
          "sub-quads per direction of split and branch-enriched elements, 2 x 2 Gauss points \
           each (eq. 35)", |v| (1..=32).contains(&v.i())),
        k("xfem", "tip_nsub", Int, Val::Int(0), "0 (= nsub) or an integer in nsub..64",
          "sub-quads per direction in tip elements", |v| (0..=64).contains(&v.i())),
        k("xfem", "r_I", Float, Val::Float(2.5), "0.5 <= r_I <= 20 element lengths",
          "radius of the interaction-integral domain, in tip-element lengths",
          |v| v.f().is_finite() && (0.5..=20.0).contains(&v.f())),
        k("xfem", "fixed_area_radius", Float, Val::Float(0.0),
          "0 (off) or a length in [1e-30, 1e30]",
          "enrich every node within this distance of a tip with the branch functions (Laborde \
           et al. 2005); 0 = the tip element's nodes only", |v| nonneg(v.f())),
        k("xfem", "area_threshold", Float, Val::Float(DEFAULT_AREA_THRESHOLD), "0 <= area_threshold < 0.5",
          "small-area rule: a Heaviside node is dropped when the smaller part of its support \
           cut by the crack is below this fraction of the support (0: only exactly zero parts)",
          |v| v.f() >= 0.0 && v.f() < 0.5),
        k("xfem", "growth_steps", Int, Val::Int(0),
          &format!("an integer in 0..{MAX_GROWTH_STEPS}"),
          "0 = solve at the reference load only; else the most LEFM growth steps (critical \
           states where G = G0)", |v| (0..=MAX_GROWTH_STEPS as i64).contains(&v.i())),
        k("xfem", "tip_tie_tol", Float, Val::Float(1e-6), "0 <= tip_tie_tol < 1",
          "growth with several tips: every tip whose critical load factor is within this \
           relative tolerance of the smallest grows in the same step (symmetric tips together)",
          |v| v.f() >= 0.0 && v.f() < 1.0),
        k("xfem", "da", Float, Val::Float(0.0),
          "0 (one element length) or a length in [1e-30, 1e30]",
          "crack extension per growth step", |v| nonneg(v.f())),
        k("xfem", "kink_rule", Str, Val::Str(KINK_RULES[0].into()), &choice(&KINK_RULES),
          "growth direction: 'hoop' (maximum hoop stress at the tip, one solve per step) or \
           'predictor_corrector' (a trial extension, the hoop angle at the trial tip, the \
           bisector: two solves per step; removes the zig-zag of curving paths)",
          |v| KINK_RULES.contains(&v.s())),
        k("xfem", "a_stop", Float, Val::Float(0.0),
          "0 (0.7 plate.width) or 0 < a_stop < plate.width",
          "growth stops once a crack length would exceed it (half-length for 'center')",
          |v| nonneg(v.f())),
        k("pd", "dx", Float, Val::Float(1.0 / 15.0), POS,
          "PD grid spacing (length); the grid must fit the plate", pos),
        k("pd", "m", Int, Val::Int(4), &format!("an integer in 1..{MAX_HORIZON_FACTOR}"),
          "horizon factor: delta = m dx", |v| (1..=MAX_HORIZON_FACTOR as i64).contains(&v.i())),
        k("pd", "center", Pair, Val::Pair([1.70, 10.5]), "two finite numbers, |x| <= 1e30",
          "centre of the CCM-PD rectangle (pure PD covers the whole plate)",
          |v| v.pair().iter().all(|&x| finite(x))),
        k("pd", "size", Pair, Val::Pair([2.73, 1.67]), "two finite numbers in [1e-30, 1e30]",
          "size of the CCM-PD rectangle along x1 and x2",
          |v| v.pair().iter().all(|&x| positive(x))),
        k("pd", "region", Str, Val::Str("fixed".into()), &choice(&PD_REGIONS),
          "CCM-PD: 'fixed' (the rectangle pd.center, pd.size) or 'adaptive' (squares of \
           pd.adapt_size horizons around the crack tips, grown before any bond within \
           pd.adapt_margin horizons of the FEM part breaks; pd.center and pd.size unused)",
          |v| PD_REGIONS.contains(&v.s())),
        k("pd", "adapt_margin", Float, Val::Float(2.0),
          &format!("0 < adapt_margin <= {MAX_ADAPT_HORIZONS}"),
          "adaptive region: no bond breaks within this many horizons of a FEM node (the \
           region grows first)", |v| v.f() > 0.0 && v.f() <= MAX_ADAPT_HORIZONS),
        k("pd", "adapt_size", Float, Val::Float(4.0),
          &format!("adapt_margin + 1 <= adapt_size <= {MAX_ADAPT_HORIZONS}"),
          "adaptive region: half-side, in horizons, of the squares it starts with (around \
           each crack tip) and grows by (around the bond about to break)",
          |v| v.f() >= 1.0 && v.f() <= MAX_ADAPT_HORIZONS),
        k("pd", "fem_grading", Float, Val::Float(1.0),
          &format!("1 <= fem_grading <= {MAX_GRADING} (> 1 for method 'ccm_pd' only)"),
          "CCM-PD: 1 = one uniform dx grid (the paper's); > 1 = a graded FEM grid: uniform dx \
           over the PD rectangles and a band of m + 1 elements around them, element sizes \
           growing by this ratio beyond, up to pd.fem_coarse dx",
          |v| v.f() >= 1.0 && v.f() <= MAX_GRADING),
        k("pd", "fem_coarse", Float, Val::Float(8.0),
          &format!("1 <= fem_coarse <= {MAX_FEM_COARSE}"),
          "CCM-PD graded grid: the largest FEM element size, in units of pd.dx",
          |v| v.f() >= 1.0 && v.f() <= MAX_FEM_COARSE),
        k("pd", "sla_steps", Int, Val::Int(500),
          &format!("an integer >= 0 (0 = the reference solution only; at most {MAX_STEPS})"),
          "most SLA steps (bond-break events)", |v| (0..=MAX_STEPS as i64).contains(&v.i())),
        k("pd", "tie_tol", Float, Val::Float(0.0), "0 <= tie_tol < 1",
          "break together every bond within this relative tolerance of the step's load factor \
           (0 = one bond per step)", |v| v.f() >= 0.0 && v.f() < 1.0),
        k("pd", "refactor_every", Int, Val::Int(0),
          &format!("an integer >= 0 (at most {MAX_STEPS})"),
          "fast solver: re-condense after this many breaks (0 = automatic: n_P / 2 dense, from \
           the cost model sparse)",
          |v| (0..=MAX_STEPS as i64).contains(&v.i())),
        k("pd", "hole_volumes", Str, Val::Str("centre".into()), &choice(&HOLE_VOLUMES),
          "volume of a node whose cell a hole cuts: 'centre' (the full cell, the centre rule) \
           or 'exact' (the cell's material part)", |v| HOLE_VOLUMES.contains(&v.s())),
        // --- pd.surface_correction ---
        k("pd", "surface_correction", Str, Val::Str("none".into()), &choice(&SURFACE_CORRECTIONS),
          "PD surface effect: 'none' (the paper's bonds) or 'energy' (Le & Bobaru 2018's \
           energy method: each bond's stiffness scaled so that a node near a hole or the \
           pre-crack has the bulk's strain energy density under uniform strain in x1 and x2, \
           the plate's outline left uncorrected; computed once on the initial model; each bond keeps its critical energy: s0 / \
           sqrt(G))",
          |v| SURFACE_CORRECTIONS.contains(&v.s())),
        // --- end pd.surface_correction ---
        k("pd", "fast", Bool, Val::Bool(true), "true or false",
          "condensation + Sherman-Morrison-Woodbury; false runs the refactorise-every-step \
           oracle", |_| true),
        k("pd", "engine", Str, Val::Str("auto".into()), &choice(&SLA_ENGINES),
          "SLA solver when fast = true: 'auto' (the cheaper of dense and sparse by the cost \
           model, reported in the result's solver), 'dense' (condensed PD system inverted), \
           'sparse' (sparse factor of it + Sherman-Morrison-Woodbury) or 'oracle' (refactorise \
           every step, as fast = false)", |v| SLA_ENGINES.contains(&v.s())),
        k("pd", "s0_calibration", Str, Val::Str(S0_CALIBRATIONS[0].into()),
          &choice(&S0_CALIBRATIONS),
          "critical stretch s0: 'continuum' (eq. 48, the paper's), 'grid' (rescaled so that the \
           energy of the grid's bonds crossing an x1-parallel line is G0 per unit area) or 'sla' \
           (rescaled so that a pure-PD reference strip of 6 x 8 horizons breaking across under \
           the SLA releases G0 per unit of new crack area; computed once per m per process: \
           about 1 s at m = 4, 20 s at m = 5, 90 s at m = 6); the factor is in the result's \
           meta['s0_calibration']",
          |v| S0_CALIBRATIONS.contains(&v.s())),
        k("pd", "stop_crack_length", Float, Val::Float(0.0),
          "a finite number >= 0 (0 = no stop; else in [1e-30, 1e30])",
          "stop the SLA once the crack is this long", |v| nonneg(v.f())),
        k("pd", "damage_at_steps", IntList, Val::IntList(Vec::new()),
          &format!("a list of at most {MAX_SNAPSHOTS} integers >= 1 (at most {MAX_STEPS})"),
          "steps after which the damage field is stored too",
          |v| v.ints().len() <= MAX_SNAPSHOTS
              && v.ints().iter().all(|&x| (1..=MAX_STEPS as i64).contains(&x))),
        k("pd", "checkpoint_every", Int, Val::Int(0),
          &format!("an integer >= 0 (at most {MAX_STEPS})"),
          "write a checkpoint every this many steps (0 = never)",
          |v| (0..=MAX_STEPS as i64).contains(&v.i())),
        k("pd", "checkpoint_path", Str, Val::Str(String::new()), "a file path (empty: none)",
          "checkpoint file, written atomically", |_| true),
        k("pd", "resume_from", Str, Val::Str(String::new()),
          "a checkpoint file path (empty: none)",
          "continue from a checkpoint of the same model and solver options", |_| true),
        k("hole", "shape", Str, Val::Str("circle".into()), &choice(&SHAPES),
          "'circle' (center, radius), 'rect' (min, max corners) or 'polygon' (points)",
          |v| SHAPES.contains(&v.s())),
        k("hole", "center", Pair, Val::Pair([0.0, 0.0]), "two finite numbers, |x| <= 1e30",
          "centre of a circle (length)", |v| v.pair().iter().all(|&x| finite(x))),
        k("hole", "radius", Float, Val::Float(0.0), "a length in [1e-30, 1e30] (0: unset)",
          "radius of a circle (length; required for circles)", |v| nonneg(v.f())),
        k("hole", "min", Pair, Val::Pair([0.0, 0.0]), "two finite numbers, |x| <= 1e30",
          "lower-left corner of a rect (length)", |v| v.pair().iter().all(|&x| finite(x))),
        k("hole", "max", Pair, Val::Pair([0.0, 0.0]), "two finite numbers, |x| <= 1e30",
          "upper-right corner of a rect (length)", |v| v.pair().iter().all(|&x| finite(x))),
        k("hole", "points", PairList, Val::PairList(Vec::new()),
          &format!("3 to {MAX_POLYGON_VERTICES} points [x1, x2] of a simple polygon"),
          "vertices of a polygon, in order (not closed)",
          |v| v.pairs().len() <= MAX_POLYGON_VERTICES
              && v.pairs().iter().all(|p| p.iter().all(|&x| finite(x)))),
        k("notch", "side", Str, Val::Str("bottom".into()),
          &choice(&["left", "right", "bottom", "top"]), "the edge the slot is cut from",
          |v| matches!(v.s(), "left" | "right" | "bottom" | "top")),
        k("notch", "at", Float, Val::Float(0.0), FINITE,
          "position of the slot's centre line along its side (x1 on bottom/top, x2 on \
           left/right; length; required)", fin),
        k("notch", "width", Float, Val::Float(0.0), "a length in [1e-30, 1e30] (0: unset)",
          "slot width (length; required)", |v| nonneg(v.f())),
        k("notch", "depth", Float, Val::Float(0.0), "a length in [1e-30, 1e30] (0: unset)",
          "slot depth from the edge (length; required); its end is flat", |v| nonneg(v.f())),
    ];
    v.extend(region_specs("support", &REGIONS, "bottom"));
    v.extend(vec![
        k(
            "support",
            "fix",
            Str,
            Val::Str("both".into()),
            &choice(&["u1", "u2", "both"]),
            "the prescribed components",
            |v| matches!(v.s(), "u1" | "u2" | "both"),
        ),
        k(
            "support",
            "u1",
            Float,
            Val::Float(0.0),
            FINITE,
            "prescribed u1 at the reference load (length)",
            fin,
        ),
        k(
            "support",
            "u2",
            Float,
            Val::Float(0.0),
            FINITE,
            "prescribed u2 at the reference load (length)",
            fin,
        ),
    ]);
    v.extend(region_specs(
        "region_load",
        &["edge", "edge_part", "point"],
        "top",
    ));
    v.extend(vec![
        k(
            "region_load",
            "normal",
            Float,
            Val::Float(0.0),
            FINITE,
            "traction along the outward normal at the reference load (stress; tension positive)",
            fin,
        ),
        k(
            "region_load",
            "shear",
            Float,
            Val::Float(0.0),
            FINITE,
            "shear traction at the reference load (stress): along +x1 on the bottom and top \
           sides, along +x2 on the left and right sides",
            fin,
        ),
        k(
            "region_load",
            "force",
            Pair,
            Val::Pair([0.0, 0.0]),
            "two finite numbers, |x| <= 1e30",
            "point force [f1, f2] at the reference load (force, over the thickness)",
            |v| v.pair().iter().all(|&x| finite(x)),
        ),
        k(
            "probe",
            "name",
            Str,
            Val::Str(String::new()),
            "a string (empty: probe[k])",
            "the response's name in results",
            |_| true,
        ),
        k(
            "probe",
            "kind",
            Str,
            Val::Str("displacement".into()),
            &choice(&PROBES),
            "'displacement' (u at the point) or 'opening' (the jump of u across a crack at the \
           crack point nearest the point)",
            |v| PROBES.contains(&v.s()),
        ),
        k(
            "probe",
            "point",
            Pair,
            Val::Pair([0.0, 0.0]),
            "two finite numbers, |x| <= 1e30",
            "the probed point (length)",
            |v| v.pair().iter().all(|&x| finite(x)),
        ),
        k(
            "probe",
            "crack",
            Int,
            Val::Int(0),
            "an integer >= 0 (a crack index)",
            "the crack of an 'opening' probe (0: the primary crack)",
            |v| v.i() >= 0,
        ),
    ]);
    v
}

/// The keys that place a support's or a load's region (`section` "support" or "region_load"),
/// the same in both: the region kind (`kinds`; "box" for supports only), the side and the part
/// of an edge, the point, the box.
fn region_specs(section: &'static str, kinds: &[&str], side: &str) -> Vec<KeySpec> {
    let k = |key, kind, default, valid: &str, doc, ok: fn(&Val) -> bool| KeySpec {
        section,
        key,
        kind,
        default,
        valid: valid.to_string(),
        doc,
        ok,
    };
    let sides = ["left", "right", "bottom", "top"];
    let fin = |v: &Val| finite(v.f());
    let mut v =
        vec![
        k("region", Kind::Str, Val::Str("edge".into()), &choice(kinds),
          "'edge' (side), 'edge_part' (side, from, to), 'point' (the nearest node: a support \
           there, or a point force) or 'box' (supports: every node in it)",
          if kinds.contains(&"box") {
              |v: &Val| REGIONS.contains(&v.s())
          } else {
              |v: &Val| matches!(v.s(), "edge" | "edge_part" | "point")
          }),
        k("side", Kind::Str, Val::Str(side.into()), &choice(&sides), "the side of an edge region",
          |v| matches!(v.s(), "left" | "right" | "bottom" | "top")),
        k("from", Kind::Float, Val::Float(0.0), FINITE,
          "start of an edge part along its side (x1 on bottom/top, x2 on left/right)", fin),
        k("to", Kind::Float, Val::Float(0.0), FINITE, "end of an edge part", fin),
        k("point", Kind::Pair, Val::Pair([0.0, 0.0]), "two finite numbers, |x| <= 1e30",
          "the point of a point region", |v| v.pair().iter().all(|&x| finite(x))),
    ];
    if kinds.contains(&"box") {
        v.push(k(
            "box",
            Kind::FloatList,
            Val::FloatList(Vec::new()),
            "a box [x0, y0, x1, y1] with x0 < x1, y0 < y1",
            "the box of a box region",
            |v| {
                v.floats().is_empty()
                    || (v.floats().len() == 4
                        && v.floats().iter().all(|&x| finite(x))
                        && v.floats()[0] < v.floats()[2]
                        && v.floats()[1] < v.floats()[3])
            },
        ));
    }
    v
}

/// The whole table (built once).
pub fn schema() -> &'static [KeySpec] {
    static S: OnceLock<Vec<KeySpec>> = OnceLock::new();
    S.get_or_init(build)
}

/// The keys of one section, in table order.
pub fn section_keys(section: &str) -> impl Iterator<Item = &'static KeySpec> + '_ {
    schema().iter().filter(move |k| k.section == section)
}

/// The spec of `section.key`.
pub fn spec(section: &str, key: &str) -> Option<&'static KeySpec> {
    schema()
        .iter()
        .find(|k| k.section == section && k.key == key)
}

/// The largest mesh (elements) and PD grid (nodes): [`MAX_ELEMENTS`].
pub const fn max_elements() -> usize {
    MAX_ELEMENTS
}
