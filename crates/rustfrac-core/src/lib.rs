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
//! copy) underneath, and [`output`] (every result as a typed record, and the table of its
//! names, kinds and units). No Python here: the `rustfrac-py` crate binds it.
//!
//! Units are consistent but unspecified; the paper's case uses N, mm, MPa.

pub mod error;
pub mod fe;
pub mod fem_driver;
pub mod geometry;
pub mod la;
#[cfg(test)]
mod layering_test;
pub mod memory;
pub mod output;
pub mod pd;
pub mod problem;
pub mod warning;
pub mod xfem;

pub use error::{Error, Result};
pub use warning::{Warning, WarningKind};
