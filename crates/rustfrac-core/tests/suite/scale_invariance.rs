//! Scale invariance: the models hold no hidden absolute tolerance. The paper's plate is run with
//! every length multiplied by `l` (plate, crack, mesh or PD grid, grip displacement u0 = 0.01 l,
//! thickness), Young's modulus multiplied by `e`, and G0 by `e l` (so that K_Ic / K_ref and s0 do not
//! change), for l from 1e-6 to 1e3 and e from 1e-6 to 1e12. Linear elasticity and LEFM then predict
//! the same dimensionless results:
//!
//! - sigma22 / E, CMOD / l, u0 / l, K / (E sqrt(l)), the crack path / l and the kink angles;
//! - the critical load factor lambda = K_Ic / K_eq(ref) = sqrt(G0 E') / K_eq (XFEM growth) and
//!   lambda = s0 / s_max (SLA), with s0 = sqrt(5 pi G0 / (12 E delta)) (eq. 48);
//! - the same bond breaking first and the same sequence of broken bonds in the SLA.
//!
//! Each is compared with the unit-scale run to 1e-9 relative (to the quantity's natural size:
//! K_II against K_I, the crack path against the plate size). A separate test checks the G0 law:
//! multiplying G0 alone by g multiplies every critical load factor by sqrt(g) and keeps the path.

use crate::common;

use common::{go_on, grips, quiet, solve_fem_plate};
use common::{GrowthParams, XfemCase};
use rustfrac_core::fe::loading::sigma22;
use rustfrac_core::fe::mesh::Mesh;
use rustfrac_core::fe::FemModel;
use rustfrac_core::fem_driver::{self, FemPlateResult};
use rustfrac_core::pd::analysis;
use rustfrac_core::problem::{Boundary, Domain, Problem, SlaParams};
use rustfrac_core::problem::{Elastic, Plane};
use rustfrac_core::problem::{Grip, PlateLoad};

const TOL: f64 = 1e-9;

/// (length scale l, modulus scale e, thickness): the extremes of the requested ranges, mixed.
const SCALES: [(f64, f64, f64); 6] = [
    (1e-6, 1e-6, 1.0),
    (1e-6, 1e12, 1e-6),
    (1e3, 1e-6, 1e3),
    (1e3, 1e12, 1.0),
    (1e-3, 1e6, 1e-3),
    (37.0, 3.3e-4, 0.01),
];

/// |got - want| <= TOL * size, with `size` the natural magnitude of the quantity.
fn check(what: &str, got: f64, want: f64, size: f64, worst: &mut f64) {
    let rel = (got - want).abs() / size.abs();
    assert!(
        got.is_finite() && rel <= TOL,
        "{what}: {got:.17e} vs {want:.17e} (relative {rel:.2e} > {TOL:e})"
    );
    *worst = worst.max(rel);
}

/// sigma22 / E and CMOD / l of a scaled run against the unit run's.
fn check_sigma_cmod(tag: &str, got: [f64; 2], want: [f64; 2], e: f64, l: f64, worst: &mut f64) {
    check(
        &format!("{tag} sigma22/E"),
        got[0] / e,
        want[0],
        want[0],
        worst,
    );
    check(
        &format!("{tag} CMOD/l"),
        got[1] / l,
        want[1],
        want[1],
        worst,
    );
}

/// A recorded critical state [lambda, sigma22, CMOD, u0] of a scaled run against the unit run's:
/// lambda itself, sigma22 / E, CMOD / l and u0 / l.
fn check_critical(tag: &str, got: [f64; 4], want: [f64; 4], e: f64, l: f64, worst: &mut f64) {
    check(&format!("{tag} lambda"), got[0], want[0], want[0], worst);
    check_sigma_cmod(tag, [got[1], got[2]], [want[1], want[2]], e, l, worst);
    let u0_size = want[3].abs().max(1e-300);
    check(&format!("{tag} u0/l"), got[3] / l, want[3], u0_size, worst);
}

fn material(e: f64, nu: f64, t: f64) -> Elastic {
    Elastic::new(1e4 * e, nu, Plane::Strain, t).unwrap()
}

