//! `pd.s0_calibration` (`rustfrac_core::pd::calibration`): the grid's discrete fracture energy,
//! the SLA reference strip (its convergence with the strip's size, its independence of dx), that a
//! calibration only rescales the load path, and the key's error.
//!
//! The Python side checks the grid energy against independently sub-sampled partial volumes and
//! the SLA rule's transfer to another strip (tests/test_energy.py).

use crate::common;

use common::{coarse, go_on, rel};
use rustfrac_core::pd::analysis;
use rustfrac_core::pd::calibration::{
    calibration, grid_energy_ratio, reference_strip, sla_energy_ratio, strip_release_ratio,
    STRIP_HEIGHT, STRIP_PRECRACK, STRIP_WIDTH,
};
use rustfrac_core::problem::value::{Table, Value};
use rustfrac_core::problem::Problem;
use rustfrac_core::problem::S0Calibration;
use std::time::Instant;

/// The strip is scale-free: the same strip in cells of dx = 1 and dx = 1/15 releases the same
/// energy per unit area over G0 (to rounding), and so does another E and G0.
#[test]
fn sla_reference_ratio_is_independent_of_dx_and_material() {
    let m = 2;
    let a = strip_release_ratio(&reference_strip(m, 1.0, 4, 4, 1).unwrap()).unwrap();
    let b = strip_release_ratio(&reference_strip(m, 1.0 / 15.0, 4, 4, 1).unwrap()).unwrap();
    let mut p = reference_strip(m, 0.37, 4, 4, 1).unwrap();
    p.material.elastic.e = 3.0e5;
    p.material.g0 = 12.5;
    let c = strip_release_ratio(&p).unwrap();
    println!("m = {m}, 4 x 4 horizons: G_sla / G0 = {a:.6} (dx 1), {b:.6} (dx 1/15), {c:.6}");
    assert!(rel(b, a) < 1e-8 && rel(c, a) < 1e-8, "{a} {b} {c}");
    // the SLA releases more than the bonds' own energy (each break snaps)
    assert!(a > grid_energy_ratio(m).unwrap());
}

/// `"grid"` and `"sla"` make their reference energy G0: factor^2 G_ref / G0 = 1; the default
/// changes nothing; the memo returns the same value.
#[test]
fn calibration_factors() {
    let c = calibration(S0Calibration::Continuum, 4).unwrap();
    assert_eq!((c.factor, c.g_ref_over_g0), (1.0, 1.0));
    for m in 1..=12 {
        let g = calibration(S0Calibration::Grid, m).unwrap();
        assert!((g.factor * g.factor * g.g_ref_over_g0 - 1.0).abs() < 1e-14);
        println!(
            "m = {m:2}: grid G_ref / G0 = {:.5}, factor {:.5}",
            g.g_ref_over_g0, g.factor
        );
    }
    let t = Instant::now();
    let s = calibration(S0Calibration::Sla, 3).unwrap();
    let first = t.elapsed().as_secs_f64();
    let t = Instant::now();
    let again = sla_energy_ratio(3).unwrap();
    let second = t.elapsed().as_secs_f64();
    println!(
        "m = 3: sla G_ref / G0 = {:.5}, factor {:.5} ({first:.3} s, memo {second:.1e} s)",
        s.g_ref_over_g0, s.factor
    );
    assert_eq!(again, s.g_ref_over_g0);
    assert!((s.factor * s.factor * s.g_ref_over_g0 - 1.0).abs() < 1e-14);
    assert!(calibration(S0Calibration::Grid, 0).is_err());
    assert!(calibration(S0Calibration::Sla, 13).is_err());
}

