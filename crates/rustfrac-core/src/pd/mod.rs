//! Bond-based peridynamics on a uniform grid (paper section 2.2, eqs. 37-58) and the sequentially
//! linear analysis of the coupled model (section 3).
//!
//! * [`partial_volume`]: the family of a node, the exact partial-volume factors `beta`
//!   (cell / disc intersection) and the family stencil.
//! * [`constants`]: gamma (Ongaro et al.), micromodulus c (eq. 47), critical stretch s0 (eq. 48),
//!   the linearised bond stiffness (eqs. 46, 55, 56), which materials PD can represent.
//! * [`calibration`]: the critical stretch calibrated on the grid (`pd.s0_calibration`).
//! * [`bonds`]: the grid, the bonds, the neighbour search and the damage index (eq. 53).
//! * [`splice`]: the splice CCM-PD coupling (section 2.2.2, eq. 58) and the pure PD model.
//! * [`surface_correction`]: the PD surface correction (energy method, Le & Bobaru 2018).
//! * [`lps`]: the linear peridynamic solid (state-based, `pd.model = "lps"`).
//! * [`cost`]: the cost model of the SLA's engines (their times and bytes), which the splice
//!   model's memory bound reads too.
//! * [`sla`]: the sequentially linear analysis (section 3), its two solvers and checkpoints.
//! * [`analysis`]: a problem's PD or CCM-PD run: the s0 calibration, the splice model with it,
//!   the SLA (the entry point; above [`calibration`], whose `"sla"` rule runs an SLA).

pub mod analysis;
pub mod bonds;
pub mod calibration;
pub mod constants;
pub mod cost;
pub mod lps;
pub mod partial_volume;
pub mod sla;
pub mod splice;
pub mod surface_correction;

pub use bonds::{damage, find_bonds, find_bonds_where, Bond, Grid, BYTES_PER_BOND};
pub use constants::{check_material, gamma, PdConstants};
pub use partial_volume::{cell_fraction, family_stencil, rect_disc_area, StencilEntry};
