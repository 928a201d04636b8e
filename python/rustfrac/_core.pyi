"""Typed stubs of the native module ``rustfrac._core`` (PyO3). Prefer the Python API
(:func:`rustfrac.run`, :class:`rustfrac.Scene`). Every scene rule (keys, kinds, defaults,
ranges, cross-parameter checks) lives in the core: :func:`scene_schema` lists it, :func:`check_scene`
applies it, :func:`run` runs a scene dict; every result entry and status is in
:func:`result_schema`."""

from typing import Any, Callable

import numpy as np
import numpy.typing as npt

# the module's exports, the same in every build; the test hooks _progress_demo and _panic_demo
# (builds with "test-hooks" only) are attributes outside __all__, typed at the end
__all__ = [
    "COND_SINGULAR",
    "COND_WARN",
    "PROGRESS_INTERVAL_S",
    "WARNING_KINDS",
    "__version__",
    "check_scene",
    "check_section",
    "crack_polylines",
    "result_schema",
    "run",
    "scene_constants",
    "scene_schema",
    "scene_warnings",
    "solve_fem_grid",
]

__version__: str
PROGRESS_INTERVAL_S: float
#: condition estimate above which a result carries a warning (rustfrac_core::solver::COND_WARN)
COND_WARN: float
#: condition estimate above which a solve raises SingularSystemError ("numerically singular",
#: rustfrac_core::solver::COND_SINGULAR)
COND_SINGULAR: float
#: kinds of the (kind, message) warning pairs: "ill_conditioned", "locking", "discretisation"
#: (Python classes: rustfrac.errors.WARNING_CLASSES)
WARNING_KINDS: list[str]

#: ``progress(done, total, message)`` (stub only: rustfrac.progress.ProgressCallback at runtime)
_ProgressCallback = Callable[[int, int, str], Any]

def scene_schema() -> list[dict[str, Any]]:
    """Every scene key: dicts with section, key, kind ("float" | "int" | "str" | "bool" | "pair"
    | "intlist" | "floatlist" | "pairlist"), default, valid (the range in words, made from the
    range the core checks), role ("physics" | "solver" | "output"), required (None, or
    {key: [values]}: required when each key has one of its values; {}: always),
    required_words and doc."""

def result_schema() -> dict[str, Any]:
    """Every result entry and status: ``{"entries": [...], "statuses": {method: [...]}}``; an
    entry is a dict with methods (list), group ("headline" | "fields" | "history" | "scalars" |
    "meta"), name, kind ("float" | "int" | "bool" | "str" | "float array" | "int array" |
    "bool array" | "float list" | "str list" | "table" | "table list"), shape (e.g.
    "(n_nodes, 2)", or None), nullable, unit, presence ("always", "when ...", "python: ...")
    and doc; a status a dict with name and doc."""

def scene_constants() -> dict[str, Any]:
    """METHODS, BCS, SECTIONS, METHOD_SECTIONS (method -> sections), CRACK_KINDS (method ->
    kinds), DEFAULT_CRACK_KIND (method -> kind), MAX_ELEMENTS, MAX_STEPS,
    DEFAULT_A_STOP_FRACTION, PD_NU, XFEM_EXTRA_RADII, S0_CALIBRATIONS (pd.s0_calibration's
    choices), SURFACE_CORRECTIONS (pd.surface_correction's choices)."""

def check_section(section: str, values: Any, name: str | None = None) -> dict[str, Any]:
    """Checks one section's values (kinds, ranges, unknown keys) and returns every key of the
    section, normalised, defaults filled in; errors name ``<name>.<key>`` (name: the section)."""

def check_scene(scene: Any) -> dict[str, Any]:
    """Checks a whole scene dict (every rule, cross-parameter checks included) and returns it
    checked: method, name, every section the method reads with every key, "crack" as a list."""

def crack_polylines(scene: Any) -> list[list[list[float]]]:
    """The polylines [[x1, x2], ...] of a scene's cracks as the method cuts them (a FEM seam on
    its grid line; empty for an uncracked scene)."""

def scene_warnings(scene: Any) -> list[tuple[str, str]]:
    """The warnings of a valid scene before it runs: [(message, kind), ...]."""

def run(
    scene: Any, progress: _ProgressCallback | None = None, condition: bool = True
) -> dict[str, Any]:
    """Runs a scene dict without the GIL: ``{method, sigma22, cmod, n_dofs, wall_time_s, fields,
    history, scalars, meta}`` (the fields of :class:`rustfrac.Result`; every key is an entry of
    :func:`result_schema`). ``condition=False`` skips
    the FEM/XFEM condition estimate. Raising from ``progress`` stops the run and re-raises."""

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
    SingularSystemError if the conditions leave a rigid-body mode free (named) or the system is
    numerically singular."""

# test hooks: present only in builds with the cargo feature "test-hooks" (the test suite's)
def _progress_demo(steps: int, step_s: float, progress: _ProgressCallback | None = None) -> int: ...
def _panic_demo() -> None: ...
