//! The result entries of XFEM, and the load's work of XFEM, PD and CCM-PD (see [`super::super::schema`]).

use super::units::*;

#[allow(clippy::too_many_lines)]
pub(super) fn rows(t: &mut Table) {
    let xfem = Methods::XFEM;
    let sla = Methods::SLA;

    // --- XFEM ---
    t.at(xfem, Fields);
    t.add(
        "reactions",
        Floats(NODE_DOFS),
        FORCE,
        "nodal reactions K u - f of the standard dofs at the reference load, interleaved [r1, r2]",
    );
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
        "every tip's kink angle (tip frame) of the maximum circumferential stress criterion, in \
         radians (the scene's crack.angle is in degrees)",
    );
    t.add(
        "tip_history_r_I",
        Floats(TIP_ROWS),
        LENGTH,
        "every tip's SIF q-radius (NaN at the origin: not computed)",
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

    t.add(
        "state_rows",
        Ints(&[Var("n_states")]),
        TEXT,
        "growth runs: the history row of each kept whole-plate state (xfem.state_every: every \
         k-th growth step and the last; row 0, the unloaded origin, has none)",
    );
    t.add(
        "state_u",
        Floats(&[Var("n_states"), Twice("n_nodes")]),
        LENGTH,
        "each state's nodal displacements at its critical load, interleaved [u1, u2] (the \
         standard dofs)",
    );
    t.add(
        "state_stress",
        Floats(&[Var("n_states"), Var("n_elements"), Fixed(3)]),
        STRESS,
        "each state's element stresses [s11, s22, s12] at its critical load: the mean of the \
         enriched stress at the element's 2 x 2 Gauss points",
    );
    t.add(
        "state_enrichment",
        Floats(&[Var("n_states"), Var("n_nodes")]),
        TEXT,
        "each state's node enrichment for its cracks: 0 standard, 1 Heaviside, 2 tip",
    );
    t.add(
        "state_cut_offsets",
        Ints(&[PlusOne("n_states")]),
        TEXT,
        "start of each state's cut polygons in state_cut_element (and the end)",
    );
    t.add(
        "state_cut_points",
        Floats(&[Var("n_state_cut_points"), Fixed(2)]),
        LENGTH,
        "the cut polygons of every state (the enriched elements of that state's cracks, 2 x 2 \
         cells per element split along the crack): their vertices, polygon after polygon \
         (state_cut_point_offsets)",
    );
    t.add(
        "state_cut_disp",
        Floats(&[Var("n_state_cut_points"), Fixed(2)]),
        LENGTH,
        "each state cut-polygon vertex's own displacement at the state's critical load",
    );
    t.add(
        "state_cut_point_offsets",
        Ints(&[PlusOne("n_state_cut_cells")]),
        TEXT,
        "start of each state cut polygon in state_cut_points (and the end)",
    );
    t.add(
        "state_cut_element",
        Ints(&[Var("n_state_cut_cells")]),
        TEXT,
        "the element each state cut polygon belongs to",
    );
    t.add(
        "state_cut_stress",
        Floats(&[Var("n_state_cut_cells"), Fixed(3)]),
        STRESS,
        "the enriched stress [s11, s22, s12] at each state cut polygon's vertex centroid, at \
         the state's critical load",
    );
    t.add(
        "state_cracks",
        Floats(&[Var("n_state_crack_points"), Fixed(2)]),
        LENGTH,
        "the crack polylines of every state (the cracks its solve ran on), crack after crack \
         and state after state (state_cracks_offsets)",
    );
    t.add(
        "state_cracks_offsets",
        Ints(&[PlusOne("n_state_cracks")]),
        TEXT,
        "start of crack c of state k in state_cracks at index k n_cracks + c (and the end)",
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
        "kink angle of the most critical tip's extension (tip frame), in radians",
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
        "the q-radius of the SIFs, shrunk where a hole would enter the domain (NaN at the origin: \
         not computed)",
    )
    .when(GROWTH);
    t.add(
        "condition",
        Floats(ROWS),
        ONE,
        "condition estimate of each step's solve (NaN at the origin: no solve)",
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
}
