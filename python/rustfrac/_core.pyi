"""Typed stubs of the native module ``rustfrac._core`` (PyO3). Prefer the Python API
(:func:`rustfrac.run`); these functions take plain numbers and do only the core's checks."""

from typing import Any, Callable

import numpy as np
import numpy.typing as npt

__version__: str
PROGRESS_INTERVAL_S: float

ProgressCallback = Callable[[int, int, str], Any]

def solve_fem_plate(
    *,
    width: float,
    height: float,
    nx: int,
    ny: int,
    e: float,
    nu: float,
    plane: str = "strain",
    thickness: float = 1.0,
    bc: str = "free",
    u0: float = 0.0,
    traction: float = 0.0,
    seam: tuple[float, float] | None = None,
    gauss: int = 2,
    progress: ProgressCallback | None = None,
) -> dict[str, Any]:
    """The paper's plate with plain Q4 FEM (GIL released). Keys: coords (n,2), elements (m,4)
    int64, u (2n,), reactions (2n,), nodal_stress (n,3), gauss_points (g,2), gauss_stress (g,3)
    as float64 arrays; sigma22, cmod, energy, residual, wall_time_s: float; n_dofs, anchor_node:
    int; seam_y: float | None; bc: str."""

def solve_fem_grid(
    *,
    width: float,
    height: float,
    nx: int,
    ny: int,
    e: float,
    nu: float,
    plane: str = "strain",
    thickness: float = 1.0,
    fixed_dofs: list[int] | npt.NDArray[np.integer[Any]],
    fixed_values: list[float] | npt.NDArray[np.floating[Any]],
    forces: list[float] | npt.NDArray[np.floating[Any]] = ...,
) -> dict[str, Any]:
    """A uniform Q4 grid with explicit Dirichlet dofs (2 node + component) and nodal forces.
    Keys: coords, elements, u, reactions, nodal_stress, energy, residual, n_dofs. Raises
    SingularSystemError if the conditions leave a rigid-body mode."""

def _progress_demo(steps: int, step_s: float, progress: ProgressCallback | None = None) -> int: ...
def _panic_demo() -> None: ...
