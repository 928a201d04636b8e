"""The whole ``rustfrac fig7`` job (paper preset: XFEM growth + CCM-PD 500 SLA steps, figures,
result folders) as a user runs it, against a baseline installation, in the same run.

Each Python interpreter given runs ``python -m rustfrac fig7 --out DIR --quiet`` as a whole
process (start-up, imports, runs, figures, files, exit); the commands alternate (A B A B ...)
``--repeat`` times after one warm-up each, the wall-time ratio is taken pair by pair, and the
medians are printed with the job's own time split (``summary.json``'s ``time_split_s``) of this
tree's last run.

Usage: python benches/bench_fig7.py [--python PYTHON] --python-base BASE_PYTHON [--repeat 7]

``--python`` (default: this interpreter) must import this tree's rustfrac (installed, or with
``PYTHONPATH=python`` in the environment); ``--python-base`` is an interpreter with the baseline
installed (e.g. a venv of commit 40dc70a: ``pip install git+...@40dc70a`` or ``maturin develop``
in a checkout of it). The environment variable PYTHONPATH is passed to the first only.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time


def run_job(python: str, out: str, env: dict[str, str]) -> float:
    """Wall seconds of one whole fig7 process into ``out``."""
    t = time.perf_counter()
    subprocess.run(
        [python, "-m", "rustfrac", "fig7", "--out", out, "--quiet"],
        check=True,
        capture_output=True,
        env=env,
    )
    return time.perf_counter() - t


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--python", default=sys.executable, help="interpreter of this tree's rustfrac")
    ap.add_argument("--python-base", required=True, help="interpreter of the baseline rustfrac")
    ap.add_argument("--repeat", type=int, default=7)
    a = ap.parse_args()
    env_new = dict(os.environ)
    env_base = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    new: list[float] = []
    base: list[float] = []
    with tempfile.TemporaryDirectory() as d:
        out_new, out_base = os.path.join(d, "new"), os.path.join(d, "base")
        run_job(a.python, out_new, env_new)  # warm-up (page cache, .pyc files)
        run_job(a.python_base, out_base, env_base)
        for _ in range(a.repeat):
            new.append(run_job(a.python, out_new, env_new))
            base.append(run_job(a.python_base, out_base, env_base))
        with open(os.path.join(out_new, "summary.json")) as f:
            split = json.load(f).get("time_split_s", {})
    ratios = [x / y for x, y in zip(new, base)]
    print(f"fig7 job, paper preset, {a.repeat} alternating pairs; load average {os.getloadavg()}")
    for name, v in (("this tree", new), ("baseline", base)):
        print(
            f"{name:10s} wall median {statistics.median(v):.3f} s (min {min(v):.3f}, max {max(v):.3f})"
        )
    print(
        f"this tree / baseline, per pair: median {statistics.median(ratios):.3f} "
        f"(min {min(ratios):.3f}, max {max(ratios):.3f}); "
        f"speed-up {1 / statistics.median(ratios):.2f}x"
    )
    if split:
        parts = ", ".join(f"{k} {v:.3f} s" for k, v in split.items())
        print(f"this tree's job split (last run, summary.json): {parts}")


if __name__ == "__main__":
    main()
