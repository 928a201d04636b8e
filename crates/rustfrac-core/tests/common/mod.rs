//! Set-ups and closed forms shared by the integration tests (`mod common;` in each test file):
//! progress callbacks, relative errors, the coarse CCM-PD plate and the pure PD strip of the SLA
//! tests, the tall traction strip and Tada's factor of the XFEM tests, and the direct FEM solve of
//! a plate under the paper's grips. Each test binary uses only some of them.
#![allow(dead_code)]

use rustfrac_core::fem::{FemModel, LinearSystem, Solution};
use rustfrac_core::loading::{plate_conditions, Grip, PlateEdges, PlateLoad};
use rustfrac_core::material::{Elastic, Plane};
use rustfrac_core::pd::sla::{CcmPdParams, Method, SlaParams};
use rustfrac_core::xfem::{GrowthParams, XfemParams};
use std::f64::consts::PI;

/// SLA progress callback that never cancels.
pub fn go_on(_: usize, _: usize) -> bool {
    true
}

/// XFEM progress callback that ignores the reports.
pub fn quiet(_: usize, _: usize) {}

/// |a - b| / |b|
pub fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

/// A coarse version of the paper's CCM-PD plate (dx = 1/5 keeps x2 = 10.5 and x1 = 1.1 between
/// nodes), with a larger PD rectangle (4.4 x 2.4, ~600 PD dofs) so that hundreds of steps stay
/// inside it.
pub fn coarse(fast: bool, steps: usize) -> CcmPdParams {
    let mut p = CcmPdParams::paper();
    p.model.dx = 0.2;
    p.model.pd_regions = vec![[0.3, 9.3, 4.7, 11.7]];
    p.sla = SlaParams {
        max_steps: steps,
        fast,
        ..SlaParams::default()
    };
    p
}

/// The paper's parameters ([`CcmPdParams::paper`]: material, G0, PD rectangle, pre-crack, load, SLA
/// options) on a `width` x `height` plate with grid spacing `dx` and horizon factor `m`.
pub fn pd_plate(method: Method, width: f64, height: f64, dx: f64, m: usize) -> CcmPdParams {
    let mut p = CcmPdParams::paper();
    p.model.method = method;
    p.model.width = width;
    p.model.height = height;
    p.model.dx = dx;
    p.model.m = m;
    p
}

/// A pure PD strip 1.2 x 2.2 (dx = 0.2, m = 2) with an edge pre-crack of 0.5 at mid-height: the SLA
/// cuts its ligament through (status "separated") within the 2000 steps allowed.
pub fn pd_strip(fast: bool, grip: Grip) -> CcmPdParams {
    let mut p = pd_plate(Method::Pd, 1.2, 2.2, 0.2, 2);
    p.model.precrack = vec![[0.0, 1.1], [0.5, 1.1]];
    p.model.load.grip = grip;
    p.sla = SlaParams {
        max_steps: 2000,
        fast,
        ..SlaParams::default()
    };
    p
}

/// Tada's edge-crack factor for a long strip under remote tension (Tada, Paris and Irwin, "The
/// Stress Analysis of Cracks Handbook"; accurate to about 0.5 % for any a/b; as in
/// reference/closed-forms.md and python/rustfrac/handbook.py), K_I = sigma sqrt(pi a) F(a/b):
/// F(x) = sqrt(2/(pi x) tan(pi x/2)) [0.752 + 2.02 x + 0.37 (1 - sin(pi x/2))^3] / cos(pi x/2).
pub fn tada_f(x: f64) -> f64 {
    let t = PI * x / 2.0;
    (2.0 / (PI * x) * t.tan()).sqrt() * (0.752 + 2.02 * x + 0.37 * (1.0 - t.sin()).powi(3))
        / t.cos()
}

/// Tall strip W = 1, H = 4 (half-height / width 2: the handbook's long strip) on nx x ny elements,
/// E = 1000, nu = 0.3, plane strain, unit traction, no extra J radii, with the crack `crack` (from
/// the left edge for the edge-crack cases).
pub fn tall_strip(crack: Vec<[f64; 2]>, nx: usize, ny: usize) -> XfemParams {
    let mut p = XfemParams::paper(Grip::Traction);
    p.width = 1.0;
    p.height = 4.0;
    p.nx = nx;
    p.ny = ny;
    p.material = Elastic::new(1000.0, 0.3, Plane::Strain, 1.0).unwrap();
    p.crack = crack;
    p.load = PlateLoad {
        grip: Grip::Traction,
        u0: 0.0,
        traction: 1.0,
    };
    p.extra_radius_factors = vec![];
    p
}

/// XFEM growth with the paper's G0 = 0.367 and the default extension per step (one element length)
/// up to the crack length `a_stop`, at most `max_steps` steps.
pub fn paper_growth(a_stop: f64, max_steps: usize) -> GrowthParams {
    GrowthParams {
        g0: 0.367,
        da: None,
        a_stop,
        max_steps,
    }
}

/// The paper's grips at the reference load: `grip`, u0 = `u0`, no traction.
pub fn grips(grip: Grip, u0: f64) -> PlateLoad {
    PlateLoad {
        grip,
        u0,
        traction: 0.0,
    }
}

/// Direct FEM solve of a plate model under the plate's edge conditions (thickness 1, Cholesky of
/// the reduced system): the edges, the load vector and the solution.
pub fn solve_fem_plate(model: &FemModel, load: &PlateLoad) -> (PlateEdges, Vec<f64>, Solution) {
    let edges = PlateEdges::of_mesh(&model.mesh);
    let (bc, f, _) = plate_conditions(&edges, load, model.n_dofs(), 1.0).unwrap();
    let sol = LinearSystem::new(model.stiffness(), &bc)
        .unwrap()
        .solve(&f, 1.0)
        .unwrap();
    (edges, f, sol)
}
