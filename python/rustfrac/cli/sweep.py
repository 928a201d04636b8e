"""``rustfrac sweep``: the paper's plate (``--preset``) or the user's scene (``SCENE.toml --param
P --levels ...``), on local processes or a dask cluster (:mod:`rustfrac.sweep`)."""

from __future__ import annotations

import argparse
import sys
import time
from collections.abc import Iterator
from contextlib import contextmanager
from typing import Any, Callable

from .._folder import check_writable
from ..errors import OutputError
from ..progress import ProgressBar
from .common import read_scene


def _parse_level(tok: str) -> Any:
    """A --levels item: NXxNY -> (nx, ny), p/q -> p / q, an integer, a float, else the text."""
    tok = tok.strip()
    for sep in ("x", "/"):
        a, _, b = tok.partition(sep)
        if _ and a.strip().isdigit() and b.strip().isdigit():
            return (int(a), int(b)) if sep == "x" else int(a) / int(b)
    for kind in (int, float):
        try:
            return kind(tok)
        except ValueError:
            pass
    return tok


@contextmanager
def _dask_scheduler(address: str | None, workers: int | None) -> Iterator[Any]:
    """The scheduler of --scheduler/--dask: None (local processes), the address, or for
    'local' a client of a LocalCluster (one thread per worker) closed afterwards."""
    if address != "local":
        yield address
        return
    try:
        from distributed import Client, LocalCluster
    except ImportError as e:
        raise ImportError(
            "sweeping on a dask cluster needs dask.distributed: pip install 'rustfrac[dask]'"
        ) from e
    import os

    with LocalCluster(
        n_workers=workers or os.cpu_count() or 1, threads_per_worker=1, processes=True,
        dashboard_address=None,
    ) as cluster, Client(cluster) as client:  # fmt: skip
        yield client


def _backend(args: argparse.Namespace) -> str:
    return f"dask {args.scheduler}" if args.scheduler else f"local, {args.workers or 'all'} workers"


def _sweep_meta(
    args: argparse.Namespace, command: str, run: tuple[int, str, float, bool, int, int]
) -> dict[str, Any]:
    """The meta every sweep writes: the command that reproduces it (``command`` plus the
    repeats, scheduler and workers options), repeats, backend, total time and completeness;
    ``run`` = (repeats, backend, start time, interrupted, points done, points total)."""
    repeats, backend, t0, interrupted, done, total = run
    return {
        "command": f"{command} --repeats {repeats}"
        + (f" --scheduler {args.scheduler}" if args.scheduler else "")
        + (f" --workers {args.workers}" if args.workers else ""),
        "repeats": repeats,
        "backend": backend,
        "total_wall_time_s": time.perf_counter() - t0,
        "interrupted": interrupted,
        "points_done": done,
        "points_total": total,
    }


def _sweep_records(
    args: argparse.Namespace, run: Callable[[Any, ProgressBar | None], list[Any]]
) -> tuple[list[Any], bool, int | None]:
    """Runs a sweep (``run(scheduler, bar)``) under ``--scheduler`` / ``--workers`` with a progress
    bar: (records, interrupted, None), or ([], False, exit code) when it could not run (Ctrl-C
    before any point finished: 130; dask missing: 2)."""
    from ..sweep import SweepInterrupted

    bar = None if args.quiet else ProgressBar(delay=0.0)
    try:
        with _dask_scheduler(args.scheduler, args.workers) as scheduler:
            return run(scheduler, bar), False, None
    except SweepInterrupted as e:
        return e.records, True, None
    except KeyboardInterrupt:
        print("rustfrac: interrupted; no sweep files written", file=sys.stderr)
        return [], False, 130
    except ImportError as e:
        print(f"rustfrac: error: {e}", file=sys.stderr)
        return [], False, 2
    finally:
        if bar is not None:
            bar.close()


