"""The sweep of the user's own scene (:mod:`rustfrac.sweep`): one knob (``mesh``, ``pd.dx`` or
any ``section.key``) at the given levels, the levels' points and runs, and :func:`extrapolate`
(Richardson with a status) of the three finest levels."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from ..errors import InvalidParameterError
from ..scene import Scene
from .analysis import PRESET_TOLERANCES, RATE_RANGE, richardson
from .backends import SweepInterrupted, sweep
from .points import Progress, check_repeats, element_size, make_point

#: default timings per point of :func:`sweep_scene` and ``rustfrac sweep`` (the minimum is kept)
DEFAULT_REPEATS = 3
#: the refinement knobs with a length scale ``h`` (Richardson applies) and the methods they fit;
#: any other scene key ``section.key`` (e.g. ``xfem.nsub``) is a plain override without ``h``
SCENE_PARAMS: dict[str, tuple[str, ...]] = {"mesh": ("fem", "xfem"), "pd.dx": ("pd", "ccm_pd")}
#: largest relative change of the element aspect (hx / hy) between the mesh levels of a study
ASPECT_TOL = 0.05


def _params_help() -> str:
    return (
        ", ".join(f"{k} ({' or '.join(m)})" for k, m in SCENE_PARAMS.items())
        + ", or a scene key section.key (e.g. xfem.nsub, mesh.gauss)"
    )


def _crack_line(scene: Scene) -> tuple[str, float] | None:
    """("x" | "y", coordinate) of the primary crack when it runs along a grid line direction
    (angle 0): the mesh count across it is then snapped (:func:`_snap`)."""
    c = scene.crack
    if c.kind == "none" or c.angle != 0:
        return None
    if c.kind == "edge" and c.side in ("bottom", "top"):
        return "x", c.x
    return "y", c.y


def _snap(n0: int, target: float, coord: float | None, length: float) -> int:
    """The element count within 1 of ``target`` that keeps a crack line at ``coord`` where it
    was inside its element row with ``n0`` elements (the nearest to ``target`` among those,
    then the larger): a crack halfway across a row stays halfway (the paper's 83 -> 167 -> 333)
    instead of landing on a grid line, which changes the XFEM enrichment and breaks the
    sequence of levels."""
    m = max(1, round(target))
    if coord is None:
        return m
    f0 = (coord * n0 / length) % 1.0

    def off(k: int) -> float:
        d = abs((coord * k / length) % 1.0 - f0)
        return round(min(d, 1.0 - d), 9)

    near = (k for k in (m - 1, m, m + 1) if k >= 1)
    return min(near, key=lambda k: (off(k), abs(k - target), -k))


def _mesh_level(scene: Scene, level: Any) -> tuple[int, int]:
    """(nx, ny) of a ``mesh`` level: a pair, or a multiplier of the scene's (nx, ny) (the count
    across a crack line snapped by :func:`_snap`)."""
    nx0, ny0 = scene.mesh.nx, scene.mesh.ny
    if isinstance(level, (list, tuple)):
        ints = all(isinstance(v, int) and not isinstance(v, bool) for v in level)
        if len(level) != 2 or not ints:
            raise InvalidParameterError(
                f"invalid mesh level {level!r}: expected a pair of integers (nx, ny) or a "
                "multiplier of the scene's mesh (a number > 0)",
                "levels",
            )
        return int(level[0]), int(level[1])
    if isinstance(level, bool) or not isinstance(level, (int, float)) or not level > 0:
        raise InvalidParameterError(
            f"invalid mesh level {level!r}: expected a multiplier of the scene's mesh "
            f"{nx0}x{ny0} (a number > 0) or a pair (nx, ny)",
            "levels",
        )
    line = _crack_line(scene)
    W, H = scene.plate.width, scene.plate.height
    nx = _snap(nx0, level * nx0, line[1] if line and line[0] == "x" else None, W)
    ny = _snap(ny0, level * ny0, line[1] if line and line[0] == "y" else None, H)
    return nx, ny


def _level_scene(scene: Scene, param: str, level: Any) -> tuple[Scene, Any, float | None, str]:
    """(scene, value, h, label) of one level of ``param``; the core validates the scene."""
    if param == "mesh":
        nx, ny = _mesh_level(scene, level)
        sc = scene.replace(mesh__nx=nx, mesh__ny=ny)
        return (
            sc,
            [nx, ny],
            element_size(nx, ny, scene.plate.width, scene.plate.height),
            f"{nx}x{ny}",
        )
    if param == "pd.dx":
        sc = scene.replace(pd__dx=level)  # the core checks that dx fits the plate
        return sc, sc.pd.dx, float(sc.pd.dx), f"dx={sc.pd.dx:.6g}"
    sec, _, key = param.partition(".")
    sc = scene.replace(**{f"{sec}__{key}": level})
    return sc, getattr(getattr(sc, sec), key, level), None, f"{key}={level}"


def scene_points(
    scene: Scene | Mapping[str, Any] | str | Path, param: str, levels: Sequence[Any]
) -> list[dict[str, Any]]:
    """The sweep points of ``param`` at ``levels`` on the user's scene (a :class:`Scene`, a
    scene dict or a TOML path), in the order given; every scene is built (and checked by the
    core) before anything runs.

    Args:
        param: ``"mesh"`` (FEM, XFEM): levels are multipliers of the scene's (nx, ny) (1, 2, 4:
            the count across a crack line kept so that the crack stays where it was inside its
            element row) or explicit (nx, ny) pairs, all with the same element aspect (within
            :data:`ASPECT_TOL`), ``h`` the element size sqrt(hx hy); ``"pd.dx"`` (PD, CCM-PD):
            grid spacings, ``h = dx`` (a dx that does not fit the plate is the core's
            :class:`InvalidParameterError`); any scene key ``"section.key"`` (``xfem.nsub``,
            ``mesh.gauss``, ``load.bc``, ...): its values, without ``h`` (no Richardson).

    Raises:
        InvalidParameterError: an unknown parameter or one the scene's method does not have,
            fewer than one level, repeated levels, a bad level (``param`` names the culprit).
    """
    from ..runner import as_scene

    scene = as_scene(scene)
    if not isinstance(param, str) or not (param in SCENE_PARAMS or "." in param.strip(".")):
        raise InvalidParameterError(f"invalid param {param!r}: expected {_params_help()}", "param")
    if param in SCENE_PARAMS and scene.method not in SCENE_PARAMS[param]:
        fits = [k for k, m in SCENE_PARAMS.items() if scene.method in m]
        raise InvalidParameterError(
            f"invalid param {param!r} for a {scene.method} scene: it refines "
            f"{' or '.join(SCENE_PARAMS[param])} only; {scene.method} has "
            + ", ".join(fits)
            + " or a scene key section.key",
            "param",
        )
    levels = list(levels)
    if not levels:
        raise InvalidParameterError("invalid levels: expected at least one level", "levels")
    base = scene.name or "scene"
    pts: list[dict[str, Any]] = []
    for level in levels:
        sc, value, h, label = _level_scene(scene, param, level)
        pts.append(
            {**make_point(param, scene.method, param, value, h, sc.replace(name=f"{base} {label}")),
             "level": level}
        )  # fmt: skip
    names = [p["scene"]["name"] for p in pts]
    if len(set(names)) < len(names):
        raise InvalidParameterError(
            f"invalid levels {levels!r}: two levels give the same {param} ({', '.join(names)})",
            "levels",
        )
    if param == "mesh":
        aspect = [(scene.plate.width / v[0]) / (scene.plate.height / v[1]) for v in
                  (p["value"] for p in pts)]  # fmt: skip
        bad = [lv for lv, a in zip(levels, aspect) if abs(a / aspect[0] - 1) > ASPECT_TOL]
        if bad:
            raise InvalidParameterError(
                f"invalid mesh levels {bad!r}: their element aspect hx/hy differs from the first "
                f"level's ({aspect[0]:.4g}) by more than {ASPECT_TOL:.0%}; refine nx and ny "
                "together (h = sqrt(hx hy) measures a refinement only at a fixed aspect)",
                "levels",
            )
    return pts


def check_quantity(record: dict[str, Any], quantity: str) -> None:
    """Raises :class:`InvalidParameterError` (``param="quantity"``) when ``quantity`` is not a
    scalar response of the record's run, listing the valid ones for its method."""
    valid = sorted(record["quantities"])
    if quantity not in valid:
        raise InvalidParameterError(
            f"invalid quantity {quantity!r} for a {record['method']} scene: expected one of "
            + ", ".join(valid),
            "quantity",
        )