// ---------------------------------------------------------------------------------------------
// FEM

fn fem_case(l: f64, e: f64, t: f64, grip: Grip) -> FemPlateResult {
    let mut p = Problem::paper("fem");
    p.domain = Domain::rect(11.0 * l, 21.0 * l);
    p.fem_mut().grid.ny = 84;
    p.material.elastic = material(e, 0.25, t);
    p.boundary = Boundary::Grips(PlateLoad {
        grip,
        u0: 0.01 * l,
        traction: 9.993 * e,
    });
    let seam = &mut p.cracks[0];
    (seam.a0, seam.y, seam.x) = (1.1 * l, 10.5 * l, 5.5 * l);
    fem_driver::run(&p).unwrap()
}

#[test]
fn fem_seam_crack_is_scale_invariant() {
    let mut worst = 0.0f64;
    for grip in [Grip::Free, Grip::Clamped, Grip::Traction] {
        let r0 = fem_case(1.0, 1.0, 1.0, grip);
        for &(l, e, t) in &SCALES {
            let r = fem_case(l, e, t, grip);
            let tag = format!("FEM {grip:?} l={l:e} e={e:e} t={t:e}");
            let (got, want) = ([r.sigma22, r.cmod], [r0.sigma22, r0.cmod]);
            check_sigma_cmod(&tag, got, want, e, l, &mut worst);
            // the stress field sigma22 / E at every Gauss point, against the largest
            let smax = r0
                .gauss_stress
                .iter()
                .map(|s| s[1].abs())
                .fold(0.0, f64::max);
            for (a, b) in r.gauss_stress.iter().zip(&r0.gauss_stress) {
                check(
                    &format!("{tag} gauss sigma22"),
                    a[1] / e,
                    b[1],
                    smax,
                    &mut worst,
                );
            }
            assert_eq!(
                r.seam_y.map(|y| (y / l * 1e6).round()),
                r0.seam_y.map(|y| (y * 1e6).round())
            );
        }
    }
    println!("FEM: worst relative deviation {worst:.2e}");
}

/// The uncracked plate's linear system solved directly (no plate driver): relative residual and
/// the pivot test do not depend on the units.
#[test]
fn fem_linear_system_is_scale_invariant() {
    let solve = |l: f64, e: f64| {
        let mesh = Mesh::uniform(0.0, 0.0, 11.0 * l, 21.0 * l, 11, 21).unwrap();
        let model = FemModel::new(mesh, material(e, 0.3, 1.0), 2).unwrap();
        let (edges, f, s) = solve_fem_plate(&model, &grips(Grip::Free, 0.01 * l));
        let s22 = sigma22(&edges, &s.reactions, &f, 11.0 * l, 1.0);
        (s22 / e, s.residual)
    };
    let (s0, _) = solve(1.0, 1.0);
    let exact = 1e4 / (1.0 - 0.09) * 2.0 * 0.01 / 21.0;
    assert!((s0 - exact).abs() < 1e-10 * exact);
    let mut worst = 0.0f64;
    for &(l, e, _) in &SCALES {
        let (s, res) = solve(l, e);
        check(&format!("uncracked l={l:e} e={e:e}"), s, s0, s0, &mut worst);
        assert!(res < 1e-12, "relative residual {res:e} at l={l:e} e={e:e}");
    }
}

// ---------------------------------------------------------------------------------------------
// XFEM

fn xfem_params(l: f64, e: f64, t: f64, grip: Grip, crack: &[[f64; 2]], growth: bool) -> XfemCase {
    let mut p = XfemCase::paper(grip);
    p.width *= l;
    p.height *= l;
    p.material = material(e, 0.25, t);
    p.crack = crack.iter().map(|q| [q[0] * l, q[1] * l]).collect();
    p.load.u0 *= l;
    p.load.traction *= e;
    p.extra_radius_factors = vec![2.0];
    if growth {
        p.growth = Some(GrowthParams {
            g0: 0.367 * e * l,
            da: None,
            a_stop: 2.4 * l,
            max_steps: 4,
        });
    }
    p
}

