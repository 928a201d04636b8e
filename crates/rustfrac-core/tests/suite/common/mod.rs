//! Set-ups and closed forms shared by the integration tests (`use crate::common;` in each module):
//! progress callbacks, relative errors, the coarse CCM-PD plate and the pure PD strip of the SLA
//! tests, the tall traction strip and Tada's factor of the XFEM tests, and the direct FEM solve of
//! a plate under the paper's grips. Each test module uses only some of them.
#![allow(dead_code)]

use rustfrac_core::fe::loading::{plate_conditions, PlateEdges};
use rustfrac_core::fe::{FemModel, LinearSystem, Solution};
use rustfrac_core::problem::Side;
use rustfrac_core::problem::{
    Boundary, CrackKind, CrackSpec, Domain, Growth, Problem, SlaEngine, SlaParams,
};
use rustfrac_core::problem::{Elastic, Plane};
use rustfrac_core::problem::{Grip, PlateLoad};
use rustfrac_core::xfem::DEFAULT_AREA_THRESHOLD;
use std::f64::consts::PI;

/// SLA progress callback that never cancels.
pub fn go_on(_: usize, _: usize) -> bool {
    true
}

/// XFEM progress callback that ignores the reports (and never cancels).
pub fn quiet(_: usize, _: usize) -> bool {
    true
}

/// |a - b| / |b|
pub fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

/// The first `n` steps of two SLA runs (e.g. the fast engine and the oracle) break the same
/// bonds (asserted, step by step); returns the largest relative difference of lambda, sigma22
/// and CMOD over them.
pub fn same_sla_history(
    a: &rustfrac_core::pd::sla::CcmPdResult,
    b: &rustfrac_core::pd::sla::CcmPdResult,
    n: usize,
) -> f64 {
    let mut worst = 0.0f64;
    for k in 0..n {
        let (x, y) = (&a.history[k], &b.history[k]);
        assert_eq!(x.bonds, y.bonds, "step {} broke different bonds", k + 1);
        for (p, q) in [
            (x.lambda, y.lambda),
            (x.sigma22, y.sigma22),
            (x.cmod, y.cmod),
        ] {
            worst = worst.max((p - q).abs() / q.abs().max(1e-300));
        }
    }
    worst
}

/// `p` with an adaptive PD region of `margin` and `size` horizons, starting around the tip.
pub fn with_adaptive(mut p: Problem, margin: f64, size: f64) -> Problem {
    let a = rustfrac_core::problem::AdaptiveRegion { margin, size };
    p.pd_mut().adaptive = Some(a);
    let (dx, m) = (p.pd().unwrap().dx, p.pd().unwrap().m);
    p.pd_mut().regions = rustfrac_core::problem::pd_region::initial(&p, dx, m, &a);
    p
}

/// The SLA engine of the tests' `fast` switch: the cost model's choice, or the oracle
/// (refactorise every step; a scene's `pd.fast = false`).
pub fn engine(fast: bool) -> SlaEngine {
    if fast {
        SlaEngine::Auto
    } else {
        SlaEngine::Oracle
    }
}

/// A coarse version of the paper's CCM-PD plate (dx = 1/5 keeps x2 = 10.5 and x1 = 1.1 between
/// nodes), with a larger PD rectangle (4.4 x 2.4, ~600 PD dofs) so that hundreds of steps stay
/// inside it.
pub fn coarse(fast: bool, steps: usize) -> Problem {
    let mut p = Problem::paper("ccm_pd");
    let pd = p.pd_mut();
    pd.dx = 0.2;
    pd.regions = vec![[0.3, 9.3, 4.7, 11.7]];
    pd.sla = SlaParams {
        max_steps: steps,
        engine: engine(fast),
        ..SlaParams::default()
    };
    p
}

/// The paper's problem ([`Problem::paper`]: material, G0, PD rectangle, pre-crack, load, SLA
/// options) solved by `method` ("pd" or "ccm_pd") on a `width` x `height` plate with grid
/// spacing `dx` and horizon factor `m`.
pub fn pd_plate(method: &str, width: f64, height: f64, dx: f64, m: usize) -> Problem {
    let mut p = Problem::paper(method);
    p.domain = Domain::rect(width, height);
    let pd = p.pd_mut();
    pd.dx = dx;
    pd.m = m;
    p
}

