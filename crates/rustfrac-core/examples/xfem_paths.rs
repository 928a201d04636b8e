//! Path convergence of XFEM mixed-mode growth and the effect of
//! `xfem.kink_rule`: the 30-degree inclined edge crack of the paper's plate under tension (free
//! grips) and the edge crack under shear (Moes et al. 1999, fig. 13), grown with several element
//! sizes h and extensions da under `hoop` and `predictor_corrector`, each path compared with a
//! fine reference path (the finest h and da, under each rule) by [`path_deviation`] over the
//! common grown length, in units of the run's h. Solves: the runs' linear solves (the initial
//! one, one per further critical state, and one corrector trial per extension).
//!
//! `cargo run --release -p rustfrac-core --example xfem_paths -- [inclined|shear|all] [fine]`
//! (`fine` adds the finest level, minutes; `PATHS_OUT=DIR` writes every path as CSV).
use rustfrac_core::problem::value::{Table, Value};
use rustfrac_core::problem::KinkRule;
use rustfrac_core::problem::Problem;
use rustfrac_core::xfem::paths::{path_deviation, turning_angles};
use rustfrac_core::xfem::{run, XfemResult};
use std::time::Instant;

fn f(x: f64) -> Value {
    Value::Float(x)
}
fn s(x: &str) -> Value {
    Value::Str(x.into())
}
fn i(x: i64) -> Value {
    Value::Int(x)
}
fn tbl(kv: &[(&str, Value)]) -> Value {
    Value::Table(kv.iter().map(|(k, v)| (k.to_string(), v.clone())).collect())
}

/// The growth options of one run.
fn xfem(da: f64, a_stop: f64, rule: &str) -> Value {
    tbl(&[
        ("growth_steps", i(400)),
        ("da", f(da)),
        ("a_stop", f(a_stop)),
        ("kink_rule", s(rule)),
    ])
}

/// The paper's plate (11 x 21, free grips) with a 30-degree edge crack of length 1.1 at
/// mid-height, `n` times the paper's 44 x 83 mesh, grown to the length 4.
fn inclined(n: i64, da: f64, rule: &str) -> Table {
    [
        ("method", s("xfem")),
        (
            "crack",
            tbl(&[
                ("kind", s("edge")),
                ("a0", f(1.1)),
                ("y", f(10.5)),
                ("angle", f(30.0)),
            ]),
        ),
        ("mesh", tbl(&[("nx", i(44 * n)), ("ny", i(83 * n))])),
        ("xfem", xfem(da, 4.0, rule)),
    ]
    .into_iter()
    .map(|(k, v)| (k.to_string(), v))
    .collect()
}

/// The edge crack under shear (`rustfrac.specimens.edge_shear`): 7 x 16, crack 3.5 at
/// mid-height, bottom fixed, unit shear on the top edge, `n` times a 28 x 64 mesh, grown to 5.5.
fn shear(n: i64, da: f64, rule: &str) -> Table {
    [
        ("method", s("xfem")),
        ("plate", tbl(&[("width", f(7.0)), ("height", f(16.0))])),
        ("material", tbl(&[("E", f(3e7)), ("nu", f(0.25))])),
        (
            "crack",
            tbl(&[("kind", s("edge")), ("a0", f(3.5)), ("y", f(8.0))]),
        ),
        ("mesh", tbl(&[("nx", i(28 * n)), ("ny", i(64 * n))])),
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
        ("xfem", xfem(da, 5.5, rule)),
    ]
    .into_iter()
    .map(|(k, v)| (k.to_string(), v))
    .collect()
}

struct Run {
    n: i64,
    da: f64,
    rule: &'static str,
    res: XfemResult,
    secs: f64,
}

fn go(case: fn(i64, f64, &str) -> Table, n: i64, da: f64, rule: &'static str) -> Run {
    let p = Problem::from_scene(&case(n, da, rule)).expect("scene");
    let t = Instant::now();
    let res = run(&p, &|_, _| true).expect("run");
    Run {
        n,
        da,
        rule,
        res,
        secs: t.elapsed().as_secs_f64(),
    }
}

/// Mean |K_II / K_I| at the tips of the grown crack (history rows 2.., the first growth
/// step's tip onwards).
fn mean_mixity(r: &XfemResult) -> f64 {
    let rows: Vec<f64> = r
        .history
        .iter()
        .skip(2)
        .map(|h| (h.k_ii / h.k_i).abs())
        .collect();
    rows.iter().sum::<f64>() / rows.len().max(1) as f64
}

