//! Sparse linear algebra under every model: CSC storage ([`csc`]), the sparsity pattern built
//! once with race-free parallel assembly ([`pattern`]), the Dirichlet elimination on the matrix
//! level ([`reduction`]), the geometric nested-dissection ordering ([`ordering`]), the direct
//! solvers on top of faer, supernodal Cholesky for the SPD FEM/XFEM systems ([`cholesky`]), the
//! block of the inverse at a few interface unknowns from one factorisation ([`schur`]), the
//! forward solve with a sparse right-hand side along the elimination tree ([`sparse_forward`]), and
//! sparse LU for the non-symmetric splice-coupled CCM-PD systems ([`lu`]), dense LU
//! in place for their condensed PD system ([`dense_lu`]; in two stages, [`block_lu`]),
//! and the condition estimate with its thresholds ([`condition`]).
//!
//! Nothing here knows about elements or meshes: the finite-element layer ([`crate::fe`]) builds
//! on it.

pub mod block_lu;
mod checks;
pub mod cholesky;
pub mod condition;
pub mod csc;
pub mod dense_lu;
pub mod lu;
pub mod ordering;
pub mod pattern;
pub mod reduction;
pub mod schur;
pub mod sparse_forward;

pub use block_lu::LeadingLu;
pub use cholesky::{Cholesky, PIVOT_TOL};
pub use condition::{
    check_condition, condition_warning, ConditionEstimate, CONDITION_ITERATIONS, COND_SINGULAR,
    COND_WARN,
};
pub use csc::CscMatrix;
pub use dense_lu::{DenseLu, DENSE_PIVOT_TOL};
pub use lu::Lu;
pub use pattern::Pattern;
pub use reduction::Reduction;
pub use schur::InterfaceCholesky;
pub use sparse_forward::{unit_vectors, written_zeros, ForwardWork, SparseColumn, SparseForward};
