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

from . import examples, plotting, scenes
from ._core import __version__
from .errors import (
    AccuracyWarning,
    CheckpointIOError,
    DiscretisationWarning,
    IllConditionedWarning,
    InternalError,
    InvalidParameterError,
    InvalidResultError,
    InvalidTypeError,
    LockingWarning,
    MethodNotAvailableError,
    OutOfMemoryError,
    OutputError,
    PlotDataError,
    ResultNotFoundError,
    RustfracError,
    SeparatedError,
    SingularSystemError,
    UnknownParameterError,
)
from .result import Result, load
from .runner import run
from .scene import METHODS, Scene

__all__ = [
    "METHODS",
    "AccuracyWarning",
    "CheckpointIOError",
    "DiscretisationWarning",
    "IllConditionedWarning",
    "InternalError",
    "InvalidParameterError",
    "InvalidResultError",
    "InvalidTypeError",
    "LockingWarning",
    "MethodNotAvailableError",
    "OutOfMemoryError",
    "OutputError",
    "PlotDataError",
    "Result",
    "ResultNotFoundError",
    "RustfracError",
    "Scene",
    "SeparatedError",
    "SingularSystemError",
    "UnknownParameterError",
    "__version__",
    "examples",
    "load",
    "plotting",
    "run",
    "scenes",
]
