"""``rustfrac.run``: dispatches a validated scene to the Rust solver of its method."""

from __future__ import annotations

import math
import time
import warnings
from collections.abc import Mapping
from pathlib import Path
from typing import Any, Callable

import numpy as np

from . import _core
from .errors import (
    WARNING_CLASSES,
    AccuracyWarning,
    InvalidParameterError,
    InvalidTypeError,
    MethodNotAvailableError,
)
from .result import Result
from .scene import Scene

__all__ = ["ProgressCallback", "run"]

#: ``progress(done, total, message)``; called from the solver at most every ~0.1 s.
ProgressCallback = Callable[[int, int, str], Any]

#: where the methods that are validated but not bound yet arrive (every method is bound now)
_PENDING: dict[str, str] = {}


def run(
    scene: Scene | Mapping[str, Any] | str | Path,
    progress: ProgressCallback | None = None,
    *,
    condition: bool = True,
) -> Result:
    """Runs a scene and returns its :class:`~rustfrac.result.Result`.

    Args:
        scene: a :class:`Scene`, a scene dict, or the path of a scene TOML file.
        progress: optional callable ``progress(done, total, message)``; the native solver calls it
            (holding the GIL only then) at most every ~0.1 s and once at the end. Raising from it
            (e.g. KeyboardInterrupt) stops the run and re-raises.
        condition: FEM and XFEM: compute the condition estimate of every solve (2 extra solves
            each: +15 % of a 1e5- and +20 % of a 1e6-unknown FEM run, benches/RESULTS.md);
            ``False`` leaves ``result.condition`` None
            ("not computed") and ``history`` without a "condition" column, and only the free
            pivot-ratio bound guards against ``_core.COND_SINGULAR``. Ignored by the PD methods.

    Warns:
        AccuracyWarning: the run completed but a known discretisation limit makes it less
            accurate: :class:`LockingWarning` (plane-strain nu >= 0.49: Q4 locking) or
            :class:`DiscretisationWarning` (PD m < 2, grounded nodes); the class follows the
            native warning kind (``meta["warning_kinds"]``), the messages are in
            ``meta["warnings"]``.

    Raises:
        InvalidParameterError: the scene is invalid (a ``ValueError``).
        SingularSystemError: the system is singular (a rigid mode left free, named; a separated
            body; a condition estimate above ``_core.COND_SINGULAR``).
        MethodNotAvailableError: the method is validated but not bound in this build yet.

    Warns:
        IllConditionedWarning: a solve's condition estimate exceeded ``_core.COND_WARN`` (the
            messages are also in ``result.warnings``).
    """
    if not isinstance(condition, bool):
        raise InvalidTypeError(
            f"invalid condition: expected True or False, got {condition!r}", "condition"
        )
    scene = _as_scene(scene)
    runner = _RUNNERS.get(scene.method)
    if runner is None:
        raise MethodNotAvailableError(
            f"method {scene.method!r} is not available in rustfrac {_core.__version__} yet: "
            f"{_PENDING.get(scene.method, 'not implemented')}; the scene itself is valid"
        )
    t0 = time.perf_counter()
    res = runner(scene, progress, condition)
    res.meta.setdefault("timings", {})["total_s"] = time.perf_counter() - t0
    msgs = res.meta.setdefault("warnings", [])
    for msg, kind in zip(msgs, res.meta.get("warning_kinds", [None] * len(msgs))):
        warnings.warn(
            f"{scene.method}: {msg}", WARNING_CLASSES.get(kind, AccuracyWarning), stacklevel=2
        )
    return res


def _warning_meta(pairs: Any) -> dict[str, list[str]]:
    """The native (kind, message) warning pairs as ``meta["warnings"]`` (the messages) and
    ``meta["warning_kinds"]`` (``_core.WARNING_KINDS`` names, same order)."""
    pairs = [(str(k), str(m)) for k, m in pairs]
    return {"warnings": [m for _, m in pairs], "warning_kinds": [k for k, _ in pairs]}


def _as_scene(scene: Scene | Mapping[str, Any] | str | Path) -> Scene:
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


