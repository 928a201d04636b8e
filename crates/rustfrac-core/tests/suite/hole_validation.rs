//! Holes and notches as a fictitious domain (`fe::fictitious`): Kirsch's plate with a
//! circular hole (energy-norm convergence and the hoop stress at the hole), a grid-aligned
//! rectangular hole against the same mesh with its elements removed, notches poking out of the
//! plate through the FEM driver, the small-fraction node rule against the condition estimate,
//! a domain without holes bit for bit as before; XFEM: a crack from a notch tip, a tip in or near
//! a hole refused, and an edge crack near a hole against the seam FEM.
//!
//! Run in release: `cargo test --release -p rustfrac-core --test suite hole_validation:: --
//! --nocapture` prints the measured numbers.

use rustfrac_core::fe::fictitious::{FictitiousDomain, DEFAULT_MIN_SUPPORT_FRACTION};
use rustfrac_core::fe::loading::{plate_conditions, PlateEdges};
use rustfrac_core::fe::mesh::Mesh;
use rustfrac_core::fe::{Dirichlet, ElementKind, FemModel, LinearSystem};
use rustfrac_core::fem_driver;
use rustfrac_core::problem::Side;
use rustfrac_core::problem::{CrackKind, Domain, Growth, Hole, Method, Problem, Shape};
use rustfrac_core::problem::{Elastic, Plane};
use rustfrac_core::xfem::MIN_HOLE_FREE_RADIUS;
use rustfrac_core::xfem::{self, GrowthStatus, XfemModel};
use std::sync::Arc;

/// Kirsch (1898; Timoshenko & Goodier, Theory of Elasticity, sec. 35): an infinite plate with a
/// traction-free circular hole of radius a at the origin under remote uniaxial stress S along
/// x1. In polar coordinates (r, theta) about the hole's centre, mu the shear modulus and
/// kappa = 3 - 4 nu (plane strain):
///
///   u_r     = S / (8 mu) [ r (kappa - 1) + 2 a^2 / r + (2 r + 2 (kappa + 1) a^2 / r - 2 a^4 / r^3) cos 2 theta ]
///   u_theta = -S / (8 mu) [ 2 r + 2 (kappa - 1) a^2 / r + 2 a^4 / r^3 ] sin 2 theta
///
/// and the stresses
///
///   sigma_rr = S/2 (1 - a^2/r^2) + S/2 (1 - 4 a^2/r^2 + 3 a^4/r^4) cos 2 theta
///   sigma_tt = S/2 (1 + a^2/r^2) - S/2 (1 + 3 a^4/r^4) cos 2 theta
///   sigma_rt = -S/2 (1 + 2 a^2/r^2 - 3 a^4/r^4) sin 2 theta
///
/// (sigma_tt = 3 S at theta = 90 degrees, r = a). `kirsch_field_is_consistent` checks that the
/// displacements give these stresses.
struct Kirsch {
    s: f64,
    a: f64,
    centre: [f64; 2],
    mu: f64,
    kappa: f64,
}

impl Kirsch {
    fn new(s: f64, a: f64, centre: [f64; 2], e: f64, nu: f64) -> Self {
        Self {
            s,
            a,
            centre,
            mu: e / (2.0 * (1.0 + nu)),
            kappa: 3.0 - 4.0 * nu,
        }
    }

    fn polar(&self, x: f64, y: f64) -> (f64, f64) {
        let (dx, dy) = (x - self.centre[0], y - self.centre[1]);
        (dx.hypot(dy), dy.atan2(dx))
    }

    fn u(&self, x: f64, y: f64) -> [f64; 2] {
        let (r, t) = self.polar(x, y);
        let (a2, a4, k) = (self.a * self.a, self.a.powi(4), self.kappa);
        let c = self.s / (8.0 * self.mu);
        let ur = c
            * (r * (k - 1.0)
                + 2.0 * a2 / r
                + (2.0 * r + 2.0 * (k + 1.0) * a2 / r - 2.0 * a4 / r.powi(3)) * (2.0 * t).cos());
        let ut = -c * (2.0 * r + 2.0 * (k - 1.0) * a2 / r + 2.0 * a4 / r.powi(3)) * (2.0 * t).sin();
        [ur * t.cos() - ut * t.sin(), ur * t.sin() + ut * t.cos()]
    }

    /// grad u by central differences (step 1e-6 of the hole radius: error ~1e-10 relative)
    fn grad(&self, x: f64, y: f64) -> [[f64; 2]; 2] {
        let h = 1e-6 * self.a;
        let (px, mx) = (self.u(x + h, y), self.u(x - h, y));
        let (py, my) = (self.u(x, y + h), self.u(x, y - h));
        [
            [(px[0] - mx[0]) / (2.0 * h), (py[0] - my[0]) / (2.0 * h)],
            [(px[1] - mx[1]) / (2.0 * h), (py[1] - my[1]) / (2.0 * h)],
        ]
    }

    /// (sigma_rr, sigma_tt, sigma_rt)
    fn polar_stress(&self, x: f64, y: f64) -> [f64; 3] {
        let (r, t) = self.polar(x, y);
        let (q2, q4, s) = ((self.a / r).powi(2), (self.a / r).powi(4), 0.5 * self.s);
        [
            s * (1.0 - q2) + s * (1.0 - 4.0 * q2 + 3.0 * q4) * (2.0 * t).cos(),
            s * (1.0 + q2) - s * (1.0 + 3.0 * q4) * (2.0 * t).cos(),
            -s * (1.0 + 2.0 * q2 - 3.0 * q4) * (2.0 * t).sin(),
        ]
    }
}

