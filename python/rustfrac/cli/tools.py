"""The small commands: ``rustfrac plot``, ``specimens``, ``specimen`` and ``examples``."""

from __future__ import annotations

import argparse
import sys


def cmd_plot(args: argparse.Namespace) -> int:
    from ..plotting import DEFAULT_UNITS, PAPER_UNITS, plot_load_path
    from ..result import load

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


def cmd_specimens(args: argparse.Namespace) -> int:
    from ..specimens import SPECIMENS

    for name, sp in SPECIMENS.items():
        print(f"{name:18s} {sp.reference}; example {sp.example}")
    return 0


def cmd_specimen(args: argparse.Namespace) -> int:
    from ..specimens import get

    sp = get(args.name)
    scene = sp.build(args.method or sp.example_method)
    try:
        scene.save_toml(args.out)
    except OSError as e:
        print(f"rustfrac: error: cannot write {args.out}: {e.strerror or e}", file=sys.stderr)
        return 2
    print(f"saved   {args.out}: {scene.describe()}")
    return 0


def cmd_examples(args: argparse.Namespace) -> int:
    from .. import examples

    if args.name is not None:
        print(examples.path(args.name))
        return 0
    for name in examples.list():
        print(f"{name:30s} {examples.path(name)}")
    return 0
