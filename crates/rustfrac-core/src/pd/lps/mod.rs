//! The linear peridynamic solid (LPS; ordinary state-based PD, Silling et al. 2007), small-strain
//! linearised, in plane strain and plane stress (docs/design.md, "The linear peridynamic solid").
//!
//! * [`influence`]: the influence function omega(|xi|) and the quadrature weight of a bond
//!   (partial volume beta, the lattice's fourth-moment correction).
//! * [`constants`]: the 2D moduli (kappa', mu), the critical stretch calibrated on G0 and the
//!   [`PdConstants`](crate::pd::PdConstants) the splice model carries.
//! * [`model`]: the weighted volume m_i of every node, the dilatation operator, the force
//!   state, and the stiffness matrix (pairwise part per bond plus one dilatation block per
//!   node), rebuilt from the broken bonds (the oracle engine).

pub mod constants;
pub mod influence;
pub mod model;

pub use constants::LpsConstants;
pub use model::LpsModel;
