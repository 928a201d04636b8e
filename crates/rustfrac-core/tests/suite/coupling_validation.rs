//! Splice coupling patch tests: rigid motions give zero internal forces, a uniform strain imposed on
//! the outer boundary is reproduced everywhere, a linear strain field (error reported), and the
//! non-symmetry of the splice matrix.

use rustfrac_core::la::Lu;
use rustfrac_core::la::Reduction;
use rustfrac_core::pd::analysis::splice_model;
use rustfrac_core::pd::splice::SpliceModel;
use rustfrac_core::problem::{Domain, Problem};

/// A 3 x 3 uncracked plate, dx = 0.1, with the PD rectangle [1.0, 2.05] x [0.9, 2.1] ("ccm_pd")
/// or PD everywhere ("pd"); the paper's material (E = 10000, nu = 0.25, plane strain).
fn spec(method: &str) -> Problem {
    let mut p = Problem::paper(method);
    p.domain = Domain::rect(3.0, 3.0);
    p.cracks.clear();
    let pd = p.pd_mut();
    pd.dx = 0.1;
    if method == "ccm_pd" {
        pd.regions = vec![[1.0, 0.9, 2.05, 2.1]];
    }
    p
}

fn inf(v: &[f64]) -> f64 {
    v.iter().fold(0.0, |a, b| a.max(b.abs()))
}

#[test]
fn rigid_motions_give_zero_internal_forces() {
    let model = splice_model(&spec("ccm_pd")).unwrap();
    let k = model.assemble(&model.precrack_broken);
    let kmax = inf(&k.val);
    println!("splice matrix asymmetry measure: {:.3e}", k.asymmetry());
    assert!(
        k.asymmetry() > 1e-6,
        "the splice matrix must not be symmetric"
    );
    let nn = model.grid.n_nodes();
    for (name, field) in [
        (
            "translation x",
            Box::new(|_: [f64; 2]| [1.0, 0.0]) as Box<dyn Fn([f64; 2]) -> [f64; 2]>,
        ),
        ("translation y", Box::new(|_: [f64; 2]| [0.0, 1.0])),
        (
            "rotation",
            Box::new(|p: [f64; 2]| [-(p[1] - 1.5), p[0] - 1.5]),
        ),
    ] {
        let mut u = vec![0.0; 2 * nn];
        for n in 0..nn {
            let v = field(model.grid.xy(n));
            u[2 * n] = v[0];
            u[2 * n + 1] = v[1];
        }
        let f = k.matvec(&u);
        let rel = inf(&f) / (kmax * inf(&u));
        println!("{name}: max |K u| / (max|K| max|u|) = {rel:.2e}");
        assert!(rel < 1e-12, "{name}: {rel}");
    }
}

/// Imposes `field` on every node within `layer` of the outer boundary and solves the splice system.
fn solve_with_boundary_field(
    model: &SpliceModel,
    layer: f64,
    field: &dyn Fn([f64; 2]) -> [f64; 2],
) -> (Vec<f64>, Vec<f64>) {
    let k = model.assemble(&model.precrack_broken);
    let nn = model.grid.n_nodes();
    let (w, h) = (model.problem.domain.width, model.problem.domain.height);
    let mut mask = vec![false; 2 * nn];
    let mut up = vec![0.0; 2 * nn];
    let mut exact = vec![0.0; 2 * nn];
    for n in 0..nn {
        let p = model.grid.xy(n);
        let v = field(p);
        exact[2 * n] = v[0];
        exact[2 * n + 1] = v[1];
        let d = p[0].min(w - p[0]).min(p[1]).min(h - p[1]);
        if d < layer {
            mask[2 * n] = true;
            mask[2 * n + 1] = true;
            up[2 * n] = v[0];
            up[2 * n + 1] = v[1];
        }
    }
    let red = Reduction::new(&k, &mask).unwrap();
    let lu = Lu::new(&red.reduce(&k)).unwrap();
    let rhs = red.rhs(&k, &vec![0.0; 2 * nn], &up);
    let uf = lu.solve(&rhs).unwrap();
    (red.expand(&uf, &up), exact)
}

#[test]
fn uniform_strain_reproduced_everywhere() {
    let model = splice_model(&spec("ccm_pd")).unwrap();
    let (e11, e22, e12) = (1e-3, -4e-4, 2.5e-4);
    let field = move |p: [f64; 2]| [e11 * p[0] + e12 * p[1], e12 * p[0] + e22 * p[1]];
    // FEM outside: the outer boundary nodes only
    let (u, ex) = solve_with_boundary_field(&model, 1e-9, &field);
    let err: Vec<f64> = u.iter().zip(&ex).map(|(a, b)| a - b).collect();
    let rel = inf(&err) / inf(&ex);
    println!(
        "coupled model ({} PD nodes): uniform strain, max relative error {rel:.2e}",
        model.pd_nodes.len()
    );
    assert!(rel < 1e-10, "{rel}");
}

#[test]
fn linear_strain_field_error_reported() {
    // u = a (x^2 - y^2, -2 x y): divergence-free and harmonic, so it is an elastic solution without
    // body force for any nu, with a strain field linear in x and y
    let model = splice_model(&spec("ccm_pd")).unwrap();
    let a = 1e-3;
    let field = move |p: [f64; 2]| {
        let (x, y) = (p[0] - 1.5, p[1] - 1.5);
        [a * (x * x - y * y), -2.0 * a * x * y]
    };
    let (u, ex) = solve_with_boundary_field(&model, 1e-9, &field);
    let err: Vec<f64> = u.iter().zip(&ex).map(|(a, b)| a - b).collect();
    let rel = inf(&err) / inf(&ex);
    let pd_err = model
        .pd_nodes
        .iter()
        .map(|&n| (err[2 * n].abs()).max(err[2 * n + 1].abs()))
        .fold(0.0, f64::max);
    println!(
        "coupled model: linear strain field, max relative displacement error {rel:.3e} (max over PD nodes {:.3e} of max |u| {:.3e})",
        pd_err,
        inf(&ex)
    );
    // not exact (Q4 and the PD sum both approximate a quadratic field) but small
    assert!(rel < 1e-2, "{rel}");
}

#[test]
fn pure_pd_reproduces_linear_fields_with_volumetric_layers() {
    // every node PD; the field is imposed on a boundary layer of thickness delta, so every free
    // node has its full family and the linear field is the exact discrete solution
    let model = splice_model(&spec("pd")).unwrap();
    let delta = model.pd.delta;
    let (e11, e22, e12) = (1e-3, -4e-4, 2.5e-4);
    let field = move |p: [f64; 2]| [e11 * p[0] + e12 * p[1] + 0.1, e12 * p[0] + e22 * p[1] - 0.2];
    let (u, ex) = solve_with_boundary_field(&model, delta - 1e-9, &field);
    let err: Vec<f64> = u.iter().zip(&ex).map(|(a, b)| a - b).collect();
    let rel = inf(&err) / inf(&ex);
    println!(
        "pure PD model ({} nodes, layer {delta}): linear field, max relative error {rel:.2e}",
        model.pd_nodes.len()
    );
    assert!(rel < 1e-10, "{rel}");
}
