"""The ``rustfrac`` command line's arguments: one subparser per command (:func:`build_parser`)."""

from __future__ import annotations

import argparse
from pathlib import Path


def _choices(name: str) -> list[str]:
    """The choices of a scene key from the core's schema (``S0_CALIBRATIONS`` for
    ``pd.s0_calibration``, ``SURFACE_CORRECTIONS`` for ``pd.surface_correction``)."""
    from .. import _core

    return list(_core.scene_constants()[name])


#: the levels of ``--log-level``, quietest last
LOG_LEVELS = ("debug", "info", "warning", "error")


def log_level(args: argparse.Namespace) -> int:
    """The ``logging`` level the options ask for: ``--log-level``, else one step below warning
    per ``-v``."""
    import logging

    if args.log_level is not None:
        return int(getattr(logging, args.log_level.upper()))
    return {0: logging.WARNING, 1: logging.INFO}.get(args.verbose, logging.DEBUG)


def _at_least_one(text: str) -> int:
    """An integer >= 1 (a count of processes or timings: 0 would silently mean the default)."""
    try:
        n = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected an integer >= 1, got {text!r}") from None
    if n < 1:
        raise argparse.ArgumentTypeError(f"expected an integer >= 1, got {n}")
    return n


def build_parser() -> argparse.ArgumentParser:
    from .. import __version__

    p = argparse.ArgumentParser(
        prog="rustfrac", description="rustfrac: crack propagation (FEM, XFEM, CCM-PD)"
    )
    p.add_argument("--version", action="version", version=f"rustfrac {__version__}")
    p.add_argument(
        "-v",
        "--verbose",
        action="count",
        default=0,
        help="show the library's log on stderr: -v its steps (info), -vv details (debug)",
    )
    p.add_argument(
        "--log-level",
        choices=LOG_LEVELS,
        default=None,
        help="the level of the library's log on stderr (default: warning; overrides -v)",
    )
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
        type=_at_least_one,
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
    w.add_argument(
        "--workers", type=_at_least_one, default=None, help="local processes (default: cores)"
    )
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
