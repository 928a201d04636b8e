//! Peridynamics validation: gamma from exact partial areas, constants, energy density of bulk nodes,
//! pure PD model under linear fields.

use rustfrac_core::pd::analysis::run;
use rustfrac_core::pd::analysis::splice_model;
use rustfrac_core::pd::splice::SpliceModel;
use rustfrac_core::pd::{family_stencil, find_bonds, gamma, Grid, PdConstants, BYTES_PER_BOND};
use rustfrac_core::problem::Calibration;
use rustfrac_core::problem::{Domain, Problem};
use rustfrac_core::problem::{Elastic, Plane};
use rustfrac_core::Error;

#[test]
fn gamma_from_exact_partial_areas() {
    // closed-forms.md values (exact areas); the paper prints 0.988895997195466 for m = 4
    let expected = [
        (2, 0.950650952289580),
        (3, 0.978471034140134),
        (4, 0.988895997198035),
        (5, 0.993153917307724),
        (6, 0.995345123916148),
    ];
    for (m, g_ref) in expected {
        let g = gamma(m).unwrap();
        println!(
            "m = {m}: gamma = {g:.15} (reference {g_ref:.15}, diff {:.2e}), family {}",
            g - g_ref,
            family_stencil(m).len()
        );
        assert!((g - g_ref).abs() < 1e-10, "m = {m}: {g} vs {g_ref}");
    }
    let g4 = gamma(4).unwrap();
    assert!((g4 - 0.988895997195466).abs() < 1e-10);
    assert!(gamma(0).is_err());
}

/// Strain energy of node `n` from the bond list: (1/4) sum over its bonds of alpha (n . eta)^2,
/// i.e. V_n (1/2) sum_j (c s^2 |xi| / 2) beta_j V_j (eqs. 43, 54).
fn node_energy(
    consts: &PdConstants,
    grid: &Grid,
    n: usize,
    u: &dyn Fn([f64; 2]) -> [f64; 2],
) -> f64 {
    let is_pd = vec![true; grid.n_nodes()];
    let bonds = find_bonds(grid, consts.m, &is_pd).unwrap();
    let mut w = 0.0;
    for b in bonds
        .iter()
        .filter(|b| b.i as usize == n || b.j as usize == n)
    {
        let (xi, xj) = (grid.xy(b.i as usize), grid.xy(b.j as usize));
        let (ui, uj) = (u(xi), u(xj));
        let l = b.length();
        let eta_n = ((uj[0] - ui[0]) * b.xi[0] + (uj[1] - ui[1]) * b.xi[1]) / l;
        w += 0.25 * consts.bond_alpha(b) * eta_n * eta_n;
    }
    w
}

#[test]
fn bulk_energy_density_matches_continuum() {
    let mat = Elastic::new(10000.0, 0.25, Plane::Strain, 1.0).unwrap();
    let (lam, mu) = (0.4 * mat.e, 0.4 * mat.e); // nu = 1/4: lambda = mu = 0.4 E
    for m in [2usize, 3, 4, 5, 6] {
        let dx = 0.05;
        let consts = PdConstants::new(&mat, 0.367, dx, m).unwrap();
        let nx = 4 * m + 2;
        let grid = Grid::uniform(nx, nx, dx, 0.0, 0.0);
        let centre = grid.node(nx / 2, nx / 2);
        let v = consts.volume;
        // uniaxial strain along x1 and along x2: exact with gamma
        let eps = 1e-3;
        for (name, f) in [
            (
                "e11",
                Box::new(move |p: [f64; 2]| [eps * p[0], 0.0]) as Box<dyn Fn([f64; 2]) -> [f64; 2]>,
            ),
            ("e22", Box::new(move |p: [f64; 2]| [0.0, eps * p[1]])),
        ] {
            let w = node_energy(&consts, &grid, centre, &*f) / v;
            let w_ref = 0.5 * (lam + 2.0 * mu) * eps * eps;
            let rel = (w / w_ref - 1.0).abs();
            println!("m = {m} {name}: W = {w:.12e}, continuum {w_ref:.12e}, rel. error {rel:.2e}");
            assert!(rel < 1e-10, "m = {m} {name}: {rel}");
        }
        // shear and biaxial: reported (gamma is calibrated on the uniaxial mode)
        let g = 1e-3;
        let w = node_energy(&consts, &grid, centre, &move |p: [f64; 2]| [g * p[1], 0.0]) / v;
        let w_ref = 0.5 * mu * g * g;
        println!("m = {m} shear: rel. error {:.3e}", w / w_ref - 1.0);
        let w = node_energy(&consts, &grid, centre, &move |p: [f64; 2]| {
            [eps * p[0], eps * p[1]]
        }) / v;
        let w_ref = (lam + mu) * 2.0 * eps * eps;
        println!("m = {m} equibiaxial: rel. error {:.3e}", w / w_ref - 1.0);
    }
    println!("memory per bond: {BYTES_PER_BOND} bytes");
}