/// Cartesian stress (xx, yy, xy) in polar components about the hole's centre at (x, y).
fn to_polar(k: &Kirsch, x: f64, y: f64, s: [f64; 3]) -> [f64; 3] {
    let (_, t) = k.polar(x, y);
    let (c, sn) = (t.cos(), t.sin());
    [
        s[0] * c * c + s[1] * sn * sn + 2.0 * s[2] * sn * c,
        s[0] * sn * sn + s[1] * c * c - 2.0 * s[2] * sn * c,
        (s[1] - s[0]) * sn * c + s[2] * (c * c - sn * sn),
    ]
}

fn material() -> Elastic {
    Elastic::new(1.0, 0.3, Plane::Strain, 1.0).unwrap()
}

fn circle(name: &str, centre: [f64; 2], radius: f64) -> Hole {
    Hole {
        name: name.into(),
        shape: Shape::Circle {
            center: centre,
            radius,
        },
    }
}

fn rect(name: &str, min: [f64; 2], max: [f64; 2]) -> Hole {
    Hole {
        name: name.into(),
        shape: Shape::Rect { min, max },
    }
}

/// Every node on the outer boundary of a structured mesh.
fn boundary_nodes(m: &Mesh) -> Vec<usize> {
    let mut b: Vec<usize> = [Side::Left, Side::Right, Side::Bottom, Side::Top]
        .iter()
        .flat_map(|&s| m.side_nodes(s))
        .collect();
    b.sort_unstable();
    b.dedup();
    b
}

/// Least-squares slope of log(err) against log(h).
fn fitted_rate(h: &[f64], e: &[f64]) -> f64 {
    let n = h.len() as f64;
    let lx: Vec<f64> = h.iter().map(|v| v.ln()).collect();
    let ly: Vec<f64> = e.iter().map(|v| v.ln()).collect();
    let (mx, my) = (lx.iter().sum::<f64>() / n, ly.iter().sum::<f64>() / n);
    let num: f64 = lx.iter().zip(&ly).map(|(x, y)| (x - mx) * (y - my)).sum();
    let den: f64 = lx.iter().map(|x| (x - mx).powi(2)).sum();
    num / den
}

/// Solves the small dense system a x = b (Gaussian elimination, partial pivoting).
fn dense_solve(mut a: Vec<Vec<f64>>, mut b: Vec<f64>) -> Vec<f64> {
    let n = b.len();
    for c in 0..n {
        let p = (c..n)
            .max_by(|&i, &j| a[i][c].abs().total_cmp(&a[j][c].abs()))
            .unwrap();
        a.swap(c, p);
        b.swap(c, p);
        let pivot = a[c].clone();
        for r in c + 1..n {
            let f = a[r][c] / pivot[c];
            for (ark, pk) in a[r].iter_mut().zip(&pivot).skip(c) {
                *ark -= f * pk;
            }
            b[r] -= f * b[c];
        }
    }
    let mut x = vec![0.0; n];
    for r in (0..n).rev() {
        let s: f64 = (r + 1..n).map(|k| a[r][k] * x[k]).sum();
        x[r] = (b[r] - s) / a[r][r];
    }
    x
}

/// The hoop stress at the hole point `p` (on the circle) by least-squares extrapolation of the
/// Gauss-point stresses: sigma_tt at the 2 x 2 Gauss points of the *material* (uncut) elements
/// within `radius` of p, fitted by a polynomial cubic in the distance rho from the hole's
/// boundary and even in the arc coordinate s along it (sigma_tt is symmetric about theta = 90
/// degrees: 1, rho, rho^2, rho^3, s^2, rho s^2), evaluated at rho = s = 0. The radius (a / 4,
/// at least 4 elements) trades the polynomial's misfit of the steep profile (d sigma_tt / dr =
/// -7 S / a, d^3 sigma_tt / dr^3 = -192 S / a^3 at the hole) against the noise of the points
/// next to the cut elements: at 128 elements per 4 a, radii 0.15, 0.2, 0.25, 0.3 a gave
/// +0.85, +0.56, +0.30, +0.08 % (a quartic fit was noisier: +0.65 % at 0.25 a). Cut elements are left out: their few material Gauss points
/// carry the fictitious domain's boundary error; the uncut elements' 2 x 2 points are Q4's
/// superconvergent stress points.
fn hoop_stress_at(model: &FemModel, u: &[f64], k: &Kirsch, p: [f64; 2], radius: f64) -> f64 {
    let fd = model.fictitious.as_ref().unwrap();
    let (pts, sig) = model.gauss_stresses(u);
    let (_, tp) = k.polar(p[0], p[1]);
    const NB: usize = 6;
    let basis = |rho: f64, s: f64| {
        let s2 = s * s;
        [1.0, rho, rho * rho, rho.powi(3), s2, rho * s2]
    };
    let mut ata = vec![vec![0.0; NB]; NB];
    let mut atb = vec![0.0; NB];
    let mut used = 0;
    for (x, s) in pts.iter().zip(&sig) {
        if (x[0] - p[0]).hypot(x[1] - p[1]) > radius {
            continue;
        }
        let (e, _, _) = model.mesh.locate(x[0], x[1]).unwrap();
        if fd.kind(e) != ElementKind::Material {
            continue;
        }
        let (r, t) = k.polar(x[0], x[1]);
        let b = basis(r - k.a, k.a * (t - tp));
        let stt = to_polar(k, x[0], x[1], *s)[1];
        for i in 0..NB {
            for j in 0..NB {
                ata[i][j] += b[i] * b[j];
            }
            atb[i] += b[i] * stt;
        }
        used += 1;
    }
    assert!(used >= 2 * NB, "{used} Gauss points in the fit");
    dense_solve(ata, atb)[0]
}

