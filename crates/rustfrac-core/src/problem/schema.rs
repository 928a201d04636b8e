//! Every scene key: its section, kind, default, valid range ([`Range`]: the check and its
//! words), role ([`Role`]: what its value changes), whether an entry must state it
//! ([`Required`]) and meaning. This table is the one place where a scene rule lives; the Python
//! package reads it (`rustfrac._core.scene_schema()`) to build its section classes and the docs
//! their key tables, and the checkpoint fingerprint hashes its physics and solver keys. A new
//! parameter is one entry here, the line of [`super::parse`] that reads it into the
//! [`super::Problem`] and the line of [`super::scene_of`] that gives it back.
//!
//! Units are consistent and up to the user; the paper's case uses N, mm and MPa (E = 10000).

use super::grid::MAX_ELEMENTS;
pub use super::key_value::{Kind, Val};
pub use super::range::{choice, Bound, Range};
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
/// `pd.surface_correction`: the PD surface correction ([`super::SurfaceCorrection`],
/// `crate::pd::surface_correction`).
pub const SURFACE_CORRECTIONS: [&str; 2] = ["none", "energy"];
/// `pd.model`: the PD constitutive model ([`super::PdModel`], `crate::pd::lps`).
pub const PD_MODELS: [&str; 2] = ["bond", "lps"];
/// `pd.influence`: the LPS influence function ([`super::Influence`]).
pub const INFLUENCES: [&str; 2] = ["constant", "conical"];
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

/// What a key's value changes. A checkpoint resumes only a run whose physics and solver keys
/// all have the checkpoint's values (`crate::pd::sla::checkpoint`; `docs/design.md`,
/// "Checkpoints").
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Role {
    /// the model and what a step records on it (plate, material, load, cracks, grids, holes,
    /// supports, probes' points)
    Physics,
    /// the solver's sequence of floating-point operations (engine, tie tolerance,
    /// re-condensation period)
    Solver,
    /// neither the model nor any recorded value of a step: step limits, stop lengths, snapshots,
    /// files, names
    Output,
}

impl Role {
    /// Stable name (the Python side and the docs show it).
    pub fn name(self) -> &'static str {
        match self {
            Role::Physics => "physics",
            Role::Solver => "solver",
            Role::Output => "output",
        }
    }
}

/// Whether an entry of a section must state a key (a missing one is refused as missing:
/// `Error::MissingKey`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Required {
    /// the default applies when the key is absent
    No,
    /// every entry states it
    Always,
    /// the entries whose key `key` (with its default when absent) is one of `values`
    When {
        key: &'static str,
        values: &'static [&'static str],
    },
}

/// One scene key.
pub struct KeySpec {
    pub section: &'static str,
    pub key: &'static str,
    pub kind: Kind,
    pub default: Val,
    /// the valid values: the check and the words
    pub range: Range,
    /// words shown after the range (the meaning of a special value, a rule with another key)
    pub note: &'static str,
    /// what the key's value changes
    pub role: Role,
    /// whether an entry must state it
    pub required: Required,
    /// what the key means, with units
    pub doc: &'static str,
}

