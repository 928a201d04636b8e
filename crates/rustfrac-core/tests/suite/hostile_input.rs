//! Hostile input to the Rust entry points (property tests, proptest): constructors and drivers
//! get random values (NaN, infinities, zero, negative, subnormal, huge, tiny), random sizes and
//! random crack geometry. None may panic; each either succeeds with finite results or returns an
//! [`Error`] (a refusal of bad input names the parameter and its range). The sparse solvers get
//! random SPD matrices (solved to a small residual) and random singular ones (an error, never
//! NaN). Case counts are kept small so the whole file runs in a few seconds in release mode.

use crate::common;
use rustfrac_core::problem::Calibration;

use common::{go_on, pd_plate, quiet};
use common::{GrowthParams, XfemCase};
use proptest::prelude::*;
use rustfrac_core::error::{Error, MAG_MAX, MAG_MIN};
use rustfrac_core::fe::mesh::Mesh;
use rustfrac_core::fem_driver;
use rustfrac_core::la::CscMatrix;
use rustfrac_core::la::{Cholesky, Lu};
use rustfrac_core::pd::sla;
use rustfrac_core::pd::splice::SpliceModel;
use rustfrac_core::pd::PdConstants;
use rustfrac_core::problem::MAX_ELEMENTS;
use rustfrac_core::problem::{Boundary, Domain, FeGrid, Problem, SlaParams};
use rustfrac_core::problem::{Elastic, Plane};
use rustfrac_core::problem::{Grip, PlateLoad};
use rustfrac_core::xfem::XfemOptions;
use rustfrac_core::WarningKind;
use std::sync::atomic::{AtomicUsize, Ordering};

/// Successful runs per driver test: each must also exercise its valid path, not only refusals.
static XFEM_OK: AtomicUsize = AtomicUsize::new(0);
static PD_OK: AtomicUsize = AtomicUsize::new(0);
static FEM_OK: AtomicUsize = AtomicUsize::new(0);

/// Any f64, with the awkward values over-represented.
fn wild() -> impl Strategy<Value = f64> {
    prop_oneof![
        3 => any::<f64>(),
        1 => Just(f64::NAN),
        1 => Just(f64::INFINITY),
        1 => Just(f64::NEG_INFINITY),
        1 => Just(0.0),
        1 => Just(-0.0),
        1 => Just(5e-324),
        1 => Just(f64::MAX),
        2 => -1e3..1e3f64,
        2 => 1e-12..1e12f64,
    ]
}

/// Mostly a valid value from `ok`, sometimes anything: so that the drivers' valid paths run too
/// (each of their ~10 parameters is bad in 1 case out of 8).
fn mostly(ok: std::ops::Range<f64>) -> impl Strategy<Value = f64> {
    prop_oneof![7 => ok, 1 => wild()]
}

fn plane() -> impl Strategy<Value = Plane> {
    prop_oneof![Just(Plane::Strain), Just(Plane::Stress)]
}

fn grip() -> impl Strategy<Value = Grip> {
    prop_oneof![Just(Grip::Free), Just(Grip::Clamped), Just(Grip::Traction)]
}

/// A refusal of bad input: `InvalidInput` naming one of `params`, with its valid range.
fn refused_naming(e: &Error, params: &[&str]) -> bool {
    match e {
        Error::InvalidInput {
            param, expected, ..
        } => params.iter().any(|p| param == p) && !expected.is_empty(),
        _ => false,
    }
}

/// A dimensional value the core accepts: finite, within [MAG_MIN, MAG_MAX].
fn mag(v: f64) -> bool {
    (MAG_MIN..=MAG_MAX).contains(&v)
}

fn valid_material(e: f64, nu: f64, t: f64) -> bool {
    mag(e) && nu.is_finite() && nu > -1.0 && nu < 0.5 && mag(t)
}