def run_scene_points(
    points: Sequence[dict[str, Any]],
    quantity: str,
    *,
    repeats: int = DEFAULT_REPEATS,
    workers: int | None = None,
    scheduler: Any = None,
    progress: Progress | None = None,
) -> list[dict[str, Any]]:
    """Runs the points of :func:`scene_points` through :func:`sweep` (local pool or dask, the
    same path as the paper's sweep): the first level alone first, so that a ``quantity`` the
    method does not give is refused after one run (:func:`check_quantity`), then the others.

    Raises:
        SweepInterrupted: on Ctrl-C, with every finished record.
    """
    points = list(points)
    repeats = check_repeats(repeats)
    if not isinstance(quantity, str):
        raise InvalidParameterError(
            f"invalid quantity {quantity!r}: expected a name such as K_I", "quantity"
        )
    kw: dict[str, Any] = {"workers": workers, "scheduler": scheduler, "repeats": repeats}
    total = len(points)

    def step(offset: int) -> Progress | None:
        if progress is None:
            return None
        return lambda done, _total, msg: progress(done + offset, total, msg)

    first = sweep(points[:1], progress=step(0), **kw)
    if first:
        check_quantity(first[0], quantity)
    try:
        rest = sweep(points[1:], progress=step(len(first)), **kw) if points[1:] else []
    except SweepInterrupted as e:
        raise SweepInterrupted(first + e.records) from None
    return first + rest


