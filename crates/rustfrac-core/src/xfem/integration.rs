//! Integration of the XFEM element blocks (paper eqs. 34-35): which quadrature rule an element
//! uses, and the standard blocks shared by every plain element.
//!
//! Tip elements: `tip_nsub x tip_nsub` sub-quads with 2 x 2 Gauss; other elements that are crossed
//! by the crack or carry branch functions: `nsub x nsub` sub-quads with 2 x 2 Gauss; every other
//! element (standard, or Heaviside-enriched but not crossed, where H - H_I is constant): the plain
//! 2 x 2 Gauss rule, exact on rectangles. An element crossed by two or more cracks uses twice the
//! sub-quads per direction (capped at 64; module [`crate::xfem`], "Several cracks"). Sub-quads
//! sample every Heaviside and branch function at their Gauss points; they do not follow the crack
//! (hence the quadrature side of the small-area rule, [`crate::xfem::enrichment`]).
//!
//! Holes ([`crate::fe::fictitious`]): a cut element integrates over its material part only. A
//! plain (or Heaviside-enriched, uncrossed) cut element uses the material part's rule (3-point
//! triangles, exact for its polynomial integrand); a cut element needing sub-quads uses the
//! material part *clipped by each sub-quad* with the 3-point rule on its triangles
//! ([`crate::fe::FictitiousDomain::subcell_rule`]): the sub-quads' sampling of the enrichment,
//! restricted to the material (no Gauss point in a hole, the hole's boundary followed exactly).
//! Void elements add nothing.
//!
//! Standard element blocks are computed once per distinct element shape and reused across growth
//! steps (the standard-standard block of an enriched element is the same polynomial integrand, so
//! it is exact either way). The enriched blocks themselves (eqs. 25-26, 34) are assembled by
//! [`crate::xfem::XfemModel::element_block`].

use crate::fe::mesh::Mesh;
use crate::fe::q4::element_stiffness;
use crate::fe::quadrature::{subquad_rule, QPoint};
use crate::geometry::sub;
use crate::problem::Elastic;
use std::collections::HashMap;

/// Standard element stiffness blocks, one per distinct element shape (dx, dy).
#[derive(Debug)]
pub(super) struct StdBlocks {
    of_element: Vec<u32>,
    blocks: Vec<Vec<f64>>,
}

impl StdBlocks {
    pub(super) fn new(mesh: &Mesh, mat: &Elastic) -> Self {
        let mut map: HashMap<(u64, u64), u32> = HashMap::new();
        let mut blocks = Vec::new();
        let rule = subquad_rule(1, 2);
        let of_element = (0..mesh.n_elements())
            .map(|e| {
                let xy = mesh.element_coords(e);
                let key = (
                    (xy[1][0] - xy[0][0]).to_bits(),
                    (xy[3][1] - xy[0][1]).to_bits(),
                );
                *map.entry(key).or_insert_with(|| {
                    let mut k = Vec::new();
                    let o = [
                        [0.0, 0.0],
                        sub(xy[1], xy[0]),
                        sub(xy[2], xy[0]),
                        sub(xy[3], xy[0]),
                    ];
                    element_stiffness(&o, mat, &rule, &mut k);
                    blocks.push(k);
                    (blocks.len() - 1) as u32
                })
            })
            .collect();
        Self { of_element, blocks }
    }

    /// The standard block (row-major, 8 x 8) of element `e`.
    pub(super) fn of(&self, e: usize) -> &[f64] {
        &self.blocks[self.of_element[e] as usize]
    }
}

/// The quadrature rule of an element (see the module documentation).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum RuleKind {
    Gauss,
    Sub,
    Tip,
    /// `Sub` or `Tip` in an element crossed by two or more cracks: twice the sub-quads per
    /// direction (module documentation, "Several cracks")
    SubMulti,
    TipMulti,
}

impl RuleKind {
    /// The rule of a tip element (`tip`), else of an element that needs sub-quads (`sub`: crossed
    /// by a crack whose Heaviside function it carries, or carrying branch functions), else 2 x 2
    /// Gauss; `multi`: the element is crossed by two or more cracks.
    pub(super) fn select(tip: bool, sub: bool, multi: bool) -> Self {
        if tip {
            if multi {
                RuleKind::TipMulti
            } else {
                RuleKind::Tip
            }
        } else if sub {
            if multi {
                RuleKind::SubMulti
            } else {
                RuleKind::Sub
            }
        } else {
            RuleKind::Gauss
        }
    }
}

/// Sub-quads per direction in an element crossed by two or more cracks, for a base of `n`.
fn multi_nsub(n: usize) -> usize {
    (2 * n).min(64)
}

/// The quadrature rules of a model, one per [`RuleKind`] (on the reference square).
#[derive(Debug, Clone)]
pub(super) struct Rules {
    nsub: usize,
    tip_nsub: usize,
    gauss: Vec<QPoint>,
    sub: Vec<QPoint>,
    tip: Vec<QPoint>,
    sub_multi: Vec<QPoint>,
    tip_multi: Vec<QPoint>,
}

impl Rules {
    /// The rules for `nsub` and `tip_nsub` sub-quads per direction (2 x 2 Gauss in each).
    pub(super) fn new(nsub: usize, tip_nsub: usize) -> Self {
        Self {
            nsub,
            tip_nsub,
            gauss: subquad_rule(1, 2),
            sub: subquad_rule(nsub, 2),
            tip: subquad_rule(tip_nsub, 2),
            sub_multi: subquad_rule(multi_nsub(nsub), 2),
            tip_multi: subquad_rule(multi_nsub(tip_nsub), 2),
        }
    }

    /// Sub-quads per direction of a rule.
    pub(super) fn nsub(&self, kind: RuleKind) -> usize {
        match kind {
            RuleKind::Gauss => 1,
            RuleKind::Sub => self.nsub,
            RuleKind::Tip => self.tip_nsub,
            RuleKind::SubMulti => multi_nsub(self.nsub),
            RuleKind::TipMulti => multi_nsub(self.tip_nsub),
        }
    }

    pub(super) fn get(&self, kind: RuleKind) -> &[QPoint] {
        match kind {
            RuleKind::Gauss => &self.gauss,
            RuleKind::Sub => &self.sub,
            RuleKind::Tip => &self.tip,
            RuleKind::SubMulti => &self.sub_multi,
            RuleKind::TipMulti => &self.tip_multi,
        }
    }
}