fn compare_xfem(
    r: &rustfrac_core::xfem::XfemResult,
    r0: &rustfrac_core::xfem::XfemResult,
    l: f64,
    e: f64,
    tag: &str,
) -> f64 {
    let mut worst = 0.0f64;
    let ks = e * l.sqrt();
    let kref = r0.k_i.hypot(r0.k_ii);
    check(&format!("{tag} K_I"), r.k_i / ks, r0.k_i, kref, &mut worst);
    check(
        &format!("{tag} K_II"),
        r.k_ii / ks,
        r0.k_ii,
        kref,
        &mut worst,
    );
    check(
        &format!("{tag} J"),
        r.j_domain / (e * l),
        r0.j_domain,
        r0.j_from_k,
        &mut worst,
    );
    let (got, want) = ([r.sigma22, r.cmod], [r0.sigma22, r0.cmod]);
    check_sigma_cmod(tag, got, want, e, l, &mut worst);
    assert_eq!(
        (r.n_heaviside_nodes, r.n_tip_nodes, r.n_dropped_nodes),
        (r0.n_heaviside_nodes, r0.n_tip_nodes, r0.n_dropped_nodes),
        "{tag}: enrichment differs"
    );
    for (a, b) in r.radii.iter().zip(&r0.radii) {
        check(
            &format!("{tag} K_I(r)"),
            a.sifs.k_i / ks,
            b.sifs.k_i,
            kref,
            &mut worst,
        );
    }
    assert_eq!(
        r.history.len(),
        r0.history.len(),
        "{tag}: growth steps differ"
    );
    assert_eq!(r.status, r0.status);
    for (k, (a, b)) in r.history.iter().zip(&r0.history).enumerate().skip(1) {
        let tag = format!("{tag} growth step {k}");
        let kb = b.k_i.hypot(b.k_ii);
        let (x, y) = (
            [a.lambda, a.sigma22, a.cmod, a.u0],
            [b.lambda, b.sigma22, b.cmod, b.u0],
        );
        check_critical(&tag, x, y, e, l, &mut worst);
        check(&format!("{tag} a"), a.a / l, b.a, b.a, &mut worst);
        check(&format!("{tag} K_I"), a.k_i / ks, b.k_i, kb, &mut worst);
        check(&format!("{tag} K_II"), a.k_ii / ks, b.k_ii, kb, &mut worst);
        check(
            &format!("{tag} kink"),
            a.kink_angle,
            b.kink_angle,
            1.0,
            &mut worst,
        );
        check(
            &format!("{tag} tip x"),
            a.tip[0] / l,
            b.tip[0],
            11.0,
            &mut worst,
        );
        check(
            &format!("{tag} tip y"),
            a.tip[1] / l,
            b.tip[1],
            11.0,
            &mut worst,
        );
    }
    assert_eq!(r.crack.len(), r0.crack.len());
    for (a, b) in r.crack.iter().zip(&r0.crack) {
        check(&format!("{tag} path x"), a[0] / l, b[0], 11.0, &mut worst);
        check(&format!("{tag} path y"), a[1] / l, b[1], 11.0, &mut worst);
    }
    worst
}

#[test]
fn xfem_single_solve_is_scale_invariant() {
    let mut worst = 0.0f64;
    // the paper's crack, midway between node rows, an inclined one cutting elements obliquely, and
    // an inclined interior crack (two tips; its CMOD is the opening at the middle)
    // an inclined interior crack (two tips; its CMOD is the opening at the middle), and on a
    // 44 x 84 mesh an inclined crack whose mouth is a node and a crack along a node row (nodes on
    // the crack: their side must not depend on the round-off of the scaled coordinates)
    let cracks: [(usize, &[[f64; 2]]); 5] = [
        (83, &[[0.0, 10.5], [1.1, 10.5]]),
        (83, &[[0.0, 10.3], [2.0, 10.9]]),
        (83, &[[4.6, 10.1], [6.4, 10.7]]),
        (84, &[[0.0, 10.5], [2.0, 11.0]]),
        (84, &[[0.0, 10.5], [1.1, 10.5]]),
    ];
    for grip in [Grip::Free, Grip::Traction] {
        for (ny, crack) in cracks {
            let params = |l: f64, e: f64, t: f64| {
                let mut p = xfem_params(l, e, t, grip, crack, false);
                p.ny = ny;
                p
            };
            let r0 = common::run(&params(1.0, 1.0, 1.0), &quiet).unwrap();
            for &(l, e, t) in &SCALES {
                let r = common::run(&params(l, e, t), &quiet).unwrap();
                let tag = format!("XFEM {grip:?} {crack:?} l={l:e} e={e:e} t={t:e}");
                worst = worst.max(compare_xfem(&r, &r0, l, e, &tag));
            }
        }
    }
    println!("XFEM single solve: worst relative deviation {worst:.2e}");
}

