"""The CPU time of each part of the ``rustfrac fig7`` job (paper preset by default), one part after the
other in one process: the imports, the four runs, matplotlib's import, each figure and each
result folder. The job itself overlaps these parts on the cores (``bench_fig7.py`` times it
whole); no overlap can make it faster than their sum divided by the number of cores.

Usage: python benches/fig7_cpu_parts.py [--preset paper]  (with this tree's rustfrac importable)
"""

from __future__ import annotations

import argparse
import resource
import tempfile
import time
from pathlib import Path


def _cpu() -> float:
    r = resource.getrusage(resource.RUSAGE_SELF)
    return r.ru_utime + r.ru_stime


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--preset", default="paper", help="the fig7 job's preset (paper, fast, full)")
    args = ap.parse_args()
    parts: list[tuple[str, float]] = []
    c0 = _cpu()

    def mark(name: str) -> None:
        nonlocal c0
        c = _cpu()
        parts.append((name, c - c0))
        c0 = c

    import numpy  # noqa: F401

    mark("import numpy")
    from rustfrac import fig7 as f7
    from rustfrac.runner import run

    mark("import rustfrac and its fig7 job")
    if args.preset not in f7.PRESETS:  # checked once imported: the imports are measured
        ap.error(f"--preset: expected one of {', '.join(f7.PRESETS)}, got {args.preset!r}")
    preset = f7.PRESETS[args.preset]
    scenes = f7._scenes(preset, "free")
    results = {}
    for name, scene in scenes.items():
        results[name] = run(scene)
        mark(f"run {name}")
    from rustfrac import figures  # noqa: F401  (matplotlib)

    mark("import matplotlib (rustfrac.figures)")
    out = Path(tempfile.mkdtemp(prefix="fig7_cpu_parts_"))
    # the job's drawings (the same as fig7 draws), without its overlap or its result folder
    job = f7._Job(
        results=results, times={n: 0.0 for n in results}, p=preset, preset=args.preset,
        bc="free", scenes=scenes, interrupted=False, t_all=time.perf_counter(),
    )  # fmt: skip
    for fname, make in job._drawings():
        make(out / fname)
        mark(f"draw {fname}")
    for name, part in f7.PARTS.items():
        results[name].save(out / part)
        mark(f"result folder {part}/")
    total = sum(s for _, s in parts)
    for name, s in parts:
        print(f"{s:7.3f} s  {name}")
    print(f"{total:7.3f} s  CPU in all (user + system, every thread of this process)")


if __name__ == "__main__":
    main()