def cmd_sweep(args: argparse.Namespace) -> int:
    from ..sweep import DEFAULT_REPEATS, SweepInterrupted, define_points, sweep, write_outputs

    scene_only = [f"--{k}" for k in ("param", "levels") if getattr(args, k) is not None]
    if args.scene is not None and args.preset is not None:
        print("rustfrac: error: --preset is for the paper's plate, not with a scene file",
              file=sys.stderr)  # fmt: skip
        return 2
    if args.scene is None and scene_only:
        print(f"rustfrac: error: {', '.join(scene_only)} need a scene file (rustfrac sweep "
              "SCENE.toml --param mesh --levels 1,2,4)", file=sys.stderr)  # fmt: skip
        return 2
    try:
        check_writable(args.out)  # before computing: a bad --out must not cost the sweep
    except OutputError as e:
        print(f"rustfrac: error: invalid --out: {e}", file=sys.stderr)
        return 2
    if args.scene is not None:
        return _cmd_sweep_scene(args)
    preset = args.preset or "full"
    repeats = args.repeats or DEFAULT_REPEATS
    log = (lambda *a: None) if args.quiet else (lambda *a: print(*a, flush=True))
    points = define_points(preset)
    backend = _backend(args)
    log(f"sweep   {len(points)} points, preset {preset}, {repeats} timings each, {backend}")
    t0 = time.perf_counter()
    records, interrupted, code = _sweep_records(
        args,
        lambda scheduler, bar: sweep(
            points, workers=args.workers, scheduler=scheduler, progress=bar, repeats=repeats
        ),
    )
    if code is not None:
        return code
    try:
        doc = write_outputs(
            args.out,
            points,
            records,
            extra={
                **_sweep_meta(
                    args,
                    f"rustfrac sweep --out {args.out} --preset {preset}",
                    (repeats, backend, t0, interrupted, len(records), len(points)),
                ),
                "preset": preset,
            },
        )
    except SweepInterrupted as e:
        interrupted, doc = True, e.doc or {}
    if interrupted:
        missing = doc.get("missing_files", [])
        print(
            f"rustfrac: interrupted; the {len(records)} finished points of {len(points)} were "
            f"written to {args.out}/" + (f"; missing: {', '.join(missing)}" if missing else ""),
            file=sys.stderr,
        )
        return 130
    for method, ps in doc["presets"].items():
        for name, p in ps.items():
            log(
                f"preset  {method} {name}: {p['point']} ({p['param']} = {p['value']}), "
                f"{p['wall_time_s']:.3f} s, max rel. error {p['err_max']:.2e}"
                + ("" if p["meets_tolerance"] else f" (tolerance {p['tolerance']:g} not met)")
                + (" (the reference level: error 0 by construction)" if p["is_reference"] else "")
            )
    files = ["sweep.csv", "sweep.json", "sweep.md"] + [
        f"sweep_{m}.png" for m in sorted({r["method"] for r in records})
    ]
    log(f"saved   {args.out}/ ({', '.join(files)})")
    return 0


def _cmd_sweep_scene(args: argparse.Namespace) -> int:
    """``rustfrac sweep SCENE.toml --param P --levels L1,L2,... [--quantity Q]``."""
    from ..sweep import (
        DEFAULT_REPEATS,
        run_scene_points,
        scene_points,
        write_scene_outputs,
    )

    if args.param is None or args.levels is None:
        print("rustfrac: error: a scene sweep needs --param and --levels (e.g. --param mesh "
              "--levels 1,2,4)", file=sys.stderr)  # fmt: skip
        return 2
    log = (lambda *a: None) if args.quiet else (lambda *a: print(*a, flush=True))
    scene = read_scene(args.scene)
    if scene is None:
        return 2
    levels = [_parse_level(t) for t in args.levels.split(",") if t.strip()]
    points = scene_points(scene, args.param, levels)  # bad param / levels: exit 2 (main)
    repeats = args.repeats or DEFAULT_REPEATS
    backend = _backend(args)
    log(f"sweep   {args.scene}: {args.param} at {len(points)} levels, {args.quantity}, "
        f"{repeats} timings each, {backend}")  # fmt: skip
    t0 = time.perf_counter()
    records, interrupted, code = _sweep_records(
        args,
        lambda scheduler, bar: run_scene_points(
            points,
            args.quantity,
            repeats=repeats,
            workers=args.workers,
            scheduler=scheduler,
            progress=bar,
        ),
    )
    if code is not None:
        return code
    doc = write_scene_outputs(
        args.out, points, records, args.quantity,
        extra={
            **_sweep_meta(
                args,
                f"rustfrac sweep {args.scene} --out {args.out} --param {args.param} "
                f"--levels {args.levels} --quantity {args.quantity}",
                (repeats, backend, t0, interrupted, len(records), len(points)),
            ),
            "scene_file": str(args.scene),
            "scene": scene.to_dict(),
        },
    )  # fmt: skip
    if interrupted:
        print(
            f"rustfrac: interrupted; the {len(records)} finished levels of {len(points)} were "
            f"written to {args.out}/",
            file=sys.stderr,
        )
        return 130
    q = args.quantity
    for r in doc["levels"]:
        h = "-" if r["h"] is None else format(r["h"], ".4g")
        log(f"level   {r['name']}: {q} = {r['q']:.10g}, h = {h}, {r['wall_time_s']:.3f} s "
            f"(spread {r['wall_time_spread_s']:.3f} s)")  # fmt: skip
    rich = doc["richardson"]
    if rich["status"] == "ok":
        log(f"richardson {q}* = {rich['value']:.10g}, observed rate {rich['rate']:.3g}")
    else:
        log(f"richardson {rich['status']}: {rich['why']}")
    log(f"saved   {args.out}/ (sweep.csv, sweep.json, sweep.md)")
    return 0