#[test]
fn kirsch_field_is_consistent() {
    let k = Kirsch::new(1.0, 1.0, [2.0, 2.0], 1.0, 0.3);
    let d = material().d_matrix();
    for &(r, t) in &[
        (1.0, 0.3),
        (1.0, std::f64::consts::FRAC_PI_2),
        (1.3, 0.7),
        (2.0, 2.5),
        (1.1, -1.0),
    ] {
        let (x, y) = (2.0 + r * f64::cos(t), 2.0 + r * f64::sin(t));
        let g = k.grad(x, y);
        let eps = [g[0][0], g[1][1], g[0][1] + g[1][0]];
        let s: Vec<f64> = (0..3)
            .map(|i| d[i][0] * eps[0] + d[i][1] * eps[1] + d[i][2] * eps[2])
            .collect();
        let sp = to_polar(&k, x, y, [s[0], s[1], s[2]]);
        let ex = k.polar_stress(x, y);
        for c in 0..3 {
            assert!(
                (sp[c] - ex[c]).abs() < 1e-7,
                "r {r} t {t}: {sp:?} vs {ex:?}"
            );
        }
    }
    assert!((k.polar_stress(2.0, 3.0)[1] - 3.0).abs() < 1e-14);
}

/// Solves Kirsch's problem on [0, 4]^2 (hole r = 1 at the centre, S = 1) with `n` elements per
/// side, the exact displacements on the outer boundary: the model and the displacements.
fn kirsch_solve(k: &Kirsch, n: usize) -> (FemModel, Vec<f64>) {
    let mesh = Mesh::uniform(0.0, 0.0, 4.0, 4.0, n, n).unwrap();
    let mut dom = Domain::rect(4.0, 4.0);
    dom.holes.push(circle("hole[0]", k.centre, k.a));
    let model = FemModel::with_domain(mesh, material(), 2, &dom).unwrap();
    let mut bc = Dirichlet::default();
    for node in boundary_nodes(&model.mesh) {
        let [x, y] = model.mesh.coords[node];
        let u = k.u(x, y);
        bc.dofs.push((2 * node, u[0]));
        bc.dofs.push((2 * node + 1, u[1]));
    }
    let mut f = vec![0.0; model.n_dofs()];
    let bc = model.constrain(bc, &mut f).unwrap();
    let sys = LinearSystem::new(model.stiffness(), &bc).unwrap();
    let u = sys.solve(&f, 1.0).unwrap().u;
    (model, u)
}

#[test]
fn kirsch_energy_norm_converges_and_hoop_stress() {
    let k = Kirsch::new(1.0, 1.0, [2.0, 2.0], 1.0, 0.3);
    let exact = |x: f64, y: f64| (k.u(x, y), k.grad(x, y));
    let (mut hs, mut errs) = (Vec::new(), Vec::new());
    let mut hoop = 0.0;
    for n in [16, 32, 64, 128] {
        let (model, u) = kirsch_solve(&k, n);
        let (_, e) = model.error_norms(&u, exact);
        let (_, norm) = model.error_norms(&vec![0.0; u.len()], exact);
        let h = 4.0 / n as f64;
        hoop = hoop_stress_at(&model, &u, &k, [2.0, 3.0], (0.25 * k.a).max(4.0 * h));
        eprintln!(
            "Kirsch n = {n}: relative energy-norm error {:.4e}, hoop stress at 90 deg {hoop:.5} \
             ({:+.3} %), removed nodes {}",
            e / norm,
            100.0 * (hoop - 3.0) / 3.0,
            model.fictitious.as_ref().unwrap().removed_nodes.len()
        );
        hs.push(h);
        errs.push(e / norm);
    }
    // Q4's optimal energy-norm rate is 1. Cut elements integrated exactly over their material
    // part keep it (the chord polygon's geometric error, 1.6e-4 of the hole's area, is far
    // below); a staircase domain or Gauss points merely masked by the level set would give
    // about h^(1/2). Measured: 0.955 (9.05e-2, 4.76e-2, 2.45e-2, 1.24e-2 on 16 .. 128).
    let rate = fitted_rate(&hs, &errs);
    eprintln!("Kirsch energy-norm rate {rate:.3}");
    assert!(rate >= 0.9, "rate {rate}");
    assert!((hoop - 3.0).abs() < 0.02 * 3.0, "hoop {hoop}");
}

