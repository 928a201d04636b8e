"""Command line (also ``python -m rustfrac``): ``rustfrac run SCENE.toml --out DIR [--quiet]`` and
``rustfrac fig7 --out DIR [--preset paper|fast|full] [--bc free|clamped] [--surface-correction
none|energy] [--quiet]`` and
``rustfrac sweep --out DIR [--preset tiny|full] [--scheduler ADDR|local] [--workers N] [--quiet]``
(the paper's plate) and ``rustfrac sweep SCENE.toml --param mesh|pd.dx|SECTION.KEY --levels
L1,L2,... [--quantity K_I] [--repeats 3] [--dask ADDR|local]`` (the user's scene) and
``rustfrac examples [NAME]`` (the shipped example scenes and their paths) and ``rustfrac plot
load-path RESULT_DIR --x COL --y COL -o FILE`` (a load path of a saved result) and ``rustfrac
specimens`` / ``rustfrac specimen NAME [--method M] -o SCENE.toml`` (the literature specimens) and
``rustfrac compare SCENE.toml --out DIR [--quick]`` (XFEM growth and CCM-PD side by side,
:mod:`rustfrac.compare`).

Exit codes: 0 success, 1 the run failed (singular system, internal error) or its output could not
be written at the end (the output is then saved to a temporary folder the message names), 2 bad
input (unreadable or invalid scene file, bad arguments, an ``--out`` that cannot be written:
checked before computing), 130 interrupted (what finished is written and the message, and for
``fig7`` / ``sweep`` / ``compare`` the summary, lists what is missing).
"""

from __future__ import annotations

import argparse
import gc
import sys
import time
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import TYPE_CHECKING, Any, Callable

from ._folder import FolderWriter, check_writable, with_fallback, writing
from .errors import InvalidParameterError, MethodNotAvailableError, OutputError, RustfracError
from .progress import ProgressBar

if TYPE_CHECKING:
    from .result import Result as _Result
    from .scene import Scene as _Scene

__all__ = ["ProgressBar", "main"]


def _choices(name: str) -> list[str]:
    """The choices of a scene key from the core's schema (``S0_CALIBRATIONS`` for
    ``pd.s0_calibration``, ``SURFACE_CORRECTIONS`` for ``pd.surface_correction``)."""
    from . import _core

    return list(_core.scene_constants()[name])


