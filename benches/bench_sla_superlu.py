"""The paper's CCM-PD SLA (500 steps, set-up included) against ONE scipy SuperLU factorisation
of the same coupled matrix, in the same run.

The Rust side is the ``sla_paper`` example binary (a whole process: model, condensation, 500
steps); the coupled matrix is the splice system on the free dofs (104 912 unknowns), written by
``sla_paper --dump DIR`` and factorised with ``scipy.sparse.linalg.splu`` (SuperLU) with its
default column ordering (COLAMD) and with ``permc_spec="MMD_AT_PLUS_A"`` (minimum degree on
A^T + A, much less fill on this structurally symmetric matrix: the faster, stricter baseline).
The commands alternate ``--repeat`` times; medians and the ratios of medians are printed.

Usage: python benches/bench_sla_superlu.py --bin target/release/examples/sla_paper
                                           [--bin-base OTHER_BINARY] [--repeat 5]
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import tempfile
import time

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla


def load_matrix(d: str) -> sp.csc_matrix:
    n = int(open(os.path.join(d, "n.txt")).read())
    cp = np.fromfile(os.path.join(d, "col_ptr.u64"), dtype="<u8").astype(np.int64)
    ri = np.fromfile(os.path.join(d, "row_idx.u64"), dtype="<u8").astype(np.int64)
    val = np.fromfile(os.path.join(d, "val.f64"), dtype="<f8")
    return sp.csc_matrix((val, ri, cp), shape=(n, n))


def time_cmd(cmd: list[str]) -> float:
    t = time.perf_counter()
    subprocess.run(cmd, check=True, capture_output=True)
    return time.perf_counter() - t


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--bin", required=True, help="the sla_paper example binary")
    ap.add_argument("--bin-base", help="a second sla_paper binary (a baseline commit)")
    ap.add_argument("--repeat", type=int, default=5)
    a = ap.parse_args()
    with tempfile.TemporaryDirectory() as d:
        subprocess.run([a.bin, "--dump", d], check=True, capture_output=True)
        k = load_matrix(d)
    b = np.ones(k.shape[0])
    specs = {"superlu_colamd": "COLAMD", "superlu_mmd": "MMD_AT_PLUS_A"}
    rows: dict[str, list[float]] = {"rust": [], **{key: [] for key in specs}}
    if a.bin_base:
        rows["rust_base"] = []
    time_cmd([a.bin])  # warm-up
    for _ in range(a.repeat):
        rows["rust"].append(time_cmd([a.bin]))
        if a.bin_base:
            rows["rust_base"].append(time_cmd([a.bin_base]))
        for key, spec in specs.items():
            t = time.perf_counter()
            lu = spla.splu(k, permc_spec=spec)
            rows[key].append(time.perf_counter() - t)
            assert np.isfinite(lu.solve(b)).all()
            del lu
    med = {key: statistics.median(v) for key, v in rows.items()}
    print(f"coupled matrix n = {k.shape[0]}, nnz = {k.nnz}; load average {os.getloadavg()}")
    for key, v in rows.items():
        print(f"{key:10s} median {med[key]:.3f} s  (min {min(v):.3f}, max {max(v):.3f})")
    for key in specs:
        print(f"rust / {key} (medians): {med['rust'] / med[key]:.2f}")
        if a.bin_base:
            print(f"rust_base / {key}: {med['rust_base'] / med[key]:.2f}")
    if a.bin_base:
        print(f"rust / rust_base: {med['rust'] / med['rust_base']:.2f}")


if __name__ == "__main__":
    main()
