//! rustfrac-core: the numerical core of rustfrac.
//!
//! Modules follow the concepts of the paper (Tuna, Ongaro, Trovalusci, Fantuzzi): [`mesh`] and
//! [`fem`] (Q4 plane elasticity), [`xfem`] (section 2.1, eqs. 1-36), [`pd`],
//! [`coupling`] and [`sla`] (section 2.2, eqs. 37-58, and the sequentially linear analysis of
//! section 3, with [`checkpoint`] for resumable runs), with [`sparse`] and [`solver`] underneath. No Python here: the `rustfrac-py` crate
//! binds it.
//!
//! Units are consistent but unspecified; the paper's case uses N, mm, MPa.

pub mod checkpoint;
pub mod coupling;
pub mod error;
pub mod fem;
pub(crate) mod geometry;
pub mod loading;
pub mod material;
pub mod mesh;
pub mod ordering;
pub mod pd;
pub mod plate;
pub mod quadrature;
pub mod sla;
pub mod solver;
pub mod sparse;
pub mod warning;
pub mod xfem;

pub use error::{Error, Result};
pub use warning::{Warning, WarningKind};