def _parser() -> argparse.ArgumentParser:
    from . import __version__

    p = argparse.ArgumentParser(
        prog="rustfrac", description="rustfrac: crack propagation (FEM, XFEM, CCM-PD)"
    )
    p.add_argument("--version", action="version", version=f"rustfrac {__version__}")
    sub = p.add_subparsers(dest="command", required=True)
    r = sub.add_parser("run", help="run a scene TOML file and save its results")
    r.add_argument("scene", type=Path, help="scene file (TOML)")
    r.add_argument("--out", type=Path, required=True, help="output directory")
    r.add_argument("--quiet", "-q", action="store_true", help="print nothing but errors")
    r.add_argument(
        "--no-vtu", action="store_true", help="skip the ParaView files (result.vtu, result.pvd)"
    )
    r.add_argument(
        "--plot",
        action="store_true",
        help="also save PNGs: the s22 field (u2 without nodal stresses: XFEM, PD), the crack "
        "path, the damage (PD), the tip deformation x50 (XFEM) and the load path (growth runs)",
    )
    r.add_argument(
        "--checkpoint",
        type=Path,
        default=None,
        metavar="FILE",
        help="pd / ccm_pd: write SLA checkpoints to FILE (sets [pd] checkpoint_path; every "
        "--checkpoint-every steps and when interrupted)",
    )
    r.add_argument(
        "--checkpoint-every",
        type=int,
        default=None,
        metavar="N",
        help="pd / ccm_pd: checkpoint every N SLA steps (sets [pd] checkpoint_every; default "
        "100 with --checkpoint)",
    )
    r.add_argument(
        "--resume",
        type=Path,
        default=None,
        metavar="FILE",
        help="pd / ccm_pd: continue the SLA from this checkpoint of the same scene (sets [pd] "
        "resume_from); the history equals an uninterrupted run's bit for bit",
    )
    f = sub.add_parser(
        "fig7", help="reproduce the paper's Fig. 7 (and Figs. 6, 8): XFEM and CCM-PD side by side"
    )
    f.add_argument("--out", type=Path, default=Path("results"), help="output directory")
    f.add_argument(
        "--preset",
        choices=("paper", "fast", "full"),
        default="paper",
        help="paper: the paper's discretisations (default); fast: coarse, seconds; full: the "
        "paper's with CCM-PD on the adaptive PD region to a = 0.7 W (both full curves; minutes)",
    )
    f.add_argument(
        "--bc", choices=("free", "clamped"), default="free", help="grip variant (u1 on the grips)"
    )
    f.add_argument(
        "--s0-calibration",
        choices=_choices("S0_CALIBRATIONS"),
        default=None,
        help="CCM-PD critical stretch (scene key pd.s0_calibration): continuum (eq. 48, the "
        "paper's, default), grid (the grid's discrete fracture energy = G0) or sla (the SLA's "
        "release in a reference strip = G0)",
    )
    f.add_argument(
        "--surface-correction",
        choices=_choices("SURFACE_CORRECTIONS"),
        default=None,
        help="the CCM-PD run's PD surface correction (scene key pd.surface_correction; "
        "default: the scene's, none)",
    )
    f.add_argument("--quiet", "-q", action="store_true", help="print nothing but errors")
    w = sub.add_parser(
        "sweep", help="speed-accuracy sweep of XFEM and CCM-PD (error against time, presets)"
    )
    w.add_argument(
        "scene",
        type=Path,
        nargs="?",
        default=None,
        help="your scene file (TOML): sweep --param at --levels; without it, the paper's plate",
    )
    w.add_argument("--out", type=Path, default=Path("sweep"), help="output directory")
    w.add_argument(
        "--preset",
        choices=("tiny", "full"),
        default=None,
        help="the paper's plate: full (default): 5+ XFEM meshes, 4 PD grids, nsub, r_I, m, PD "
        "size (minutes); tiny: seconds",
    )
    w.add_argument(
        "--param",
        default=None,
        help="with SCENE: mesh (fem, xfem), pd.dx (pd, ccm_pd) or a scene key section.key",
    )
    w.add_argument(
        "--levels",
        default=None,
        help="with SCENE, comma-separated: mesh multipliers (1,2,4) or NXxNY pairs (22x41,44x83); "
        "dx values (0.2,1/9); values of a scene key",
    )
    w.add_argument(
        "--quantity",
        default="K_I",
        help="with SCENE: the scalar response studied (K_I, K_II, J, sigma22, cmod, "
        "peak_sigma22, ...; default K_I)",
    )
    w.add_argument(
        "--repeats",
        type=int,
        default=None,
        help="timings per point, the minimum kept (default 3)",
    )
    w.add_argument(
        "--scheduler",
        "--dask",
        dest="scheduler",
        default=None,
        metavar="ADDRESS|local",
        help="run on dask.distributed: a scheduler address (tcp://host:port) or 'local' (a "
        "LocalCluster of --workers processes); default: local processes",
    )
    w.add_argument("--workers", type=int, default=None, help="local processes (default: cores)")
    w.add_argument("--quiet", "-q", action="store_true", help="print nothing but errors")
    e = sub.add_parser(
        "examples", help="list the example scenes shipped with rustfrac (name and path)"
    )
    e.add_argument(
        "name",
        nargs="?",
        default=None,
        help="print only this example's path (e.g. rustfrac run $(rustfrac examples pd_coarse))",
    )
    pl = sub.add_parser("plot", help="draw a figure of a saved result folder")
    plsub = pl.add_subparsers(dest="figure", required=True)
    lp = plsub.add_parser(
        "load-path",
        help="two history columns of a growth / SLA result against each other (e.g. --x "
        "load_displacement --y force:load[0]:2)",
    )
    lp.add_argument("result", type=Path, help="result folder (written by rustfrac run)")
    lp.add_argument("--x", default="u0", help="history column on the x axis (default u0)")
    lp.add_argument("--y", default="sigma22", help="history column on the y axis (default sigma22)")
    lp.add_argument("-o", "--out", type=Path, required=True, help="image file (format from suffix)")
    lp.add_argument(
        "--units",
        choices=("default", "paper"),
        default="default",
        help="axis units: default (length, force) or paper (mm, N, MPa)",
    )
    c = sub.add_parser(
        "compare",
        help="XFEM growth and CCM-PD side by side on one scene: paths, curves, energy, cost",
    )
    c.add_argument("scene", type=Path, help="scene file (TOML), any method")
    c.add_argument("--out", type=Path, required=True, help="output directory")
    c.add_argument(
        "--quick",
        action="store_true",
        help="4 XFEM growth steps instead of 24 when the scene sets none (seconds)",
    )
    c.add_argument(
        "--dx",
        type=float,
        default=None,
        help="PD grid spacing (default: a PD scene's, else the XFEM element size, coarsened to "
        "keep the PD rectangle within the comparison's budget)",
    )
    c.add_argument(
        "--m", type=int, default=None, help="PD horizon factor (default: the scene's, else 4)"
    )
    c.add_argument(
        "--margin",
        type=float,
        default=None,
        metavar="HORIZONS",
        help="margin of the PD rectangle around the XFEM path, in horizons (default 3)",
    )
    c.add_argument(
        "--region",
        default=None,
        metavar="X0,Y0,X1,Y1|auto|adaptive",
        help="the PD rectangle; auto: around the XFEM path (default, unless a ccm_pd scene "
        "states its own rectangle); adaptive: the adaptive PD region, grown where the crack goes",
    )
    c.add_argument(
        "--surface-correction",
        choices=_choices("SURFACE_CORRECTIONS"),
        default=None,
        help="the CCM-PD run's PD surface correction (scene key pd.surface_correction; "
        "default: a PD scene's, else none)",
    )
    c.add_argument("--growth-steps", type=int, default=None, help="XFEM growth steps")
    c.add_argument("--sla-steps", type=int, default=None, help="most SLA steps (bond breaks)")
    c.add_argument(
        "--allow-slow",
        action="store_true",
        help="run even when the PD rectangle exceeds the comparison's budget of free PD dofs",
    )
    c.add_argument(
        "--vtu", action="store_true", help="also write the ParaView files of both results"
    )
    c.add_argument("--quiet", "-q", action="store_true", help="print nothing but errors")
    sub.add_parser("specimens", help="list the literature specimens (rustfrac.specimens)")
    s1 = sub.add_parser("specimen", help="write one specimen's scene as a TOML file")
    s1.add_argument("name", help="specimen name (see rustfrac specimens)")
    s1.add_argument(
        "--method",
        default=None,
        help="fem | xfem | pd | ccm_pd (default: the specimen's example method)",
    )
    s1.add_argument("-o", "--out", type=Path, required=True, help="scene file to write (TOML)")
    return p


