//! The finite-element foundations (paper section 2.1.1, eqs. 4-14): Gauss quadrature
//! ([`quadrature`]), structured Q4 meshes ([`mesh`]), the Q4 element ([`q4`]), the assembled
//! plane-elasticity model ([`model`]), Dirichlet conditions with the rigid-mode check
//! ([`dirichlet`]), holes and notches as a fictitious domain ([`fictitious`]), the eliminated and
//! factorised linear system ([`linear_system`]), the loading of the paper's plate ([`loading`])
//! and supports and loads on boundary regions ([`regions`]).
//!
//! Built on [`crate::la`] from the description in [`crate::problem`] (the material, the grid,
//! the grips, the sides); XFEM and CCM-PD build on it.

pub mod dirichlet;
pub mod fictitious;
pub mod linear_system;
pub mod loading;
pub mod mesh;
pub mod model;
pub mod q4;
pub mod quadrature;
pub mod regions;

pub use dirichlet::Dirichlet;
pub use fictitious::{ElementKind, FictitiousDomain};
pub use linear_system::{LinearSystem, Solution};
pub use mesh::Mesh;
pub use model::{edge_traction, FemModel};
