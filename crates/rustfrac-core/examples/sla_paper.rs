//! The paper's CCM-PD case, fast SLA, 500 steps (set-up included), as one process for
//! whole-process timing: `cargo run --release --example sla_paper [-- --dump DIR]`.
//!
//! With `--dump DIR` it writes instead the coupled splice matrix on the free dofs (the matrix the
//! oracle factorises with sparse LU) as raw little-endian CSC arrays `DIR/{col_ptr,row_idx}.u64`,
//! `DIR/val.f64` and `DIR/n.txt`, for `benches/bench_sla_superlu.py` (scipy SuperLU).
use rustfrac_core::la::Reduction;
use rustfrac_core::pd::analysis::run;
use rustfrac_core::pd::analysis::splice_model;
use rustfrac_core::problem::Problem;
use std::io::Write;
use std::time::Instant;

fn write_raw(path: std::path::PathBuf, bytes: impl Iterator<Item = [u8; 8]>) {
    let mut f = std::io::BufWriter::new(std::fs::File::create(&path).expect("create"));
    for b in bytes {
        f.write_all(&b).expect("write");
    }
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let mut p = Problem::paper("ccm_pd");
    p.pd_mut().sla.max_steps = 500;
    if let Some(i) = args.iter().position(|a| a == "--dump") {
        let dir = std::path::PathBuf::from(args.get(i + 1).expect("--dump DIR"));
        std::fs::create_dir_all(&dir).expect("mkdir");
        let model = splice_model(&p).expect("model");
        let k = model.assemble(&model.precrack_broken);
        let a = Reduction::new(&k, &model.mask)
            .expect("reduction")
            .reduce(&k);
        write_raw(
            dir.join("col_ptr.u64"),
            a.col_ptr.iter().map(|&v| (v as u64).to_le_bytes()),
        );
        write_raw(
            dir.join("row_idx.u64"),
            a.row_idx.iter().map(|&v| (v as u64).to_le_bytes()),
        );
        write_raw(dir.join("val.f64"), a.val.iter().map(|&v| v.to_le_bytes()));
        std::fs::write(dir.join("n.txt"), format!("{}\n", a.nrows)).expect("n.txt");
        println!("coupled matrix: n = {}, nnz = {}", a.nrows, a.nnz());
        return;
    }
    let t = Instant::now();
    let r = run(&p, &|_, _| true).expect("fast run");
    let last = r.history.last().expect("steps");
    println!(
        "fast: {} steps, status {}, setup {:.3} s, SLA {:.3} s, total {:.3} s; step {}: lambda {:.12}, CMOD {:.9}",
        r.history.len(),
        r.run.status,
        r.timings.setup_seconds,
        r.timings.sla_seconds,
        t.elapsed().as_secs_f64(),
        last.step,
        last.lambda,
        last.cmod
    );
}