def _cmd_plot(args: argparse.Namespace) -> int:
    from .plotting import DEFAULT_UNITS, PAPER_UNITS, plot_load_path
    from .result import load

    res = load(args.result)
    units = PAPER_UNITS if args.units == "paper" else DEFAULT_UNITS
    fig = plot_load_path(res, x=args.x, y=args.y, units=units)
    try:
        fig.savefig(args.out, dpi=150, bbox_inches="tight")
    except (OSError, ValueError) as e:  # unwritable path, unknown image format
        print(f"rustfrac: error: cannot write {args.out}: {e}", file=sys.stderr)
        return 2
    print(f"saved   {args.out} ({args.y} against {args.x})")
    return 0


def _cmd_specimens(args: argparse.Namespace) -> int:
    from .specimens import SPECIMENS

    for name, sp in SPECIMENS.items():
        print(f"{name:18s} {sp.reference}; example {sp.example}")
    return 0


def _cmd_specimen(args: argparse.Namespace) -> int:
    from .specimens import get

    sp = get(args.name)
    scene = sp.build(args.method or sp.example_method)
    try:
        scene.save_toml(args.out)
    except OSError as e:
        print(f"rustfrac: error: cannot write {args.out}: {e.strerror or e}", file=sys.stderr)
        return 2
    print(f"saved   {args.out}: {scene.describe()}")
    return 0


