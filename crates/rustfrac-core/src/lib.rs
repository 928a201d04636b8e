//! rustfrac-core: the numerical core of rustfrac.
//!
//! Modules follow the concepts of the paper (Tuna, Ongaro, Trovalusci, Fantuzzi): [`mesh`] and
//! [`fem`] (Q4 plane elasticity), [`xfem`] and [`sif`] (section 2.1, eqs. 1-36), [`pd`] (section
//! 2.2, eqs. 37-58: bonds, the splice coupling [`pd::splice`], and the sequentially linear
//! analysis of section 3, [`pd::sla`], with [`pd::sla::checkpoint`] for resumable runs), with
//! [`sparse`] and [`solver`] underneath. No Python here: the `rustfrac-py` crate binds it.
//!
//! Units are consistent but unspecified; the paper's case uses N, mm, MPa.

pub mod error;
pub mod fem;
pub mod loading;
pub mod material;
pub mod mesh;
pub mod ordering;
pub mod pd;
pub mod plate;
pub mod quadrature;
pub mod sif;
pub mod solver;
pub mod sparse;
pub mod warning;
pub mod xfem;

pub use error::{Error, Result};
pub use warning::{Warning, WarningKind};
