"""rustfrac: crack propagation in 2D plates -- FEM, XFEM and coupled peridynamics.

A Rust core (``rustfrac._core``) with a small Python API::

    import rustfrac as rf
    scene = rf.scenes.edge_crack_plate(method="fem", crack="seam", bc="free")
    res = rf.run(scene)
    print(res.sigma22, res.cmod, res.n_dofs, res.wall_time_s)
    res.save("out/")

Units are consistent; the paper's case uses N, mm and MPa.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

# numpy imported here, before the native core: the core's initialisation reaches numpy's C API,
# and a Ctrl-C landing in a numpy import made from there ended in a Rust panic ("Failed to access
# NumPy array API capsule") instead of a clean KeyboardInterrupt (tests/test_fault_campaign.py)
import numpy as _numpy  # noqa: F401

from . import errors as _errors
from . import examples, scenes, specimens
from ._core import __version__
from .errors import *  # noqa: F403 (the exception and warning classes, errors.__all__)
from .result import STATUSES, Result, load, result_schema
from .runner import run
from .scene import METHODS, Scene

if TYPE_CHECKING:
    from . import (
        agreement,
        compare,
        energy,
        fig7,
        figures,
        handbook,
        paths,
        pd_region,
        plotting,
        progress,
        sweep,
    )


#: the public submodules imported at their first use as ``rustfrac.NAME``: plotting and the
#: studies import matplotlib, which would otherwise make ``import rustfrac`` ten times slower
#: (0.5 s instead of 0.05 s)
LAZY_SUBMODULES = (
    "agreement",
    "compare",
    "energy",
    "fig7",
    "figures",
    "handbook",
    "paths",
    "pd_region",
    "plotting",
    "progress",
    "sweep",
)


def __getattr__(name: str) -> Any:
    """``rustfrac.plotting``, ``rustfrac.handbook``, ... (:data:`LAZY_SUBMODULES`) are imported
    at their first use."""
    if name in LAZY_SUBMODULES:
        import importlib

        return importlib.import_module(f".{name}", __name__)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


__all__ = [
    "METHODS",
    "Result",
    "STATUSES",
    "Scene",
    "__version__",
    "agreement",
    "compare",
    "energy",
    "examples",
    "fig7",
    "figures",
    "handbook",
    "load",
    "paths",
    "pd_region",
    "plotting",
    "progress",
    "result_schema",
    "run",
    "scenes",
    "specimens",
    "sweep",
    *_errors.__all__,
]