fn all_finite(v: &[f64]) -> bool {
    v.iter().all(|x| x.is_finite())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, failure_persistence: None, ..ProptestConfig::default() })]

    /// E, nu, thickness: accepted exactly on E > 0, -1 < nu < 0.5, h > 0 (all finite).
    #[test]
    fn elastic_accepts_exactly_the_valid_range(e in wild(), nu in wild(), t in wild(), p in plane()) {
        match Elastic::new(e, nu, p, t) {
            Ok(m) => {
                prop_assert!(valid_material(e, nu, t));
                prop_assert!(m.d_matrix().iter().flatten().all(|v| v.is_finite()));
            }
            Err(err) => {
                prop_assert!(!valid_material(e, nu, t));
                prop_assert!(refused_naming(&err, &["E", "nu", "thickness"]), "{err}");
                let msg = err.to_string();
                prop_assert!(msg.contains("expected"), "{msg}");
            }
        }
    }

    /// Grids: refused (quickly, before allocating) beyond MAX_ELEMENTS; otherwise consistent.
    #[test]
    fn mesh_uniform_refuses_or_builds(
        x0 in wild(), y0 in wild(), w in wild(), h in wild(),
        nx in prop_oneof![0usize..40, Just(usize::MAX), 1000usize..5000],
        ny in prop_oneof![0usize..40, Just(usize::MAX / 2), 1000usize..5000],
    ) {
        match Mesh::uniform(x0, y0, w, h, nx, ny) {
            Ok(m) => {
                prop_assert!(nx >= 1 && ny >= 1 && nx * ny <= MAX_ELEMENTS);
                prop_assert_eq!(m.n_elements(), nx * ny);
                prop_assert!(m.coords.iter().all(|c| c[0].is_finite() && c[1].is_finite()));
                prop_assert!(m.xs.windows(2).all(|v| v[1] > v[0]));
            }
            Err(err) => prop_assert!(
                refused_naming(&err, &["x0", "y0", "width", "height", "nx", "ny", "nx * ny", "xs", "ys"]),
                "{err}"
            ),
        }
    }

    #[test]
    fn xfem_options_validate(nsub in 0usize..70, tip in 0usize..70, r in prop::option::of(wild()), t in wild()) {
        let o = XfemOptions { nsub, tip_nsub: tip, fixed_area_radius: r, area_threshold: t };
        let ok = (1..=32).contains(&nsub)
            && (nsub..=64).contains(&tip)
            // the scene's rule: 0 means off (Some(0.0) enriches no node beyond the tip element's)
            && r.is_none_or(|v| v == 0.0 || mag(v))
            && (0.0..0.5).contains(&t);
        match o.validate() {
            Ok(()) => prop_assert!(ok),
            Err(err) => {
                prop_assert!(!ok);
                prop_assert!(refused_naming(&err, &["xfem.nsub", "xfem.tip_nsub", "xfem.fixed_area_radius", "xfem.area_threshold"]), "{err}");
            }
        }
    }

    #[test]
    fn pd_constants_validate(e in wild(), nu in prop_oneof![Just(0.25), wild()], t in wild(), g0 in wild(), dx in wild(), m in 0usize..16) {
        let mat = Elastic { e, nu, plane: Plane::Strain, thickness: t };
        match PdConstants::new(&mat, g0, dx, m) {
            Ok(c) => {
                prop_assert!(valid_material(e, nu, t) && nu == 0.25 && mag(g0) && mag(dx));
                for v in [c.s0, c.c, c.gamma, c.volume] {
                    prop_assert!(v.is_finite() && v > 0.0, "{v}");
                }
            }
            Err(err) => prop_assert!(refused_naming(&err, &["E", "nu", "thickness", "G0", "dx", "m"]), "{err}"),
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, failure_persistence: None, ..ProptestConfig::default() })]

    /// The FEM plate driver with a material built literally (bypassing `Elastic::new`): bad
    /// values are refused naming their scene key, good ones give finite results.
    #[test]
    fn fem_plate_refuses_or_is_finite(
        e in mostly(1e-3..1e6), nu in mostly(-0.99..0.4999), t in mostly(0.1..10.0), p in plane(),
        g in grip(), u0 in mostly(-1.0..1.0), tr in mostly(-10.0..10.0), w in mostly(0.5..20.0),
        nx in 1usize..8, ny in 1usize..8,
        seam in prop::option::of((mostly(0.05..0.5), mostly(0.1..1.9))), gauss in 0usize..7,
    ) {
        let mut problem = Problem::paper("fem");
        problem.domain = Domain::rect(w, 2.0);
        problem.fem_mut().grid = FeGrid::uniform(nx, ny);
        problem.fem_mut().gauss = gauss;
        problem.material.elastic = Elastic { e, nu, plane: p, thickness: t };
        problem.boundary = Boundary::Grips(PlateLoad { grip: g, u0, traction: tr });
        match seam {
            Some((a, y)) => (problem.cracks[0].a0, problem.cracks[0].y) = (a, y),
            None => problem.cracks.clear(),
        }
        match fem_driver::run(&problem) {
            Ok(r) => {
                prop_assert!(valid_material(e, nu, t));
                prop_assert!(r.sigma22.is_finite() && r.cmod.is_finite(), "{} {}", r.sigma22, r.cmod);
                prop_assert!(all_finite(&r.u) && all_finite(&r.reactions));
                // the locking warning exactly when it applies (a condition warning may come too)
                let locking = r.warnings.iter().any(|w| w.kind == WarningKind::Locking && w.message.contains("nearly incompressible"));
                prop_assert_eq!(locking, p == Plane::Strain && nu >= 0.49, "{:?}", r.warnings);
                FEM_OK.fetch_add(1, Ordering::Relaxed);
            }
            Err(err) => prop_assert!(
                refused_naming(&err, &[
                    "plate.width", "material.E", "material.nu", "material.thickness", "load.u0",
                    "load.traction", "crack.a0", "crack.y", "mesh.gauss",
                ]) || matches!(err, Error::Singular { .. } | Error::NotPositiveDefinite { .. }),
                "{err}"
            ),
        }
    }

    /// XFEM on small meshes with random cracks, materials, loads and options.
    #[test]
    fn xfem_refuses_or_is_finite(
        e in mostly(1.0..1e4), nu in mostly(-0.9..0.4999),
        g in grip(), u0 in mostly(-1.0..1.0), tr in mostly(-10.0..10.0),
        nx in 3usize..12, ny in 3usize..12,
        // a straight edge crack from the left edge (or, with `interior`, a centre crack without
        // its mouth point): the problem states straight cracks
        y0 in mostly(0.5..1.5), a in mostly(0.3..1.2), dy in mostly(-0.4..0.4), interior in any::<bool>(),
        nsub in prop_oneof![6 => 1usize..5, 1 => Just(0usize), 1 => 33usize..40], rif in mostly(0.5..2.0),
        growth in prop::option::of((mostly(1e-3..1.0), prop::option::of(mostly(0.05..0.5)), mostly(0.5..1.6), prop_oneof![6 => 1usize..3, 1 => Just(0usize)])),
    ) {
        let pts = [(if interior { 0.4 } else { 0.0 }, y0), (a, y0 + dy)];
        let mut p = XfemCase::paper(g);
        p.width = 2.0;
        p.height = 2.0;
        p.nx = nx;
        p.ny = ny;
        p.material = Elastic { e, nu, plane: Plane::Strain, thickness: 1.0 };
        p.load.u0 = u0;
        p.load.traction = tr;
        p.crack = pts.iter().map(|&(x, y)| [x, y]).collect();
        p.nsub = nsub;
        p.tip_nsub = nsub;
        p.r_i_factor = rif;
        p.extra_radius_factors = vec![];
        p.growth = growth.map(|(g0, da, a_stop, max_steps)| GrowthParams { g0, da, a_stop, max_steps });
        match common::run(&p, &quiet) {
            Ok(r) => {
                prop_assert!(valid_material(e, nu, 1.0));
                for v in [r.k_i, r.k_ii, r.j_domain, r.sigma22, r.cmod] {
                    prop_assert!(v.is_finite(), "{v}");
                }
                prop_assert!(all_finite(&r.u));
                for h in &r.history {
                    prop_assert!(h.lambda.is_finite() && h.cmod.is_finite() && h.k_i.is_finite());
                }
                XFEM_OK.fetch_add(1, Ordering::Relaxed);
            }
            Err(err) => prop_assert!(
                matches!(err, Error::InvalidInput { .. } | Error::Singular { .. } | Error::NotPositiveDefinite { .. } | Error::OutOfMemory { .. }),
                "{err}"
            ),
        }
    }

    /// CCM-PD / PD on small grids with random material, pre-crack, PD rectangle and SLA options.
    #[test]
    fn ccm_pd_refuses_or_is_finite(
        pd_all in any::<bool>(), e in mostly(1.0..1e4),
        nu in prop_oneof![7 => Just(0.25), 1 => wild()], g0 in mostly(1e-3..1.0),
        dx in prop_oneof![7 => Just(0.25), 1 => wild()], m in 1usize..6, g in grip(),
        u0 in mostly(-0.1..0.1),
        // a pre-crack along x2 = 1.125 (midway between node rows) of random length, or garbage
        a in mostly(0.3..1.6), garbage in prop::collection::vec((wild(), wild()), 0..3),
        region in (mostly(0.0..0.4), mostly(0.2..0.7), mostly(1.8..3.0), mostly(1.6..2.5)),
        steps in 0usize..4, tie in prop_oneof![7 => Just(0.0), 1 => wild()],
        stop in prop::option::of(mostly(0.5..2.0)),
    ) {
        let region = [region.0, region.1, region.2, region.3];
        let method = if pd_all { "pd" } else { "ccm_pd" };
        let mut p = pd_plate(method, 3.0, 2.5, dx, m);
        p.material.elastic = Elastic { e, nu, plane: Plane::Strain, thickness: 1.0 };
        p.material.g0 = g0;
        p.load_mut().grip = g;
        p.load_mut().u0 = u0;
        p.load_mut().traction = u0;
        (p.cracks[0].a0, p.cracks[0].y) = (a, 1.125);
        if !pd_all {
            p.pd_mut().regions = vec![region];
        }
        p.pd_mut().sla = SlaParams { max_steps: steps, tie_tol: tie, stop_crack_length: stop, ..SlaParams::default() };
        // the problem's straight pre-crack, or a garbage polyline through the model-level API
        let run = if garbage.is_empty() {
            rustfrac_core::pd::analysis::run(&p, &go_on)
        } else {
            let crack = garbage.iter().map(|&(x, y)| [x, y]).collect();
            SpliceModel::with_precrack(&p, crack, Calibration::continuum()).and_then(|model| sla::run_model(&model, &go_on))
        };
        match run {
            Ok(r) => {
                prop_assert!(valid_material(e, nu, 1.0) && nu == 0.25);
                prop_assert!(r.reference.sigma22.is_finite() && r.reference.cmod.is_finite());
                prop_assert!(all_finite(&r.reference.u) && all_finite(&r.final_state.damage));
                for h in &r.history {
                    prop_assert!(h.lambda.is_finite() && h.sigma22.is_finite() && h.cmod.is_finite());
                }
                PD_OK.fetch_add(1, Ordering::Relaxed);
            }
            Err(err) => prop_assert!(
                matches!(err, Error::InvalidInput { .. } | Error::Singular { .. } | Error::Separated { .. } | Error::NotPositiveDefinite { .. } | Error::OutOfMemory { .. }),
                "{err}"
            ),
        }
    }
}

