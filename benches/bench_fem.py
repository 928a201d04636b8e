"""End-to-end FEM benchmark: assemble + factorise + solve the paper's uncracked plate with
rustfrac, scipy.sparse (SuperLU, its default) and CHOLMOD (scikit-sparse), in the same run.

The plate: W = 11, L = 21, E = 10000, nu = 0.25, plane strain, thickness 1, u2 = +-0.01 on the
top/bottom edges, u1 free except at the bottom-right corner node (rustfrac's ``bc="free"``).
Q4 meshes (50, 98), (160, 310), (510, 980) elements: about 1e4, 1e5 and 1e6 unknowns.

Every case runs in its own subprocess, so the peak RSS (``ru_maxrss``) belongs to one solver, and a
case that exceeds ``--timeout`` is killed and reported as "> timeout". Every solver must give
sigma22 = E/(1-nu^2) 2 u0/L to 1e-8 relative; otherwise the benchmark stops with an error.

Solvers:
  rustfrac          ``rustfrac._core.run`` (method fem): the whole pipeline (mesh, assembly,
                    elimination, nested-dissection ordering, faer Cholesky, solve, reactions,
                    Gauss and nodal stresses) in one call; "call" is the Python wall time of the
                    call, "core" the core's own ``wall_time_s``. Includes the condition
                    estimate (2 extra solves).
  rustfrac-nocond   as rustfrac with ``condition=False`` (no condition estimate).
  rust-phases       the core's ``plate_phases`` example binary (same code, per-phase times), used
                    for the rustfrac factorise+solve column; skipped when the binary is absent.
  scipy             vectorised numpy COO assembly, Dirichlet elimination, ``spsolve`` (SuperLU,
                    COLAMD), reactions.
  cholmod           the same assembly and reduced matrix, ``sksparse.cholmod.cholesky`` with its
                    default ordering and the system BLAS.
  cholmod-openblas  as cholmod with OpenBLAS loaded instead of the system BLAS (only with
                    ``--openblas-dir``: a directory holding an OpenBLAS libblas.so.3/liblapack.so.3).

Usage: python benches/bench_fem.py [--sizes small,medium,large] [--repeat 3]
                                   [--out benches/results_fem.json] [--timeout 900]
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import re
import resource
import statistics
import subprocess
import sys
import time
from pathlib import Path

W, L, E, NU, U0 = 11.0, 21.0, 10000.0, 0.25, 0.01
SIGMA_EXACT = E / (1.0 - NU**2) * 2.0 * U0 / L
RTOL = 1e-8
SIZES = {"small": (50, 98), "medium": (160, 310), "large": (510, 980)}
ROOT = Path(__file__).resolve().parent.parent


# --------------------------------------------------------------------------------------------
# workers (each runs in its own process)
# --------------------------------------------------------------------------------------------


def peak_rss_mb() -> float:
    """Peak resident set size of this process in MiB (Linux reports KiB)."""
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def assemble_numpy(nx: int, ny: int):
    """Q4 plate stiffness (CSC, full symmetric) by vectorised COO assembly; one element matrix
    (all elements are equal rectangles; 2 x 2 Gauss is exact for them)."""
    import numpy as np
    import scipy.sparse as sp

    hx, hy = W / nx, L / ny
    c = E / ((1.0 + NU) * (1.0 - 2.0 * NU))
    d = c * np.array([[1.0 - NU, NU, 0.0], [NU, 1.0 - NU, 0.0], [0.0, 0.0, 0.5 - NU]])
    xi_n = np.array([-1.0, 1.0, 1.0, -1.0])
    eta_n = np.array([-1.0, -1.0, 1.0, 1.0])
    g = 1.0 / np.sqrt(3.0)
    ke = np.zeros((8, 8))
    for xi in (-g, g):
        for eta in (-g, g):
            dndx = 0.25 * xi_n * (1.0 + eta_n * eta) * (2.0 / hx)
            dndy = 0.25 * eta_n * (1.0 + xi_n * xi) * (2.0 / hy)
            b = np.zeros((3, 8))
            b[0, 0::2] = dndx
            b[1, 1::2] = dndy
            b[2, 0::2] = dndy
            b[2, 1::2] = dndx
            ke += b.T @ d @ b * (hx * hy / 4.0)
    # nodes row by row from the bottom-left corner: node(i, j) = j (nx + 1) + i
    i, j = np.meshgrid(np.arange(nx), np.arange(ny), indexing="xy")
    n0 = (j * (nx + 1) + i).ravel()
    nodes = np.stack([n0, n0 + 1, n0 + nx + 2, n0 + nx + 1], axis=1)
    n_dofs = 2 * (nx + 1) * (ny + 1)
    idx = np.int32 if n_dofs < 2**31 - 1 else np.int64
    edofs = np.empty((nodes.shape[0], 8), dtype=idx)
    edofs[:, 0::2] = 2 * nodes
    edofs[:, 1::2] = 2 * nodes + 1
    rows = np.repeat(edofs, 8, axis=1).ravel()
    cols = np.tile(edofs, (1, 8)).ravel()
    vals = np.broadcast_to(ke.ravel(), (nodes.shape[0], 64)).ravel()
    k = sp.csc_matrix((vals, (rows, cols)), shape=(n_dofs, n_dofs))  # sums duplicates
    k.sum_duplicates()
    return k


def plate_conditions(nx: int, ny: int):
    """(fixed dofs, their values, top u2 dofs): u2 = -+u0 on bottom/top, u1 = 0 at the
    bottom-right corner node (the anchor of rustfrac's free grips)."""
    import numpy as np

    bottom = np.arange(nx + 1)
    top = ny * (nx + 1) + np.arange(nx + 1)
    anchor = nx
    fixed = np.concatenate([2 * bottom + 1, 2 * top + 1, [2 * anchor]])
    vals = np.concatenate([np.full(nx + 1, -U0), np.full(nx + 1, U0), [0.0]])
    return fixed, vals, 2 * top + 1


def check_sigma(name: str, s22: float) -> float:
    rel = abs(s22 - SIGMA_EXACT) / SIGMA_EXACT
    if not rel <= RTOL:
        raise SystemExit(
            f"FAIL {name}: sigma22 = {s22!r}, exact {SIGMA_EXACT!r}, relative error {rel:.3e} > {RTOL}"
        )
    return rel


def loaded_blas() -> list[str]:
    """The BLAS/LAPACK shared libraries mapped into this process (to confirm which BLAS CHOLMOD
    uses; numpy's own OpenBLAS is listed too)."""
    try:
        with open("/proc/self/maps") as f:
            return sorted(
                {ln.split()[-1] for ln in f if "blas" in ln.lower() or "lapack" in ln.lower()}
            )
    except OSError:
        return []


def work_rustfrac(nx: int, ny: int, condition: bool = True) -> dict:
    from rustfrac import _core

    c0, t0 = time.process_time(), time.perf_counter()
    scene = {
        "method": "fem",
        "plate": {"width": W, "height": L},
        "mesh": {"nx": nx, "ny": ny},
        "material": {"E": E, "nu": NU, "plane": "strain"},
        "load": {"bc": "free", "u0": U0},
        "crack": {"kind": "none"},
    }
    r = _core.run(scene, None, condition)
    call = time.perf_counter() - t0
    cpu = time.process_time() - c0
    rel = check_sigma("rustfrac", float(r["sigma22"]))
    return {
        "n_dofs": int(r["n_dofs"]),
        "total_s": call,
        "core_s": float(r["wall_time_s"]),
        "cpu_s": cpu,
        "sigma22": float(r["sigma22"]),
        "sigma22_rel_err": rel,
        "residual": float(r["residual"]),
    }


def find_phases_bin() -> Path | None:
    for base in (os.environ.get("CARGO_TARGET_DIR"), str(ROOT / "target"), "/work/target"):
        if base:
            p = Path(base) / "release" / "examples" / "plate_phases"
            if p.is_file():
                return p
    return None


def work_rust_phases(nx: int, ny: int, binary: str) -> dict:
    """Runs the core's plate_phases example and parses its per-phase times."""
    t0 = time.perf_counter()
    out = subprocess.run([binary, str(nx), str(ny)], capture_output=True, text=True, check=True)
    wall = time.perf_counter() - t0
    ph = {m[1]: float(m[2]) for m in re.finditer(r"^\s*(\w+): ([0-9.eE+-]+) s$", out.stdout, re.M)}
    nnz = re.search(r"factor nnz (\d+)", out.stdout)
    ru = resource.getrusage(resource.RUSAGE_CHILDREN)
    return {
        "assemble_s": ph["pattern"] + ph["assemble"],
        "reduce_s": ph["reduce"] + ph.get("gather", 0.0),
        "symbolic_s": ph["symbolic"],
        "numeric_s": ph["numeric"],
        "solve_s": ph["solve"],
        "factor_solve_s": ph["symbolic"] + ph["numeric"] + ph["solve"],
        "post_s": ph["post"],
        "total_s": sum(ph.values()),
        "process_wall_s": wall,
        "factor_nnz": int(nnz[1]) if nnz else None,
        "phases": ph,
        "cpu_s": ru.ru_utime + ru.ru_stime,
        "peak_rss_mb_override": ru.ru_maxrss / 1024.0,
    }


def work_sparse(nx: int, ny: int, solver: str) -> dict:
    import numpy as np
    import scipy.sparse  # noqa: F401 - imported before the clock starts
    from scipy.sparse.linalg import spsolve

    if solver == "cholmod":
        from sksparse.cholmod import analyze

    c0, t0 = time.process_time(), time.perf_counter()
    k = assemble_numpy(nx, ny)
    t1 = time.perf_counter()
    fixed, fvals, top_u2 = plate_conditions(nx, ny)
    n = k.shape[0]
    mask = np.ones(n, dtype=bool)
    mask[fixed] = False
    free = np.flatnonzero(mask)
    kf = k[:, free]
    kff = kf[free, :].tocsc()
    rhs = -(k[:, fixed][free, :] @ fvals)
    t2 = time.perf_counter()
    extra = {}
    if solver == "scipy":
        x = spsolve(kff, rhs)
        t3 = time.perf_counter()
    else:
        fac = analyze(kff)
        ta = time.perf_counter()
        fac.cholesky_inplace(kff)
        tf = time.perf_counter()
        x = fac(rhs)
        t3 = time.perf_counter()
        extra = {"analyze_s": ta - t2, "numeric_s": tf - ta, "solve_s": t3 - tf}
        extra["blas_libs"] = loaded_blas()
    u = np.zeros(n)
    u[free] = x
    u[fixed] = fvals
    reactions = k @ u  # no applied forces
    s22 = float(reactions[top_u2].sum() / W)
    t4 = time.perf_counter()
    cpu = time.process_time() - c0
    rel = check_sigma(solver, s22)
    resid = float(np.linalg.norm(kff @ x - rhs) / np.linalg.norm(rhs))
    return {
        "n_dofs": int(n),
        "n_free": int(free.size),
        "assemble_s": t1 - t0,
        "reduce_s": t2 - t1,
        "factor_solve_s": t3 - t2,
        "post_s": t4 - t3,
        "total_s": t4 - t0,
        "cpu_s": cpu,
        "sigma22": s22,
        "sigma22_rel_err": rel,
        "residual": resid,
        **extra,
    }


def worker(args: argparse.Namespace) -> None:
    if args.mem_limit_gb > 0:
        lim = int(args.mem_limit_gb * 2**30)
        resource.setrlimit(resource.RLIMIT_AS, (lim, lim))
    nx, ny = args.nx, args.ny
    load0 = os.getloadavg()[0]
    try:
        if args.worker in ("rustfrac", "rustfrac-nocond"):
            res = work_rustfrac(nx, ny, condition=args.worker == "rustfrac")
        elif args.worker == "rust-phases":
            res = work_rust_phases(nx, ny, args.phases_bin)
        else:
            res = work_sparse(nx, ny, args.worker)
    except MemoryError as e:
        res = {"error": f"out of memory (limit {args.mem_limit_gb} GiB): {e}"}
    res["peak_rss_mb"] = res.pop("peak_rss_mb_override", None) or peak_rss_mb()
    res["load1_start"] = load0
    res["load1_end"] = os.getloadavg()[0]
    print("RESULT " + json.dumps(res), flush=True)


# --------------------------------------------------------------------------------------------
# driver
# --------------------------------------------------------------------------------------------


def run_case(args, solver: str, nx: int, ny: int) -> dict:
    cmd = [
        sys.executable,
        str(Path(__file__).resolve()),
        "--worker",
        solver,
        "--nx",
        str(nx),
        "--ny",
        str(ny),
        "--mem-limit-gb",
        str(args.mem_limit_gb),
    ]
    env = dict(os.environ)
    if solver == "rust-phases":
        cmd += ["--phases-bin", str(args.phases_bin)]
    if solver == "cholmod-openblas":
        cmd[cmd.index("--worker") + 1] = "cholmod"
        env["LD_LIBRARY_PATH"] = str(Path(args.openblas_dir).resolve()) + (
            ":" + env["LD_LIBRARY_PATH"] if env.get("LD_LIBRARY_PATH") else ""
        )
    try:
        p = subprocess.run(cmd, capture_output=True, text=True, timeout=args.timeout, env=env)
    except subprocess.TimeoutExpired:
        return {"timeout": True}
    line = next((s for s in p.stdout.splitlines() if s.startswith("RESULT ")), None)
    if p.returncode != 0 or line is None:
        sys.stderr.write(p.stdout + p.stderr)
        raise SystemExit(f"FAIL: {solver} at ({nx}, {ny}) exited with {p.returncode}")
    return json.loads(line[len("RESULT ") :])


def med(runs: list[dict], key: str) -> float | None:
    v = [r[key] for r in runs if r.get(key) is not None]
    return statistics.median(v) if v else None


def fmt(v, nd=2) -> str:
    if v is None:
        return "-"
    if isinstance(v, str):
        return v
    return f"{v:.{nd}f}" if v < 100 else f"{v:.0f}"


BASELINES = ("scipy", "cholmod", "cholmod-openblas")
KEYS = ("assemble_s", "reduce_s", "factor_solve_s", "total_s", "cpu_s", "core_s", "peak_rss_mb")


def case_stats(runs: list[dict]) -> dict | None:
    """Medians over the repeats of one case, or its timeout / error."""
    if not runs:
        return None
    if any(r.get("timeout") for r in runs):
        return {"timeout": True}
    err = next((r["error"] for r in runs if "error" in r), None)
    if err:
        return {"error": err}
    st = {k: med(runs, k) for k in KEYS}
    if st["assemble_s"] is not None:
        st["asm"] = st["assemble_s"] + (st["reduce_s"] or 0.0)
    st["n"] = len(runs)
    return st


def summarise(results: dict, solvers: list[str], timeout: float) -> str:
    """Markdown: the medians per case, then the ratios against rustfrac."""
    lines = [
        "| size | unknowns (free) | solver | runs | assemble+reduce [s] | factorise+solve [s] "
        "| total [s] | CPU [s] | peak RSS [MiB] |",
        "|---|---|---|---:|---:|---:|---:|---:|---:|",
    ]
    ratio_lines = [
        "| size | baseline | baseline / rustfrac, total | baseline / rustfrac, factorise+solve |",
        "|---|---|---:|---:|",
    ]
    for size, res in results.items():
        stats = {s: case_stats(res.get(s, [])) for s in solvers}
        first = [r for runs in res.values() for r in runs if r.get("n_dofs")]
        n_dofs = first[0]["n_dofs"] if first else "?"
        n_free = next((r["n_free"] for r in first if r.get("n_free")), "?")
        for s in solvers:
            st = stats[s]
            if st is None:
                continue
            label = {
                "rustfrac": "rustfrac `_core.run` (call)",
                "rustfrac-nocond": "rustfrac `_core.run(condition=False)` (call)",
                "rust-phases": "rustfrac phases (`plate_phases` example)",
            }.get(s, s)
            if s.startswith("rustfrac") and st.get("core_s") is not None:
                label += f"; core {fmt(st['core_s'])} s"
            if st.get("timeout"):
                row = ["-", "-", "-", f"> {timeout:g}", "-", "-"]
            elif st.get("error"):
                row = ["-", "-", "-", st["error"], "-", "-"]
            else:
                row = [
                    str(st["n"]),
                    fmt(st.get("asm")),
                    fmt(st.get("factor_solve_s")),
                    fmt(st["total_s"]),
                    fmt(st.get("cpu_s")),
                    fmt(st["peak_rss_mb"], 0),
                ]
            lines.append(f"| {size} | {n_dofs} ({n_free}) | {label} | " + " | ".join(row) + " |")
        rust_tot = (stats.get("rustfrac") or {}).get("total_s")
        rust_fs = (stats.get("rust-phases") or {}).get("factor_solve_s")
        for base in BASELINES:
            b = stats.get(base)
            if b is None:
                continue
            if b.get("timeout"):
                tot = f"> {timeout / rust_tot:.1f}" if rust_tot else "-"
                fs = f"> {timeout / rust_fs:.1f}" if rust_fs else "-"
            elif b.get("error"):
                tot = fs = "-"
            else:
                tot = fmt(b["total_s"] / rust_tot) if rust_tot else "-"
                fs = fmt(b["factor_solve_s"] / rust_fs) if rust_fs else "-"
            ratio_lines.append(f"| {size} | {base} | {tot} | {fs} |")
    return "\n".join(lines) + "\n\n" + "\n".join(ratio_lines)


def machine() -> dict:
    cpu = "?"
    try:
        for s in Path("/proc/cpuinfo").read_text().splitlines():
            if s.startswith("model name"):
                cpu = s.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    info = {"nproc": os.cpu_count(), "cpu": cpu, "python": platform.python_version()}
    for mod in ("numpy", "scipy", "sksparse", "rustfrac"):
        try:
            m = __import__(mod)
            info[mod] = getattr(m, "__version__", "?")
        except Exception as e:  # report what is missing, do not fail here
            info[mod] = f"unavailable ({type(e).__name__})"
    return info


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--sizes", default="small,medium,large")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--out", default=str(ROOT / "benches" / "results_fem.json"))
    ap.add_argument("--timeout", type=float, default=900.0, help="seconds per case")
    ap.add_argument(
        "--solvers", default="rustfrac,rustfrac-nocond,rust-phases,scipy,cholmod,cholmod-openblas"
    )
    ap.add_argument("--phases-bin", default=None, help="plate_phases example binary")
    ap.add_argument(
        "--openblas-dir",
        default=None,
        help="directory with an OpenBLAS libblas.so.3 for the cholmod-openblas case",
    )
    ap.add_argument(
        "--mem-limit-gb", type=float, default=14.0, help="address-space limit per case (0: none)"
    )
    ap.add_argument("--worker", help=argparse.SUPPRESS)
    ap.add_argument("--nx", type=int, help=argparse.SUPPRESS)
    ap.add_argument("--ny", type=int, help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.worker:
        worker(args)
        return

    sizes = [s.strip() for s in args.sizes.split(",") if s.strip()]
    for s in sizes:
        if s not in SIZES:
            ap.error(f"unknown size {s!r}; choose from {', '.join(SIZES)}")
    solvers = [s.strip() for s in args.solvers.split(",") if s.strip()]
    if "rust-phases" in solvers:
        b = args.phases_bin or find_phases_bin()
        if b is None:
            print(
                "note: plate_phases binary not found (cargo build --release -p rustfrac-core "
                "--example plate_phases); skipping rust-phases",
                file=sys.stderr,
            )
            solvers.remove("rust-phases")
        args.phases_bin = str(b)
    if "cholmod-openblas" in solvers and not args.openblas_dir:
        solvers.remove("cholmod-openblas")
    info = machine()
    if "sksparse" in info and str(info["sksparse"]).startswith("unavailable"):
        print("note: scikit-sparse unavailable; skipping CHOLMOD", file=sys.stderr)
        solvers = [s for s in solvers if not s.startswith("cholmod")]
    info["load_at_start"] = os.getloadavg()
    print(f"machine: {info}", flush=True)
    print(f"sigma22 exact = {SIGMA_EXACT!r}, tolerance {RTOL} relative", flush=True)

    results: dict[str, dict[str, list]] = {}
    for size in sizes:
        nx, ny = SIZES[size]
        results[size] = {s: [] for s in solvers}
        for rep in range(args.repeat):
            # rotate the order each repeat, so that no solver always runs right after another
            # one (e.g. after the freeing of a large process) or always first
            for s in solvers[rep % len(solvers) :] + solvers[: rep % len(solvers)]:
                runs = results[size][s]
                if any(r.get("timeout") or "error" in r for r in runs):
                    continue  # do not repeat a case that timed out or ran out of memory
                r = run_case(args, s, nx, ny)
                runs.append(r)
                what = (
                    "> timeout"
                    if r.get("timeout")
                    else r.get("error")
                    or f"total {r['total_s']:.3f} s, peak {r['peak_rss_mb']:.0f} MiB, "
                    f"load {r['load1_start']:.2f}"
                )
                print(f"  {size} ({nx}x{ny}) rep {rep + 1} {s}: {what}", flush=True)
    info["load_at_end"] = os.getloadavg()
    table = summarise(results, solvers, args.timeout)
    print()
    print(table)
    out = {
        "command": " ".join([Path(sys.executable).name, *sys.argv]),
        "date_utc": time.strftime("%Y-%m-%d %H:%M:%S", time.gmtime()),
        "machine": info,
        "sigma22_exact": SIGMA_EXACT,
        "sizes": {s: SIZES[s] for s in sizes},
        "timeout_s": args.timeout,
        "results": results,
        "table_markdown": table,
    }
    Path(args.out).parent.mkdir(parents=True, exist_ok=True)
    Path(args.out).write_text(json.dumps(out, indent=1) + "\n")
    print(f"\nwritten {args.out}")


if __name__ == "__main__":
    main()