impl KeySpec {
    /// `section.key`, the name errors carry.
    pub fn param(&self) -> String {
        format!("{}.{}", self.section, self.key)
    }
    /// The valid values in words (messages and docs): the range's words and the note.
    pub fn valid(&self) -> String {
        let w = self.range.words(self.kind, self.key);
        if self.note.is_empty() {
            w
        } else {
            format!("{w} {}", self.note)
        }
    }
    /// The check of a value of the right kind.
    pub fn ok(&self, v: &Val) -> bool {
        self.range.contains(v)
    }
    /// Whether an entry with the checked values `s` must state this key.
    pub fn required_in(&self, s: &dyn Fn(&str) -> Option<String>) -> bool {
        match self.required {
            Required::No => false,
            Required::Always => true,
            Required::When { key, values } => s(key).is_some_and(|v| values.contains(&v.as_str())),
        }
    }
    /// The condition of [`Required`] in words ("" when not required).
    pub fn required_words(&self) -> String {
        match self.required {
            Required::No => String::new(),
            Required::Always => "required".into(),
            Required::When { key, values } => {
                let q: Vec<String> = values.iter().map(|v| format!("'{v}'")).collect();
                format!("required for {key} {}", q.join(" or "))
            }
        }
    }
    fn note(mut self, note: &'static str) -> Self {
        self.note = note;
        self
    }
    fn role(mut self, role: Role) -> Self {
        self.role = role;
        self
    }
    fn required(mut self, required: Required) -> Self {
        self.required = required;
        self
    }
    fn when(self, key: &'static str, values: &'static [&'static str]) -> Self {
        self.required(Required::When { key, values })
    }
}

/// A key of `section`: its default (which gives the kind), range and meaning; a physics key,
/// never required, without a note (the builders above change these).
fn k(
    section: &'static str,
    key: &'static str,
    default: Val,
    range: Range,
    doc: &'static str,
) -> KeySpec {
    KeySpec {
        section,
        key,
        kind: default.kind(),
        default,
        range,
        note: "",
        role: Role::Physics,
        required: Required::No,
        doc,
    }
}

/// The PD horizon factor m = delta / dx (`pd.m`; every use of m meets it:
/// [`check_horizon_factor`]). Bonds per node grow as m^2.
pub const HORIZON_FACTOR: Range = Range::Int {
    lo: 1,
    hi: Some(MAX_HORIZON_FACTOR as i64),
};

/// Refuses a horizon factor outside [`HORIZON_FACTOR`], naming `pd.m`.
pub fn check_horizon_factor(m: usize) -> crate::Result<()> {
    let v = i64::try_from(m).unwrap_or(i64::MAX);
    if HORIZON_FACTOR.contains_i(v) {
        Ok(())
    } else {
        Err(crate::error::Error::invalid(
            "pd.m",
            &HORIZON_FACTOR.words(Kind::Int, "m"),
            m,
        ))
    }
}

/// `pd.fast = false` is another name of `pd.engine = "oracle"` (the refactorise-every-step
/// solver; one policy, two keys): the engine name the two keys select, or None when they
/// contradict each other (`fast = false` beside `engine = "dense"` or `"sparse"`).
pub fn sla_engine(fast: bool, engine: &str) -> Option<&str> {
    match (fast, engine) {
        (true, e) => Some(e),
        (false, "auto" | "oracle") => Some("oracle"),
        (false, _) => None,
    }
}

/// The four sides of the plate.
pub const SIDES: [&str; 4] = ["left", "right", "bottom", "top"];
/// Crack kinds (each method accepts some: [`crack_kinds`]).
pub const CRACK_KINDS: [&str; 4] = ["none", "seam", "edge", "center"];
/// Most sub-quads per direction of split and branch-enriched elements (`xfem.nsub`).
pub const MAX_NSUB: i64 = 32;
/// Most sub-quads per direction of tip elements (`xfem.tip_nsub`).
pub const MAX_TIP_NSUB: i64 = 64;

const POS: Range = Range::Positive;
const FIN: Range = Range::Finite;
/// a length that may be left 0 (unset) in a list entry
const UNSET_OR_POS: Range = Range::ZeroOr("unset", &Range::Positive);
const PAIR_FIN: Range = Range::Each {
    max: Some(2),
    each: &Range::Finite,
};
const STEPS: Range = Range::Int {
    lo: 0,
    hi: Some(MAX_STEPS as i64),
};
const TOL: Range = Range::Interval {
    lo: Bound::Closed(0.0),
    hi: Bound::Open(1.0),
};

#[allow(clippy::too_many_lines)]
#[rustfmt::skip]
fn build() -> Vec<KeySpec> {
    use Range::{Int, Interval, OneOf, ZeroOr};
    use Role::{Output, Solver};
    let (f, s) = (Val::Float, |v: &str| Val::Str(v.into()));
    let at_least = |lo| Int { lo, hi: None };
    let closed = |lo, hi| Interval {
        lo: Bound::Closed(lo),
        hi: Bound::Closed(hi),
    };
    let mut v = vec![
        k("plate", "width", f(11.0), POS,
          "plate width W along x1 (length); the plate is [0, W] x [0, L]"),
        k("plate", "height", f(21.0), POS, "plate height L along x2 (length)"),
        k("material", "E", f(10000.0), POS, "Young's modulus (stress)"),
        k("material", "nu", f(0.25), Interval { lo: Bound::Open(-1.0), hi: Bound::Open(0.5) },
          "Poisson's ratio (bond-based PD fixes 0.25)"),
        k("material", "plane", s("strain"), OneOf(&["strain", "stress"]),
          "plane strain or plane stress"),
        k("material", "thickness", f(1.0), POS, "out-of-plane thickness h (length)"),
        k("material", "G0", f(0.367), POS,
          "critical energy release rate (force / length): LEFM growth and PD bond strength"),
        k("load", "bc", s("free"), OneOf(&BCS),
          "grips on the top and bottom edges (eq. 61): 'free' (u2 = +-u0, u1 free, one anchor \
           node), 'clamped' (u2 = +-u0, u1 = 0) or 'traction' (uniform normal stress)"),
        k("load", "u0", f(0.01), FIN,
          "reference grip displacement (length), non-zero under displacement grips"),
        k("load", "traction", f(9.993), FIN,
          "reference traction (stress) of bc = 'traction', non-zero there"),
        k("crack", "kind", s("seam"), OneOf(&CRACK_KINDS),
          "'none', 'seam' (FEM: duplicated nodes on the grid line nearest y), 'edge' (XFEM level \
           set / PD pre-broken bonds) or 'center' (XFEM interior crack); without a [crack] \
           section: 'seam' for FEM, else 'edge'"),
        k("crack", "a0", f(1.1), POS,
          "crack length (length); the half-length of a 'center' crack"),
        k("crack", "y", f(10.5), POS,
          "x2 of the crack mouth (left/right edge cracks) or centre"),
        k("crack", "angle", f(0.0), closed(-180.0, 180.0),
          "degrees counter-clockwise from x1 ('center'), or from the side's inward normal \
           (edge cracks); XFEM only, 0 elsewhere").note("degrees"),
        k("crack", "x", f(5.5), POS,
          "x1 of a 'center' crack's centre, or of the mouth of a bottom/top edge crack"),
        k("crack", "side", s("left"), OneOf(&SIDES),
          "the edge an XFEM edge crack starts from (other methods: 'left')"),
        k("mesh", "nx", Val::Int(44), at_least(1), "Q4 elements along x1 (FEM, XFEM)"),
        k("mesh", "ny", Val::Int(83), at_least(1), "Q4 elements along x2 (FEM, XFEM)"),
        k("mesh", "gauss", Val::Int(2), Int { lo: 2, hi: Some(5) },
          "Gauss points per direction of the standard elements (2 is exact for rectangles)")
          .note("(1 point per direction leaves the Q4 element's hourglass modes: the stiffness \
                 is rank deficient)"),
        k("mesh", "xs", Val::FloatList(Vec::new()), Range::Each { max: None, each: &FIN },
          "the vertical grid lines of a tensor grid (then mesh.nx is their count - 1)")
          .note("(empty: uniform; else strictly increasing x1 grid lines from 0 to plate.width)"),
        k("mesh", "ys", Val::FloatList(Vec::new()), Range::Each { max: None, each: &FIN },
          "the horizontal grid lines of a tensor grid (then mesh.ny is their count - 1)")
          .note("(empty: uniform; else strictly increasing x2 grid lines from 0 to \
                 plate.height)"),
        k("mesh", "refine", Val::FloatList(Vec::new()), Range::BoxOrEmpty,
          "graded grid: elements of size mesh.refine_h in this box, growing by mesh.grading \
           per element away from it up to the uniform grid's size (plate / mesh.nx, mesh.ny)")
          .note("(empty: off)"),
        k("mesh", "refine_h", f(0.0), ZeroOr("off", &POS),
          "element size in the refinement box"),
        k("mesh", "grading", f(1.2), closed(1.0, MAX_GRADING),
          "ratio of neighbouring element sizes outside the refinement box"),
        k("xfem", "nsub", Val::Int(4), Int { lo: 1, hi: Some(MAX_NSUB) },
          "sub-quads per direction of split and branch-enriched elements, 2 x 2 Gauss points \
           each (eq. 35)"),
        k("xfem", "tip_nsub", Val::Int(0),
          ZeroOr("= nsub", &Int { lo: 1, hi: Some(MAX_TIP_NSUB) }),
          "sub-quads per direction in tip elements").note("(at least nsub)"),
        k("xfem", "r_I", f(2.5), closed(0.5, 20.0),
          "radius of the interaction-integral domain, in tip-element lengths")
          .note("element lengths"),
        k("xfem", "fixed_area_radius", f(0.0), ZeroOr("off", &POS),
          "enrich every node within this distance of a tip with the branch functions (Laborde \
           et al. 2005); 0 = the tip element's nodes only"),
        k("xfem", "area_threshold", f(DEFAULT_AREA_THRESHOLD),
          Interval { lo: Bound::Closed(0.0), hi: Bound::Open(0.5) },
          "small-area rule: a Heaviside node is dropped when the smaller part of its support \
           cut by the crack is below this fraction of the support (0: only exactly zero parts)"),
        k("xfem", "growth_steps", Val::Int(0), Int { lo: 0, hi: Some(MAX_GROWTH_STEPS as i64) },
          "0 = solve at the reference load only; else the most LEFM growth steps (critical \
           states where G = G0)").role(Output),
        k("xfem", "tip_tie_tol", f(1e-6), TOL,
          "growth with several tips: every tip whose critical load factor is within this \
           relative tolerance of the smallest grows in the same step (symmetric tips together)")
          .role(Solver),
        k("xfem", "da", f(0.0), ZeroOr("one element length", &POS),
          "crack extension per growth step"),
        k("xfem", "kink_rule", s(KINK_RULES[0]), OneOf(&KINK_RULES),
          "growth direction: 'hoop' (maximum hoop stress at the tip, one solve per step) or \
           'predictor_corrector' (a trial extension, the hoop angle at the trial tip, the \
           bisector: two solves per step; removes the zig-zag of curving paths)"),
        k("xfem", "a_stop", f(0.0), ZeroOr("0.7 plate.width", &POS),
          "growth stops once a crack length would exceed it (half-length for 'center')")
          .note("(less than plate.width)").role(Output),
        k("xfem", "state_every", Val::Int(1), Int { lo: 0, hi: Some(MAX_GROWTH_STEPS as i64) },
          "growth runs: keep the whole plate's state (displacements, element and cut-cell \
           stresses, cut cells, cracks) of every this many growth steps and of the last one, for \
           the ParaView series and the plots of each state (0 = none; a state holds about 5 \
           floats per node)").role(Output),
        k("pd", "dx", f(1.0 / 15.0), POS,
          "PD grid spacing (length); the grid must fit the plate"),
        k("pd", "m", Val::Int(4), HORIZON_FACTOR, "horizon factor: delta = m dx"),
        k("pd", "center", Val::Pair([1.70, 10.5]), PAIR_FIN,
          "centre of the CCM-PD rectangle (pure PD covers the whole plate)"),
        k("pd", "size", Val::Pair([2.73, 1.67]), Range::Each { max: Some(2), each: &POS },
          "size of the CCM-PD rectangle along x1 and x2"),
        k("pd", "region", s("fixed"), OneOf(&PD_REGIONS),
          "CCM-PD: 'fixed' (the rectangle pd.center, pd.size) or 'adaptive' (squares of \
           pd.adapt_size horizons around the crack tips, grown before any bond within \
           pd.adapt_margin horizons of the FEM part breaks; pd.center and pd.size unused)"),
        k("pd", "adapt_margin", f(2.0),
          Interval { lo: Bound::Open(0.0), hi: Bound::Closed(MAX_ADAPT_HORIZONS) },
          "adaptive region: no bond breaks within this many horizons of a FEM node (the \
           region grows first)"),
        k("pd", "adapt_size", f(4.0), closed(1.0, MAX_ADAPT_HORIZONS),
          "adaptive region: half-side, in horizons, of the squares it starts with (around \
           each crack tip) and grows by (around the bond about to break)")
          .note("(and adapt_size >= adapt_margin + 1)"),
        k("pd", "fem_grading", f(1.0), closed(1.0, MAX_GRADING),
          "CCM-PD: 1 = one uniform dx grid (the paper's); > 1 = a graded FEM grid: uniform dx \
           over the PD rectangles and a band of m + 1 elements around them, element sizes \
           growing by this ratio beyond, up to pd.fem_coarse dx")
          .note("(> 1 for method 'ccm_pd' only)"),
        k("pd", "fem_coarse", f(8.0), closed(1.0, MAX_FEM_COARSE),
          "CCM-PD graded grid: the largest FEM element size, in units of pd.dx"),
        k("pd", "sla_steps", Val::Int(500), STEPS, "most SLA steps (bond-break events)")
          .note("(0 = the reference solution only)").role(Output),
        k("pd", "tie_tol", f(0.0), TOL,
          "break together every bond within this relative tolerance of the step's load factor \
           (0 = one bond per step)").role(Solver),
        k("pd", "refactor_every", Val::Int(0), STEPS,
          "fast solver: re-condense after this many breaks (0 = automatic: n_P / 2 dense, from \
           the cost model sparse)").role(Solver),
        k("pd", "hole_volumes", s("centre"), OneOf(&HOLE_VOLUMES),
          "volume of a node whose cell a hole cuts: 'centre' (the full cell, the centre rule) \
           or 'exact' (the cell's material part)"),
        k("pd", "surface_correction", s("none"), OneOf(&SURFACE_CORRECTIONS),
          "PD surface effect: 'none' (the paper's bonds) or 'energy' (Le & Bobaru 2018's \
           energy method: each bond's stiffness scaled so that a node near a hole or the \
           pre-crack has the bulk's strain energy density under uniform strain in x1 and x2, \
           the plate's outline left uncorrected; computed once on the initial model; each bond \
           keeps its critical energy: s0 / sqrt(G))"),
        k("pd", "fast", Val::Bool(true), Range::Any,
          "condensation + Sherman-Morrison-Woodbury; false is another name of engine = \
           'oracle' (refactorise every step)").role(Solver),
        k("pd", "engine", s("auto"), OneOf(&SLA_ENGINES),
          "SLA solver: 'auto' (the cheaper of dense and sparse by the cost model, reported in \
           the result's solver), 'dense' (condensed PD system inverted), 'sparse' (sparse \
           factor of it + Sherman-Morrison-Woodbury) or 'oracle' (refactorise every step; \
           fast = false is another name of it)")
          .note("('auto' or 'oracle' with fast = false)").role(Solver),
        k("pd", "s0_calibration", s(S0_CALIBRATIONS[0]), OneOf(&S0_CALIBRATIONS),
          "critical stretch s0: 'continuum' (eq. 48, the paper's), 'grid' (rescaled so that the \
           energy of the grid's bonds crossing an x1-parallel line is G0 per unit area) or 'sla' \
           (rescaled so that a pure-PD reference strip of 6 x 8 horizons breaking across under \
           the SLA releases G0 per unit of new crack area; computed once per m per process: \
           about 1 s at m = 4, 20 s at m = 5, 90 s at m = 6); the factor is in the result's \
           meta['s0_calibration']"),
        k("pd", "model", s(PD_MODELS[0]), OneOf(&PD_MODELS),
          "PD model: 'bond' (bond-based, the paper's: nu = 1/4 in plane strain only) or 'lps' \
           (the linear peridynamic solid, ordinary state-based, Silling et al. 2007: any nu; \
           method 'pd' only, the oracle engine; docs/design.md, 'The linear peridynamic solid')"),
        k("pd", "influence", s(INFLUENCES[0]), OneOf(&INFLUENCES),
          "LPS influence function omega(|xi|): 'constant' (1) or 'conical' (1 - |xi| / delta)")
          .note("(used with pd.model = 'lps')"),
        k("pd", "stop_crack_length", f(0.0), ZeroOr("no stop", &POS),
          "stop the SLA once the crack is this long").role(Output),
        k("pd", "damage_at_steps", Val::IntList(Vec::new()),
          Range::Each {
              max: Some(MAX_SNAPSHOTS),
              each: &Int { lo: 1, hi: Some(MAX_STEPS as i64) },
          },
          "steps after which the damage field is stored too").role(Output),
        k("pd", "checkpoint_every", Val::Int(0), STEPS,
          "write a checkpoint every this many steps (0 = never)").role(Output),
        k("pd", "checkpoint_path", s(""), Range::Any, "checkpoint file, written atomically")
          .note("(a file path; empty: none)").role(Output),
        k("pd", "resume_from", s(""), Range::Any,
          "continue from a checkpoint of the same model and solver options (the same physics \
           and solver keys)")
          .note("(a checkpoint file path; empty: none)").role(Output),
        k("hole", "shape", s("circle"), OneOf(&SHAPES),
          "'circle' (center, radius), 'rect' (min, max corners) or 'polygon' (points)"),
        k("hole", "center", Val::Pair([0.0, 0.0]), PAIR_FIN, "centre of a circle (length)")
          .when("shape", &["circle"]),
        k("hole", "radius", f(0.0), UNSET_OR_POS, "radius of a circle (length)")
          .when("shape", &["circle"]),
        k("hole", "min", Val::Pair([0.0, 0.0]), PAIR_FIN, "lower-left corner of a rect (length)")
          .when("shape", &["rect"]),
        k("hole", "max", Val::Pair([0.0, 0.0]), PAIR_FIN,
          "upper-right corner of a rect (length)").when("shape", &["rect"]),
        k("hole", "points", Val::PairList(Vec::new()),
          Range::Each { max: Some(MAX_POLYGON_VERTICES), each: &FIN },
          "vertices of a polygon, in order (not closed)")
          .note("(at least 3, a simple polygon)").when("shape", &["polygon"]),
        k("notch", "side", s("bottom"), OneOf(&SIDES), "the edge the slot is cut from"),
        k("notch", "at", f(0.0), FIN,
          "position of the slot's centre line along its side (x1 on bottom/top, x2 on \
           left/right; length)").required(Required::Always),
        k("notch", "width", f(0.0), UNSET_OR_POS, "slot width (length)")
          .required(Required::Always),
        k("notch", "depth", f(0.0), UNSET_OR_POS,
          "slot depth from the edge (length); its end is flat").required(Required::Always),
    ];
    v.extend(region_specs("support", &REGIONS, "bottom"));
    v.extend([
        k("support", "fix", s("both"), OneOf(&["u1", "u2", "both"]), "the prescribed components"),
        k("support", "u1", f(0.0), FIN, "prescribed u1 at the reference load (length)"),
        k("support", "u2", f(0.0), FIN, "prescribed u2 at the reference load (length)"),
    ]);
    v.extend(region_specs("region_load", &REGIONS[..3], "top"));
    v.extend([
        k("region_load", "normal", f(0.0), FIN,
          "traction along the outward normal at the reference load (stress; tension positive)"),
        k("region_load", "shear", f(0.0), FIN,
          "shear traction at the reference load (stress): along +x1 on the bottom and top \
           sides, along +x2 on the left and right sides"),
        k("region_load", "force", Val::Pair([0.0, 0.0]), PAIR_FIN,
          "point force [f1, f2] at the reference load (force, over the thickness)"),
        k("probe", "name", s(""), Range::Any, "the response's name in results")
          .note("(empty: probe[k])").role(Output),
        k("probe", "kind", s("displacement"), OneOf(&PROBES),
          "'displacement' (u at the point) or 'opening' (the jump of u across a crack at the \
           crack point nearest the point)"),
        k("probe", "point", Val::Pair([0.0, 0.0]), PAIR_FIN, "the probed point (length)")
          .required(Required::Always),
        k("probe", "crack", Val::Int(0), at_least(0),
          "the crack of an 'opening' probe (0: the primary crack)").note("(a crack index)"),
    ]);
    v
}

/// The keys that place a support's or a load's region (`section` "support" or "region_load"),
/// the same in both: the region kind (`kinds`; "box" for supports only), the side and the part
/// of an edge, the point, the box.
#[rustfmt::skip]
fn region_specs(
    section: &'static str,
    kinds: &'static [&'static str],
    side: &str,
) -> Vec<KeySpec> {
    let s = |v: &str| Val::Str(v.into());
    let mut v = vec![
        k(section, "region", s("edge"), Range::OneOf(kinds),
          "'edge' (side), 'edge_part' (side, from, to), 'point' (the nearest node: a support \
           there, or a point force) or 'box' (supports: every node in it)"),
        k(section, "side", s(side), Range::OneOf(&SIDES), "the side of an edge region")
            .when("region", &["edge", "edge_part"]),
        k(section, "from", Val::Float(0.0), FIN,
          "start of an edge part along its side (x1 on bottom/top, x2 on left/right)")
            .when("region", &["edge_part"]),
        k(section, "to", Val::Float(0.0), FIN, "end of an edge part")
            .when("region", &["edge_part"]),
        k(section, "point", Val::Pair([0.0, 0.0]), PAIR_FIN, "the point of a point region")
            .when("region", &["point"]),
    ];
    if kinds.contains(&"box") {
        v.push(
            k(section, "box", Val::FloatList(Vec::new()), Range::BoxOrEmpty,
              "the box of a box region").when("region", &["box"]),
        );
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
