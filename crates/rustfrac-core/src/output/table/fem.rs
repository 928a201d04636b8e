//! The result entries of FEM (see [`super::super::schema`]).

use super::units::*;

#[allow(clippy::too_many_lines)]
pub(super) fn rows(t: &mut Table) {
    let fem = Methods::FEM;

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
}