fn study(name: &str, case: fn(i64, f64, &str) -> Table, h0: f64, fine: bool) {
    println!("\n## {name} (h0 = {h0})");
    // (mesh multiplier, da in units of h0)
    let mut levels: Vec<(i64, f64)> = vec![(1, 1.0), (1, 0.5), (2, 1.0), (2, 0.5), (2, 0.25)];
    let reference = if fine { (4, 0.125) } else { (2, 0.25) };
    if fine {
        levels.extend([(4, 0.25), reference]);
    }
    let mut runs = Vec::new();
    for &(n, d) in &levels {
        for rule in ["hoop", "predictor_corrector"] {
            runs.push(go(case, n, d * h0, rule));
        }
    }
    let find = |rule: &str| {
        runs.iter()
            .find(|r| r.n == reference.0 && r.da == reference.1 * h0 && r.rule == rule)
            .unwrap()
    };
    let (ref_pc, ref_hoop) = (find("predictor_corrector"), find("hoop"));
    let (refp, refh) = (ref_pc.res.crack.clone(), ref_hoop.res.crack.clone());
    let dd = path_deviation(&refh, &refp, 1, 400);
    println!(
        "references: mesh x{} (h = {}), da = {}, {} steps; tips {:?} (predictor_corrector), {:?} \
         (hoop); hoop reference vs predictor_corrector reference: mean {:.5}, max {:.5} over {:.3}",
        ref_pc.n,
        h0 / ref_pc.n as f64,
        ref_pc.da,
        ref_pc.res.history.len() - 1,
        refp.last().unwrap(),
        refh.last().unwrap(),
        dd.mean,
        dd.max,
        dd.length
    );
    println!(
        "| mesh | h | da | rule | steps | solves | time s | mean / h (ref pc) | max / h (ref pc) | mean / h (ref hoop) | max / h (ref hoop) | common L | mean abs K_II/K_I | kinks (deg) |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|");
    for (tag, r) in [("predictor_corrector", ref_pc), ("hoop", ref_hoop)] {
        let k: Vec<String> = turning_angles(&r.res.crack, 1)
            .iter()
            .map(|a| format!("{:+.2}", a.to_degrees()))
            .collect();
        println!("reference kinks ({tag}, deg): {}", k.join(" "));
    }
    if let Ok(dir) = std::env::var("PATHS_OUT") {
        // every path as CSV rows: run, x, y (for figures)
        let mut csv = String::from("case,mesh,da,rule,x,y\n");
        let case = name.replace(',', ";");
        for r in &runs {
            for q in &r.res.crack {
                csv += &format!("{case},x{},{},{},{},{}\n", r.n, r.da, r.rule, q[0], q[1]);
            }
        }
        let file = format!(
            "{dir}/{}.csv",
            name.split_whitespace().next().unwrap_or("case")
        );
        std::fs::write(&file, csv).expect("write the paths");
    }
    for r in &runs {
        let h = h0 / r.n as f64;
        let d = path_deviation(&r.res.crack, &refp, 1, 400);
        let dh = path_deviation(&r.res.crack, &refh, 1, 400);
        let k: Vec<String> = turning_angles(&r.res.crack, 1)
            .iter()
            .take(8)
            .map(|a| format!("{:+.1}", a.to_degrees()))
            .collect();
        let steps = r.res.history.len() - 1;
        let rule = KinkRule::from_name(r.rule).expect("a rule");
        let solves = 1 + (steps - 1) * rule.solves_per_step();
        println!(
            "| x{} | {h:.4} | {:.4} | {} | {steps} | {solves} | {:.2} | {:.3} | {:.3} | {:.3} | {:.3} | {:.3} | {:.4} | {} |",
            r.n,
            r.da,
            r.rule,
            r.secs,
            d.mean / h,
            d.max / h,
            dh.mean / h,
            dh.max / h,
            d.length,
            mean_mixity(&r.res),
            k.join(" ")
        );
    }
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let which = args.first().map_or("all", String::as_str);
    let fine = args.iter().any(|a| a == "fine");
    if which == "all" || which == "inclined" {
        study(
            "30-degree edge crack, paper plate, tension",
            inclined,
            0.25,
            fine,
        );
    }
    if which == "all" || which == "shear" {
        study("edge crack under shear (edge_shear)", shear, 0.25, fine);
    }
}