#[test]
fn grid_aligned_rect_hole_equals_removed_elements() {
    let mesh = Mesh::uniform(0.0, 0.0, 2.0, 1.0, 8, 4).unwrap();
    let (lo, hi) = ([0.5, 0.25], [1.25, 0.75]);
    let mut dom = Domain::rect(2.0, 1.0);
    dom.holes.push(rect("hole[0]", lo, hi));
    let model = FemModel::with_domain(mesh.clone(), material(), 2, &dom).unwrap();
    // the reference: the same mesh without the elements in the rectangle
    let mut cut = mesh.clone();
    let inside = |p: [f64; 2]| p[0] > lo[0] && p[0] < hi[0] && p[1] > lo[1] && p[1] < hi[1];
    cut.elements.retain(|e| {
        let c = e.iter().fold([0.0; 2], |a, &n| {
            [
                a[0] + 0.25 * mesh.coords[n][0],
                a[1] + 0.25 * mesh.coords[n][1],
            ]
        });
        !inside(c)
    });
    assert_eq!(cut.elements.len(), 32 - 6);
    let reference = FemModel::new(cut, material(), 2).unwrap();
    let mut bc = Dirichlet::default();
    bc.fix(&mesh.side_nodes(Side::Left), 0, 0.0);
    bc.fix(&mesh.side_nodes(Side::Left), 1, 0.0);
    for n in mesh.side_nodes(Side::Right) {
        bc.dofs.push((2 * n, 0.01));
        bc.dofs.push((2 * n + 1, 0.002 * mesh.coords[n][1]));
    }
    let mut f = vec![0.0; model.n_dofs()];
    let bc_h = model.constrain(bc.clone(), &mut f).unwrap();
    let fd = model.fictitious.as_ref().unwrap();
    let orphans: Vec<usize> = (0..mesh.n_nodes())
        .filter(|&n| inside(mesh.coords[n]))
        .collect();
    assert_eq!(fd.removed_nodes, orphans);
    let mut bc_r = bc;
    bc_r.fix(&orphans, 0, 0.0);
    bc_r.fix(&orphans, 1, 0.0);
    let uh = LinearSystem::new(model.stiffness(), &bc_h)
        .unwrap()
        .solve(&f, 1.0)
        .unwrap();
    let ur = LinearSystem::new(reference.stiffness(), &bc_r)
        .unwrap()
        .solve(&f, 1.0)
        .unwrap();
    let umax = ur.u.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    let diff =
        uh.u.iter()
            .zip(&ur.u)
            .fold(0.0f64, |a, (x, y)| a.max((x - y).abs()));
    eprintln!(
        "rect hole vs removed elements: max |du| / max |u| = {:.3e}",
        diff / umax
    );
    assert!(diff <= 1e-10 * umax, "{diff:e}");
    assert!((uh.energy - ur.energy).abs() <= 1e-10 * ur.energy);
}

/// The paper's FEM plate, uncracked, 40 x 80.
fn paper_plate() -> Problem {
    let mut p = Problem::paper("fem");
    p.cracks.clear();
    p.fem_mut().grid.nx = 40;
    p.fem_mut().grid.ny = 80;
    p
}

#[test]
fn notches_poking_outside_the_plate_work() {
    let plain = fem_driver::run(&paper_plate()).unwrap();
    let mut p = paper_plate();
    let (w, l) = (p.domain.width, p.domain.height);
    // a slot from the left edge at mid-height, and one through the top (gripped) edge
    p.domain
        .holes
        .push(rect("notch[0]", [-1.0, 0.49 * l], [0.3 * w, 0.51 * l]));
    p.domain
        .holes
        .push(rect("notch[1]", [0.6 * w, 0.9 * l], [0.7 * w, l + 1.0]));
    let r = fem_driver::run(&p).unwrap();
    eprintln!(
        "notched plate: sigma22 {:.5} (plain {:.5}), residual {:.2e}",
        r.sigma22, plain.sigma22, r.residual
    );
    assert!(r.u.iter().all(|v| v.is_finite()) && r.residual < 1e-8);
    // more compliant under the same grip displacement
    assert!(r.sigma22 < plain.sigma22 && r.sigma22 > 0.5 * plain.sigma22);
    let fd = FictitiousDomain::new(
        &Mesh::uniform(0.0, 0.0, w, l, 40, 80).unwrap(),
        &p.domain,
        2,
        DEFAULT_MIN_SUPPORT_FRACTION,
    )
    .unwrap()
    .unwrap();
    // nodes inside the notches carry no displacement; no Gauss point lies in a notch
    assert!(!fd.removed_nodes.is_empty());
    for &n in &fd.removed_nodes {
        assert_eq!((r.u[2 * n], r.u[2 * n + 1]), (0.0, 0.0));
    }
    assert!(r.gauss_points.iter().all(|&x| p.domain.level_set(x) > 0.0));
    assert!(r.nodal_stress.iter().flatten().all(|v| v.is_finite()));
}

#[test]
fn no_holes_is_bit_identical() {
    let mesh = Mesh::uniform(0.0, 0.0, 2.0, 1.0, 6, 3).unwrap();
    let a = FemModel::new(mesh.clone(), material(), 2).unwrap();
    let b = FemModel::with_domain(mesh, material(), 2, &Domain::rect(2.0, 1.0)).unwrap();
    assert!(b.fictitious.is_none());
    let (ka, kb) = (a.stiffness(), b.stiffness());
    assert_eq!(ka.val.len(), kb.val.len());
    assert!(ka
        .val
        .iter()
        .zip(&kb.val)
        .all(|(x, y)| x.to_bits() == y.to_bits()));
    let p = paper_plate();
    let (r1, r2) = (fem_driver::run(&p).unwrap(), fem_driver::run(&p).unwrap());
    assert!(r1
        .u
        .iter()
        .zip(&r2.u)
        .all(|(x, y)| x.to_bits() == y.to_bits()));
}