def extrapolate(hs: Sequence[float | None], qs: Sequence[float | None]) -> dict[str, Any]:
    """Richardson extrapolation of a refinement study from its three finest levels.

    ``hs`` are the levels' sizes (any order; None: no length scale), ``qs`` the quantity. With
    the finest three ordered coarse to fine (h1 > h2 > h3, refinement ratios r12 = h1/h2 and
    r23 = h2/h3), the observed rate p solves (q1 - q2) / (q2 - q3) = (h1^p - h2^p) /
    (h2^p - h3^p), which for a constant ratio r is ``p = log(|q2 - q1| / |q3 - q2|) / log(r)``
    (:func:`richardson`); non-uniform ratios are allowed. The extrapolated value is
    q* = q3 - (q2 - q3) h3^p / (h2^p - h3^p), and each level's error estimate q_i - q*.

    Returns a dict: ``status`` "ok" | "not in the asymptotic range" (the differences change
    sign or vanish, or p is outside [0.5, 6]: ``value`` and ``rate`` are then None, never a
    wrong number) | "not applicable" (fewer than 3 levels, no length scale, a missing value),
    ``why``, ``value``, ``rate``, ``ratios`` [r12, r23], ``constant_ratio``, ``levels`` (the
    indices of the three levels used, finest last) and ``error_estimates`` (per level, in the
    order given: ``{"abs": q_i - q*, "rel": |q_i - q*| / |q*|}``, or None).
    """
    n = len(hs)
    out: dict[str, Any] = {
        "status": "not applicable", "why": "", "value": None, "rate": None, "ratios": None,
        "constant_ratio": None, "levels": None, "error_estimates": [None] * n,
    }  # fmt: skip
    if any(h is None for h in hs):
        out["why"] = "the parameter has no length scale h (Richardson needs mesh or pd.dx)"
        return out
    if any(q is None for q in qs):
        out["why"] = "the quantity is missing at some level"
        return out
    if n < 3:
        out["why"] = f"fewer than 3 levels ({n})"
        return out
    order = sorted(range(n), key=lambda i: -float(hs[i]))  # type: ignore[arg-type]
    use = order[-3:]
    h3 = [float(hs[i]) for i in use]  # type: ignore[arg-type]
    q3 = [float(qs[i]) for i in use]  # type: ignore[arg-type]
    out["levels"] = use
    if not h3[0] > h3[1] > h3[2] > 0:
        out["why"] = "two of the finest levels have the same h"
        return out
    r12, r23 = h3[0] / h3[1], h3[1] / h3[2]
    out.update(ratios=[r12, r23], constant_ratio=abs(r12 / r23 - 1) < 1e-6)
    rich = richardson(h3, q3)
    if rich is None:
        d1, d2 = q3[0] - q3[1], q3[1] - q3[2]
        out["status"] = "not in the asymptotic range"
        if d1 == 0 or d2 == 0:
            out["why"] = "a difference between the finest levels is zero"
        elif (d1 > 0) != (d2 > 0):
            out["why"] = "the differences between the finest levels change sign"
        else:
            out["why"] = (
                f"the observed rate is outside [{RATE_RANGE[0]:g}, {RATE_RANGE[1]:g}] "
                f"(|q1 - q2| = {abs(d1):.3g}, |q2 - q3| = {abs(d2):.3g})"
            )
        return out
    value, rate = rich
    out.update(status="ok", value=value, rate=rate)
    out["error_estimates"] = [
        {"abs": float(q) - value, "rel": abs(float(q) - value) / abs(value) if value else None}
        for q in qs  # type: ignore[arg-type]
    ]
    return out


