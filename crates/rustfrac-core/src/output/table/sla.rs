//! The result entries of PD and CCM-PD (the SLA) (see [`super::super::schema`]).

use super::units::*;

#[allow(clippy::too_many_lines)]
pub(super) fn rows(t: &mut Table) {
    let sla = Methods::SLA;

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
}