/// A node whose support holds material fraction f keeps its standard dofs (only nodes without
/// material are removed): the condition estimate against f, and Kirsch's plate against the
/// enrichment threshold (which plain Q4 must not see).
///
/// Measured: the condition estimate (of the Jacobi-equilibrated K_ff, the number that governs
/// the Cholesky solve's accuracy, `la::condition`) does not grow as the sliver thins: 2.72e4
/// without a sliver, 2.84e4 .. 2.89e4 for f = 1e-1 .. 1e-9 (the sliver node's function, scaled to
/// unit diagonal, is not close to a combination of the others: plain Q4 has no near-dependence
/// like a Heaviside enrichment's). The unscaled matrix's condition grows like 1 / f, which only
/// an unpreconditioned iterative solver would see. Holding the sliver nodes at 0 instead (the
/// former rule) made them hidden supports: with the hole off the grid's symmetry, thresholds
/// 1e-4, 1e-3, 1e-2 changed Kirsch's energy-norm error by +1.8e-5, +4.1e-4, +59 %.
#[test]
fn small_fraction_rule_bounds_the_condition() {
    let n = 32;
    let h = 1.0 / n as f64;
    let cond = |f: f64| {
        let mesh = Mesh::uniform(0.0, 0.0, 1.0, 1.0, n, n).unwrap();
        // the hole's top lies 2 f h below grid line 20: the interior nodes of line 19 keep
        // the sliver of the two elements above them, a support fraction f
        let mut dom = Domain::rect(1.0, 1.0);
        dom.holes
            .push(rect("hole[0]", [0.3, 0.3], [0.7, 20.0 * h - 2.0 * f * h]));
        let mut model = FemModel::new(mesh, material(), 2).unwrap();
        model.fictitious =
            FictitiousDomain::new(&model.mesh, &dom, 2, DEFAULT_MIN_SUPPORT_FRACTION).unwrap();
        let m = &model.mesh;
        let mut bc = Dirichlet::default();
        bc.fix(&m.side_nodes(Side::Left), 0, 0.0);
        bc.fix(&m.side_nodes(Side::Left), 1, 0.0);
        bc.fix(&m.side_nodes(Side::Right), 0, 1e-3);
        let mut fv = vec![0.0; model.n_dofs()];
        let bc = model.constrain(bc, &mut fv).unwrap();
        let sys = LinearSystem::new(model.stiffness(), &bc).unwrap();
        let c = sys.condition_estimate().unwrap().value();
        let fd = model.fictitious.as_ref().unwrap();
        let smallest = (0..m.n_nodes())
            .filter(|&k| !fd.is_removed(k))
            .map(|k| fd.node_fraction[k])
            .fold(f64::INFINITY, f64::min);
        (c, smallest)
    };
    let (base, _) = cond(0.5);
    for f in [1e-1, 1e-2, 1e-3, 1e-4, 1e-5, 1e-7, 1e-9] {
        let (c, smallest) = cond(f);
        eprintln!(
            "sliver fraction {f:.0e}: condition {c:.3e} (smallest kept fraction {smallest:.1e}); no sliver {base:.3e}"
        );
        // the sliver nodes are kept (they hold material)
        assert!(smallest <= f * (1.0 + 1e-6), "{smallest:e} vs {f:e}");
        assert!(c <= 1.5 * base, "{c:e} vs {base:e}");
    }
    // Kirsch on 64 x 64, the hole off the grid's symmetry (slivers of every size): the
    // enrichment threshold changes nothing in plain Q4, bit for bit, and removes no node
    let k = Kirsch::new(1.0, 1.0, [2.0 + 0.37 / 16.0, 2.0 + 0.21 / 16.0], 1.0, 0.3);
    let exact = |x: f64, y: f64| (k.u(x, y), k.grad(x, y));
    let err = |threshold: f64| {
        let mesh = Mesh::uniform(0.0, 0.0, 4.0, 4.0, 64, 64).unwrap();
        let mut dom = Domain::rect(4.0, 4.0);
        dom.holes.push(circle("hole[0]", k.centre, k.a));
        let mut model = FemModel::new(mesh, material(), 2).unwrap();
        model.fictitious = FictitiousDomain::new(&model.mesh, &dom, 2, threshold).unwrap();
        let mut bc = Dirichlet::default();
        for node in boundary_nodes(&model.mesh) {
            let [x, y] = model.mesh.coords[node];
            let u = k.u(x, y);
            bc.dofs.push((2 * node, u[0]));
            bc.dofs.push((2 * node + 1, u[1]));
        }
        let mut f = vec![0.0; model.n_dofs()];
        let bc = model.constrain(bc, &mut f).unwrap();
        let u = LinearSystem::new(model.stiffness(), &bc)
            .unwrap()
            .solve(&f, 1.0)
            .unwrap()
            .u;
        let fd = model.fictitious.as_ref().unwrap();
        let removed = fd.removed_nodes.len();
        // a removed node has no material at all
        assert!(fd.removed_nodes.iter().all(|&n| fd.node_fraction[n] == 0.0));
        (model.error_norms(&u, exact).1, removed)
    };
    let (e0, r0) = err(0.0);
    for t in [1e-6, 1e-4, DEFAULT_MIN_SUPPORT_FRACTION, 1e-2] {
        let (e, r) = err(t);
        eprintln!(
            "Kirsch 64 x 64, threshold {t:.0e}: energy error {e:.6e} (threshold 0: {e0:.6e})"
        );
        assert_eq!(e.to_bits(), e0.to_bits(), "{t}: {e} vs {e0}");
        assert_eq!(r, r0);
    }
}

