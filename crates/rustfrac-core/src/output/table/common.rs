//! The result entries of the headline and the meta of every method, the general scene's responses, the mesh of FEM and XFEM (see [`super::super::schema`]).

use super::units::*;

#[allow(clippy::too_many_lines)]
pub(super) fn rows(t: &mut Table) {
    let all = Methods::ALL;
    let mesh = Methods::MESH;

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
}
