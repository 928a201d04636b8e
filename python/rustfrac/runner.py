"""``rustfrac.run``: hands a validated scene to the native core and wraps what comes back.

The core reads the scene, runs its method and returns the result already in the shape
:class:`~rustfrac.result.Result` stores (fields, history, scalars, meta); this module adds the
scene itself and the total wall time to ``meta`` and turns the core's warnings into Python
warnings of the class of their kind.
"""

from __future__ import annotations

import time
import warnings
from collections.abc import Mapping
from pathlib import Path
from typing import Any, Callable

from . import _core
from . import progress as _progress
from ._log import logger
from .errors import WARNING_CLASSES, AccuracyWarning, InvalidTypeError
from .progress import ProgressCallback
from .result import Result
from .scene import METHODS, Scene

__all__ = ["ProgressCallback", "run"]


def run(
    scene: Scene | Mapping[str, Any] | str | Path,
    progress: ProgressCallback | bool | None = None,
    *,
    condition: bool = True,
) -> Result:
    """Runs a scene and returns its :class:`~rustfrac.result.Result`.

    Args:
        scene: a :class:`Scene`, a scene dict, or the path of a scene TOML file.
        progress: optional callable ``progress(done, total, message)``; the native solver calls it
            (holding the GIL only then) at most every ~0.1 s and once at the end. The SLA counts
            steps of ``pd.sla_steps``; with ``pd.stop_crack_length`` (e.g. the adaptive run to
            0.7 W) thousandths of the crack's advance to it (or of the steps, if further), so the
            fraction and the time left follow the crack. Raising from it
            (e.g. KeyboardInterrupt) stops the run and re-raises. Ctrl-C stops a long run with
            or without a callback: the ``KeyboardInterrupt`` carries the finished part as
            ``.result`` (XFEM growth and the SLA: the steps so far, status "cancelled"). ``True``: a ``tqdm.auto`` bar
            (a widget in Jupyter) when tqdm is installed, else a text bar on stderr
            (:func:`rustfrac.progress.callback`).
        condition: FEM and XFEM: compute the condition estimate of every solve (2 extra solves
            each: +15 % of a 1e5- and +20 % of a 1e6-unknown FEM run, benches/RESULTS.md);
            ``False`` leaves ``result.condition`` None ("not computed") and ``history`` without a
            "condition" column, and only the free pivot-ratio bound guards against
            ``_core.COND_SINGULAR``. Ignored by the PD methods.

    Raises:
        InvalidParameterError: the scene is invalid (a ``ValueError``; ``param`` names the key).
        SingularSystemError: the system is singular (a rigid mode left free, named; a separated
            body; a condition estimate above ``_core.COND_SINGULAR``).

    Warns:
        AccuracyWarning: the run completed but a known discretisation limit makes it less
            accurate: :class:`LockingWarning` (plane-strain nu >= 0.49: Q4 locking) or
            :class:`DiscretisationWarning` (PD m < 2, grounded nodes; before the run: a default
            sized for another plate, an estimated cost past its budget); the class follows the
            native warning kind (``meta["warning_kinds"]``), the messages are in
            ``meta["warnings"]``.
        IllConditionedWarning: a solve's condition estimate exceeded ``_core.COND_WARN``.
    """
    if not isinstance(condition, bool):
        raise InvalidTypeError(
            f"invalid condition: expected True or False, got {condition!r}", "condition"
        )
    scene = as_scene(scene)
    logger.debug("run %s", scene.describe())
    # the scene's own warnings (a default sized for another plate, the estimated cost past its
    # budget) come before the run; the result carries them too
    before = _core.scene_warnings(scene.to_dict())
    for msg, kind in before:
        warnings.warn(
            f"{scene.method}: {msg}", WARNING_CLASSES.get(kind, AccuracyWarning), stacklevel=2
        )
    cb = _progress.callback(progress, desc=f"rustfrac {scene.method}")
    t0 = time.perf_counter()
    try:
        res = _RUNNERS[scene.method](scene, cb, condition)
    finally:
        close = getattr(cb, "close", None)
        if cb is not progress and close is not None:
            close()  # a bar made here
    res.meta.setdefault("timings", {})["total_s"] = time.perf_counter() - t0
    logger.debug("done %s", res.summary())
    msgs = res.meta.setdefault("warnings", [])
    said = {msg for msg, _ in before}
    for msg, kind in zip(msgs, res.meta.get("warning_kinds", [None] * len(msgs))):
        if msg in said:
            continue
        warnings.warn(
            f"{scene.method}: {msg}", WARNING_CLASSES.get(kind, AccuracyWarning), stacklevel=2
        )
    return res


def as_scene(scene: Scene | Mapping[str, Any] | str | Path) -> Scene:
    """A :class:`Scene` from a Scene, a scene dict or a TOML path (what :func:`run` takes)."""
    if isinstance(scene, Scene):
        return scene
    if isinstance(scene, Mapping):
        return Scene.from_dict(scene)
    if isinstance(scene, (str, Path)):
        return Scene.from_toml(scene)
    raise InvalidTypeError(
        f"invalid scene: run() takes a Scene, a dict or a TOML path, got {type(scene).__name__}",
        "scene",
    )


def _run_native(scene: Scene, progress: ProgressCallback | None, condition: bool) -> Result:
    """The core's run of the scene, as a :class:`Result` (meta gains the scene itself)."""
    d = scene.to_dict()
    try:
        out = _core.run(d, progress, condition)
    except KeyboardInterrupt as e:
        # the core stopped the run (XFEM growth and the SLA with status "cancelled") and attached
        # what finished; it travels on as ``e.result``
        partial = getattr(e, "partial", None)
        if isinstance(partial, dict):
            partial["meta"]["scene"] = d
            e.result = Result(**partial)  # type: ignore[attr-defined]
        raise
    out["meta"]["scene"] = d
    return Result(**out)


#: the runner of each method (one native entry point serves all; a seam for tests)
_RUNNERS: dict[str, Callable[[Scene, ProgressCallback | None, bool], Result]] = {
    m: _run_native for m in METHODS
}
