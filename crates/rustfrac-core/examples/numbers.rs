//! Prints the numbers the restructurings must not change, as exact bit patterns (hex of each f64),
//! so that two commits can be compared with `diff`:
//! `cargo run --release -p rustfrac-core --example numbers > numbers.txt`.
//!
//! Covers the FEM plate (every grip, uncracked and seam), XFEM (paper case, single solve and
//! growth on 44 x 83, two cracks), CCM-PD (the paper's 500 SLA steps, fast solver) and pure PD and
//! the oracle on a coarse grid.
use rustfrac_core::fem_driver;
use rustfrac_core::pd::analysis;
use rustfrac_core::problem::Side;
use rustfrac_core::problem::{CrackSpec, Growth, Problem, SlaEngine, SlaParams};
use rustfrac_core::problem::{Grip, PlateLoad};
use rustfrac_core::xfem;

fn h(v: f64) -> String {
    format!("{:016x}", v.to_bits())
}

fn hs(v: &[f64]) -> String {
    // a digest of a long vector: the bits of every entry, folded (FNV-1a)
    let mut x: u64 = 0xcbf29ce484222325;
    for &e in v {
        x ^= e.to_bits();
        x = x.wrapping_mul(0x100000001b3);
    }
    format!("{x:016x}[{}]", v.len())
}

fn fem() {
    for grip in [Grip::Free, Grip::Clamped, Grip::Traction] {
        for seam in [false, true] {
            let mut p = Problem::paper("fem").with_grip(grip);
            p.fem_mut().grid.ny = 84;
            if !seam {
                p.cracks.clear();
            }
            let r = fem_driver::run(&p).unwrap();
            println!(
                "fem {} seam={:?}: sigma22 {} cmod {} energy {} u {} anchor {} cond {:?}",
                grip.name(),
                seam,
                h(r.sigma22),
                h(r.cmod),
                h(r.energy),
                hs(&r.u),
                r.anchor_node,
                r.condition.map(|c| h(c.value()))
            );
        }
    }
}

fn xfem_case(name: &str, p: &Problem) {
    let r = xfem::run(p, &|_, _| true).unwrap();
    println!(
        "xfem {name}: K_I {} K_II {} J {} Jd {} sigma22 {} cmod {} u {} status {} n_dofs {}",
        h(r.k_i),
        h(r.k_ii),
        h(r.j_from_k),
        h(r.j_domain),
        h(r.sigma22),
        h(r.cmod),
        hs(&r.u),
        r.status.name(),
        r.n_dofs
    );
    for s in &r.radii {
        println!(
            "  radius {} K_I {} K_II {}",
            h(s.factor),
            h(s.sifs.k_i),
            h(s.sifs.k_ii)
        );
    }
    for (k, s) in r.history.iter().enumerate() {
        println!(
            "  step {k}: lambda {} s22 {} cmod {} a {} K_I {} K_II {} kink {} tip {} {}",
            h(s.lambda),
            h(s.sigma22),
            h(s.cmod),
            h(s.a),
            h(s.k_i),
            h(s.k_ii),
            h(s.kink_angle),
            h(s.tip[0]),
            h(s.tip[1])
        );
    }
}

/// Growth with the paper's G0 and one element length per step.
fn growth(a_stop: f64, max_steps: usize) -> Option<Growth> {
    Some(Growth {
        max_steps,
        da: None,
        a_stop,
        kink_rule: rustfrac_core::problem::KinkRule::Hoop,
        state_every: 0,
    })
}