#[test]
fn xfem_growth_is_scale_invariant() {
    let mut worst = 0.0f64;
    // mixed mode: the inclined crack kinks, so the path itself is compared
    let crack: &[[f64; 2]] = &[[0.0, 10.5], [1.1, 10.9]];
    let r0 = common::run(&xfem_params(1.0, 1.0, 1.0, Grip::Free, crack, true), &quiet).unwrap();
    assert_eq!(r0.history.len(), 5, "status {}", r0.status);
    for &(l, e, t) in &SCALES[..4] {
        let r = common::run(&xfem_params(l, e, t, Grip::Free, crack, true), &quiet).unwrap();
        let tag = format!("XFEM growth l={l:e} e={e:e} t={t:e}");
        worst = worst.max(compare_xfem(&r, &r0, l, e, &tag));
    }
    println!("XFEM growth: worst relative deviation {worst:.2e}");
}

/// lambda = K_Ic / K_eq = sqrt(G0 E') / K_eq: G0 times g gives lambda times sqrt(g), and the same
/// path (the kink angle depends on K_II / K_I only).
#[test]
fn xfem_critical_load_scales_with_sqrt_g0() {
    let crack: &[[f64; 2]] = &[[0.0, 10.5], [1.1, 10.9]];
    let base = xfem_params(1.0, 1.0, 1.0, Grip::Free, crack, true);
    let r0 = common::run(&base, &quiet).unwrap();
    let mut worst = 0.0f64;
    for g in [1e-8, 1e6] {
        let mut p = base.clone();
        p.growth.as_mut().unwrap().g0 *= g;
        let r = common::run(&p, &quiet).unwrap();
        assert_eq!(r.history.len(), r0.history.len());
        for (a, b) in r.history.iter().zip(&r0.history).skip(1) {
            let sg = g.sqrt();
            check("lambda", a.lambda / sg, b.lambda, b.lambda, &mut worst);
            check("cmod", a.cmod / sg, b.cmod, b.cmod, &mut worst);
            check("K_I", a.k_i / sg, b.k_i, b.k_i.hypot(b.k_ii), &mut worst);
            check("tip x", a.tip[0], b.tip[0], 11.0, &mut worst);
            check("tip y", a.tip[1], b.tip[1], 11.0, &mut worst);
        }
        // K_Ic = sqrt(G0 E') at every critical state: K_eq(lambda) = K_Ic
        let gg = base.growth.unwrap().g0 * g;
        let kic = (gg * base.material.e_prime()).sqrt();
        for h in &r.history[1..] {
            let keq = rustfrac_core::xfem::k_equivalent(h.k_i, h.k_ii);
            check("K_eq = K_Ic", keq, kic, kic, &mut worst);
        }
    }
    println!("XFEM G0 scaling: worst relative deviation {worst:.2e}");
}

// ---------------------------------------------------------------------------------------------
// CCM-PD

