//! The finite-element foundations (paper section 2.1.1, eqs. 4-14): Gauss quadrature
//! ([`quadrature`]), structured Q4 meshes ([`mesh`]), linear elastic materials ([`material`]), the
//! Q4 element ([`q4`]), the assembled plane-elasticity model ([`model`]), Dirichlet conditions with
//! the rigid-mode check ([`dirichlet`]), holes and notches as a fictitious domain
//! ([`fictitious`]), the eliminated and factorised linear system ([`linear_system`]), the
//! loading of the paper's plate ([`loading`]), supports and loads on boundary regions
//! ([`regions`]) and graded grids ([`grading`]).
//!
//! Built on [`crate::la`]; XFEM and CCM-PD build on it.

pub mod dirichlet;
pub mod fictitious;
pub mod grading;
pub mod linear_system;
pub mod loading;
pub mod material;
pub mod mesh;
pub mod model;
pub mod q4;
pub mod quadrature;
pub mod regions;

pub use dirichlet::Dirichlet;
pub use fictitious::{ElementKind, FictitiousDomain};
pub use linear_system::{LinearSystem, Solution};
pub use material::{Elastic, Plane};
pub use mesh::{Mesh, Side};
pub use model::{edge_traction, FemModel};