#[test]
fn constants_follow_eqs_47_48() {
    let mat = Elastic::new(10000.0, 0.25, Plane::Strain, 1.0).unwrap();
    let c = PdConstants::new(&mat, 0.367, 1.0 / 15.0, 4).unwrap();
    let delta = 4.0 / 15.0;
    let pi = std::f64::consts::PI;
    assert!((c.delta - delta).abs() < 1e-15);
    assert!((c.c - 48.0 * 10000.0 * c.gamma / (5.0 * pi * delta.powi(3))).abs() < 1e-6 * c.c);
    assert!((c.s0 - (5.0 * pi * 0.367 / (12.0 * 10000.0 * delta)).sqrt()).abs() < 1e-15);
    println!("paper: delta = {delta}, c = {:.6e}, s0 = {:.6e}", c.c, c.s0);
}

#[test]
fn bad_inputs_are_refused_with_reasons() {
    let mat = Elastic::new(10000.0, 0.3, Plane::Strain, 1.0).unwrap();
    match PdConstants::new(&mat, 0.367, 0.1, 4) {
        Err(Error::InvalidInput {
            param, expected, ..
        }) => {
            assert_eq!(param, "nu");
            assert!(expected.contains("1/4"), "{expected}");
        }
        other => panic!("{other:?}"),
    }
    let stress = Elastic::new(10000.0, 1.0 / 3.0, Plane::Stress, 1.0).unwrap();
    assert!(matches!(
        PdConstants::new(&stress, 0.367, 0.1, 4),
        Err(Error::InvalidInput { .. })
    ));
    let ok = Elastic::new(10000.0, 0.25, Plane::Strain, 1.0).unwrap();
    for (g0, dx, m, name) in [
        (0.0, 0.1, 4, "G0"),
        (0.3, -1.0, 4, "dx"),
        (0.3, 0.1, 0, "pd.m"),
        (0.3, 0.1, 13, "pd.m"),
        (f64::NAN, 0.1, 4, "G0"),
    ] {
        match PdConstants::new(&ok, g0, dx, m) {
            Err(Error::InvalidInput { param, .. }) => assert_eq!(param, name),
            other => panic!("{other:?}"),
        }
    }
    let base = Problem::paper("ccm_pd");
    let check = |p: Problem, name: &str| match run(&p, &|_, _| true) {
        Err(Error::InvalidInput { param, .. }) => assert_eq!(param, name),
        other => panic!("{name}: {:?}", other.map(|r| r.run.status)),
    };
    let mut p = base.clone();
    p.pd_mut().dx = 0.07; // does not fit W = 11
    check(p, "pd.dx");
    let mut p = base.clone();
    (p.cracks[0].a0, p.cracks[0].y) = (1.0, 10.0); // along a node row
    check(p, "crack.y");
    let mut p = base.clone();
    p.pd_mut().regions = vec![[3.0, 1.0, 2.0, 2.0]];
    check(p, "pd.size");
    let mut p = base.clone();
    p.pd_mut().sla.tie_tol = -1.0;
    check(p, "pd.tie_tol");
    let mut p = base.clone();
    p.material.elastic.nu = 0.3;
    check(p, "material.nu");
    let mut p = base;
    p.pd_mut().regions.clear();
    check(p, "pd.size");
    // a hand-made pre-crack of one point is refused by the model
    let mut p = Problem::paper("pd");
    p.domain = Domain::rect(1.0, 1.0);
    p.cracks.clear();
    p.pd_mut().dx = 0.1;
    p.material.g0 = 0.3;
    assert!(splice_model(&p).is_ok());
    assert!(SpliceModel::with_precrack(&p, vec![[0.0, 0.55]], Calibration::continuum()).is_err());
}