/// The paper's XFEM plate (free grips) on `nx` x `ny`, its crack an edge crack from the left
/// side at y = 10.5 of length `a0`.
fn xfem_plate(nx: usize, ny: usize, a0: f64) -> Problem {
    let mut p = Problem::paper("xfem");
    p.xfem_mut().grid.nx = nx;
    p.xfem_mut().grid.ny = ny;
    let c = &mut p.cracks[0];
    c.kind = CrackKind::Edge;
    c.side = Side::Left;
    c.angle = 0.0;
    c.y = 10.5;
    c.a0 = a0;
    p
}

/// One XFEM solve of `crack` in `p`'s plate by the model API (free grips at the reference
/// load): K_I at r_I = 2.5 tip elements and the CMOD.
fn xfem_solve(p: &Problem, crack: Vec<[f64; 2]>) -> (f64, f64) {
    let (model, u) = xfem_model_solve(p, crack);
    let s = model.sifs(&u, 0, 2.5 * model.tip_element_size(0)).unwrap();
    (s.k_i, model.cmod(&u).unwrap())
}

/// The model and displacements of one XFEM solve of `crack` in `p`'s plate (free grips at the
/// reference load).
fn xfem_model_solve(p: &Problem, crack: Vec<[f64; 2]>) -> (XfemModel, Vec<f64>) {
    let Method::Xfem(x) = &p.method else {
        unreachable!()
    };
    let d = &p.domain;
    let mesh = Arc::new(Mesh::uniform(0.0, 0.0, d.width, d.height, x.grid.nx, x.grid.ny).unwrap());
    let model =
        XfemModel::new_in_domain(mesh.clone(), p.material.elastic, vec![crack], x.options, d)
            .unwrap();
    let edges = PlateEdges::of_mesh(&mesh);
    let t = p.material.elastic.thickness;
    let (bc, mut f, _) =
        plate_conditions(&edges, &p.boundary.plate_load(), model.n_dofs, t).unwrap();
    let bc = model.constrain(bc, &mut f).unwrap();
    let sys = LinearSystem::new(model.stiffness().unwrap(), &bc).unwrap();
    let u = sys.solve(&f, 1.0).unwrap().u;
    (model, u)
}

/// A crack from a notch tip (its polyline starts on the notch: the mouth) against the same crack
/// drawn from the plate's edge through the notch (the driver's edge crack, Heaviside-enriched
/// across the notch too) and against a sharp crack of the same depth.
///
/// The notch is 0.6 wide (4.7 elements): a slot narrower than about two elements is not
/// separated by the fictitious domain alone (the nodes inside it carry shape functions on both
/// faces, gluing them): measured with a 0.06 slot (half an element), K_I 14.78 against 27.12
/// for the crack drawn through it (`fe::fictitious`, "Holes thinner than two elements").
#[test]
fn xfem_crack_from_a_notch_tip() {
    let p0 = xfem_plate(88, 166, 2.0);
    let mut p = p0.clone();
    p.domain
        .holes
        .push(rect("notch[0]", [-1.0, 10.2], [1.0, 10.8]));
    let (k_notch, cmod_notch) = xfem_solve(&p, vec![[1.0, 10.5], [2.0, 10.5]]);
    let through = xfem::run(&p, &|_, _| true).unwrap();
    let plain = xfem::run(&p0, &|_, _| true).unwrap();
    eprintln!(
        "notch + crack: K_I {k_notch:.5} (mouth at the notch tip), {:.5} (crack through the \
         notch), {:.5} (sharp crack of the same depth); CMOD at the notch tip {cmod_notch:.6}, \
         at the edge {:.6} / {:.6}",
        through.k_i, plain.k_i, through.cmod, plain.cmod
    );
    // measured: K_I 27.12108 both ways, 27.12523 for the sharp crack (-0.015 %); the CMOD of
    // the crack drawn through the notch is read where it enters the material, the notch tip
    assert_eq!(through.tips.len(), 1);
    assert!((k_notch / through.k_i - 1.0).abs() < 1e-6);
    assert!((cmod_notch / through.cmod - 1.0).abs() < 1e-6);
    assert!((k_notch / plain.k_i - 1.0).abs() < 1e-2);
}

/// A slot narrower than two elements is glued by the fictitious domain alone: the run warns,
/// naming it (the measured effect: a crack from the tip of a half-element slot gives K_I 14.78
/// instead of 27.12, above); the 4.7-element notch of the test above does not warn.
#[test]
fn a_slot_narrower_than_two_elements_warns() {
    let glued = |w: f64| {
        let mut p = xfem_plate(88, 166, 2.0);
        p.domain.holes.push(rect(
            "notch[0]",
            [-1.0, 10.5 - w / 2.0],
            [1.0, 10.5 + w / 2.0],
        ));
        let r = xfem::run(&p, &|_, _| true).unwrap();
        r.warnings
            .iter()
            .find(|w| w.message.contains("notch[0]") && w.message.contains("elements across"))
            .map(|w| w.message.clone())
    };
    let w = glued(0.06).expect("a half-element slot warns");
    assert!(w.contains("along x2") && w.contains("refine"), "{w}");
    eprintln!("{w}");
    assert_eq!(glued(0.6), None);
}