/// A calibration only rescales s0: the same bonds break in the same order, lambda, sigma22 and
/// CMOD scale by the factor (coarse CCM-PD plate, 40 steps), against the continuum run.
#[test]
fn calibration_scales_the_history_and_nothing_else() {
    let base = analysis::run(&coarse(true, 40), &go_on).unwrap();
    for rule in [S0Calibration::Grid, S0Calibration::Sla] {
        let mut p = coarse(true, 40);
        p.pd_mut().s0_calibration = rule;
        let r = analysis::run(&p, &go_on).unwrap();
        let f = calibration(rule, p.pd().unwrap().m).unwrap().factor;
        assert!(
            (f - 1.0).abs() > 1e-3,
            "{rule:?}: factor {f}: the test could not fail"
        );
        assert!(rel(r.constants.pd.s0, f * base.constants.pd.s0) < 1e-14);
        assert_eq!(r.history.len(), base.history.len());
        let mut worst = 0.0f64;
        for (x, y) in r.history.iter().zip(&base.history) {
            assert_eq!(
                x.bonds, y.bonds,
                "{rule:?}: step {} broke other bonds",
                x.step
            );
            assert_eq!(x.crack_length, y.crack_length);
            for (a, b) in [
                (x.lambda, y.lambda),
                (x.sigma22, y.sigma22),
                (x.cmod, y.cmod),
                (x.u0, y.u0),
            ] {
                worst = worst.max(rel(a, f * b));
            }
        }
        println!(
            "{rule:?}: factor {f:.5}, worst relative deviation from f x continuum {worst:.1e}"
        );
        assert!(worst < 1e-9, "{rule:?}: {worst}");
        // the reference solution (no break) is the same
        assert_eq!(
            (r.reference.sigma22, r.reference.cmod),
            (base.reference.sigma22, base.reference.cmod)
        );
    }
}

/// A checkpoint of one rule is not resumed under another (the loads differ); the default
/// hashes nothing new.
#[test]
fn checkpoint_fingerprint_carries_the_rule() {
    use rustfrac_core::pd::sla::checkpoint::fingerprint;
    let p = coarse(true, 10);
    let fp = |p: &Problem| fingerprint(p, &p.pd_precrack(), 100, 1000);
    let mut q = p.clone();
    q.pd_mut().s0_calibration = S0Calibration::Continuum;
    assert_eq!(fp(&p), fp(&q));
    q.pd_mut().s0_calibration = S0Calibration::Grid;
    let mut r = p.clone();
    r.pd_mut().s0_calibration = S0Calibration::Sla;
    assert!(fp(&q) != fp(&p) && fp(&r) != fp(&p) && fp(&q) != fp(&r));
}

/// An unknown choice is refused, naming the key and its choices.
#[test]
fn unknown_calibration_is_refused() {
    let mut t = Table::new();
    t.insert("method".into(), Value::Str("ccm_pd".into()));
    let mut pd = Table::new();
    pd.insert("s0_calibration".into(), Value::Str("exact".into()));
    t.insert("pd".into(), Value::Table(pd));
    let e = Problem::from_scene(&t).unwrap_err().to_string();
    assert!(e.contains("pd.s0_calibration"), "{e}");
    assert!(e.contains("'continuum', 'grid', 'sla'"), "{e}");
}

/// The size study behind [`STRIP_WIDTH`] x [`STRIP_HEIGHT`] (run with `--ignored --nocapture`):
/// G_sla / G0 of strips of w x h horizons per m, and the cost of each run.
#[test]
#[ignore]
fn sla_reference_strip_size_study() {
    let ms: Vec<usize> = std::env::var("CALIB_MS")
        .map(|s| s.split(',').map(|x| x.parse().unwrap()).collect())
        .unwrap_or_else(|_| vec![2, 3, 4]);
    for m in ms {
        for (w, h) in [(4, 4), (6, 6), (8, 6), (6, 8), (8, 8), (10, 10)] {
            let t = Instant::now();
            let mut p = reference_strip(m, 1.0, w, h, STRIP_PRECRACK).unwrap();
            if std::env::var("CALIB_CLAMPED").is_ok() {
                p = p.with_grip(rustfrac_core::problem::Grip::Clamped);
            }
            let r = strip_release_ratio(&p).unwrap();
            let steps = analysis::run(&p, &go_on).unwrap().history.len();
            println!(
                "m = {m}, {w} x {h} horizons: G_sla / G0 = {r:.5} ({steps} steps, {:.2} s){}",
                t.elapsed().as_secs_f64(),
                if (w, h) == (STRIP_WIDTH, STRIP_HEIGHT) {
                    "  <- the reference"
                } else {
                    ""
                }
            );
        }
    }
}
