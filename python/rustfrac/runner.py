"""``rustfrac.run``: dispatches a validated scene to the Rust solver of its method."""

from __future__ import annotations

import time
from collections.abc import Mapping
from pathlib import Path
from typing import Any, Callable

import numpy as np

from . import _core
from .errors import InvalidTypeError, MethodNotAvailableError
from .result import Result
from .scene import Scene

__all__ = ["ProgressCallback", "run"]

#: ``progress(done, total, message)``; called from the solver at most every ~0.1 s.
ProgressCallback = Callable[[int, int, str], Any]

#: where the methods that are validated but not bound yet arrive
_PENDING: dict[str, str] = {
    "xfem": "XFEM arrives with issue #3",
    "pd": "peridynamics arrives with issue #4",
    "ccm_pd": "the CCM-PD coupling arrives with issue #4",
}


def run(
    scene: Scene | Mapping[str, Any] | str | Path,
    progress: ProgressCallback | None = None,
) -> Result:
    """Runs a scene and returns its :class:`~rustfrac.result.Result`.

    Args:
        scene: a :class:`Scene`, a scene dict, or the path of a scene TOML file.
        progress: optional callable ``progress(done, total, message)``; the native solver calls it
            (holding the GIL only then) at most every ~0.1 s and once at the end. Raising from it
            (e.g. KeyboardInterrupt) stops the run and re-raises.

    Raises:
        InvalidParameterError: the scene is invalid (a ``ValueError``).
        SingularSystemError: the system is singular (a rigid mode left, a separated body).
        MethodNotAvailableError: the method is validated but not bound in this build yet.
    """
    scene = _as_scene(scene)
    runner = _RUNNERS.get(scene.method)
    if runner is None:
        raise MethodNotAvailableError(
            f"method {scene.method!r} is not available in rustfrac {_core.__version__} yet: "
            f"{_PENDING.get(scene.method, 'not implemented')}; the scene itself is valid"
        )
    t0 = time.perf_counter()
    res = runner(scene, progress)
    res.meta.setdefault("timings", {})["total_s"] = time.perf_counter() - t0
    return res


def _as_scene(scene: Scene | Mapping[str, Any] | str | Path) -> Scene:
    if isinstance(scene, Scene):
        return scene
    if isinstance(scene, Mapping):
        return Scene.from_dict(scene)
    if isinstance(scene, (str, Path)):
        return Scene.from_toml(scene)
    raise InvalidTypeError(
        f"run() takes a Scene, a dict or a TOML path, got {type(scene).__name__}", "scene"
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


def _run_fem(scene: Scene, progress: ProgressCallback | None) -> Result:
    p, mat, load, c, mesh = scene.plate, scene.material, scene.load, scene.crack, scene.mesh
    out = _core.solve_fem_plate(
        width=p.width,
        height=p.height,
        nx=mesh.nx,
        ny=mesh.ny,
        e=mat.E,
        nu=mat.nu,
        plane=mat.plane,
        thickness=mat.thickness,
        bc=load.bc,
        u0=load.u0,
        traction=load.traction,
        seam=(c.a0, c.y) if c.kind == "seam" else None,
        gauss=mesh.gauss,
        progress=progress,
    )
    fields = {k: v for k, v in out.items() if isinstance(v, np.ndarray)}
    return Result(
        method="fem",
        sigma22=float(out["sigma22"]),
        cmod=float(out["cmod"]),
        n_dofs=int(out["n_dofs"]),
        wall_time_s=float(out["wall_time_s"]),
        fields=fields,
        scalars={"energy": out["energy"], "residual": out["residual"]},
        meta=_meta(
            scene,
            _BC_DESC[load.bc],
            None if load.bc == "clamped" else int(out["anchor_node"]),
            seam_y=out["seam_y"],
            timings={"rust_s": float(out["wall_time_s"])},
        ),
    )


_RUNNERS: dict[str, Callable[[Scene, ProgressCallback | None], Result]] = {"fem": _run_fem}


def _run_pd(scene: Scene, progress: ProgressCallback | None) -> Result:
    """Pure PD (``method="pd"``, PD on the whole plate) or CCM-PD (``"ccm_pd"``, PD in the scene's
    rectangle, FEM elsewhere), then the sequentially linear analysis.

    ``history`` holds one row per SLA step, recorded at the load that breaks the step's bond(s),
    preceded by the unloaded origin as step 0 (load_factor = sigma22 = cmod = u0 = 0, crack_length
    = the pre-crack length, bond = node_i = node_j = -1, n_broken = 0), so that plotting
    sigma22 against cmod starts with the linear loading branch from (0, 0). Under ``bc =
    "traction"`` the load factor scales the traction and ``u0`` is 0 (no prescribed displacement).
    """
    p, mat, load, c, pd = scene.plate, scene.material, scene.load, scene.crack, scene.pd
    regions = []
    if scene.method == "ccm_pd":
        (cx, cy), (sx, sy) = pd.center, pd.size
        regions = [(cx - sx / 2, cy - sy / 2, cx + sx / 2, cy + sy / 2)]
    precrack = [(0.0, c.y), (c.a0, c.y)] if c.kind == "edge" else []
    out = _core.solve_pd_plate(
        method=scene.method,
        width=p.width,
        height=p.height,
        dx=pd.dx,
        m=pd.m,
        e=mat.E,
        nu=mat.nu,
        plane=mat.plane,
        thickness=mat.thickness,
        g0=mat.G0,
        bc=load.bc,
        # traction grips prescribe no displacement: history "u0" is then 0
        u0=0.0 if load.bc == "traction" else load.u0,
        traction=load.traction,
        pd_regions=regions,
        precrack=precrack,
        sla_steps=pd.sla_steps,
        stop_crack_length=pd.stop_crack_length or None,
        tie_tol=pd.tie_tol,
        refactor_every=pd.refactor_every,
        fast=pd.fast,
        damage_at_steps=list(pd.damage_at_steps),
        progress=progress,
    )
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