def _meta(scene: Scene, bc_desc: str, anchor: int | None, **extra: Any) -> dict[str, Any]:
    return {
        "version": _core.__version__,
        "method": scene.method,
        "scene": scene.to_dict(),
        "bc": scene.load.bc,
        "bc_description": bc_desc,
        "anchor_node": anchor,
        **extra,
    }


_BC_DESC = {
    "free": "u2 = +-u0 on top/bottom, u1 free (u1 = 0 at the anchor node only)",
    "clamped": "u2 = +-u0 and u1 = 0 on top/bottom (clamped grips)",
    "traction": "uniform normal traction on top/bottom (u1, u2 = 0 at the anchor node, "
    "u1 = 0 at the top-right corner)",
}


def _plate_kwargs(scene: Scene) -> dict[str, Any]:
    """The native solvers' common keywords: plate, material and load of the scene."""
    p, mat, load = scene.plate, scene.material, scene.load
    return {
        "width": p.width,
        "height": p.height,
        "e": mat.E,
        "nu": mat.nu,
        "plane": mat.plane,
        "thickness": mat.thickness,
        "bc": load.bc,
        # traction grips prescribe no displacement (the PD history's "u0" is then 0)
        "u0": 0.0 if load.bc == "traction" else load.u0,
        "traction": load.traction,
    }


def _condition_scalars(out: Mapping[str, Any]) -> dict[str, float | None]:
    """The solve's condition estimate (FEM and XFEM): see ``Result.condition``; None when not
    computed (``run(..., condition=False)``)."""
    return {
        k: None if out[k] is None else float(out[k])
        for k in ("condition", "condition_pivot_ratio")
    }


def _run_fem(scene: Scene, progress: ProgressCallback | None, condition: bool = True) -> Result:
    load, c, mesh = scene.load, scene.crack, scene.mesh
    try:
        out = _core.solve_fem_plate(
            **_plate_kwargs(scene),
            nx=mesh.nx,
            ny=mesh.ny,
            seam=(c.a0, c.y) if c.kind == "seam" else None,
            gauss=mesh.gauss,
            condition=condition,
            progress=progress,
        )
    except InvalidParameterError as e:
        raise _scene_param(e) from e
    fields = {k: v for k, v in out.items() if isinstance(v, np.ndarray)}
    return Result(
        method="fem",
        sigma22=float(out["sigma22"]),
        cmod=float(out["cmod"]),
        n_dofs=int(out["n_dofs"]),
        wall_time_s=float(out["wall_time_s"]),
        fields=fields,
        scalars={
            "energy": out["energy"],
            "residual": out["residual"],
            **_condition_scalars(out),
        },
        meta=_meta(
            scene,
            _BC_DESC[load.bc],
            None if load.bc == "clamped" else int(out["anchor_node"]),
            seam_y=out["seam_y"],
            **_warning_meta(out["warnings"]),
            timings={"rust_s": float(out["wall_time_s"])},
        ),
    )


#: history keys of an XFEM growth run (``history_<key>`` in the native dict)
XFEM_HISTORY: tuple[str, ...] = (
    "load_factor",
    "sigma22",
    "cmod",
    "u0",
    "traction",
    "a",
    "K_I",
    "K_II",
    "kink_angle",
    "tip_x",
    "tip_y",
    "condition",
)
_XFEM_SCALARS: tuple[str, ...] = (
    "K_I",
    "K_II",
    "J",
    "J_domain",
    "r_i",
    "n_std",
    "n_heaviside_nodes",
    "n_tip_nodes",
    "n_dropped_nodes",
)


#: radii (tip-element lengths) at which the SIFs are also reported, where the domain fits
XFEM_EXTRA_RADII: tuple[float, ...] = (1.5, 2.0, 3.0, 3.5)


def _extra_radii(scene: Scene) -> list[float]:
    """The radii of :data:`XFEM_EXTRA_RADII` whose q-domain around the primary tip stays clear of
    the other tip and of the other cracks, as the core requires (the plate boundary may clip it)."""
    p, m, c = scene.plate, scene.mesh, scene.crack
    dx, dy = p.width / m.nx, p.height / m.ny
    h = math.sqrt(dx * dy)
    pts = c.polyline(p)
    tx, ty = pts[-1]
    room = math.inf
    if c.kind == "center":
        room = min(room, 2 * c.a0 - 1.5 * h)
    for other in scene.extra_cracks:
        # the q-function reaches one element beyond its radius
        room = min(room, _distance_to_segment((tx, ty), *other.polyline(p)) - dx - dy)
    return [f for f in XFEM_EXTRA_RADII if f * h < (1 - 1e-9) * room]


