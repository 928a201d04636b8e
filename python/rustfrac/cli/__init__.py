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
input (unreadable or invalid scene file, bad arguments, a missing or invalid result folder or
checkpoint to read, an ``--out`` that cannot be written: checked before computing), 130 interrupted (what finished is written and the message, and for
``fig7`` / ``sweep`` / ``compare`` the summary, lists what is missing).

One module per command: ``run.py``, ``sweep.py``, ``jobs.py`` (``fig7``, ``compare``) and
``tools.py`` (``plot``, ``specimens``, ``specimen``, ``examples``); their arguments in
``parser.py``, the scene file they read in ``common.py``; :func:`main` maps their errors to the
exit codes. ``-v`` / ``--log-level`` show the package's log (``logging.getLogger("rustfrac")``)
on stderr.
"""

from __future__ import annotations

import argparse
import gc
import logging
import sys

from .._log import logger
from ..errors import (
    InvalidParameterError,
    InvalidResultError,
    MethodNotAvailableError,
    OutputError,
    RustfracError,
)
from ..progress import ProgressBar
from .jobs import cmd_compare, cmd_fig7, job_console
from .parser import build_parser, log_level
from .run import cmd_run
from .sweep import cmd_sweep
from .tools import cmd_examples, cmd_plot, cmd_specimen, cmd_specimens

__all__ = ["ProgressBar", "console", "job_console", "main"]


def main(argv: list[str] | None = None) -> int:
    """Entry point of the ``rustfrac`` console script; returns the exit code."""
    args = build_parser().parse_args(argv)
    handler = _log_to_stderr(log_level(args))
    try:
        return _dispatch(args)
    finally:
        logger.removeHandler(handler)


def _log_to_stderr(level: int) -> logging.Handler:
    """The package's log on the stderr of the moment, at ``level`` (one handler per call)."""
    handler = logging.StreamHandler(sys.stderr)
    handler.setFormatter(logging.Formatter("rustfrac: %(levelname)s: %(message)s"))
    handler.setLevel(level)
    logger.addHandler(handler)
    logger.setLevel(min(level, logger.level or logging.WARNING))
    return handler


def _dispatch(args: argparse.Namespace) -> int:
    commands = {
        "run": cmd_run,
        "fig7": cmd_fig7,
        "sweep": cmd_sweep,
        "examples": cmd_examples,
        "plot": cmd_plot,
        "specimens": cmd_specimens,
        "specimen": cmd_specimen,
        "compare": cmd_compare,
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
    except InvalidResultError as e:  # a result folder given to read: missing or not a result
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