// ---------------------------------------------------------------------------------------------
// solvers

/// Dense n x n matrix as CSC (entries below `drop` in magnitude left out).
fn csc(n: usize, a: &[f64]) -> CscMatrix {
    let mut t = Vec::new();
    for c in 0..n {
        for r in 0..n {
            if a[r * n + c] != 0.0 {
                t.push((r, c, a[r * n + c]));
            }
        }
    }
    CscMatrix::from_triplets(n, n, &t).unwrap()
}

/// B B^T (n x n) for B n x k with small integer entries (exact in floating point), times `scale`.
fn gram(n: usize, k: usize, b: &[i8], scale: f64) -> Vec<f64> {
    let mut a = vec![0.0; n * n];
    for i in 0..n {
        for j in 0..n {
            let s: i32 = (0..k)
                .map(|l| b[i * k + l] as i32 * b[j * k + l] as i32)
                .sum();
            a[i * n + j] = s as f64 * scale;
        }
    }
    a
}

fn residual(n: usize, a: &[f64], x: &[f64], b: &[f64]) -> f64 {
    let mut r: f64 = 0.0;
    let mut s: f64 = 0.0;
    for i in 0..n {
        let ax: f64 = (0..n).map(|j| a[i * n + j] * x[j]).sum();
        r = r.max((ax - b[i]).abs());
        s = s.max((0..n).map(|j| (a[i * n + j] * x[j]).abs()).sum::<f64>() + b[i].abs());
    }
    r / s
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 200, failure_persistence: None, ..ProptestConfig::default() })]

    /// SPD matrices of any scale (1e-200 .. 1e200): both solvers succeed, residual ~ round-off.
    #[test]
    fn spd_matrices_solve(n in 1usize..25, seed in prop::collection::vec(-3i8..=3, 25 * 25), exp in -200i32..200) {
        let scale = 10f64.powi(exp);
        let mut a = gram(n, n, &seed, scale);
        for i in 0..n {
            a[i * n + i] += scale; // B B^T + I: SPD with a bounded condition number
        }
        let b: Vec<f64> = (0..n).map(|i| (i as f64 + 1.0) * scale).collect();
        let m = csc(n, &a);
        let x = Cholesky::new(&m).and_then(|c| c.solve(&b));
        prop_assert!(x.is_ok(), "{:?}", x.err());
        let x = x.unwrap();
        prop_assert!(residual(n, &a, &x, &b) < 1e-10, "Cholesky residual {}", residual(n, &a, &x, &b));
        let y = Lu::new(&m).and_then(|l| l.solve(&b)).unwrap();
        prop_assert!(residual(n, &a, &y, &b) < 1e-10, "LU residual {}", residual(n, &a, &y, &b));
    }

    /// A zero row and column (an unconstrained dof, a node cut loose) in an otherwise SPD matrix
    /// of any scale: both solvers report it, never NaN.
    #[test]
    fn structurally_singular_matrices_are_reported(n in 2usize..20, seed in prop::collection::vec(-3i8..=3, 20 * 20), exp in -200i32..200, z in 0usize..20) {
        let scale = 10f64.powi(exp);
        let mut a = gram(n, n, &seed, scale);
        for i in 0..n {
            a[i * n + i] += scale;
        }
        let z = z % n;
        for j in 0..n {
            a[z * n + j] = 0.0;
            a[j * n + z] = 0.0;
        }
        let m = csc(n, &a);
        let b: Vec<f64> = (0..n).map(|i| ((i * 7 % 5) as f64 - 2.0) * scale).collect();
        let e = Cholesky::new(&m).and_then(|c| c.solve(&b)).err();
        prop_assert!(matches!(e, Some(Error::Singular { .. } | Error::NotPositiveDefinite { .. })), "{e:?}");
        let e = Lu::new(&m).and_then(|l| l.solve(&b)).err();
        prop_assert!(matches!(e, Some(Error::Singular { .. })), "{e:?}");
    }

    /// Rank-deficient B B^T (exact integer entries) at any scale. Round-off turns the zero pivots
    /// into tiny ones, and when one of them lands above the relative threshold
    /// (solver::PIVOT_TOL x max diagonal) the matrix is merely very ill-conditioned to the
    /// solvers: then the solution must still be finite and backward stable (a small residual);
    /// otherwise the error is reported. Never NaN.
    #[test]
    fn rank_deficient_matrices_error_or_backward_stable(n in 2usize..20, rank_def in 1usize..4, seed in prop::collection::vec(-3i8..=3, 20 * 20), exp in -200i32..200) {
        let scale = 10f64.powi(exp);
        let k = n.saturating_sub(rank_def).clamp(1, n - 1);
        let a = gram(n, k, &seed, scale);
        let m = csc(n, &a);
        let b: Vec<f64> = (0..n).map(|i| ((i * 7 % 5) as f64 - 2.0) * scale).collect();
        match Cholesky::new(&m).and_then(|c| c.solve(&b)) {
            Ok(x) => prop_assert!(all_finite(&x) && residual(n, &a, &x, &b) < 1e-8, "Cholesky: residual {}", residual(n, &a, &x, &b)),
            Err(e) => prop_assert!(matches!(e, Error::Singular { .. } | Error::NotPositiveDefinite { .. }), "{e}"),
        }
        match Lu::new(&m).and_then(|l| l.solve(&b)) {
            Ok(x) => prop_assert!(all_finite(&x) && residual(n, &a, &x, &b) < 1e-8, "LU: residual {}", residual(n, &a, &x, &b)),
            Err(e) => prop_assert!(matches!(e, Error::Singular { .. }), "{e}"),
        }
    }

    /// Non-finite entries are refused by name before any factorisation.
    #[test]
    fn non_finite_entries_refused(n in 1usize..6, bad in prop_oneof![Just(f64::NAN), Just(f64::INFINITY), Just(f64::NEG_INFINITY)], at in 0usize..36) {
        let mut a = vec![0.0; n * n];
        for i in 0..n {
            a[i * n + i] = 1.0;
        }
        a[at % (n * n)] = bad;
        let m = csc(n, &a);
        let e = Cholesky::new(&m).err().unwrap();
        prop_assert!(refused_naming(&e, &["matrix entry"]), "{e}");
        let e = Lu::new(&m).err().unwrap();
        prop_assert!(refused_naming(&e, &["matrix entry"]), "{e}");
    }
}

