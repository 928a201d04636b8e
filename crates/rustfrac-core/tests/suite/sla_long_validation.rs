//! Long SLA runs: bounded solver memory over thousands of steps, nodes detached
//! during the run, checkpoints and bit-for-bit resume, refusal of foreign or corrupt checkpoints.

use crate::common;
use rustfrac_core::pd::analysis::run;

use common::{coarse, go_on};
use rustfrac_core::pd::cost::auto_refactor_every;
use rustfrac_core::pd::sla::checkpoint;
use rustfrac_core::pd::sla::CcmPdResult;
use rustfrac_core::problem::{Probe, ProbeKind, Problem};
use rustfrac_core::Error;
use rustfrac_core::WarningKind;
use std::path::PathBuf;

fn tmpdir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("rustfrac-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Thousands of steps on the coarse plate: the fast solver never holds more update vectors than
/// its re-condensation interval (automatic: n_P / 2), so its memory does not grow with the steps;
/// the history holds one small row per step and no displacement field. The first steps agree with
/// an unbounded run (no re-condensation) and the oracle.
#[test]
fn long_run_keeps_the_solver_memory_bounded() {
    let n = 3000;
    let r = run(&coarse(true, n), &go_on).unwrap();
    let n_updates: usize = r.history.iter().map(|s| s.bonds.len()).sum::<usize>()
        + r.final_state
            .detached_nodes
            .iter()
            .filter(|d| d.0 > 0)
            .count();
    let np = 2 * r.counts.n_pd_nodes; // upper bound of the free PD dofs
    println!(
        "{} steps ({}), {} PD nodes, {} bonds; re-condensation every {} updates (auto), {} condensations, at most {} update vectors held; {} updates ({} groundings of detached nodes); SLA {:.2} s; peak RSS {:.0} MB; history row {} B + bonds",
        r.history.len(),
        r.run.status,
        r.counts.n_pd_nodes,
        r.counts.n_bonds,
        r.run.solver.refactor_interval,
        r.work.n_refactorisations,
        r.work.max_update_rank,
        n_updates,
        r.final_state.detached_nodes.len(),
        r.timings.sla_seconds,
        r.timings.peak_memory_bytes.unwrap_or(0) as f64 / 1e6,
        std::mem::size_of::<rustfrac_core::pd::sla::SlaStep>()
    );
    assert_eq!(r.history.len(), n, "{}", r.run.status);
    assert!(r.run.solver.refactor_interval <= auto_refactor_every(np));
    assert!(r.run.solver.refactor_interval >= 64);
    // the bound holds and is reached: the update vectors are recycled, not accumulated
    assert!(r.work.max_update_rank <= r.run.solver.refactor_interval);
    assert_eq!(r.work.max_update_rank, r.run.solver.refactor_interval);
    assert!(r.work.n_refactorisations > (n_updates - 1) / r.run.solver.refactor_interval);
    // the final state is a regular solution
    assert!(r.final_state.u.iter().all(|v| v.is_finite()));

    // first 400 steps: automatic re-condensation = no re-condensation = oracle (to 1e-8)
    let m = 400;
    let mut p = coarse(true, m);
    p.pd_mut().sla.refactor_every = 1_000_000;
    let unbounded = run(&p, &go_on).unwrap();
    let oracle = run(&coarse(false, m), &go_on).unwrap();
    assert_eq!(unbounded.work.max_update_rank, m);
    let mut worst = 0.0f64;
    for k in 0..m {
        let (a, b, c) = (&r.history[k], &unbounded.history[k], &oracle.history[k]);
        assert_eq!(a.bonds, c.bonds, "step {}", k + 1);
        assert_eq!(b.bonds, c.bonds, "step {}", k + 1);
        for (x, y) in [
            (a.lambda, c.lambda),
            (b.lambda, c.lambda),
            (a.sigma22, c.sigma22),
        ] {
            worst = worst.max((x - y).abs() / y.abs());
        }
    }
    println!("first {m} steps: worst relative difference to the oracle {worst:.2e}");
    assert!(worst < 1e-8);
}

/// With m = 2 and ties within 1e-6 broken together, a node of the rectangle loses its last bonds
/// across the load (keeps only parallel ones) after about 700 steps, while the plate still carries
/// load (lambda within 100 x the first step's; later, near 1300 steps, the shredded rectangle is a
/// mechanism with lambda ~ 1e10 and whether a node detaches before the run separates depends on
/// round-off). The node is grounded, reported, and the run goes on with a regular system and
/// finite numbers (before this, the first such node ended the run as "separated").
#[test]
fn nodes_detached_during_the_sla_are_grounded() {
    let mut p = coarse(true, 800);
    p.pd_mut().m = 2;
    p.pd_mut().sla.tie_tol = 1e-6;
    let r = run(&p, &go_on).unwrap();
    let during: Vec<_> = r
        .final_state
        .detached_nodes
        .iter()
        .filter(|d| d.0 > 0)
        .collect();
    println!(
        "m = 2: {} after {} steps; detached during the SLA (step, node): {:?}; warnings {:?}",
        r.run.status,
        r.history.len(),
        during,
        r.warnings
    );
    assert!(!during.is_empty());
    let first = during[0].0;
    let (l1, lf) = (r.history[0].lambda, r.history[first - 1].lambda);
    assert!(
        lf < 100.0 * l1,
        "lambda {lf} at the detachment, {l1} at step 1"
    );
    assert!(
        r.history.len() > first,
        "the run went on after step {first}"
    );
    for &&(step, node) in &during {
        assert!(r.history[step - 1].detached.contains(&node));
    }
    assert!(r
        .history
        .iter()
        .all(|s| s.lambda.is_finite() && s.sigma22.is_finite() && s.cmod.is_finite()));
    assert!(r
        .warnings
        .iter()
        .any(|w| w.kind == WarningKind::Discretisation && w.message.contains("grounded")));
}

fn same(a: &CcmPdResult, b: &CcmPdResult) {
    assert_eq!(a.history.len(), b.history.len());
    for (x, y) in a.history.iter().zip(&b.history) {
        // exact equality, bit for bit
        assert_eq!(x, y);
        assert_eq!(x.lambda.to_bits(), y.lambda.to_bits());
        assert_eq!(x.sigma22.to_bits(), y.sigma22.to_bits());
        assert_eq!(x.cmod.to_bits(), y.cmod.to_bits());
    }
    assert_eq!(a.run.status, b.run.status);
    assert_eq!(a.final_state.broken, b.final_state.broken);
    assert_eq!(a.final_state.damage, b.final_state.damage);
    assert_eq!(a.final_state.detached_nodes, b.final_state.detached_nodes);
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&a.final_state.u), bits(&b.final_state.u));
}

