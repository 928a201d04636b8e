"""The jobs of several runs: ``rustfrac fig7`` (:mod:`rustfrac.fig7`) and ``rustfrac compare``
(:mod:`rustfrac.compare`), with their console (a log and a progress bar per run)."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import Any, Callable

from .._folder import check_writable
from ..errors import OutputError
from ..progress import ProgressBar
from .common import read_scene


def cmd_fig7(args: argparse.Namespace) -> int:
    from ..fig7 import Fig7Interrupted, fig7

    try:
        check_writable(args.out)  # before computing: a bad --out must not cost the runs
    except OutputError as e:
        print(f"rustfrac: error: invalid --out: {e}", file=sys.stderr)
        return 2
    bars: list[ProgressBar] = []
    log, progress = job_console(bars, args.quiet)

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


def cmd_compare(args: argparse.Namespace) -> int:
    from ..compare import DEFAULT_MARGIN_HORIZONS, CompareInterrupted, compare

    scene = read_scene(args.scene)
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
    log, progress = job_console(bars, args.quiet)

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


def job_console(
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