def _cmd_examples(args: argparse.Namespace) -> int:
    from . import examples

    if args.name is not None:
        print(examples.path(args.name))
        return 0
    for name in examples.list():
        print(f"{name:30s} {examples.path(name)}")
    return 0


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
    from .sweep import SweepInterrupted

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


def _cmd_sweep(args: argparse.Namespace) -> int:
    from .sweep import DEFAULT_REPEATS, SweepInterrupted, define_points, sweep, write_outputs

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
    from .sweep import (
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
    scene = _read_scene(args.scene)
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


def _cmd_fig7(args: argparse.Namespace) -> int:
    from .fig7 import Fig7Interrupted, fig7

    try:
        check_writable(args.out)  # before computing: a bad --out must not cost the runs
    except OutputError as e:
        print(f"rustfrac: error: invalid --out: {e}", file=sys.stderr)
        return 2
    bars: list[ProgressBar] = []
    log, progress = _job_console(bars, args.quiet)

    try:
        fig7(
            args.out, preset=args.preset, bc=args.bc, s0_calibration=args.s0_calibration,
            surface_correction=args.surface_correction, log=log, progress=progress,
        )  # fmt: skip
    except Fig7Interrupted as e:
        return _interrupted(args.out, e.summary["missing"])
    except KeyboardInterrupt:
        print(
            f"rustfrac: interrupted while writing {args.out}/: it may hold parts of two runs "
            "(rustfrac.fig7.load_summary refuses those)",
            file=sys.stderr,
        )
        return 130
    finally:
        for b in bars:
            b.close()
    return 0


def _cmd_compare(args: argparse.Namespace) -> int:
    from .compare import DEFAULT_MARGIN_HORIZONS, CompareInterrupted, compare

    scene = _read_scene(args.scene)
    if scene is None:
        return 2
    region: Any = None
    if args.region in ("auto", "adaptive"):
        region = args.region
    elif args.region is not None:
        try:
            region = tuple(float(v) for v in args.region.split(","))
        except ValueError:
            region = ()
        if len(region) != 4:
            print(
                f"rustfrac: error: invalid --region: expected X0,Y0,X1,Y1, got {args.region!r}",
                file=sys.stderr,
            )
            return 2
    try:
        check_writable(args.out)  # before computing: a bad --out must not cost the runs
    except OutputError as e:
        print(f"rustfrac: error: invalid --out: {e}", file=sys.stderr)
        return 2
    bars: list[ProgressBar] = []
    log, progress = _job_console(bars, args.quiet)

    try:
        compare(
            scene, args.out, quick=args.quick, dx=args.dx, m=args.m,
            margin_horizons=DEFAULT_MARGIN_HORIZONS if args.margin is None else args.margin,
            growth_steps=args.growth_steps, sla_steps=args.sla_steps, region=region,
            surface_correction=args.surface_correction, allow_slow=args.allow_slow, vtu=args.vtu, log=log, progress=progress,
        )  # fmt: skip
    except CompareInterrupted as e:
        return _interrupted(args.out, e.summary["missing"])
    finally:
        for b in bars:
            b.close()
    return 0


def _job_console(
    bars: list[ProgressBar], quiet: bool
) -> tuple[Callable[[str], None] | None, Callable[[str], ProgressBar | None]]:
    """The log and the progress factory of a job of several runs (fig7, compare; None and no
    bars with ``quiet``). The factory gives a fresh text bar per run, the previous ones' lines
    ended; they are kept in ``bars`` so the command closes the last. The runs may report from
    two threads (fig7 runs CCM-PD beside the XFEM runs): a log line is one write, after the
    line of any bar drawn on a terminal is ended, so that neither overwrites the other."""

    def log(s: str) -> None:
        for b in bars:
            b.end_line()
        sys.stdout.write(s + "\n")
        sys.stdout.flush()

    def progress(name: str) -> ProgressBar | None:
        if quiet:
            return None
        for b in bars:
            b.close()
        bars.append(ProgressBar())
        return bars[-1]

    return (None if quiet else log), progress


def _interrupted(out: Path, missing: list[str]) -> int:
    """Says that a job was interrupted and what it wrote; the exit status of a Ctrl-C (130)."""
    print(
        f"rustfrac: interrupted; the finished parts were written to {out}/"
        + (f"; missing: {', '.join(missing)}" if missing else ""),
        file=sys.stderr,
    )
    return 130


def _read_scene(path: Path) -> _Scene | None:
    """The scene in the TOML file ``path``, or None after saying why it cannot be read (the
    commands then exit with 2)."""
    from .scene import Scene

    try:
        return Scene.from_toml(path)
    except OSError as e:
        print(f"rustfrac: error: cannot read scene {path}: {e.strerror or e}", file=sys.stderr)
    except InvalidParameterError as e:
        print(f"rustfrac: error: invalid scene {path}: {e}", file=sys.stderr)
    return None


def _cmd_run(args: argparse.Namespace) -> int:
    from .result import JSON_NAME, OWNED_NAMES, PVD_NAME, Result
    from .runner import run

    log = (lambda *a: None) if args.quiet else (lambda *a: print(*a, flush=True))
    scene = _read_scene(args.scene)
    if scene is None:
        return 2
    scene = _checkpoint_options(scene, args)
    try:
        check_writable(args.out)  # before computing: a bad --out must not cost the run
    except OutputError as e:
        print(f"rustfrac: error: invalid --out: {e}", file=sys.stderr)
        return 2
    log(f"scene   {args.scene}: {scene.describe()}")
    growth = scene.method == "xfem" and scene.xfem.growth_steps > 0
    bar = None if args.quiet else ProgressBar(delay=0.0 if growth else 0.5)
    try:
        res: Result = run(scene, progress=bar)
    except KeyboardInterrupt as e:
        partial = getattr(e, "result", None)
        if isinstance(partial, Result):
            # keep what finished (XFEM growth and the SLA stop with status "cancelled")
            partial.save(args.out, vtu=not args.no_vtu)
            print(
                f"rustfrac: interrupted; the finished part ({partial.summary()}) was written "
                f"to {args.out}",
                file=sys.stderr,
            )
        if scene.method in ("pd", "ccm_pd") and scene.pd.checkpoint_path:
            print(
                f"rustfrac: interrupted; checkpoint written to {scene.pd.checkpoint_path} "
                f"(continue with: rustfrac run {args.scene} --out {args.out} --resume "
                f"{scene.pd.checkpoint_path})",
                file=sys.stderr,
            )
        raise
    finally:
        if bar is not None:
            bar.close()
    anchor = res.meta.get("anchor_node")
    log(
        f"built   {res.n_dofs} unknowns, method {res.method}, bc {res.meta.get('bc')}: "
        f"{res.meta.get('bc_description', '')}"
        + (f"; anchor node {anchor}" if anchor is not None else "")
    )
    enr = res.meta.get("enrichment")
    if enr:
        log(
            f"enrich  {enr['n_std']} standard + {res.n_dofs - enr['n_std']} enriched unknowns: "
            f"{enr['n_heaviside_nodes']} Heaviside nodes, {enr['n_tip_nodes']} tip nodes, "
            f"{enr['n_dropped_nodes']} dropped (small-area rule)"
        )
    log(
        f"result  sigma22 = {res.sigma22:.10g}, CMOD = {res.cmod:.10g}, "
        f"solve {res.wall_time_s:.3f} s"
    )
    if res.K_I is not None:
        log(
            f"sifs    K_I = {res.K_I:.10g}, K_II = {res.K_II:.10g}, J = {res.J:.10g} "
            f"(domain J = {res.scalars.get('J_domain', float('nan')):.10g}, "
            f"r_I = {res.meta.get('r_I', float('nan')):.6g})"
        )
        tips = res.tip_sifs
        if len(tips) > 1:
            for k, t in enumerate(tips):
                log(
                    f"  tip {k} (crack {t['crack']}) at ({t['x1']:.6g}, {t['x2']:.6g}): "
                    f"K_I = {t['K_I']:.10g}, K_II = {t['K_II']:.10g}"
                )
    for name, r in res.regions.items():
        f = r["force"]
        ms = r.get("mean_stress")
        log(
            f"region  {name}: force ({f[0]:.10g}, {f[1]:.10g})"
            + (f", mean stress {ms:.10g}" if ms is not None else "")
        )
    for name, (a, b) in res.probes.items():
        log(f"probe   {name}: ({a:.10g}, {b:.10g})")
    if res.method in ("pd", "ccm_pd"):
        _log_pd(log, res)
    elif "status" in res.meta:
        n = len(res.history.get("a", ()))
        extra = (
            f", {n - 1} critical states, a = {res.history['a'][-1]:.6g} at the last"
            if n > 1
            else ""
        )
        log(f"status  {res.meta['status']}{extra}")
    plots: list[str] = []
    missing: list[str] = []

    def write(d: Path) -> Path:
        plots.clear()
        missing.clear()
        with writing(d, owned=OWNED_NAMES, last=JSON_NAME) as w:
            res._stage(w, vtu=not args.no_vtu)
            if args.plot:
                _stage_plots(res, w, plots, missing)
        return d

    try:
        out = with_fallback(args.out, write, "run")
    except OutputError as e:
        print(f"rustfrac: error: {e}", file=sys.stderr)
        return 1
    log(
        f"saved   {out}/ (result.json, fields.npz{'' if args.no_vtu else ', result.vtu'}"
        + (f", {PVD_NAME} + series" if (Path(out) / PVD_NAME).exists() else "")
        + "".join(", " + p for p in plots)
        + ")"
    )
    if missing:
        print(
            f"rustfrac: interrupted while plotting; the result was saved to {out}/ without "
            f"{', '.join(missing)}",
            file=sys.stderr,
        )
        return 130
    return 0


def _stage_plots(res: _Result, w: FolderWriter, plots: list[str], missing: list[str]) -> None:
    """``rustfrac run --plot``: the PNGs of a result, staged into its folder; Ctrl-C drops the
    plot being drawn and lists it and the rest in ``missing`` (the result is still written)."""
    from .plotting import (
        plot_crack_path,
        plot_damage,
        plot_field,
        plot_load_path,
        plot_tip_deformation,
    )

    name = "s22.png" if "nodal_stress" in res.fields else "u2.png"
    todo: list[tuple[str, Callable[[], Any]]] = [
        (name, lambda: plot_field(res)),
        ("crack_path.png", lambda: plot_crack_path(res)),
    ]
    if res.damage is not None:
        todo.append(("damage.png", lambda: plot_damage(res)))
    if "deformed_cells" in res.fields:
        todo.append(("tip_x50.png", lambda: plot_tip_deformation(res, scale=50.0)))
    if res.history:
        todo.append(("load_path.png", lambda: plot_load_path(res)))
    done, _ = w.stage_each(
        (name, lambda p, d=draw: d().figure.savefig(p, format="png", dpi=150, bbox_inches="tight"))
        for name, draw in todo
    )
    plots.extend(done)
    missing.extend(n for n, _ in todo if n not in done)


def _checkpoint_options(scene: _Scene, args: argparse.Namespace) -> _Scene:
    """Applies ``--checkpoint``, ``--checkpoint-every`` and ``--resume`` to a PD scene."""
    if args.checkpoint is None and args.checkpoint_every is None and args.resume is None:
        return scene
    if scene.method not in ("pd", "ccm_pd"):
        raise InvalidParameterError(
            "invalid --checkpoint/--resume: checkpoints are for the SLA of methods 'pd' and "
            f"'ccm_pd', the scene runs {scene.method!r}",
            "resume_from",
        )
    changes: dict[str, Any] = {}
    if args.checkpoint is not None:
        changes["pd__checkpoint_path"] = str(args.checkpoint)
        if args.checkpoint_every is None and scene.pd.checkpoint_every == 0:
            changes["pd__checkpoint_every"] = 100
    if args.checkpoint_every is not None:
        changes["pd__checkpoint_every"] = args.checkpoint_every
    if args.resume is not None:
        changes["pd__resume_from"] = str(args.resume)
    return scene.replace(**changes)


def _log_pd(log: Callable[..., None], res: _Result) -> None:
    """The PD / CCM-PD lines of ``rustfrac run``: model size, gamma, SLA outcome."""
    m, n = res.meta, res.meta.get("counts", {})
    log(
        f"pd      {n.get('n_pd_nodes')} PD nodes of {n.get('n_nodes')} grid nodes, "
        f"{n.get('n_bonds')} bonds ({n.get('bytes_per_bond')} B/bond, "
        f"{n.get('n_precrack_bonds')} pre-broken), {n.get('n_removed_elements')} FEM elements "
        f"removed; gamma = {res.gamma:.15g}, s0 = {res.scalars.get('s0', float('nan')):.6g}"
    )
    h = res.history
    steps = m.get("sla_steps_done", 0)
    last = (
        f"; last step: load factor {h['load_factor'][-1]:.6g}, sigma22 {h['sigma22'][-1]:.6g}, "
        f"crack length {h['crack_length'][-1]:.6g}"
        if steps
        else ""
    )
    t = m.get("timings", {})
    log(
        f"sla     status {m.get('status')} after {steps} steps{last}; solver {m.get('solver')}; "
        f"setup {t.get('setup_s', 0.0):.3f} s, SLA {t.get('sla_s', 0.0):.3f} s"
    )
    if m.get("resumed_steps") or m.get("n_checkpoints"):
        log(
            f"ckpt    {m.get('resumed_steps', 0)} steps replayed from {m.get('resumed_from')}; "
            f"{m.get('n_checkpoints', 0)} checkpoints written to {m.get('checkpoint_path')}"
        )
    for w in m.get("warnings", []):
        log(f"warning {w}")


def main(argv: list[str] | None = None) -> int:
    """Entry point of the ``rustfrac`` console script; returns the exit code."""
    args = _parser().parse_args(argv)
    commands = {
        "run": _cmd_run,
        "fig7": _cmd_fig7,
        "sweep": _cmd_sweep,
        "examples": _cmd_examples,
        "plot": _cmd_plot,
        "specimens": _cmd_specimens,
        "specimen": _cmd_specimen,
        "compare": _cmd_compare,
    }
    # one mapping of errors to exit codes for every command (commands handle only their own
    # special cases, such as an unreadable scene file or an interrupted sweep)
    try:
        return commands[args.command](args)
    except KeyboardInterrupt:
        print("rustfrac: interrupted", file=sys.stderr)
        return 130
    except (InvalidParameterError, MethodNotAvailableError) as e:
        print(f"rustfrac: error: invalid input: {e}", file=sys.stderr)
        return 2
    except OutputError as e:  # at the end of a run: the message says where the output went
        print(f"rustfrac: error: {e}", file=sys.stderr)
        return 1
    except RustfracError as e:
        print(f"rustfrac: run failed: {type(e).__name__}: {e}", file=sys.stderr)
        return 1


def console() -> int:
    """The ``rustfrac`` command itself (console script, ``python -m rustfrac``): :func:`main`,
    then ``gc.freeze()`` before the interpreter exits. Freezing moves every live object out of
    the cyclic collector's reach, so the collections of the interpreter's shutdown do not
    traverse matplotlib's and the results' objects: 0.15-0.2 s of a ``rustfrac fig7`` process
    (benches/RESULTS.md). Objects are still released by reference counting; only finalizers of
    cyclic garbage are skipped, which the command does not rely on (its files are closed, the
    standard streams flushed by the interpreter). Not in :func:`main`, which tests call in their
    own process."""
    code = main()
    gc.freeze()
    return code


if __name__ == "__main__":  # pragma: no cover
    sys.exit(console())