def _distance_to_segment(
    x: tuple[float, float], a: tuple[float, float], b: tuple[float, float]
) -> float:
    dx, dy = b[0] - a[0], b[1] - a[1]
    t = min(1.0, max(0.0, ((x[0] - a[0]) * dx + (x[1] - a[1]) * dy) / (dx * dx + dy * dy)))
    return math.hypot(x[0] - a[0] - t * dx, x[1] - a[1] - t * dy)


def _growth_progress(scene: Scene, progress: ProgressCallback | None) -> ProgressCallback | None:
    """Rescales the core's growth progress (step k of at most ``growth_steps``) to the number of
    steps the run needs to reach ``a_stop`` (an estimate from a0, da and a_stop)."""
    x, c, p, m = scene.xfem, scene.crack, scene.plate, scene.mesh
    if progress is None or x.growth_steps == 0:
        return progress
    t = math.radians(c.angle)
    dx, dy = p.width / m.nx, p.height / m.ny
    da = x.da or min(
        dx / abs(math.cos(t)) if abs(math.cos(t)) > 1e-12 else math.inf,
        dy / abs(math.sin(t)) if abs(math.sin(t)) > 1e-12 else math.inf,
    )
    a_stop = x.a_stop or 0.7 * p.width
    est = max(1, min(x.growth_steps, math.floor((a_stop - c.a0) / da + 1e-9) + 1))

    def cb(done: int, total: int, message: str) -> Any:
        if total != x.growth_steps:
            return progress(done, total, message)
        if message.startswith("xfem: growth step"):
            message = f"xfem: growth step {done} of ~{est} (a_stop {a_stop:g})"
        elif done == total:
            done = est
        return progress(min(done, est), est, message)

    return cb


#: core parameter names -> scene keys, for errors the core finds (e.g. an r_I domain that leaves
#: the plate on a coarse mesh, or a zero reference load)
_CORE_PARAMS: dict[str, str] = {
    "E": "material.E",
    "nu": "material.nu",
    "thickness": "material.thickness",
    "plane": "material.plane",
    "G0": "material.G0",
    "width": "plate.width",
    "height": "plate.height",
    "u0": "load.u0",
    "traction": "load.traction",
    "bc": "load.bc",
    "gauss": "mesh.gauss",
    "a0": "crack.a0",
    "crack_y": "crack.y",
    "dx": "pd.dx",
    "m": "pd.m",
    "pd_regions": "pd.center",
    "precrack": "crack.a0",
    "tie_tol": "pd.tie_tol",
    "stop_crack_length": "pd.stop_crack_length",
    "nx": "mesh.nx",
    "ny": "mesh.ny",
    "nx * ny": "mesh.nx",
    "nsub": "xfem.nsub",
    "tip_nsub": "xfem.tip_nsub",
    "r_I": "xfem.r_I",
    "r_i_factor": "xfem.r_I",
    "fixed_area_radius": "xfem.fixed_area_radius",
    "area_threshold": "xfem.area_threshold",
    "da": "xfem.da",
    "a_stop": "xfem.a_stop",
    "g0": "material.G0",
    "crack": "crack.a0",
    "cracks": "crack",
}


def _scene_param(err: InvalidParameterError) -> InvalidParameterError:
    """The core's error naming the scene key (``invalid r_I: ...`` -> ``xfem.r_I``; the core's
    ``cracks[k]`` -> ``crack[k]``, ``crack`` for k = 0)."""
    msg = str(err)
    if err.param is None and msg.startswith("invalid ") and ":" in msg:
        core = msg[len("invalid ") : msg.index(":")]
        key = _CORE_PARAMS.get(core.split("[")[0])
        if core.startswith("cracks[") and core.endswith("]"):
            k = int(core[len("cracks[") : -1])
            key = "crack.a0" if k == 0 else f"crack[{k}]"
        if key is not None:
            return InvalidParameterError(f"invalid {key} (core: {msg})", key)
    return err