/// Replaces the pre-crack of `p` by an edge crack from the left edge of length `a0` at height
/// `y` (no crack for `a0 = 0`).
pub fn set_precrack(p: &mut Problem, a0: f64, y: f64) {
    p.cracks = if a0 > 0.0 {
        vec![CrackSpec {
            kind: CrackKind::Edge,
            a0,
            y,
            angle: 0.0,
            x: 0.0,
            side: Side::Left,
        }]
    } else {
        Vec::new()
    };
}

/// A pure PD strip 1.2 x 2.2 (dx = 0.2, m = 2) with an edge pre-crack of 0.5 at mid-height: the SLA
/// cuts its ligament through (status "separated") within the 2000 steps allowed.
pub fn pd_strip(fast: bool, grip: Grip) -> Problem {
    let mut p = pd_plate("pd", 1.2, 2.2, 0.2, 2).with_grip(grip);
    set_precrack(&mut p, 0.5, 1.1);
    p.pd_mut().sla = SlaParams {
        max_steps: 2000,
        engine: engine(fast),
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
pub fn tall_strip(crack: Vec<[f64; 2]>, nx: usize, ny: usize) -> XfemCase {
    let mut p = XfemCase::paper(Grip::Traction);
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

/// Growth options of an [`XfemCase`] with the fracture energy G0 (which the problem keeps in its
/// material).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GrowthParams {
    pub g0: f64,
    pub da: Option<f64>,
    pub a_stop: f64,
    pub max_steps: usize,
}

/// An XFEM test case stated by crack polylines (straight 2-point cracks: from the left, right,
/// bottom or top edge, or interior), converted to the [`Problem`] the driver reads by
/// [`XfemCase::problem`].
#[derive(Debug, Clone)]
pub struct XfemCase {
    pub width: f64,
    pub height: f64,
    pub nx: usize,
    pub ny: usize,
    pub material: Elastic,
    pub crack: Vec<[f64; 2]>,
    pub extra_cracks: Vec<Vec<[f64; 2]>>,
    pub load: PlateLoad,
    pub nsub: usize,
    pub tip_nsub: usize,
    pub r_i_factor: f64,
    pub extra_radius_factors: Vec<f64>,
    pub fixed_area_radius: Option<f64>,
    pub area_threshold: f64,
    pub growth: Option<GrowthParams>,
    pub condition: bool,
}

impl XfemCase {
    /// The paper's case ([`Problem::paper`]("xfem")) under `grip`.
    pub fn paper(grip: Grip) -> Self {
        Self {
            width: 11.0,
            height: 21.0,
            nx: 44,
            ny: 83,
            material: Elastic {
                e: 10000.0,
                nu: 0.25,
                plane: Plane::Strain,
                thickness: 1.0,
            },
            crack: vec![[0.0, 10.5], [1.1, 10.5]],
            extra_cracks: Vec::new(),
            load: PlateLoad {
                grip,
                u0: 0.01,
                traction: 9.993,
            },
            nsub: 4,
            tip_nsub: 4,
            r_i_factor: 2.5,
            extra_radius_factors: vec![1.5, 2.0, 3.0, 3.5],
            fixed_area_radius: None,
            area_threshold: DEFAULT_AREA_THRESHOLD,
            growth: None,
            condition: true,
        }
    }

    /// The problem of this case.
    pub fn problem(&self) -> Problem {
        let mut p = Problem::paper("xfem");
        p.domain = Domain::rect(self.width, self.height);
        p.material.elastic = self.material;
        if let Some(g) = &self.growth {
            p.material.g0 = g.g0;
        }
        p.boundary = Boundary::Grips(self.load);
        p.cracks = std::iter::once(&self.crack)
            .chain(&self.extra_cracks)
            .map(|c| crack_of(c, &p.domain))
            .collect();
        let x = p.xfem_mut();
        x.grid.nx = self.nx;
        x.grid.ny = self.ny;
        x.options.nsub = self.nsub;
        x.options.tip_nsub = self.tip_nsub;
        x.options.fixed_area_radius = self.fixed_area_radius;
        x.options.area_threshold = self.area_threshold;
        x.r_i = self.r_i_factor;
        x.extra_radii = self.extra_radius_factors.clone();
        x.growth = self.growth.map(|g| Growth {
            max_steps: g.max_steps,
            da: g.da,
            a_stop: g.a_stop,
            kink_rule: rustfrac_core::problem::KinkRule::Hoop,
            state_every: 0,
        });
        x.condition = self.condition;
        p
    }
}

/// The straight crack of a 2-point polyline: an edge crack when one end lies on an edge of the
/// plate (that end is its mouth), else a centre crack. Axis-aligned edge cracks are exact.
pub fn crack_of(line: &[[f64; 2]], d: &Domain) -> CrackSpec {
    assert_eq!(line.len(), 2, "a straight crack: {line:?}");
    let (w, h) = (d.width, d.height);
    let on = |q: [f64; 2]| q[0] == 0.0 || q[0] == w || q[1] == 0.0 || q[1] == h;
    let (m, t) = if on(line[1]) && !on(line[0]) {
        (line[1], line[0])
    } else {
        (line[0], line[1])
    };
    let (dx, dy) = (t[0] - m[0], t[1] - m[1]);
    let a0 = dx.hypot(dy);
    let edge = |side, y, x, angle: f64| CrackSpec {
        kind: CrackKind::Edge,
        a0,
        y,
        angle: angle.to_degrees(),
        x,
        side,
    };
    if !on(m) {
        return CrackSpec {
            kind: CrackKind::Center,
            a0: 0.5 * a0,
            y: 0.5 * (m[1] + t[1]),
            angle: dy.atan2(dx).to_degrees(),
            x: 0.5 * (m[0] + t[0]),
            side: Side::Left,
        };
    }
    if m[0] == 0.0 {
        edge(Side::Left, m[1], 0.0, dy.atan2(dx))
    } else if m[0] == w {
        edge(Side::Right, m[1], 0.0, (-dy).atan2(-dx))
    } else if m[1] == 0.0 {
        edge(Side::Bottom, 0.0, m[0], (-dx).atan2(dy))
    } else {
        edge(Side::Top, 0.0, m[0], dx.atan2(-dy))
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

/// Runs the XFEM driver on the problem of `case`.
pub fn run(
    case: &XfemCase,
    progress: &(dyn Fn(usize, usize) -> bool + Sync),
) -> rustfrac_core::Result<rustfrac_core::xfem::XfemResult> {
    rustfrac_core::xfem::run(&case.problem(), progress)
}

/// Scene tables built in Rust, as a TOML file would state them (`Problem::from_scene`).
pub mod scene_values {
    use rustfrac_core::problem::value::{Table, Value};

    pub fn f(x: f64) -> Value {
        Value::Float(x)
    }
    pub fn s(x: &str) -> Value {
        Value::Str(x.into())
    }
    pub fn i(x: i64) -> Value {
        Value::Int(x)
    }
    pub fn pair(a: f64, b: f64) -> Value {
        Value::List(vec![f(a), f(b)])
    }
    pub fn floats(v: &[f64]) -> Value {
        Value::List(v.iter().map(|&x| f(x)).collect())
    }
    pub fn tbl(kv: &[(&str, Value)]) -> Value {
        Value::Table(kv.iter().map(|(k, v)| (k.to_string(), v.clone())).collect())
    }
    pub fn scene(kv: &[(&str, Value)]) -> Table {
        kv.iter().map(|(k, v)| (k.to_string(), v.clone())).collect()
    }

    /// The edge crack under shear (Moes et al. 1999, fig. 13): a 7 x 16 plate, an edge crack of
    /// length 3.5 at mid-height, the bottom edge fixed, a unit shear traction on the top edge,
    /// E = 3e7, nu = 0.25, plane strain.
    pub fn edge_shear(nx: i64, ny: i64) -> Table {
        scene(&[
            ("method", s("xfem")),
            ("plate", tbl(&[("width", f(7.0)), ("height", f(16.0))])),
            ("material", tbl(&[("E", f(3e7)), ("nu", f(0.25))])),
            (
                "crack",
                tbl(&[("kind", s("edge")), ("a0", f(3.5)), ("y", f(8.0))]),
            ),
            ("mesh", tbl(&[("nx", i(nx)), ("ny", i(ny))])),
            (
                "support",
                Value::List(vec![tbl(&[("region", s("edge")), ("side", s("bottom"))])]),
            ),
            (
                "load",
                Value::List(vec![tbl(&[
                    ("region", s("edge")),
                    ("side", s("top")),
                    ("shear", f(1.0)),
                ])]),
            ),
        ])
    }
}
