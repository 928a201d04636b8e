//! The integration tests of rustfrac-core, one module per concept, linked into ONE test binary
//! (each file under `tests/` would be its own binary, linked once more under release LTO).
//!
//! One module: `cargo test --release -p rustfrac-core --test suite fem_validation::`; the slow
//! paper-scale tests are `#[ignore]`d: `cargo test --release -p rustfrac-core --test suite --
//! --ignored`. A new test file is a new `mod` line here.

mod common;

mod ccm_pd_adaptive;
mod ccm_pd_graded;
mod ccm_pd_holes;
mod coupling_validation;
mod fem_validation;
mod general_scenes;
mod hole_reactions;
mod hole_validation;
mod hostile_input;
mod near_incompressible;
mod pd_extremes_validation;
mod pd_general;
mod pd_lps;
mod pd_rigid_modes;
mod pd_surface_correction;
mod pd_validation;
mod problem_description;
mod s0_calibration;
mod scale_invariance;
mod scene_refusals;
mod singular_detection;
mod sla_accuracy_guard;
mod sla_long_validation;
mod sla_screening;
mod sla_sparse_validation;
mod sla_validation;
mod xfem_extremes;
mod xfem_growth_reuse;
mod xfem_multicrack_validation;
mod xfem_paths;
mod xfem_validation;
