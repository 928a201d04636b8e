//! Every result entry of every method: its group, name, kind (with the shape of an array),
//! unit and meaning, and when it is present. This table is the one place a result name lives:
//! the bindings export it (`rustfrac._core.result_schema()`), Python's `Result`, its files and
//! figures read names and units from it, and a test checks every record a run emits against it
//! (`output/tests.rs`). Adding a result key: one `t.add(..)` line in `build` here and the line
//! of the method's conversion (`output/{fem,xfem,pd}.rs`) that sets it.
//!
//! Units are the scene's (consistent, chosen by the user; the paper's case N, mm, MPa) and are
//! named by dimension: "length", "stress", "force" (over the thickness), "energy",
//! "energy/area" (J, G), "stress sqrt(length)" (K), "1" (dimensionless), "rad", "s", "bytes";
//! "" for text, tables and indices. Names with a `<region>` or `<name>` part stand for one
//! entry per region (`support[0]`, `load[1]`) or probe of the scene.

use super::record::Group;
use std::sync::OnceLock;

/// A dimension of an array's shape: a fixed size, or a size named for what it counts (the same
/// name means the same size within one record).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Dim {
    Fixed(usize),
    /// `n`
    Var(&'static str),
    /// `2 n` (interleaved components)
    Twice(&'static str),
    /// `n + 1` (offsets into a concatenation of n parts)
    PlusOne(&'static str),
}

impl Dim {
    /// The dimension in words: "2", "n_nodes", "2 n_nodes", "n_cracks + 1".
    pub fn text(&self) -> String {
        match self {
            Dim::Fixed(n) => n.to_string(),
            Dim::Var(v) => (*v).to_string(),
            Dim::Twice(v) => format!("2 {v}"),
            Dim::PlusOne(v) => format!("{v} + 1"),
        }
    }
}

/// The kind of a result value.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    Float,
    Int,
    Bool,
    Str,
    /// a numpy float64 array of this shape
    Floats(&'static [Dim]),
    /// a numpy int64 array of this shape
    Ints(&'static [Dim]),
    /// a numpy bool array of this shape
    Bools(&'static [Dim]),
    /// a plain (nested) list of floats of this shape
    FloatList(&'static [Dim]),
    /// a plain list of strings
    StrList,
    /// a nested table; its entries are named `<table>.<key>`
    Table,
    /// a list of tables; their entries are named `<list>.<key>`
    TableList,
}

impl Kind {
    /// The stable name (Python's `result_schema()`).
    pub fn name(&self) -> &'static str {
        match self {
            Kind::Float => "float",
            Kind::Int => "int",
            Kind::Bool => "bool",
            Kind::Str => "str",
            Kind::Floats(_) => "float array",
            Kind::Ints(_) => "int array",
            Kind::Bools(_) => "bool array",
            Kind::FloatList(_) => "float list",
            Kind::StrList => "str list",
            Kind::Table => "table",
            Kind::TableList => "table list",
        }
    }

    /// The shape of an array or list kind.
    pub fn shape(&self) -> Option<&'static [Dim]> {
        match self {
            Kind::Floats(s) | Kind::Ints(s) | Kind::Bools(s) | Kind::FloatList(s) => Some(s),
            _ => None,
        }
    }

    /// The shape in words, e.g. "(n_nodes, 2)" (None for kinds without a shape).
    pub fn shape_text(&self) -> Option<String> {
        let dims: Vec<String> = self.shape()?.iter().map(Dim::text).collect();
        Some(match dims.len() {
            1 => format!("({},)", dims[0]),
            _ => format!("({})", dims.join(", ")),
        })
    }
}

/// The methods an entry belongs to (a set of [`crate::problem::schema::METHODS`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Methods(u8);

impl Methods {
    pub const FEM: Methods = Methods(1);
    pub const XFEM: Methods = Methods(2);
    pub const PD: Methods = Methods(4);
    pub const CCM_PD: Methods = Methods(8);
    /// both SLA methods (PD and CCM-PD)
    pub const SLA: Methods = Methods(4 | 8);
    /// the mesh methods (FEM and XFEM)
    pub const MESH: Methods = Methods(1 | 2);
    pub const ALL: Methods = Methods(15);

    /// The union of two sets.
    pub const fn or(self, o: Methods) -> Methods {
        Methods(self.0 | o.0)
    }

    /// Whether the set holds the method named `m`.
    pub fn has(self, m: &str) -> bool {
        crate::problem::schema::METHODS
            .iter()
            .position(|x| *x == m)
            .is_some_and(|i| self.0 & (1 << i) != 0)
    }

    /// The names of the methods in the set, in the docs' order.
    pub fn names(self) -> Vec<&'static str> {
        crate::problem::schema::METHODS
            .iter()
            .enumerate()
            .filter(|(i, _)| self.0 & (1 << i) != 0)
            .map(|(_, m)| *m)
            .collect()
    }
}

/// When an entry is present.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Presence {
    /// in every record of its methods
    Always,
    /// only under this condition (in words)
    When(&'static str),
    /// added by Python's `rustfrac.run` after the core's run (in words: what adds it)
    Python(&'static str),
}

impl Presence {
    /// "always", "when ...", "python: ...".
    pub fn text(&self) -> String {
        match self {
            Presence::Always => "always".into(),
            Presence::When(c) => format!("when {c}"),
            Presence::Python(c) => format!("python: {c}"),
        }
    }
}

/// One result entry.
#[derive(Debug, Clone)]
pub struct Entry {
    pub methods: Methods,
    pub group: Group,
    /// the key; `<region>` / `<name>` parts stand for any region or probe name, and
    /// `<table>.<key>` names an entry of a [`Kind::Table`] or [`Kind::TableList`]
    pub name: &'static str,
    pub kind: Kind,
    /// whether the value may be None instead (e.g. "not computed")
    pub nullable: bool,
    pub unit: &'static str,
    pub presence: Presence,
    /// what the entry means
    pub doc: &'static str,
}

impl Entry {
    /// Whether the key `key` is this entry's (a pattern's `<...>` parts match any non-empty
    /// text without a ':').
    pub fn matches(&self, key: &str) -> bool {
        pattern_matches(self.name, key)
    }

    /// The entry's value may be None.
    pub fn or_none(&mut self) -> &mut Self {
        self.nullable = true;
        self
    }

    /// The entry is present only under `condition`.
    pub fn when(&mut self, condition: &'static str) -> &mut Self {
        self.presence = Presence::When(condition);
        self
    }

    /// The entry is added by Python's `rustfrac.run`.
    pub fn python(&mut self, what: &'static str) -> &mut Self {
        self.presence = Presence::Python(what);
        self
    }
}

pub(super) fn pattern_matches(pat: &str, key: &str) -> bool {
    match pat.find('<') {
        None => pat == key,
        Some(i) => {
            let Some(close) = pat[i..].find('>') else {
                return false;
            };
            let (head, tail) = (&pat[..i], &pat[i + close + 1..]);
            let Some(rest) = key.strip_prefix(head) else {
                return false;
            };
            // the variable part: the shortest non-empty text without a separator that lets the
            // rest of the pattern match
            (1..=rest.len())
                .filter(|&n| rest.is_char_boundary(n))
                .take_while(|&n| !rest[..n].contains(':'))
                .any(|n| pattern_matches(tail, &rest[n..]))
        }
    }
}

/// The table being built: entries are added for the current methods and group.
struct Table {
    v: Vec<Entry>,
    methods: Methods,
    group: Group,
}

impl Table {
    fn at(&mut self, methods: Methods, group: Group) {
        (self.methods, self.group) = (methods, group);
    }

    fn add(
        &mut self,
        name: &'static str,
        kind: Kind,
        unit: &'static str,
        doc: &'static str,
    ) -> &mut Entry {
        self.v.push(Entry {
            methods: self.methods,
            group: self.group,
            name,
            kind,
            nullable: false,
            unit,
            presence: Presence::Always,
            doc,
        });
        self.v.last_mut().expect("just pushed")
    }
}

const LENGTH: &str = "length";
const STRESS: &str = "stress";
const FORCE: &str = "force";
const ENERGY: &str = "energy";
const G_UNIT: &str = "energy/area";
const K_UNIT: &str = "stress sqrt(length)";
const ONE: &str = "1";
const RAD: &str = "rad";
const SECONDS: &str = "s";
const BYTES: &str = "bytes";
const TEXT: &str = "";

use Dim::{Fixed, PlusOne, Twice, Var};
use Kind::{Float, FloatList, Floats, Int, Ints, Str, StrList, TableList};

const ROWS: &[Dim] = &[Var("n_rows")];
const XY: &[Dim] = &[Var("n_nodes"), Fixed(2)];
const NODE_DOFS: &[Dim] = &[Twice("n_nodes")];
const PAIR: &[Dim] = &[Fixed(2)];
const PAIRS: &[Dim] = &[Var("n_points"), Fixed(2)];
const BOXES: &[Dim] = &[Var("n_boxes"), Fixed(4)];
const QUADS: &[Dim] = &[Var("n_patch_cells"), Fixed(4), Fixed(2)];
const SNAP_QUADS: &[Dim] = &[Var("n_snapshot_cells"), Fixed(4), Fixed(2)];
const TIP_ROWS: &[Dim] = &[Var("n_tip_rows"), Var("n_tips")];
const GAUSS_XY: &[Dim] = &[Var("n_gauss"), Fixed(2)];
const GAUSS_S: &[Dim] = &[Var("n_gauss"), Fixed(3)];

const REGIONS: &str = "the scene has supports or loads on regions ([[support]], [[load]])";
const PROBES: &str = "the scene has probes ([[probe]])";
const EDGE_REGIONS: &str = "an edge region of the scene (a support or load on an edge)";
const GROWTH: &str = "a growth run (xfem.growth)";

#[allow(clippy::too_many_lines)]
fn build() -> Vec<Entry> {
    use Group::{Fields, Headline, History, Meta, Scalars};
    let mut t = Table {
        v: Vec::new(),
        methods: Methods::ALL,
        group: Headline,
    };
    let all = Methods::ALL;
    let (fem, xfem, mesh, sla) = (Methods::FEM, Methods::XFEM, Methods::MESH, Methods::SLA);

    // --- the headline and the meta of every method ---
    t.at(all, Headline);
    t.add(
        "method",
        Str,
        TEXT,
        "the method that ran: fem, xfem, pd or ccm_pd",
    );
    t.add(
        "sigma22",
        Float,
        STRESS,
        "mean normal stress on the loaded top edge (reaction / width) at the reference load; \
         with supports and loads on regions the mean normal stress on the first loaded edge \
         region, or a point load's force along its direction",
    );
    t.add(
        "cmod",
        Float,
        LENGTH,
        "crack mouth opening displacement at x1 = 0 (an interior crack: its centre's opening) at \
         the reference load; 0 when uncracked",
    );
    t.add(
        "n_dofs",
        Int,
        ONE,
        "number of unknowns (displacement dofs, Dirichlet ones included)",
    );
    t.add("wall_time_s", Float, SECONDS, "wall time of the core's run");

    t.at(all, Meta);
    t.add("version", Str, TEXT, "the rustfrac version that ran");
    t.add("method", Str, TEXT, "the method that ran");
    t.add(
        "bc",
        Str,
        TEXT,
        "the boundary condition: a grip (free, clamped, traction) or regions",
    );
    t.add(
        "bc_description",
        Str,
        TEXT,
        "the boundary condition in words",
    );
    t.add(
        "warnings",
        StrList,
        TEXT,
        "numerical and accuracy warnings of the run (messages)",
    );
    t.add(
        "warning_kinds",
        StrList,
        TEXT,
        "the kind of each warning (ill_conditioned, locking, discretisation)",
    );
    t.add(
        "anchor_node",
        Int,
        TEXT,
        "the node carrying the u1 = 0 anchor (None under clamped grips and with supports on \
         regions, which need none)",
    )
    .or_none();
    t.add(
        "timings",
        Kind::Table,
        TEXT,
        "wall times of the run's parts",
    );
    t.add(
        "timings.rust_s",
        Float,
        SECONDS,
        "wall time of the core's run",
    );
    t.add(
        "timings.total_s",
        Float,
        SECONDS,
        "wall time of rustfrac.run (Python included)",
    )
    .python("rustfrac.run");
    t.add(
        "scene",
        Kind::Table,
        TEXT,
        "the scene that ran, as a dict (its TOML layout)",
    )
    .python("rustfrac.run");

    // --- the general scene's responses (every method) ---
    t.at(all, Scalars);
    t.add(
        "force:<region>:1",
        Float,
        FORCE,
        "x1 force the region receives from outside (a support's reaction, a load's resultant) \
         at the reference load",
    )
    .when(REGIONS);
    t.add(
        "force:<region>:2",
        Float,
        FORCE,
        "x2 force the region receives from outside",
    )
    .when(REGIONS);
    t.add(
        "displacement:<region>:1",
        Float,
        LENGTH,
        "the region's mean u1 at the reference load",
    )
    .when(REGIONS);
    t.add(
        "displacement:<region>:2",
        Float,
        LENGTH,
        "the region's mean u2 at the reference load",
    )
    .when(REGIONS);
    t.add(
        "mean_stress:<region>",
        Float,
        STRESS,
        "mean normal traction on an edge region (tension positive) at the reference load",
    )
    .when(EDGE_REGIONS);
    t.add(
        "probe:<name>:1",
        Float,
        LENGTH,
        "the probe's first value at the reference load: u1 (a point probe) or the crack's \
         normal opening (an opening probe)",
    )
    .when(PROBES);
    t.add(
        "probe:<name>:2",
        Float,
        LENGTH,
        "the probe's second value: u2 or the crack's sliding jump",
    )
    .when(PROBES);
    t.add(
        "load_displacement",
        Float,
        LENGTH,
        "the primary load region's mean displacement along its drive direction (the \
         load-point displacement)",
    )
    .when(REGIONS);

    // --- FEM and XFEM: the mesh ---
    t.at(mesh, Fields);
    t.add("coords", Floats(XY), LENGTH, "node coordinates");
    t.add(
        "elements",
        Ints(&[Var("n_elements"), Fixed(4)]),
        TEXT,
        "Q4 connectivity (node indices, counter-clockwise)",
    );
    t.add(
        "u",
        Floats(NODE_DOFS),
        LENGTH,
        "nodal displacements at the reference load, interleaved [u1, u2] (XFEM: the standard \
         dofs; the shifted enrichments vanish at the nodes)",
    );
    t.add(
        "gauss_points",
        Floats(GAUSS_XY),
        LENGTH,
        "the 2 x 2 Gauss points of every element, element by element",
    );
    t.add(
        "gauss_stress",
        Floats(GAUSS_S),
        STRESS,
        "the stresses [s11, s22, s12] at the Gauss points (XFEM: of the enriched field)",
    );
    t.at(mesh, Scalars);
    t.add(
        "condition",
        Float,
        ONE,
        "condition estimate of the (first) solve: the larger of the Hager-Higham 1-norm \
         estimate and the pivot ratio of the Jacobi-scaled stiffness; None when not computed",
    )
    .or_none();
    t.add(
        "condition_pivot_ratio",
        Float,
        ONE,
        "largest over smallest pivot of the factorisation (a lower bound of the condition); \
         None when not computed",
    )
    .or_none();

    // --- FEM ---
    t.at(fem, Fields);
    t.add(
        "reactions",
        Floats(NODE_DOFS),
        FORCE,
        "nodal reactions, interleaved [r1, r2]",
    );
    t.add(
        "nodal_stress",
        Floats(&[Var("n_nodes"), Fixed(3)]),
        STRESS,
        "nodal stresses [s11, s22, s12] (element values averaged at the nodes)",
    );
    t.at(fem, Scalars);
    t.add("energy", Float, ENERGY, "strain energy of the solution");
    t.add("residual", Float, ONE, "relative residual of the solve");
    t.at(fem, Meta);
    t.add(
        "seam_y",
        Float,
        LENGTH,
        "y of the seam crack used (the grid line nearest the requested one); None uncracked",
    )
    .or_none();
    t.add(
        "seam_length",
        Float,
        LENGTH,
        "length of the seam cut: from x1 = 0 to the first grid node at or beyond a0; None \
         uncracked",
    )
    .or_none();

    // --- XFEM ---
    t.at(xfem, Fields);
    t.add(
        "u_enriched",
        Floats(&[Var("n_dofs")]),
        LENGTH,
        "all dofs at the reference load: the standard ones, then the enriched ones",
    );
    t.add(
        "enrichment",
        Floats(&[Var("n_nodes")]),
        TEXT,
        "each node's enrichment: 0 standard, 1 Heaviside, 2 tip",
    );
    t.add(
        "heaviside_nodes",
        Ints(&[Var("n_heaviside_set")]),
        TEXT,
        "the Heaviside-enriched nodes of any crack (sorted, each once)",
    );
    t.add(
        "tip_nodes",
        Ints(&[Var("n_tip_set")]),
        TEXT,
        "the tip-enriched nodes (sorted, each once)",
    );
    t.add(
        "crack",
        Floats(&[Var("n_crack_points"), Fixed(2)]),
        LENGTH,
        "final polyline of the primary crack",
    );
    t.add(
        "crack_initial",
        Floats(&[Var("n_initial_points"), Fixed(2)]),
        LENGTH,
        "initial polyline of the primary crack",
    );
    t.add(
        "cut_points",
        Floats(&[Var("n_cut_points"), Fixed(2)]),
        LENGTH,
        "the enriched elements as polygons on each side of the crack: their vertices, polygon \
         after polygon (cut_offsets)",
    );
    t.add(
        "cut_disp",
        Floats(&[Var("n_cut_points"), Fixed(2)]),
        LENGTH,
        "each cut-polygon vertex's own displacement at the reference load",
    );
    t.add(
        "cut_offsets",
        Ints(&[PlusOne("n_cut_cells")]),
        TEXT,
        "start of each cut polygon in cut_points (and the end)",
    );
    t.add(
        "cut_element",
        Ints(&[Var("n_cut_cells")]),
        TEXT,
        "the element each cut polygon belongs to",
    );
    t.add(
        "cut_stress",
        Floats(&[Var("n_cut_cells"), Fixed(3)]),
        STRESS,
        "the enriched stress [s11, s22, s12] at each cut polygon's vertex centroid",
    );
    t.add(
        "deformed_cells",
        Floats(QUADS),
        LENGTH,
        "deformed-mesh cells near the primary tip of the initial crack (5 element lengths \
         around it, 4 x 4 cells per element): corner coordinates",
    );
    t.add(
        "deformed_disp",
        Floats(QUADS),
        LENGTH,
        "the cells' corner displacements at the reference load",
    );
    t.add(
        "radii",
        Floats(&[Var("n_radii"), Fixed(5)]),
        TEXT,
        "the primary tip's SIFs at r_I and the extra radii, sorted by radius: [radius (length), \
         K_I, K_II (stress sqrt(length)), J_from_K, J_domain (energy/area)]",
    );
    t.add(
        "radii_factor",
        Floats(&[Var("n_radii")]),
        ONE,
        "each radius in tip-element lengths",
    );
    t.add(
        "tips",
        Floats(&[Var("n_tips"), Fixed(6)]),
        TEXT,
        "every tip at the reference load: [x1, x2 (length), K_I, K_II (stress sqrt(length)), \
         J_from_K, J_domain (energy/area)], tips numbered crack by crack",
    );
    t.add(
        "tip_crack",
        Ints(&[Var("n_tips")]),
        TEXT,
        "the crack of each tip (0: the primary crack)",
    );
    t.add(
        "cracks",
        Floats(&[Var("n_all_crack_points"), Fixed(2)]),
        LENGTH,
        "final polylines of all cracks, one after the other (cracks_offsets)",
    );
    t.add(
        "cracks_offsets",
        Ints(&[PlusOne("n_cracks")]),
        TEXT,
        "start of each crack in cracks (and the end)",
    );
    t.add(
        "tip_history_x",
        Floats(TIP_ROWS),
        LENGTH,
        "every tip's x1 at every history row (growth runs; no rows otherwise)",
    );
    t.add(
        "tip_history_y",
        Floats(TIP_ROWS),
        LENGTH,
        "every tip's x2 at every history row",
    );
    t.add(
        "tip_history_K_I",
        Floats(TIP_ROWS),
        K_UNIT,
        "every tip's K_I at every critical state (0 at the origin)",
    );
    t.add(
        "tip_history_K_II",
        Floats(TIP_ROWS),
        K_UNIT,
        "every tip's K_II at every critical state",
    );
    t.add(
        "tip_history_kink_angle",
        Floats(TIP_ROWS),
        RAD,
        "every tip's kink angle (tip frame) of the maximum circumferential stress criterion",
    );
    t.add(
        "tip_history_r_I",
        Floats(TIP_ROWS),
        LENGTH,
        "every tip's SIF q-radius (0 at the origin)",
    );
    t.add(
        "tip_history_grows",
        Floats(TIP_ROWS),
        ONE,
        "1 where the tip was critical and grew, else 0",
    );
    t.add(
        "snapshot_cells",
        Floats(SNAP_QUADS),
        LENGTH,
        "growth runs: the deformed patch around the growing tip at every critical state, \
         snapshot after snapshot (snapshot_offsets); snapshot k belongs to history row k + 1",
    );
    t.add(
        "snapshot_disp",
        Floats(SNAP_QUADS),
        LENGTH,
        "the snapshots' corner displacements at the critical load",
    );
    t.add(
        "snapshot_offsets",
        Ints(&[PlusOne("n_snapshots")]),
        TEXT,
        "start of each snapshot in snapshot_cells (and the end)",
    );

    t.at(xfem, History);
    t.add(
        "load_factor",
        Floats(ROWS),
        ONE,
        "load factor on the reference load (0 at the origin)",
    )
    .when(GROWTH);
    t.add(
        "sigma22",
        Floats(ROWS),
        STRESS,
        "sigma22 at each critical state",
    )
    .when(GROWTH);
    t.add("cmod", Floats(ROWS), LENGTH, "CMOD at each critical state")
        .when(GROWTH);
    t.add(
        "u0",
        Floats(ROWS),
        LENGTH,
        "grip displacement (displacement grips; 0 under traction)",
    )
    .when(GROWTH);
    t.add(
        "traction",
        Floats(ROWS),
        STRESS,
        "applied traction (traction grips; 0 otherwise)",
    )
    .when(GROWTH);
    t.add(
        "a",
        Floats(ROWS),
        LENGTH,
        "length of the crack of the most critical tip",
    )
    .when(GROWTH);
    t.add(
        "K_I",
        Floats(ROWS),
        K_UNIT,
        "K_I of the most critical tip at the critical load",
    )
    .when(GROWTH);
    t.add(
        "K_II",
        Floats(ROWS),
        K_UNIT,
        "K_II of the most critical tip",
    )
    .when(GROWTH);
    t.add(
        "kink_angle",
        Floats(ROWS),
        RAD,
        "kink angle of the most critical tip's extension (tip frame)",
    )
    .when(GROWTH);
    t.add("tip_x", Floats(ROWS), LENGTH, "x1 of the most critical tip")
        .when(GROWTH);
    t.add("tip_y", Floats(ROWS), LENGTH, "x2 of the most critical tip")
        .when(GROWTH);
    t.add(
        "r_I",
        Floats(ROWS),
        LENGTH,
        "the q-radius of the SIFs, shrunk where a hole would enter the domain (0 at the origin)",
    )
    .when(GROWTH);
    t.add(
        "condition",
        Floats(ROWS),
        ONE,
        "condition estimate of each step's solve (0 at the origin)",
    )
    .when("a growth run with the condition estimate (run(..., condition=True))");

    t.at(xfem, Scalars);
    t.add(
        "K_I",
        Float,
        K_UNIT,
        "mode-I SIF of the primary tip at r_I, reference load",
    );
    t.add("K_II", Float, K_UNIT, "mode-II SIF of the primary tip");
    t.add("J", Float, G_UNIT, "J of the primary tip from its SIFs");
    t.add(
        "J_domain",
        Float,
        G_UNIT,
        "J of the primary tip from its own domain integral",
    );
    t.add(
        "r_I",
        Float,
        LENGTH,
        "the SIFs' q-radius (xfem.r_I element sizes, or less clear of holes)",
    );
    t.add("n_std", Int, ONE, "standard dofs");
    t.add(
        "n_heaviside_nodes",
        Int,
        ONE,
        "Heaviside enrichments (nodes, summed over the cracks)",
    );
    t.add(
        "n_tip_nodes",
        Int,
        ONE,
        "tip enrichments (nodes, summed over the cracks)",
    );
    t.add(
        "n_dropped_nodes",
        Int,
        ONE,
        "nodes dropped by the small-area rule, summed over the cracks",
    );

    t.at(xfem, Meta);
    t.add(
        "status",
        Str,
        TEXT,
        "why the run stopped (a growth status, see statuses)",
    );
    t.add("enrichment", Kind::Table, TEXT, "the enrichment's counts");
    t.add("enrichment.n_std", Int, ONE, "standard dofs");
    t.add(
        "enrichment.n_heaviside_nodes",
        Int,
        ONE,
        "Heaviside enrichments",
    );
    t.add("enrichment.n_tip_nodes", Int, ONE, "tip enrichments");
    t.add(
        "enrichment.n_dropped_nodes",
        Int,
        ONE,
        "nodes dropped by the small-area rule",
    );
    t.add("r_I", Float, LENGTH, "the SIFs' q-radius");
    t.add(
        "r_I_elements",
        Float,
        ONE,
        "the scene's xfem.r_I, in element sizes",
    );
    t.add(
        "crack_initial",
        FloatList(PAIRS),
        LENGTH,
        "initial polyline of the primary crack",
    );
    t.add(
        "cracks_initial",
        FloatList(&[Var("n_cracks"), Var("n_points"), Fixed(2)]),
        LENGTH,
        "initial polylines of all cracks (a list of polylines; their lengths differ)",
    );

    // --- XFEM, PD, CCM-PD: the load's work ---
    t.at(xfem.or(sla), Meta);
    t.add(
        "work_conjugate",
        FloatList(PAIR),
        TEXT,
        "the pair (a, b) whose product with the history's sigma22 and u0 is twice the load's \
         work (displacement grips: a = W t, b = 2); None for loads whose work the history does \
         not give",
    )
    .or_none();
    t.at(xfem, History);
    t.add(
        "load_displacement",
        Floats(ROWS),
        LENGTH,
        "the load-point displacement at each state",
    )
    .when("a growth run with supports and loads on regions");
    t.add(
        "probe:<name>:1",
        Floats(ROWS),
        LENGTH,
        "the probe's first value at each state",
    )
    .when("a growth run with probes");
    t.add(
        "probe:<name>:2",
        Floats(ROWS),
        LENGTH,
        "the probe's second value at each state",
    )
    .when("a growth run with probes");
    t.add(
        "force:<region>:1",
        Floats(ROWS),
        FORCE,
        "the region's x1 force at each state",
    )
    .when("a growth run with supports and loads on regions");
    t.add(
        "force:<region>:2",
        Floats(ROWS),
        FORCE,
        "the region's x2 force at each state",
    )
    .when("a growth run with supports and loads on regions");
    t.add(
        "mean_stress:<region>",
        Floats(ROWS),
        STRESS,
        "an edge region's mean normal traction at each state",
    )
    .when("a growth run with an edge region");

    // --- PD and CCM-PD (the SLA) ---
    t.at(sla, History);
    t.add(
        "step",
        Ints(ROWS),
        ONE,
        "the SLA step (0: the unloaded origin)",
    );
    t.add(
        "load_factor",
        Floats(ROWS),
        ONE,
        "load factor lambda = min s0 / s of the step",
    );
    t.add(
        "sigma22",
        Floats(ROWS),
        STRESS,
        "sigma22 at the step's load",
    );
    t.add("cmod", Floats(ROWS), LENGTH, "CMOD at the step's load");
    t.add(
        "u0",
        Floats(ROWS),
        LENGTH,
        "grip (or load-point) displacement at the step's load",
    );
    t.add(
        "crack_length",
        Floats(ROWS),
        LENGTH,
        "the crack's length after the step (the pre-crack's at the origin)",
    );
    t.add(
        "bond",
        Ints(ROWS),
        ONE,
        "the step's critical bond (-1 at the origin)",
    );
    t.add("n_broken", Ints(ROWS), ONE, "bonds broken in the step");
    t.add(
        "node_i",
        Ints(ROWS),
        ONE,
        "first end node of the critical bond (-1 at the origin)",
    );
    t.add(
        "node_j",
        Ints(ROWS),
        ONE,
        "second end node of the critical bond (-1 at the origin)",
    );
    t.add(
        "n_detached",
        Ints(ROWS),
        ONE,
        "PD nodes grounded in the step (they lost all stiffness along a direction)",
    );
    t.add(
        "probe:<name>:1",
        Floats(ROWS),
        LENGTH,
        "the probe's first value at the step's load (0 at the origin)",
    )
    .when(PROBES);
    t.add(
        "probe:<name>:2",
        Floats(ROWS),
        LENGTH,
        "the probe's second value at the step's load",
    )
    .when(PROBES);

    t.at(sla, Fields);
    t.add(
        "damage_at_steps",
        Ints(&[Var("n_damage_snapshots")]),
        ONE,
        "the steps after which damage_at holds the damage (pd.damage_at)",
    );
    t.add(
        "damage_at",
        Floats(&[Var("n_damage_snapshots"), Var("n_pd_nodes")]),
        ONE,
        "damage of every PD node after each step of damage_at_steps",
    );
    t.add(
        "node_xy",
        Floats(XY),
        LENGTH,
        "grid node coordinates (PD and FEM nodes)",
    );
    t.add(
        "u",
        Floats(NODE_DOFS),
        LENGTH,
        "displacements at the reference load before any SLA break, interleaved [u1, u2]",
    );
    t.add(
        "u_final",
        Floats(&[Var("n_final_dofs")]),
        LENGTH,
        "displacements at the reference load after the last break (2 n_nodes; empty when the \
         body separated)",
    );
    t.add(
        "pd_nodes",
        Ints(&[Var("n_pd_nodes")]),
        TEXT,
        "the PD nodes (indices of node_xy)",
    );
    t.add(
        "pd_node_xy",
        Floats(&[Var("n_pd_nodes"), Fixed(2)]),
        LENGTH,
        "the PD nodes' coordinates",
    );
    t.add(
        "damage",
        Floats(&[Var("n_pd_nodes")]),
        ONE,
        "damage index of every PD node at the end",
    );
    t.add(
        "broken",
        Kind::Bools(&[Var("n_bonds")]),
        TEXT,
        "which bonds are broken at the end (pre-crack included)",
    );
    t.add(
        "bond_nodes",
        Ints(&[Var("n_bonds"), Fixed(2)]),
        TEXT,
        "the end nodes of every bond",
    );
    t.add(
        "detached_nodes",
        Ints(&[Var("n_detached"), Fixed(2)]),
        TEXT,
        "(step, node) of every grounding of a detached node; step 0: by the pre-crack",
    );

    t.at(sla, Scalars);
    t.add(
        "gamma",
        Float,
        ONE,
        "the PD stiffness correction factor of the discretisation",
    );
    t.add(
        "c",
        Float,
        "stress/length^4",
        "the micromodulus c = 48 E gamma / (5 pi h delta^3)",
    );
    t.add(
        "s0",
        Float,
        ONE,
        "the critical stretch (calibrated by pd.s0_calibration)",
    );
    t.add("delta", Float, LENGTH, "the horizon m dx");

    t.at(sla, Meta);
    t.add(
        "anchor_xy",
        FloatList(PAIR),
        LENGTH,
        "the anchor node's coordinates (None without an anchor)",
    )
    .or_none();
    t.add(
        "status",
        Str,
        TEXT,
        "how the SLA ended (an SLA status, see statuses)",
    );
    t.add(
        "solver",
        Str,
        TEXT,
        "the SLA engine that ran, with its fallbacks explained",
    );
    t.add("sla_steps_done", Int, ONE, "SLA steps run");
    t.at(Methods::PD, Meta);
    t.add(
        "pd_regions",
        Str,
        TEXT,
        "\"the whole plate\" (PD everywhere)",
    );
    t.at(Methods::CCM_PD, Meta);
    t.add(
        "pd_regions",
        FloatList(BOXES),
        LENGTH,
        "the PD rectangles [x0, y0, x1, y1] at the end",
    );
    t.add(
        "pd_regions_initial",
        FloatList(BOXES),
        LENGTH,
        "the PD rectangles the adaptive region started from",
    )
    .when("an adaptive PD region (pd.region = \"adaptive\")");
    t.at(sla, Meta);
    t.add(
        "pd_region",
        Str,
        TEXT,
        "the scene's pd.region: fixed or adaptive",
    );
    t.add(
        "surface_correction",
        Str,
        TEXT,
        "the scene's pd.surface_correction",
    );
    let sc = "pd.surface_correction = \"energy\"";
    t.add(
        "surface_nodes_corrected",
        Int,
        ONE,
        "PD nodes with a node factor other than 1",
    )
    .when(sc);
    t.add(
        "surface_node_factor_range",
        FloatList(PAIR),
        ONE,
        "smallest and largest node factor over the PD nodes and both directions",
    )
    .when(sc);
    t.add(
        "surface_bond_factor_range",
        FloatList(PAIR),
        ONE,
        "smallest and largest bond factor over the bonds the pre-crack leaves",
    )
    .when(sc);
    t.add(
        "s0_calibration",
        Kind::Table,
        TEXT,
        "the critical stretch's rule (pd.s0_calibration): s0 = factor x eq. 48's",
    );
    t.add(
        "s0_calibration.rule",
        Str,
        TEXT,
        "the rule: continuum, grid or sla",
    );
    t.add(
        "s0_calibration.factor",
        Float,
        ONE,
        "s0 / eq. 48's s0 (1 for the continuum rule)",
    );
    t.add(
        "s0_calibration.G_ref_over_G0",
        Float,
        ONE,
        "G_ref / G0 with eq. 48's s0 (1 for the continuum rule)",
    );
    t.add(
        "region_switches",
        TableList,
        TEXT,
        "the adaptive region's growths, in order (empty for a fixed region)",
    );
    t.add(
        "region_switches.step",
        Int,
        ONE,
        "the first step solved on the grown region",
    );
    t.add(
        "region_switches.n_regions",
        Int,
        ONE,
        "PD rectangles from then on",
    );
    t.add(
        "region_switches.n_pd_nodes",
        Int,
        ONE,
        "PD nodes of the new model",
    );
    t.add(
        "region_switches.n_dofs",
        Int,
        ONE,
        "unknowns of the new model",
    );
    t.add(
        "region_switches.seconds",
        Float,
        SECONDS,
        "wall time to build the new model and its solver",
    );
    t.add(
        "interface_distance_min",
        Float,
        ONE,
        "the smallest distance, in horizons, from a bond the SLA broke to the nearest FEM node \
         at its break (None: pure PD, no bond broke, or none within 10 horizons)",
    )
    .or_none();
    t.add(
        "precrack",
        FloatList(PAIRS),
        LENGTH,
        "the pre-crack's polyline (a centre crack: its ends and centre)",
    );
    t.add(
        "out_of_balance",
        FloatList(PAIR),
        FORCE,
        "sum of all external nodal forces (x1, x2) at the reference load",
    );
    t.add(
        "n_refactorisations",
        Int,
        ONE,
        "factorisations of the SLA's solver",
    );
    t.add(
        "max_update_rank",
        Int,
        ONE,
        "most low-rank update vectors the fast solver held at once (0: oracle)",
    );
    t.add(
        "inverse_columns",
        Int,
        ONE,
        "columns of the inverse the sparse engine computed (0: dense engine, oracle)",
    );
    t.add(
        "screened_steps",
        Int,
        ONE,
        "steps whose critical bond the bond screening found",
    );
    t.add(
        "screened_bonds",
        Int,
        ONE,
        "bonds the screening evaluated exactly in them",
    );
    t.add(
        "refactor_interval",
        Int,
        ONE,
        "the re-condensation interval in use (0: oracle)",
    );
    t.add(
        "resumed_steps",
        Int,
        ONE,
        "steps replayed from pd.resume_from (0 without resume)",
    );
    t.add("n_checkpoints", Int, ONE, "checkpoints this run wrote");
    t.add(
        "checkpoint_path",
        Str,
        TEXT,
        "the scene's pd.checkpoint_path (None: none)",
    )
    .or_none();
    t.add(
        "resumed_from",
        Str,
        TEXT,
        "the scene's pd.resume_from (None: a fresh run)",
    )
    .or_none();
    t.add(
        "peak_memory_bytes",
        Int,
        BYTES,
        "peak resident memory of the process (None where the OS does not say)",
    )
    .or_none();
    t.add("counts", Kind::Table, TEXT, "the model's sizes");
    t.add("counts.n_nodes", Int, ONE, "grid nodes");
    t.add("counts.n_dofs", Int, ONE, "unknowns");
    t.add("counts.n_pd_nodes", Int, ONE, "PD nodes");
    t.add("counts.n_bonds", Int, ONE, "bonds");
    t.add(
        "counts.n_precrack_bonds",
        Int,
        ONE,
        "bonds the pre-crack broke",
    );
    t.add(
        "counts.n_removed_elements",
        Int,
        ONE,
        "FEM elements removed (cut by a crack or a hole)",
    );
    t.add(
        "counts.bytes_per_bond",
        Int,
        BYTES,
        "memory per bond of the bond list",
    );
    t.add(
        "timings.setup_s",
        Float,
        SECONDS,
        "wall time of building the model",
    );
    t.add(
        "timings.sla_s",
        Float,
        SECONDS,
        "wall time of the SLA steps",
    );
    t.add(
        "timings.region_switch_s",
        Float,
        SECONDS,
        "wall time of the adaptive region's growths",
    );
    t.v
}

/// Every result entry of every method.
pub fn schema() -> &'static [Entry] {
    static S: OnceLock<Vec<Entry>> = OnceLock::new();
    S.get_or_init(build)
}

/// The entries of `method`, in table order.
pub fn entries(method: &str) -> impl Iterator<Item = &'static Entry> + '_ {
    schema().iter().filter(move |e| e.methods.has(method))
}

/// The entry of `method` a key of group `g` is (None: not in the table).
pub fn entry(method: &str, g: Group, key: &str) -> Option<&'static Entry> {
    entries(method).find(|e| e.group == g && e.matches(key))
}