def scene_study(
    points: Sequence[dict[str, Any]], records: Sequence[dict[str, Any]], quantity: str
) -> dict[str, Any]:
    """The study of a scene sweep: ``levels`` (one row per finished point, in point order:
    name, level, value, h, n_dofs, the quantity as ``q``, times, error estimates),
    ``richardson`` (:func:`extrapolate`), ``presets`` (per :data:`PRESET_TOLERANCES`, the
    cheapest level whose estimated relative error is within it; only with a Richardson value)
    and ``missing_points``."""
    by = {r["name"]: r for r in records}
    rows = []
    for p in points:
        r = by.get(p["scene"].get("name", ""))
        if r is None:
            continue
        rows.append({
            "name": r["name"], "level": p.get("level"), "value": p["value"], "h": p["h"],
            "n_dofs": r["n_dofs"], "q": r["quantities"].get(quantity),
            "wall_time_s": r["wall_time_s"], "wall_time_spread_s": r["wall_time_spread_s"],
            "repeats": r["repeats"], "solver_time_s": r["solver_time_s"],
            "peak_rss_mb": r["peak_rss_mb"],
        })  # fmt: skip
    rich = extrapolate([r["h"] for r in rows], [r["q"] for r in rows])
    for row, e in zip(rows, rich["error_estimates"]):
        row["err_est"] = None if e is None else e["abs"]
        row["rel_err_est"] = None if e is None else e["rel"]
    presets: dict[str, Any] = {}
    if rich["status"] == "ok":
        for name, tol in PRESET_TOLERANCES.items():
            ok = [r for r in rows if r["rel_err_est"] is not None and r["rel_err_est"] <= tol]
            best = min(ok, key=lambda r: r["wall_time_s"]) if ok else None
            presets[name] = {
                "tolerance": tol,
                "point": None if best is None else best["name"],
                "value": None if best is None else best["value"],
                "wall_time_s": None if best is None else best["wall_time_s"],
                "rel_err_est": None if best is None else best["rel_err_est"],
            }
    done = set(by)
    return {
        "kind": "scene",
        "method": points[0]["method"] if points else None,
        "param": points[0]["param"] if points else None,
        "quantity": quantity,
        "levels": rows,
        "richardson": rich,
        "presets": presets,
        "missing_points": [p["scene"].get("name", "") for p in points
                           if p["scene"].get("name", "") not in done],
    }  # fmt: skip


def sweep_scene(
    scene: Scene | Mapping[str, Any] | str | Path,
    param: str,
    levels: Sequence[Any],
    quantity: str = "K_I",
    *,
    repeats: int = DEFAULT_REPEATS,
    workers: int | None = None,
    scheduler: Any = None,
    progress: Progress | None = None,
) -> dict[str, Any]:
    """A refinement (or parameter) study of the user's scene: runs ``param`` at ``levels``
    (:func:`scene_points`) locally or on dask (``scheduler``, as :func:`sweep`), each point
    ``repeats`` times (the minimum time is kept), and returns :func:`scene_study` of
    ``quantity`` (any scalar response of the method's result: ``K_I``, ``K_II``, ``J``,
    ``sigma22``, ``cmod``, ``peak_sigma22``, ...; :func:`quantities_of`) with the records
    (``records``) and scenes. E.g.
    ``sweep_scene("my.toml", "mesh", [1, 2, 4], "K_I")["richardson"]["value"]``.

    Raises:
        InvalidParameterError: a bad ``param``, level or ``repeats`` (before any run), or a
            ``quantity`` the method does not give (after the first level's run).
        SweepInterrupted: on Ctrl-C, with the finished records.
    """
    points = scene_points(scene, param, levels)
    records = run_scene_points(
        points, quantity, repeats=repeats, workers=workers, scheduler=scheduler,
        progress=progress,
    )  # fmt: skip
    return {
        **scene_study(points, records, quantity),
        "records": records,
        "scenes": {p["scene"].get("name", ""): p["scene"] for p in points},
    }