/// The extremes of the accepted ranges together (E = 1e30, h = 1e-30, u0 = 1e-30, nu = 0.4999)
/// still give finite results, with the locking warning. (It also prints how many random driver
/// cases ran their valid path, when run after them: `--test-threads=1 --nocapture`.)
#[test]
fn zz_extreme_valid_fem_case_is_finite_and_warns() {
    let mut p = Problem::paper("fem");
    p.domain = Domain::rect(2.0, 2.0);
    p.fem_mut().grid = FeGrid::uniform(4, 4);
    p.material.elastic = Elastic::new(1e30, 0.4999, Plane::Strain, 1e-30).unwrap();
    p.boundary = Boundary::Grips(PlateLoad {
        grip: Grip::Clamped,
        u0: 1e-30,
        traction: 0.0,
    });
    (p.cracks[0].a0, p.cracks[0].y) = (1.0, 1.0);
    let r = fem_driver::run(&p).unwrap();
    assert!(r.sigma22.is_finite() && r.cmod.is_finite() && r.sigma22 > 0.0);
    assert_eq!(r.warnings.len(), 1, "locking warning expected");
    eprintln!(
        "valid runs so far: FEM {}, XFEM {}, CCM-PD {}",
        FEM_OK.load(Ordering::Relaxed),
        XFEM_OK.load(Ordering::Relaxed),
        PD_OK.load(Ordering::Relaxed)
    );
}