def _run_xfem(scene: Scene, progress: ProgressCallback | None, condition: bool = True) -> Result:
    """XFEM: ``fields["u"]`` holds the nodal displacements (the standard dofs: the shifted
    enrichments vanish at the nodes), ``fields["u_enriched"]`` the whole solution vector; the
    growth history (origin first) is in ``history``."""
    mat, load, c, mesh, x = scene.material, scene.load, scene.crack, scene.mesh, scene.xfem
    growth = x.growth_steps > 0
    try:
        out = _core.solve_xfem_plate(
            **_plate_kwargs(scene),
            nx=mesh.nx,
            ny=mesh.ny,
            crack=c.polyline(scene.plate),
            extra_cracks=[e.polyline(scene.plate) for e in scene.extra_cracks],
            nsub=x.nsub,
            tip_nsub=x.tip_nsub,
            r_i=x.r_I,
            extra_radii=_extra_radii(scene),
            fixed_area_radius=x.fixed_area_radius or None,
            area_threshold=x.area_threshold,
            growth_steps=x.growth_steps,
            g0=mat.G0 if growth else None,
            da=x.da or None,
            a_stop=x.a_stop or None,
            condition=condition,
            progress=_growth_progress(scene, progress),
        )
    except InvalidParameterError as e:
        raise _scene_param(e) from e
    n_std = int(out["n_std"])
    fields = {
        k: v for k, v in out.items() if isinstance(v, np.ndarray) and not k.startswith("history_")
    }
    fields["u_enriched"] = fields["u"]
    fields["u"] = fields["u_enriched"][:n_std]
    # per node: 0 standard, 1 Heaviside-enriched, 2 tip-enriched (a VTU point field)
    enrichment = np.zeros(n_std // 2)
    enrichment[fields["heaviside_nodes"]] = 1.0
    enrichment[fields["tip_nodes"]] = 2.0
    fields["enrichment"] = enrichment
    history = {k: out["history_" + k] for k in XFEM_HISTORY} if growth else {}
    if growth and history["condition"] is None:
        del history["condition"]  # not computed
    scalars: dict[str, Any] = {k: out[k] for k in _XFEM_SCALARS}
    scalars["r_I"] = scalars.pop("r_i")
    scalars = {k: (int(v) if k.startswith("n_") else float(v)) for k, v in scalars.items()}
    scalars.update(_condition_scalars(out))
    return Result(
        method="xfem",
        sigma22=float(out["sigma22"]),
        cmod=float(out["cmod"]),
        n_dofs=int(out["n_dofs"]),
        wall_time_s=float(out["wall_time_s"]),
        fields=fields,
        history=history,
        scalars=scalars,
        meta=_meta(
            scene,
            _BC_DESC[load.bc],
            None if load.bc == "clamped" else int(out["anchor_node"]),
            status=str(out["status"]),
            **_warning_meta(out["warnings"]),
            enrichment={
                "n_std": n_std,
                "n_heaviside_nodes": int(out["n_heaviside_nodes"]),
                "n_tip_nodes": int(out["n_tip_nodes"]),
                "n_dropped_nodes": int(out["n_dropped_nodes"]),
            },
            r_I=float(out["r_i"]),
            r_I_elements=x.r_I,
            crack_initial=[list(map(float, q)) for q in c.polyline(scene.plate)],
            cracks_initial=[
                [list(map(float, q)) for q in e.polyline(scene.plate)] for e in scene.cracks
            ],
            timings={"rust_s": float(out["wall_time_s"])},
        ),
    )


_RUNNERS: dict[str, Callable[[Scene, ProgressCallback | None, bool], Result]] = {
    "fem": _run_fem,
    "xfem": _run_xfem,
}


def _run_pd(scene: Scene, progress: ProgressCallback | None, condition: bool = True) -> Result:
    """Pure PD (``method="pd"``, PD on the whole plate) or CCM-PD (``"ccm_pd"``, PD in the scene's
    rectangle, FEM elsewhere), then the sequentially linear analysis.

    ``history`` holds one row per SLA step, recorded at the load that breaks the step's bond(s),
    preceded by the unloaded origin as step 0 (load_factor = sigma22 = cmod = u0 = 0, crack_length
    = the pre-crack length, bond = node_i = node_j = -1, n_broken = 0), so that plotting
    sigma22 against cmod starts with the linear loading branch from (0, 0). Under ``bc =
    "traction"`` the load factor scales the traction and ``u0`` is 0 (no prescribed displacement).
    """
    mat, load, c, pd = scene.material, scene.load, scene.crack, scene.pd
    regions = []
    if scene.method == "ccm_pd":
        (cx, cy), (sx, sy) = pd.center, pd.size
        regions = [(cx - sx / 2, cy - sy / 2, cx + sx / 2, cy + sy / 2)]
    precrack = [(0.0, c.y), (c.a0, c.y)] if c.kind == "edge" else []
    try:
        out = _core.solve_pd_plate(
            method=scene.method,
            **_plate_kwargs(scene),
            dx=pd.dx,
            m=pd.m,
            g0=mat.G0,
            pd_regions=regions,
            precrack=precrack,
            sla_steps=pd.sla_steps,
            stop_crack_length=pd.stop_crack_length or None,
            tie_tol=pd.tie_tol,
            refactor_every=pd.refactor_every,
            fast=pd.fast,
            damage_at_steps=list(pd.damage_at_steps),
            checkpoint_every=pd.checkpoint_every,
            checkpoint_path=pd.checkpoint_path or None,
            resume_from=pd.resume_from or None,
            progress=progress,
        )
    except InvalidParameterError as e:
        raise _scene_param(e) from e
    run_warnings = _warning_meta(out["warnings"])
    prefix = "history_"
    a0 = c.a0 if c.kind == "edge" else 0.0
    origin = {"crack_length": a0, "bond": -1, "node_i": -1, "node_j": -1}
    history = {
        k[len(prefix) :]: np.concatenate(
            [np.array([origin.get(k[len(prefix) :], 0)], dtype=v.dtype), v]
        )
        for k, v in out.items()
        if k.startswith(prefix)
    }
    fields = {
        k: v for k, v in out.items() if isinstance(v, np.ndarray) and not k.startswith(prefix)
    }
    meta_arrays = ("out_of_balance", "anchor_xy")
    for k in meta_arrays:
        fields.pop(k)
    n_steps = len(out["history_step"])
    return Result(
        method=scene.method,
        sigma22=float(out["sigma22"]),
        cmod=float(out["cmod"]),
        n_dofs=int(out["n_dofs"]),
        wall_time_s=float(out["wall_time_s"]),
        fields=fields,
        history=history,
        scalars={k: float(out[k]) for k in ("gamma", "c", "s0", "delta")},
        meta=_meta(
            scene,
            _BC_DESC[load.bc]
            + ("" if scene.method == "ccm_pd" else "; on volumetric PD boundary layers"),
            None if load.bc == "clamped" else int(out["anchor_node"]),
            anchor_xy=None if load.bc == "clamped" else out["anchor_xy"].tolist(),
            status=out["status"],
            solver=out["solver"],
            sla_steps_done=n_steps,
            pd_regions=[list(r) for r in regions] if regions else "the whole plate",
            precrack=[list(q) for q in precrack],
            out_of_balance=out["out_of_balance"].tolist(),
            n_refactorisations=int(out["n_refactorisations"]),
            max_update_rank=int(out["max_update_rank"]),
            refactor_interval=int(out["refactor_interval"]),
            resumed_steps=int(out["resumed_steps"]),
            n_checkpoints=int(out["n_checkpoints"]),
            checkpoint_path=pd.checkpoint_path or None,
            resumed_from=pd.resume_from or None,
            **run_warnings,
            peak_memory_bytes=out["peak_memory_bytes"],
            counts={
                k: int(out[k])
                for k in (
                    "n_nodes",
                    "n_dofs",
                    "n_pd_nodes",
                    "n_bonds",
                    "n_precrack_bonds",
                    "n_removed_elements",
                    "bytes_per_bond",
                )
            },
            timings={
                "rust_s": float(out["wall_time_s"]),
                "setup_s": float(out["setup_seconds"]),
                "sla_s": float(out["sla_seconds"]),
            },
        ),
    )


_RUNNERS["pd"] = _run_pd
_RUNNERS["ccm_pd"] = _run_pd