#[test]
fn xfem_tip_in_a_hole_is_refused() {
    let mut p = xfem_plate(44, 83, 1.1);
    p.domain.holes.push(circle("hole[0]", [1.2, 10.5], 0.3));
    let e = xfem::run(&p, &|_, _| true).unwrap_err().to_string();
    assert!(
        e.contains("crack.a0") && e.contains("inside hole[0]"),
        "{e}"
    );
    p.domain.holes[0] = circle("hole[0]", [1.8, 10.5], 0.4);
    let e = xfem::run(&p, &|_, _| true).unwrap_err().to_string();
    assert!(e.contains("crack.a0") && e.contains("near hole[0]"), "{e}");
}

/// XFEM with a hole near the crack tip against the seam FEM on a fine mesh (the J/I-integral is
/// not available for FEM, so the CMOD): the hole's effect on the CMOD must agree.
#[test]
fn xfem_edge_crack_near_a_hole_against_seam_fem() {
    let hole = circle("hole[0]", [2.5, 11.5], 0.5);
    let cmods = |with_hole: bool| {
        let mut x = xfem_plate(88, 166, 1.1);
        let mut f = Problem::paper("fem");
        f.fem_mut().grid.nx = 220;
        f.fem_mut().grid.ny = 420;
        f.cracks[0].kind = CrackKind::Seam;
        f.cracks[0].a0 = 1.1;
        f.cracks[0].y = 10.5;
        if with_hole {
            x.domain.holes.push(hole.clone());
            f.domain.holes.push(hole.clone());
        }
        let rx = xfem::run(&x, &|_, _| true).unwrap();
        let rf = fem_driver::run(&f).unwrap();
        assert_eq!(rf.seam_length, Some(1.1));
        (rx.cmod, rf.cmod, rx.k_i)
    };
    let (x0, f0, k0) = cmods(false);
    let (x1, f1, k1) = cmods(true);
    eprintln!(
        "CMOD without the hole: XFEM {x0:.6} seam FEM {f0:.6} ({:+.3} %); with: XFEM {x1:.6} \
         seam FEM {f1:.6} ({:+.3} %); the hole raises the CMOD by {:+.3} % (XFEM) and {:+.3} % \
         (FEM), K_I by {:+.3} % (XFEM)",
        100.0 * (x0 / f0 - 1.0),
        100.0 * (x1 / f1 - 1.0),
        100.0 * (x1 / x0 - 1.0),
        100.0 * (f1 / f0 - 1.0),
        100.0 * (k1 / k0 - 1.0)
    );
    assert!(x1 > x0 && f1 > f0);
    assert!(((x1 / x0) / (f1 / f0) - 1.0).abs() < 2e-3);
    assert!((x1 / f1 - 1.0).abs() < 1e-2);
}

/// The small-area rule measures the material: a crack drawn through a notch 0.1 wide at 0.05
/// below the notch's top face leaves the nodes of the grid line under the notch (y = 10.3735)
/// with material on the crack's lower side only (their enriched function vanishes on the
/// material). Measured on full elements (40 % above the crack) they would be kept and make the
/// matrix singular; measured on the material they are dropped.
#[test]
fn xfem_small_area_rule_sees_the_material() {
    let mut p = xfem_plate(88, 166, 2.0);
    p.cracks[0].y = 10.45;
    p.domain
        .holes
        .push(rect("notch[0]", [-1.0, 10.40], [1.0, 10.50]));
    let r = xfem::run(&p, &|_, _| true).unwrap();
    eprintln!(
        "crack through a notch: K_I {:.5}, {} Heaviside nodes dropped, CMOD {:.6}",
        r.k_i, r.n_dropped_nodes, r.cmod
    );
    assert!(r.k_i.is_finite() && r.k_i > 0.0 && r.cmod > 0.0);
    assert!(r.n_dropped_nodes >= 8);
}

/// Growth towards a hole stops with `ligament_used_up` once the next tip would come closer to
/// the hole than the tip clearance (or the hole would enter the SIF domain), instead of failing.
#[test]
fn xfem_growth_towards_a_hole_stops_at_the_ligament() {
    let mut p = xfem_plate(44, 83, 1.1);
    // the tip at 2.6 is 0.55 (2.2 elements) from the hole: its default domain would take the
    // hole in (the old rule stopped there), the shrunk one does not
    p.domain.holes.push(circle("hole[0]", [3.9, 10.5], 0.75));
    if let Method::Xfem(x) = &mut p.method {
        x.growth = Some(Growth {
            max_steps: 40,
            da: None,
            a_stop: 8.0,
            kink_rule: rustfrac_core::problem::KinkRule::Hoop,
            state_every: 0,
        });
    }
    let r = xfem::run(&p, &|_, _| true).unwrap();
    let tip = *r.crack.last().unwrap();
    let gap = p.domain.level_set(tip);
    eprintln!(
        "growth towards a hole: {} steps, status {}, last tip {tip:?} {gap:.3} from the hole",
        r.history.len() - 1,
        r.status.name()
    );
    assert_eq!(r.status, GrowthStatus::LigamentUsedUp);
    assert!(r.history.len() > 2 && gap > 0.0);
    assert!(r.history.iter().all(|h| h.lambda.is_finite()));
    // the SIF domain shrinks clear of the hole instead of stopping the growth: the last steps
    // ran with r_I < 2.5 element sizes (never below the minimum), and a warning says so
    let h = 11.0 / 44.0_f64 * (21.0 / 83.0_f64 / (11.0 / 44.0)).sqrt();
    for row in &r.history[1..] {
        eprintln!(
            "  tip ({:.3}, {:.3}) a {:.3} K_I {:.4} r_I {:.3} h",
            row.tip[0],
            row.tip[1],
            row.a,
            row.k_i,
            row.r_i / h
        );
        assert!(row.r_i >= MIN_HOLE_FREE_RADIUS * h * (1.0 - 1e-9));
    }
    let last = r.history.last().unwrap();
    assert!(last.r_i < 2.5 * h * (1.0 - 1e-6), "{}", last.r_i / h);
    assert!(r.history[1].r_i > 2.5 * h * (1.0 - 1e-9));
    assert!(r.tip_history.last().unwrap()[0].r_i == last.r_i);
    assert!(
        r.warnings.iter().any(|w| w.message.contains("shrunk")),
        "{:?}",
        r.warnings
    );
}