fn xfem_cases() {
    let paper = |grip| Problem::paper("xfem").with_grip(grip);
    for grip in [Grip::Free, Grip::Clamped, Grip::Traction] {
        xfem_case(grip.name(), &paper(grip));
    }
    let mut g = paper(Grip::Free);
    g.xfem_mut().growth = growth(0.7 * 11.0, 1000);
    xfem_case("growth", &g);
    // a0 and the angle put the tip exactly at (1.5, 10.8), the polyline of earlier commits
    let mut inclined = paper(Grip::Clamped);
    inclined.cracks[0] = CrackSpec {
        a0: 1.7,
        y: 10.0,
        angle: 28.07248693585296,
        ..inclined.cracks[0]
    };
    assert_eq!(
        inclined.crack_polylines()[0],
        vec![[0.0, 10.0], [1.5, 10.8]]
    );
    inclined.xfem_mut().growth = growth(4.0, 20);
    xfem_case("inclined growth", &inclined);
    // 11 - 9.9 is exact, so the second crack's tip is exactly at x1 = 9.9
    let mut two = paper(Grip::Free);
    two.cracks.push(CrackSpec {
        side: Side::Right,
        a0: 11.0 - 9.9,
        ..two.cracks[0]
    });
    assert_eq!(two.crack_polylines()[1], vec![[11.0, 10.5], [9.9, 10.5]]);
    two.xfem_mut().growth = growth(3.0, 10);
    xfem_case("two cracks", &two);
}

fn sla_case(name: &str, p: &Problem) {
    let r = analysis::run(p, &|_, _| true).unwrap();
    println!(
        "sla {name}: gamma {} c {} s0 {} sigma22 {} cmod {} u {} ufinal {} status {} n_dofs {} bonds {}",
        h(r.constants.pd.gamma),
        h(r.constants.pd.c),
        h(r.constants.pd.s0),
        h(r.reference.sigma22),
        h(r.reference.cmod),
        hs(&r.reference.u),
        hs(&r.final_state.u),
        r.run.status,
        r.counts.n_dofs,
        r.counts.n_bonds
    );
    let lam: Vec<f64> = r.history.iter().map(|s| s.lambda).collect();
    let s22: Vec<f64> = r.history.iter().map(|s| s.sigma22).collect();
    let cm: Vec<f64> = r.history.iter().map(|s| s.cmod).collect();
    let cl: Vec<f64> = r.history.iter().map(|s| s.crack_length).collect();
    let bonds: Vec<f64> = r
        .history
        .iter()
        .flat_map(|s| s.bonds.iter().map(|&b| b as f64))
        .collect();
    println!(
        "  history lambda {} s22 {} cmod {} crack {} bonds {} damage {}",
        hs(&lam),
        hs(&s22),
        hs(&cm),
        hs(&cl),
        hs(&bonds),
        hs(&r.final_state.damage)
    );
}

fn sla_cases() {
    sla_case("paper 500", &Problem::paper("ccm_pd"));
    let mut clamped = Problem::paper("ccm_pd");
    clamped.load_mut().grip = Grip::Clamped;
    clamped.pd_mut().sla.max_steps = 100;
    sla_case("paper clamped 100", &clamped);
    // dx = 1/3: the pre-crack x2 = 10.5 lies midway between node rows (dx = 0.25 or 0.5 would put
    // it on a row, which the model refuses)
    let mut coarse = Problem::paper("ccm_pd");
    coarse.pd_mut().dx = 1.0 / 3.0;
    coarse.pd_mut().m = 3;
    coarse.pd_mut().regions = vec![[0.0, 8.5, 5.0, 12.5]];
    for fast in [true, false] {
        let mut p = coarse.clone();
        p.pd_mut().sla = SlaParams {
            max_steps: 60,
            engine: if fast {
                SlaEngine::Auto
            } else {
                SlaEngine::Oracle
            },
            ..SlaParams::default()
        };
        sla_case(&format!("coarse fast={fast}"), &p);
    }
    let mut pure = Problem::paper("pd");
    pure.pd_mut().dx = 1.0 / 3.0;
    pure.pd_mut().m = 3;
    *pure.load_mut() = PlateLoad {
        grip: Grip::Traction,
        u0: 0.0,
        traction: 9.993,
    };
    pure.pd_mut().sla.max_steps = 40;
    sla_case("pure pd traction", &pure);
}

fn main() {
    fem();
    xfem_cases();
    sla_cases();
}
