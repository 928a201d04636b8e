//! rustfrac-core: the numerical core of rustfrac.
//!
//! Modules follow the concepts of the paper (Tuna, Ongaro, Trovalusci, Fantuzzi): [`problem`]
//! (the one problem description every driver reads: scene schema, parsing, validation), [`fe`]
//! (Q4 plane elasticity: mesh, material, element, Dirichlet conditions, plate loading) and its
//! plate driver [`fem_driver`] (plain FEM, uncracked or with a seam crack), [`xfem`] (section
//! 2.1, eqs. 1-36: crack level sets, enrichment, integration, SIFs, growth), [`pd`] (section
//! 2.2, eqs. 37-58: bonds, the splice coupling [`pd::splice`], and the sequentially linear
//! analysis of section 3, [`pd::sla`], with
//! [`pd::sla::checkpoint`] for resumable runs), with [`la`] (sparse matrices, ordering, direct
//! solvers, condition) and [`geometry`] (plane geometry: orientation, distances, clipping; one
//! copy) underneath. No Python here: the `rustfrac-py` crate binds it.
//!
//! Units are consistent but unspecified; the paper's case uses N, mm, MPa.

pub mod error;
pub mod fe;
pub mod fem_driver;
pub mod geometry;
pub mod la;
pub mod pd;
pub mod problem;
pub mod warning;
pub mod xfem;

pub use error::{Error, Result};
pub use warning::{Warning, WarningKind};

// temporary: old path, removed after the architecture merge
#[doc(hidden)]
pub use fe::{loading, material, mesh, quadrature};
// temporary: old path, removed after the architecture merge
#[doc(hidden)]
pub use la::ordering;

/// Temporary: old path, removed after the architecture merge (the items of the former
/// `solver.rs`, now in [`la`]).
#[doc(hidden)]
pub mod solver {
    pub use crate::la::cholesky::{Cholesky, PIVOT_TOL};
    pub use crate::la::condition::{
        check_condition, condition_warning, ConditionEstimate, CONDITION_ITERATIONS, COND_SINGULAR,
        COND_WARN,
    };
    pub use crate::la::lu::Lu;
}

/// Temporary: old path, removed after the architecture merge (the items of the former
/// `sparse.rs`, now in [`la`]).
#[doc(hidden)]
pub mod sparse {
    pub use crate::la::csc::CscMatrix;
    pub use crate::la::pattern::Pattern;
    pub use crate::la::reduction::Reduction;
}

/// Temporary: old path, removed after the architecture merge (the items of the former `fem.rs`,
/// now in [`fe`]).
#[doc(hidden)]
pub mod fem {
    pub use crate::fe::dirichlet::Dirichlet;
    pub use crate::fe::linear_system::{LinearSystem, Solution};
    pub use crate::fe::model::{edge_traction, FemModel};
    pub use crate::fe::q4::{add_btdb, dshape, element_stiffness, geometry, shape, strain, stress};
}