fn pd_params(l: f64, e: f64, t: f64, steps: usize, method: &str, grip: Grip) -> Problem {
    let mut p = Problem::paper(method).with_grip(grip);
    p.load_mut().traction = 9.993 * e;
    p.domain.width *= l;
    p.domain.height *= l;
    p.pd_mut().dx = 0.2 * l;
    p.material.elastic = material(e, 0.25, t);
    p.material.g0 = 0.367 * e * l;
    if method == "ccm_pd" {
        p.pd_mut().regions = vec![[0.3 * l, 9.3 * l, 4.7 * l, 11.7 * l]];
    }
    (p.cracks[0].a0, p.cracks[0].y) = (1.1 * l, 10.5 * l);
    p.load_mut().u0 *= l;
    if method == "pd" {
        // PD everywhere: a smaller plate (22 x 21 cells) keeps the dense condensation cheap
        p.domain.width = 4.4 * l;
        p.domain.height = 4.2 * l;
        p.cracks[0].y = 2.1 * l;
    }
    p.pd_mut().sla = SlaParams {
        max_steps: steps,
        ..SlaParams::default()
    };
    p
}

#[test]
fn ccm_pd_sla_is_scale_invariant() {
    let mut worst = 0.0f64;
    for (method, grip, scales) in [
        ("ccm_pd", Grip::Free, &SCALES[..]),
        ("ccm_pd", Grip::Traction, &SCALES[..3]),
        ("pd", Grip::Clamped, &SCALES[..2]),
    ] {
        let t0 = std::time::Instant::now();
        worst = worst.max(pd_case(method, grip, scales));
        println!("{method} {grip:?}: {:.2} s", t0.elapsed().as_secs_f64());
    }
    println!("CCM-PD / PD: worst relative deviation {worst:.2e}");
}

fn pd_case(method: &str, grip: Grip, scales: &[(f64, f64, f64)]) -> f64 {
    let steps = 12;
    let r0 = analysis::run(&pd_params(1.0, 1.0, 1.0, steps, method, grip), &go_on).unwrap();
    assert_eq!(r0.history.len(), steps);
    let mut worst = 0.0f64;
    for &(l, e, t) in scales {
        let r = analysis::run(&pd_params(l, e, t, steps, method, grip), &go_on).unwrap();
        let tag = format!("{method} {grip:?} l={l:e} e={e:e} t={t:e}");
        assert_eq!(r.run.status, r0.run.status, "{tag}");
        assert_eq!(
            r.counts.n_precrack_bonds, r0.counts.n_precrack_bonds,
            "{tag}"
        );
        assert_eq!(
            r.counts.n_removed_elements, r0.counts.n_removed_elements,
            "{tag}"
        );
        let (got, want) = (
            [r.reference.sigma22, r.reference.cmod],
            [r0.reference.sigma22, r0.reference.cmod],
        );
        check_sigma_cmod(&tag, got, want, e, l, &mut worst);
        check(
            &format!("{tag} s0"),
            r.constants.pd.s0,
            r0.constants.pd.s0,
            r0.constants.pd.s0,
            &mut worst,
        );
        check(
            &format!("{tag} gamma"),
            r.constants.pd.gamma,
            r0.constants.pd.gamma,
            r0.constants.pd.gamma,
            &mut worst,
        );
        // c = 48 E gamma / (5 pi h delta^3) (eq. 47)
        check(
            &format!("{tag} c"),
            r.constants.pd.c * t * l.powi(3) / e,
            r0.constants.pd.c,
            r0.constants.pd.c,
            &mut worst,
        );
        assert_eq!(r.history.len(), r0.history.len(), "{tag}");
        for (a, b) in r.history.iter().zip(&r0.history) {
            let tag = format!("{tag} step {}", a.step);
            assert_eq!(a.bonds, b.bonds, "{tag}: different bonds broke");
            assert_eq!(a.nodes, b.nodes, "{tag}");
            let (x, y) = (
                [a.lambda, a.sigma22, a.cmod, a.u0],
                [b.lambda, b.sigma22, b.cmod, b.u0],
            );
            check_critical(&tag, x, y, e, l, &mut worst);
            check(
                &format!("{tag} crack length"),
                a.crack_length / l,
                b.crack_length,
                b.crack_length,
                &mut worst,
            );
        }
        for (a, b) in r.final_state.damage.iter().zip(&r0.final_state.damage) {
            assert_eq!(a, b, "{tag}: damage differs");
        }
    }
    worst
}