/// 2N + k steps straight against N steps with checkpoints every N, stopped (step limit, and a
/// cancel from the progress callback), then resumed: the same history bit for bit, for the fast
/// solver (re-condensing every 25 updates, so the replay crosses re-condensations) and the oracle.
#[test]
fn checkpoint_and_resume_are_bit_for_bit() {
    let dir = tmpdir("ckpt");
    for (fast, n, k) in [(true, 40usize, 7usize), (false, 6, 3)] {
        let total = 2 * n + k;
        let mut base = coarse(fast, total);
        base.pd_mut().sla.refactor_every = 25;
        base.pd_mut().sla.damage_at_steps = vec![n / 2, n + 1, total];
        // probes ride in the history (and in the checkpoint, version 2)
        base.probes = vec![
            Probe {
                name: "mouth".into(),
                kind: ProbeKind::Opening {
                    point: [0.0, 10.5],
                    crack: 0,
                },
            },
            Probe {
                name: "corner".into(),
                kind: ProbeKind::Displacement([11.0, 21.0]),
            },
        ];
        let straight = run(&base, &go_on).unwrap();
        assert_eq!(straight.history.len(), total);
        let path = dir.join(format!("run-{fast}.ckpt"));

        // (a) stopped by the step limit at N + 5: the last checkpoint is the one after step N
        let mut p = base.clone();
        p.pd_mut().sla.max_steps = n + 5;
        p.pd_mut().sla.checkpoint_every = n;
        p.pd_mut().sla.checkpoint_path = Some(path.clone());
        let first = run(&p, &go_on).unwrap();
        assert_eq!(first.run.n_checkpoints, 1);
        let mut q = base.clone();
        q.pd_mut().sla.resume_from = Some(path.clone());
        let resumed = run(&q, &go_on).unwrap();
        assert_eq!(resumed.run.resumed_steps, n);
        same(&straight, &resumed);
        assert_eq!(
            straight.final_state.damage_at,
            resumed.final_state.damage_at
        );

        // (b) cancelled from the progress callback after step N + 2: a checkpoint is written then
        let stop = n + 2;
        let cancel = move |s: usize, _: usize| s < stop;
        let c = run(&p, &cancel).unwrap();
        assert_eq!(c.run.status.name(), "cancelled");
        assert_eq!(c.history.len(), stop);
        assert_eq!(c.run.n_checkpoints, 2);
        let resumed = run(&q, &go_on).unwrap();
        assert_eq!(resumed.run.resumed_steps, stop);
        same(&straight, &resumed);
        println!(
            "fast = {fast}: {total} steps straight = checkpoint at {n} / cancel at {stop} + resume, bit for bit ({} condensations straight)",
            straight.work.n_refactorisations
        );
        // written atomically: no temporary file is left next to the checkpoint
        let names: Vec<_> = std::fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().into_string().unwrap())
            .collect();
        assert!(names.iter().all(|f| !f.contains(".tmp")), "{names:?}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn foreign_or_corrupt_checkpoints_are_refused() {
    let dir = tmpdir("ckpt-bad");
    let path = dir.join("a.ckpt");
    let mut p = coarse(true, 12);
    p.pd_mut().sla.checkpoint_every = 10;
    p.pd_mut().sla.checkpoint_path = Some(path.clone());
    run(&p, &go_on).unwrap();
    let expect_refusal = |q: Problem, what: &str| match run(&q, &go_on) {
        Err(Error::InvalidInput {
            param, expected, ..
        }) => {
            assert_eq!(param, "pd.resume_from");
            assert!(expected.contains(what), "{expected}");
            println!("refused ({what}): {expected}");
        }
        other => panic!("{what}: {:?}", other.map(|r| r.run.status)),
    };
    // a different model (horizon) and a different solver option: refused
    let mut q = coarse(true, 20);
    q.pd_mut().sla.resume_from = Some(path.clone());
    q.pd_mut().m = 3;
    expect_refusal(q, "different");
    let mut q = coarse(true, 20);
    q.pd_mut().sla.resume_from = Some(path.clone());
    q.pd_mut().sla.refactor_every = 7;
    expect_refusal(q, "different");
    // the same model resumes (and may change the step limit)
    let mut q = coarse(true, 20);
    q.pd_mut().sla.resume_from = Some(path.clone());
    assert_eq!(run(&q, &go_on).unwrap().run.resumed_steps, 10);
    // a flipped byte: checksum
    let mut bytes = std::fs::read(&path).unwrap();
    let mid = bytes.len() / 2;
    bytes[mid] ^= 0x40;
    let bad = dir.join("bad.ckpt");
    std::fs::write(&bad, &bytes).unwrap();
    let mut q = coarse(true, 20);
    q.pd_mut().sla.resume_from = Some(bad.clone());
    expect_refusal(q, "intact");
    // not a checkpoint at all
    std::fs::write(&bad, b"hello, this is not a checkpoint at all, really not").unwrap();
    let mut q = coarse(true, 20);
    q.pd_mut().sla.resume_from = Some(bad);
    expect_refusal(q, "checkpoint file");
    // missing file: an I/O error naming the path
    let mut q = coarse(true, 20);
    q.pd_mut().sla.resume_from = Some(dir.join("missing.ckpt"));
    assert!(
        matches!(run(&q, &go_on), Err(Error::Io { path, .. }) if path.contains("missing.ckpt"))
    );
    // checkpoint_every without a path
    let mut q = coarse(true, 20);
    q.pd_mut().sla.checkpoint_every = 5;
    assert!(
        matches!(run(&q, &go_on), Err(Error::InvalidInput { param, .. }) if param == "pd.checkpoint_path")
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// The checkpoint fingerprint of the paper's parameters is pinned (a fixed byte sequence of the
/// scene's physics and solver keys, floats by their bits: the same on every run and platform). It
/// follows the model and the solver options, not the step limit or the checkpoint options.
#[test]
fn checkpoint_fingerprint_is_stable() {
    let p = Problem::paper("ccm_pd");
    let fp = |q: &Problem| checkpoint::fingerprint(q, &q.pd_precrack(), 1000, 2000);
    assert_eq!(fp(&p), PAPER_FINGERPRINT, "{:016x}", fp(&p));
    let mut q = p.clone();
    q.pd_mut().sla.max_steps = 7;
    q.pd_mut().sla.checkpoint_every = 3;
    assert_eq!(fp(&q), fp(&p));
    let mut q = p.clone();
    q.pd_mut().m = 3;
    assert_ne!(fp(&q), fp(&p));
    let mut q = p.clone();
    q.pd_mut().sla.tie_tol = 1e-9;
    assert_ne!(fp(&q), fp(&p));
}

/// [`checkpoint_fingerprint_is_stable`]'s pin.
const PAPER_FINGERPRINT: u64 = 0xec6d_ac1f_20e3_0896;

/// FNV-1a 64 of `b` (the checkpoint checksum, written out here independently of the crate).
fn fnv(b: &[u8]) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for &x in b {
        h ^= x as u64;
        h = h.wrapping_mul(0x0100_0000_01b3);
    }
    h
}

/// `bytes` with the word at byte offset `at` replaced by `word` and the checksum recomputed: a
/// crafted checkpoint that passes the integrity check.
fn crafted(bytes: &[u8], at: usize, word: u64) -> Vec<u8> {
    let mut b = bytes[..bytes.len() - 8].to_vec();
    b[at..at + 8].copy_from_slice(&word.to_le_bytes());
    let h = fnv(&b);
    b.extend_from_slice(&h.to_le_bytes());
    b
}

/// Hostile checkpoints: a FIFO and a directory are refused before
/// they are opened (no hang), an oversized file before it is read, crafted files with a valid
/// checksum but NaN values or a bond listed twice in a step are refused, a `checkpoint_path`
/// naming an existing non-checkpoint file leaves it untouched, and no temporary file remains.
#[test]
fn hostile_checkpoints_are_refused() {
    let dir = tmpdir("ckpt-hostile");
    let path = dir.join("a.ckpt");
    let mut p = coarse(true, 6);
    p.pd_mut().sla.checkpoint_every = 6;
    p.pd_mut().sla.checkpoint_path = Some(path.clone());
    run(&p, &go_on).unwrap();
    let good = std::fs::read(&path).unwrap();
    let refused = |file: PathBuf, what: &str| {
        let mut q = coarse(true, 10);
        q.pd_mut().sla.resume_from = Some(file);
        let t = std::time::Instant::now();
        match run(&q, &go_on) {
            Err(Error::InvalidInput {
                param, expected, ..
            }) => {
                assert_eq!(param, "pd.resume_from");
                assert!(expected.contains(what), "{what}: {expected}");
                println!(
                    "refused in {:.2} s ({what}): {expected}",
                    t.elapsed().as_secs_f64()
                );
            }
            other => panic!("{what}: {:?}", other.map(|r| r.run.status)),
        }
    };
    // a FIFO (opening it would block) and a directory
    let fifo = dir.join("fifo");
    let made = std::process::Command::new("mkfifo").arg(&fifo).status();
    if made.is_ok_and(|s| s.success()) {
        refused(fifo, "regular");
    }
    refused(dir.clone(), "regular");
    // a file larger than any checkpoint of this model, sparse (nothing is read)
    let big = dir.join("big.ckpt");
    std::fs::File::create(&big)
        .unwrap()
        .set_len(1 << 40)
        .unwrap();
    refused(big.clone(), "at most");
    std::fs::remove_file(&big).unwrap();
    // crafted: after the header (magic 8, version 4, fingerprint 8, step count 8 bytes) step 1
    // holds its number, lambda, sigma22, cmod, u0, crack length, 2 nodes, the bond count and
    // the bonds (8 bytes each); lambda = NaN, then lambda = -1, then the first bond repeated
    let bad = dir.join("bad.ckpt");
    std::fs::write(&bad, crafted(&good, 36, f64::NAN.to_bits())).unwrap();
    refused(bad.clone(), "finite");
    std::fs::write(&bad, crafted(&good, 36, (-1.0f64).to_bits())).unwrap();
    refused(bad.clone(), "positive");
    let count_at = 28 + 8 * 8;
    let n = u64::from_le_bytes(good[count_at..count_at + 8].try_into().unwrap());
    assert_eq!(n, 1, "one bond per step (tie_tol = 0)");
    // make it 2 bonds, the same one twice (insert a copy of the bond word)
    let mut twice = good[..good.len() - 8].to_vec();
    twice[count_at..count_at + 8].copy_from_slice(&2u64.to_le_bytes());
    let bond = twice[count_at + 8..count_at + 16].to_vec();
    twice.splice(count_at + 16..count_at + 16, bond);
    let h = fnv(&twice);
    twice.extend_from_slice(&h.to_le_bytes());
    std::fs::write(&bad, &twice).unwrap();
    refused(bad, "once");
    // checkpoint_path naming a file that is not a checkpoint: refused, the file intact
    let precious = dir.join("notes.txt");
    std::fs::write(&precious, b"not a checkpoint").unwrap();
    let mut q = coarse(true, 4);
    q.pd_mut().sla.checkpoint_every = 2;
    q.pd_mut().sla.checkpoint_path = Some(precious.clone());
    assert!(matches!(
        run(&q, &go_on),
        Err(Error::InvalidInput { param, .. }) if param == "pd.checkpoint_path"
    ));
    assert_eq!(std::fs::read(&precious).unwrap(), b"not a checkpoint");
    // a symlink planted at the old predictable temporary name is not followed
    let target = dir.join("victim");
    std::fs::write(&target, b"victim").unwrap();
    let planted = dir.join(format!(".a.ckpt.tmp{}", std::process::id()));
    std::os::unix::fs::symlink(&target, &planted).unwrap();
    run(&p, &go_on).unwrap();
    assert_eq!(std::fs::read(&target).unwrap(), b"victim");
    assert_eq!(
        std::fs::read(&path).unwrap(),
        good,
        "the same run, the same checkpoint"
    );
    let left: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|f| f.contains(".tmp-"))
        .collect();
    assert!(left.is_empty(), "{left:?}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// A checkpoint written with `pd.hole_volumes = "centre"` does not resume an `"exact"` run (a key
/// the hand-made fingerprint once missed); a changed step limit (an output key) resumes.
#[test]
fn a_centre_checkpoint_does_not_resume_an_exact_run() {
    let dir = tmpdir("ckpt-volumes");
    let path = dir.join("centre.ckpt");
    let mut p = coarse(true, 4);
    p.pd_mut().sla.checkpoint_every = 4;
    p.pd_mut().sla.checkpoint_path = Some(path.clone());
    run(&p, &go_on).unwrap();
    let mut q = coarse(true, 8);
    q.pd_mut().sla.resume_from = Some(path.clone());
    assert_eq!(run(&q, &go_on).unwrap().run.resumed_steps, 4);
    q.pd_mut().hole_volumes = rustfrac_core::problem::HoleVolumes::Exact;
    assert!(matches!(
        run(&q, &go_on),
        Err(Error::InvalidInput { param, expected, .. })
            if param == "pd.resume_from" && expected.contains("fingerprint")
    ));
    let _ = std::fs::remove_dir_all(&dir);
}

/// Checkpoints of the format versions before the schema's fingerprint (1 to 3) are refused
/// with a message saying why, not resumed and not mistaken for another model's. The old files
/// are made here from a current one by changing its version word (the checksum recomputed).
#[test]
fn checkpoints_of_earlier_versions_are_refused() {
    let dir = tmpdir("ckpt-old");
    let path = dir.join("now.ckpt");
    let mut p = coarse(true, 6);
    p.pd_mut().sla.checkpoint_every = 6;
    p.pd_mut().sla.checkpoint_path = Some(path.clone());
    run(&p, &go_on).unwrap();
    let b = std::fs::read(&path).unwrap();
    assert_eq!(
        u32::from_le_bytes(b[8..12].try_into().unwrap()),
        checkpoint::VERSION
    );
    let mut q = coarse(true, 10);
    q.pd_mut().sla.resume_from = Some(path.clone());
    assert_eq!(run(&q, &go_on).unwrap().run.resumed_steps, 6);
    for version in 1..checkpoint::VERSION {
        let mut old = b[..b.len() - 8].to_vec();
        old[8..12].copy_from_slice(&version.to_le_bytes());
        old.extend_from_slice(&fnv(&old).to_le_bytes());
        let file = dir.join(format!("v{version}.ckpt"));
        std::fs::write(&file, &old).unwrap();
        q.pd_mut().sla.resume_from = Some(file);
        match run(&q, &go_on) {
            Err(Error::InvalidInput {
                param, expected, ..
            }) => {
                assert_eq!(param, "pd.resume_from");
                assert!(expected.contains("earlier model fingerprint"), "{expected}");
            }
            other => panic!("version {version}: {:?}", other.map(|r| r.run.status)),
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}
