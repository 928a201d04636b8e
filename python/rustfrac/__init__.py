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

from . import errors as _errors
from . import examples, plotting, scenes, specimens
from ._core import __version__
from .errors import *  # noqa: F403 (the exception and warning classes, errors.__all__)
from .result import Result, load
from .runner import run
from .scene import METHODS, Scene

__all__ = [
    "METHODS",
    "Result",
    "Scene",
    "__version__",
    "examples",
    "load",
    "plotting",
    "run",
    "scenes",
    "specimens",
    *_errors.__all__,
]
