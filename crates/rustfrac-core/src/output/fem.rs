//! The record of a FEM plate run ([`FemPlateResult`]).

use super::common::{self, Headline};
use super::record::{Record, Value};
use crate::fem_driver::FemPlateResult;
use crate::problem::Problem;

impl FemPlateResult {
    /// The run's record (names: [`super::schema`]): fields coords, elements, u, reactions,
    /// nodal_stress, gauss_points, gauss_stress; scalars energy, residual, condition,
    /// condition_pivot_ratio and the responses; meta anchor_node, seam_y, seam_length, timings.
    pub fn into_record(self, p: &Problem) -> Record {
        let r = self;
        let h = Headline {
            sigma22: r.sigma22,
            cmod: r.cmod,
            n_dofs: r.n_dofs,
            wall_time_s: r.wall_time_s,
        };
        let mut rec = common::start(p, h, &r.warnings);
        let f = &mut rec.fields;
        f.set("coords", Value::rows(r.coords));
        f.set("elements", Value::index_rows(r.elements));
        f.set("u", Value::floats(r.u));
        f.set("reactions", Value::floats(r.reactions));
        f.set("nodal_stress", Value::rows(r.nodal_stress));
        f.set("gauss_points", Value::rows(r.gauss_points));
        f.set("gauss_stress", Value::rows(r.gauss_stress));
        let sc = &mut rec.scalars;
        sc.set("energy", r.energy);
        sc.set("residual", r.residual);
        sc.set("condition", Value::opt(r.condition.map(|c| c.value())));
        sc.set(
            "condition_pivot_ratio",
            Value::opt(r.condition.map(|c| c.pivot_ratio)),
        );
        common::anchor(&mut rec, p, r.anchor_node);
        common::responses(&mut rec, p, &r.responses);
        rec.meta.set("seam_y", Value::opt(r.seam_y));
        rec.meta.set("seam_length", Value::opt(r.seam_length));
        common::timings(&mut rec, r.wall_time_s, &[]);
        rec
    }
}