/// The SIF domain shrunk clear of a hole (`XfemModel::sifs_clear_of_holes`): an edge crack
/// (a = 1.1 at y = 10.5) whose tip is 0.6 from a hole of radius 0.5 ahead of it, so that the
/// default r_I = 2.5 elements of the coarse mesh (h = 0.25) would take the hole in. First the
/// radius study on the same crack without the hole (K_I against r_I: what justifies
/// `MIN_HOLE_FREE_RADIUS`), then K_I with the shrunk domain on the coarse and a medium mesh
/// against the fine mesh (h = 0.0625, whose default domain of 2.5 elements stays clear of the
/// hole), the reference.
#[test]
fn xfem_sif_domain_radius_near_a_hole() {
    let crack = vec![[0.0, 10.5], [1.1, 10.5]];
    let (m0, u0) = xfem_model_solve(&xfem_plate(44, 83, 1.1), crack.clone());
    let h0 = m0.tip_element_size(0);
    let k_ref0 = m0.sifs(&u0, 0, 2.5 * h0).unwrap().k_i;
    let mut worst_above_min: f64 = 0.0;
    for f in [0.75, 1.0, 1.25, 1.5, 2.0, 3.0, 4.0] {
        let k = m0.sifs(&u0, 0, f * h0).unwrap().k_i;
        eprintln!(
            "no hole, r_I = {f:.2} h: K_I {k:.5} ({:+.3} % of r_I = 2.5 h)",
            100.0 * (k / k_ref0 - 1.0)
        );
        if f >= MIN_HOLE_FREE_RADIUS {
            worst_above_min = worst_above_min.max((k / k_ref0 - 1.0).abs());
        }
    }
    assert!(worst_above_min < 1e-2, "{worst_above_min}");
    let hole = circle("hole[0]", [2.2, 10.5], 0.5);
    let mut ks = Vec::new();
    for (nx, ny) in [(44, 83), (88, 167), (176, 335)] {
        let mut p = xfem_plate(nx, ny, 1.1);
        p.domain.holes.push(hole.clone());
        let (m, u) = xfem_model_solve(&p, crack.clone());
        let h = m.tip_element_size(0);
        let full = 2.5 * h;
        let s = m.sifs_clear_of_holes(&u, 0, full).unwrap();
        let shrunk = s.radius < full;
        assert_eq!(shrunk, m.hole_in_domain(0, full).is_some());
        assert!(m.hole_in_domain(0, s.radius).is_none());
        eprintln!(
            "hole 0.6 ahead, mesh {nx} x {ny}: r_I {:.3} h (shrunk: {shrunk}), K_I {:.5}, J_dom / J_K {:.4}",
            s.radius / h,
            s.k_i,
            s.j_domain / s.j_from_k
        );
        // the same solution with a domain of 8 elements, shrunk clear of the hole: the error
        // of the shrinking alone against the unshrunk domain
        let big = m.sifs_clear_of_holes(&u, 0, 8.0 * h).unwrap();
        eprintln!(
            "  r_I = 8 h shrunk to {:.3} h: K_I {:.5} ({:+.3} % of r_I {:.3} h)",
            big.radius / h,
            big.k_i,
            100.0 * (big.k_i / s.k_i - 1.0),
            s.radius / h
        );
        assert!(big.radius <= 8.0 * h && big.radius >= MIN_HOLE_FREE_RADIUS * h);
        if !shrunk {
            assert!((big.k_i / s.k_i - 1.0).abs() < 5e-3);
        }
        ks.push((shrunk, s.k_i));
    }
    // a domain that would have to shrink below the minimum is refused, naming the hole
    // (tip at 1.2, 0.51 from the hole: the nearest node of a cut element is 0.3 = 1.2 h away)
    let mut p = xfem_plate(44, 83, 1.2);
    p.domain.holes.push(circle("hole[0]", [2.11, 10.5], 0.4));
    let (m, u) = xfem_model_solve(&p, vec![[0.0, 10.5], [1.2, 10.5]]);
    let e = m
        .sifs_clear_of_holes(&u, 0, 2.5 * m.tip_element_size(0))
        .unwrap_err()
        .to_string();
    assert!(e.contains("r_I") && e.contains("hole[0]"), "{e}");
    let k_ref = ks[2].1;
    assert!(ks[0].0 && !ks[2].0);
    for (shrunk, k) in &ks[..2] {
        eprintln!(
            "  shrunk {shrunk}: {:+.3} % of the fine mesh",
            100.0 * (k / k_ref - 1.0)
        );
    }
    assert!((ks[0].1 / k_ref - 1.0).abs() < 1e-2);
    assert!((ks[1].1 / k_ref - 1.0).abs() < 5e-3);
    // the hole raises K_I against the same crack without it
    assert!(ks[0].1 > k_ref0);
}
