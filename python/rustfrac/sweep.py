"""Speed-accuracy sweep (``rustfrac sweep --out DIR [--preset tiny|full]``).

Runs independent scenes of the paper's plate, one record per point, in a local process pool
(default) or on a dask.distributed cluster (``scheduler="tcp://..."`` or a ``distributed.Client``;
optional extra ``rustfrac[dask]``). Each worker runs with ``RAYON_NUM_THREADS=1`` (one thread per
worker, sequential solver inside), so that the numbers are identical, bit for bit, on both
backends.

Studies (method, varied parameter):

- XFEM: element size (``mesh``), sub-quads per direction (``nsub``), I-integral radius (``r_I``);
- CCM-PD: grid spacing (``dx``; 21 / dx must be odd so that the pre-crack x2 = 10.5 passes between
  grid rows), horizon factor (``m``), size of the PD rectangle (``pd_scale`` times 2.73 x 1.67).

Errors: each quantity is compared with a reference per method, taken from that method's refinement
study (XFEM ``mesh``, CCM-PD ``dx``): the Richardson extrapolation of its three finest levels when
they show a consistent observed rate (0.5 <= p <= 6, monotone differences), else the finest level
itself. ``err_finest_<q>`` is always against the finest level (0 there by construction).

The user's own scene (:func:`sweep_scene`, ``rustfrac sweep SCENE.toml --param P --levels ...``):
one knob (``mesh``, ``pd.dx`` or any ``section.key``) at the given levels, any scalar response as
the quantity (:func:`quantities_of`), the same backends, and :func:`extrapolate` (Richardson with
a status) of the three finest levels. Every point is timed ``repeats`` times, the minimum kept.
"""

from __future__ import annotations

import functools
import json
import math
import os
import resource
import sys
import time
from collections.abc import Callable, Iterable, Mapping, Sequence
from pathlib import Path
from typing import Any

from ._folder import atomic_file, with_fallback, writing
from .errors import InvalidParameterError
from .scene import Scene
from .scenes import edge_crack_plate
from .study import csv_text, fmt, machine, table

__all__ = [
    "DEFAULT_REPEATS",
    "FILES",
    "QUANTITIES",
    "SCENE_PARAMS",
    "SweepInterrupted",
    "check_quantity",
    "choose_presets",
    "define_points",
    "errors",
    "extrapolate",
    "quantities_of",
    "richardson",
    "run_point",
    "run_scene_points",
    "scene_points",
    "scene_study",
    "sweep",
    "sweep_scene",
    "write_outputs",
    "write_scene_outputs",
]

#: quantities compared per record (None where a method does not give it)
QUANTITIES: tuple[str, ...] = ("K_I", "cmod", "sigma22", "peak_sigma22")
#: the study of each method that defines its reference (a refinement study)
REFINEMENT: dict[str, str] = {"xfem": "mesh", "ccm_pd": "dx"}
#: keys of a record that must agree bit for bit between backends
NUMERIC_KEYS: tuple[str, ...] = (
    "K_I",
    "cmod",
    "sigma22",
    "peak_sigma22",
    "peak_step",
    "peak_crack_length",
    "n_steps",
    "n_dofs",
    "n_bonds",
    "n_pd_nodes",
)
PD_SIZE = (2.73, 1.67)

Progress = Callable[[int, int, str], Any]


class SweepInterrupted(KeyboardInterrupt):
    """Ctrl-C during :func:`sweep`: ``records`` holds the points that finished (in point order);
    raised by :func:`write_outputs` too (Ctrl-C while drawing), with ``doc`` the JSON written."""

    def __init__(self, records: list[dict[str, Any]], doc: dict[str, Any] | None = None) -> None:
        super().__init__(f"sweep interrupted after {len(records)} points")
        self.records = records
        self.doc = doc


# --------------------------------------------------------------------------- points


def _h(nx: int, ny: int, width: float = 11.0, height: float = 21.0) -> float:
    return math.sqrt(width / nx * height / ny)


def _point(study: str, method: str, param: str, value: Any, h: float | None, scene: Scene) -> dict:
    return {
        "study": study,
        "method": method,
        "param": param,
        "value": value,
        "h": h,
        "scene": scene.to_dict(),
    }


def define_points(preset: str = "full") -> list[dict[str, Any]]:
    """The sweep points of a preset: "tiny" (seconds, for tests and CI) or "full".

    XFEM points run the reference load plus ``growth_steps`` critical states (the first critical
    state is the peak of the displacement-controlled load path); CCM-PD points run the SLA with
    ``sla_steps`` bond breaks (the peak is the largest sigma22 of those steps).
    """
    if preset == "tiny":
        meshes = [(44, 83), (88, 167), (176, 333)]
        nsubs, r_is, growth = [1, 4], [2.0, 3.0], 2
        dxs, ms, scales, sla, pd_base_dx = [1 / 5, 1 / 9], [3, 4], [1.0], 20, 1 / 5
    elif preset == "full":
        meshes = [(33, 62), (44, 83), (66, 125), (88, 167), (176, 333), (352, 665)]
        nsubs, r_is, growth = [1, 2, 4, 8], [1.5, 2.0, 2.5, 3.0, 3.5], 3
        dxs, ms, scales, sla, pd_base_dx = (
            [1 / 5, 1 / 9, 1 / 15, 1 / 25],
            [2, 3, 4, 5, 6],
            [0.8, 1.0, 1.2],
            500,
            1 / 15,
        )
    else:
        raise ValueError(f"unknown sweep preset {preset!r} (tiny | full)")
    pts: list[dict[str, Any]] = []
    for nx, ny in meshes:
        sc = edge_crack_plate(
            "xfem", mesh=(nx, ny), growth_steps=growth, name=f"xfem mesh {nx}x{ny}"
        )
        pts.append(_point("mesh", "xfem", "nx", nx, _h(nx, ny), sc))
    for n in nsubs:
        sc = edge_crack_plate("xfem", nsub=n, growth_steps=growth, name=f"xfem nsub {n}")
        pts.append(_point("nsub", "xfem", "nsub", n, None, sc))
    for r in r_is:
        sc = edge_crack_plate("xfem", r_I=r, growth_steps=growth, name=f"xfem r_I {r}")
        pts.append(_point("r_I", "xfem", "r_I", r, None, sc))
    for dx in dxs:
        sc = edge_crack_plate("ccm_pd", dx=dx, sla_steps=sla, name=f"ccm_pd dx 1/{round(1 / dx)}")
        pts.append(_point("dx", "ccm_pd", "dx", dx, dx, sc))
    for m in ms:
        sc = edge_crack_plate("ccm_pd", dx=pd_base_dx, m=m, sla_steps=sla, name=f"ccm_pd m {m}")
        pts.append(_point("m", "ccm_pd", "m", m, None, sc))
    for s in scales:
        size = (PD_SIZE[0] * s, PD_SIZE[1] * s)
        sc = edge_crack_plate(
            "ccm_pd", dx=pd_base_dx, pd_size=size, sla_steps=sla, name=f"ccm_pd size x{s}"
        )
        pts.append(_point("pd_size", "ccm_pd", "pd_scale", s, None, sc))
    return pts


# --------------------------------------------------------------------------- one point


def run_point(point: dict[str, Any], repeats: int = 1) -> dict[str, Any]:
    """Runs one point in this process ``repeats`` times and returns its record (no fields,
    numbers only).

    ``wall_time_s`` and ``solver_time_s`` are the minimum over the repeats (the first run of a
    fresh process pays for page faults and lazy start-up, so one timing alone lets timer noise
    order equal-cost points), ``wall_times_s`` every repeat's time and ``wall_time_spread_s``
    their range; the numbers are those of the first run (one thread: every repeat gives the
    same ones). ``quantities`` holds every scalar response of the run (:func:`quantities_of`).

    Sets ``RAYON_NUM_THREADS=1`` before the first solve of the process (one thread per worker).
    ``peak_rss_mb`` is this process's ``ru_maxrss`` after the runs; ``rss_before_mb`` the same
    before them (a worker reused for several points reports its high-water mark: the point's own
    peak is exact when the local pool runs one point per process, as it does by default).
    """
    os.environ["RAYON_NUM_THREADS"] = "1"
    from .runner import run

    repeats = _check_repeats(repeats)
    before = _maxrss_mb()
    scene = Scene.from_dict(point["scene"])
    walls, solver, res = [], [], None
    for _ in range(repeats):
        t0 = time.perf_counter()
        r = run(scene)
        walls.append(time.perf_counter() - t0)
        solver.append(float(r.wall_time_s))
        if res is None:
            res = r
    assert res is not None
    rec: dict[str, Any] = {k: point[k] for k in ("study", "method", "param", "value", "h")}
    rec["name"] = point["scene"].get("name", "")
    rec["wall_time_s"] = min(walls)
    rec["solver_time_s"] = min(solver)
    rec["wall_times_s"] = walls
    rec["wall_time_spread_s"] = max(walls) - min(walls)
    rec["repeats"] = repeats
    rec["rss_before_mb"] = before
    rec["peak_rss_mb"] = _maxrss_mb()
    counts = res.meta.get("counts", {})
    rec["n_dofs"] = int(res.n_dofs)
    rec["n_bonds"] = counts.get("n_bonds")
    rec["n_pd_nodes"] = counts.get("n_pd_nodes")
    q = quantities_of(res)
    rec["quantities"] = q
    rec["K_I"] = res.K_I
    rec["cmod"] = float(res.cmod)
    rec["sigma22"] = float(res.sigma22)
    h = res.history
    peak = _peak_index(h.get("sigma22"))
    if peak is not None:
        a = h.get("a", h.get("crack_length"))
        rec["peak_sigma22"] = q["peak_sigma22"]
        rec["peak_step"] = peak
        rec["peak_crack_length"] = None if a is None else float(a[peak])
        rec["n_steps"] = len(h["sigma22"]) - 1
    else:
        rec.update(peak_sigma22=None, peak_step=None, peak_crack_length=None, n_steps=0)
    return rec


def _peak_index(s: Any) -> int | None:
    """Row of the largest value of a history column (None without a load path: < 2 rows)."""
    if s is None or len(s) < 2:
        return None
    return max(range(len(s)), key=lambda j: float(s[j]))


def quantities_of(res: Any) -> dict[str, float]:
    """Every scalar response of a :class:`~rustfrac.result.Result`, by name: ``sigma22``,
    ``cmod``, ``n_dofs``, each number of ``res.scalars`` (XFEM ``K_I``, ``K_II``, ``J``,
    ``J_domain``, ...; FEM ``energy``, ...; PD ``gamma``, ...) and, for a load path (growth or
    SLA history of 2+ rows), ``peak_<column>``: the largest value of each float column of the
    history (``peak_sigma22`` is the peak load). Integers are kept as floats."""
    out: dict[str, float] = {
        "sigma22": float(res.sigma22),
        "cmod": float(res.cmod),
        "n_dofs": float(res.n_dofs),
    }
    for k, v in res.scalars.items():
        if isinstance(v, (int, float)) and not isinstance(v, bool):
            out[k] = float(v)
    for k, col in res.history.items():
        i = _peak_index(col)
        if i is not None and getattr(col, "dtype", None) is not None and col.dtype.kind == "f":
            out[f"peak_{k}"] = float(col[i])
    return out


def _check_repeats(repeats: Any) -> int:
    if isinstance(repeats, bool) or not isinstance(repeats, int) or not 1 <= repeats <= 100:
        raise InvalidParameterError(
            f"invalid repeats: expected an integer in 1..100 (timings per point, the minimum "
            f"is reported), got {repeats!r}",
            "repeats",
        )
    return repeats


def _maxrss_mb() -> float:
    r = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    return r / 1024.0 / (1024.0 if sys.platform == "darwin" else 1.0)


def _init_worker() -> None:
    os.environ["RAYON_NUM_THREADS"] = "1"


# --------------------------------------------------------------------------- backends


def sweep(
    points: Sequence[dict[str, Any]],
    *,
    workers: int | None = None,
    scheduler: Any = None,
    progress: Progress | None = None,
    repeats: int = 1,
) -> list[dict[str, Any]]:
    """Runs every point and returns their records, in the order of ``points``.

    Args:
        points: from :func:`define_points` (or dicts with ``study, method, param, value, h,
            scene``).
        workers: local processes (default: the number of cores); ignored with ``scheduler``.
        scheduler: None (local process pool), a scheduler address ``"tcp://host:port"``, or a
            ``distributed.Client``.
        progress: ``progress(done, total, message)`` after each finished point.
        repeats: runs per point (in its worker); the record's time is their minimum
            (:func:`run_point`).

    Raises:
        SweepInterrupted: on Ctrl-C (a ``KeyboardInterrupt``), with the finished records; the
            points still running are cancelled.
    """
    points = list(points)
    repeats = _check_repeats(repeats)
    if scheduler is not None:
        return _sweep_dask(points, scheduler, progress, repeats)
    return _sweep_local(points, workers, progress, repeats)


def _sweep_local(
    points: list[dict[str, Any]], workers: int | None, progress: Progress | None, repeats: int
) -> list[dict[str, Any]]:
    import multiprocessing as mp
    from concurrent.futures import ProcessPoolExecutor, as_completed

    n = max(1, min(workers or os.cpu_count() or 1, len(points) or 1))
    kw: dict[str, Any] = {"max_workers": n, "initializer": _init_worker}
    if sys.version_info >= (3, 11):
        # a fresh process per point: exact peak memory, no state carried between points
        kw.update(max_tasks_per_child=1, mp_context=mp.get_context("spawn"))
    out: list[dict[str, Any] | None] = [None] * len(points)
    ex = ProcessPoolExecutor(**kw)
    try:
        futs = {ex.submit(run_point, p, repeats): i for i, p in enumerate(points)}
        for k, f in enumerate(as_completed(futs), 1):
            i = futs[f]
            out[i] = f.result()
            if progress is not None:
                progress(k, len(points), f"sweep: {out[i]['name']}")
    except KeyboardInterrupt:
        # cancel the queued points, let the running ones end (a terminal's Ctrl-C interrupts
        # them too) and keep every point that finished
        ex.shutdown(wait=True, cancel_futures=True)
        for f, i in futs.items():
            if out[i] is None and f.done() and not f.cancelled() and f.exception() is None:
                out[i] = f.result()
        raise SweepInterrupted([r for r in out if r is not None]) from None
    ex.shutdown()
    return [r for r in out if r is not None]


def _sweep_dask(
    points: list[dict[str, Any]], scheduler: Any, progress: Progress | None, repeats: int
) -> list[dict[str, Any]]:
    try:
        from distributed import Client, as_completed
    except ImportError as e:
        raise ImportError(
            "sweeping on a dask cluster needs dask.distributed: pip install 'rustfrac[dask]'"
        ) from e
    own = not isinstance(scheduler, Client)
    client = Client(scheduler) if own else scheduler
    try:
        futs = client.map(run_point, points, repeats=repeats, pure=False)
        index = {f.key: i for i, f in enumerate(futs)}
        out: list[dict[str, Any] | None] = [None] * len(points)
        try:
            for k, f in enumerate(as_completed(futs), 1):
                i = index[f.key]
                out[i] = f.result()
                if progress is not None:
                    progress(k, len(points), f"sweep: {out[i]['name']}")
        except KeyboardInterrupt:
            client.cancel(futs)
            raise SweepInterrupted([r for r in out if r is not None]) from None
        return [r for r in out if r is not None]
    finally:
        if own:
            client.close()


# --------------------------------------------------------------------------- errors


#: the observed rates a Richardson extrapolation accepts (outside: no consistent rate)
RATE_RANGE: tuple[float, float] = (0.5, 6.0)


def richardson(hs: Sequence[float], fs: Sequence[float]) -> tuple[float, float] | None:
    """Richardson extrapolation of three levels (h decreasing): (extrapolated value, observed
    rate p), or None when the levels show no consistent rate (non-monotone differences, or p
    outside [0.5, 6]). Solves (f1 - f2) / (f2 - f3) = (h1^p - h2^p) / (h2^p - h3^p) for p."""
    (h1, h2, h3), (f1, f2, f3) = hs, fs
    d1, d2 = f1 - f2, f2 - f3
    if d1 == 0 or d2 == 0 or (d1 > 0) != (d2 > 0) or not h1 > h2 > h3 > 0:
        return None
    target = d1 / d2

    def g(p: float) -> float:
        return (h1**p - h2**p) / (h2**p - h3**p) - target

    lo, hi = RATE_RANGE
    if g(lo) * g(hi) > 0:
        return None
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if g(lo) * g(mid) <= 0:
            hi = mid
        else:
            lo = mid
    p = 0.5 * (lo + hi)
    c = d2 / (h2**p - h3**p)
    return f3 - c * h3**p, p


def references(records: Sequence[dict[str, Any]]) -> dict[str, dict[str, dict[str, Any]]]:
    """Per method and quantity: {"value", "finest", "kind" ("richardson" | "finest"), "rate",
    "levels"} from the method's refinement study."""
    refs: dict[str, dict[str, dict[str, Any]]] = {}
    for method, study in REFINEMENT.items():
        lv = sorted(
            (r for r in records if r["method"] == method and r["study"] == study),
            key=lambda r: -r["h"],
        )
        if not lv:
            continue
        refs[method] = {}
        for q in QUANTITIES:
            pts = [(r["h"], r[q]) for r in lv if r.get(q) is not None]
            if not pts:
                continue
            finest = pts[-1][1]
            ref = {
                "value": finest,
                "finest": finest,
                "kind": "finest",
                "rate": None,
                "levels": len(pts),
                "finest_h": pts[-1][0],
                "why": "fewer than 3 levels" if len(pts) < 3 else "no consistent rate",
            }
            if len(pts) >= 3:
                hs, fs = zip(*pts[-3:])
                rich = richardson(hs, fs)
                if rich is not None:
                    ref.update(value=rich[0], kind="richardson", rate=rich[1], why="")
            refs[method][q] = ref
    return refs


def errors(
    records: Sequence[dict[str, Any]], refs: dict[str, dict[str, dict[str, Any]]]
) -> list[dict[str, Any]]:
    """Records with ``err_<q>`` (relative error against the reference), ``err_finest_<q>``
    (against the finest level) and ``err_max`` (the largest ``err_<q>`` of the record)."""
    out = []
    for r in records:
        r = dict(r)
        worst = None
        for q in QUANTITIES:
            ref = refs.get(r["method"], {}).get(q)
            if ref is None or r.get(q) is None:
                r[f"err_{q}"] = r[f"err_finest_{q}"] = None
                continue
            e = abs(r[q] - ref["value"]) / abs(ref["value"])
            r[f"err_{q}"] = e
            r[f"err_finest_{q}"] = abs(r[q] - ref["finest"]) / abs(ref["finest"])
            worst = e if worst is None else max(worst, e)
        r["err_max"] = worst
        out.append(r)
    return out


def pareto(records: Iterable[dict[str, Any]]) -> list[dict[str, Any]]:
    """The non-dominated records in (wall time, err_max), by increasing time.

    Records of one method with the same unknowns and the same ``err_max`` are one choice (the
    same discretisation reached by two studies, e.g. the base mesh and ``nsub`` at its default,
    or an ``r_I`` that changes no compared quantity): their times differ by timer noise only, so
    the first of them in point order (the refinement study's) stands for them all, with their
    smallest time. Otherwise noise would decide which name a preset gets."""
    groups: dict[tuple[Any, ...], dict[str, Any]] = {}
    for r in records:
        if r.get("err_max") is None:
            continue
        key = (r["method"], r.get("n_dofs"), r["err_max"])
        g = groups.get(key)
        if g is None:
            groups[key] = dict(r)
        elif r["wall_time_s"] < g["wall_time_s"]:
            g["wall_time_s"] = r["wall_time_s"]
    rs = sorted(groups.values(), key=lambda r: (r["wall_time_s"], r["err_max"]))
    front, best = [], math.inf
    for r in rs:
        if r["err_max"] < best:
            front.append(r)
            best = r["err_max"]
    return front


#: preset -> largest err_max it accepts (the cheapest front point below it is chosen)
PRESET_TOLERANCES: dict[str, float] = {"fast": 0.05, "balanced": 0.01, "accurate": 0.002}


def choose_presets(
    records: Sequence[dict[str, Any]], points: Sequence[dict[str, Any]] | None = None
) -> dict[str, dict[str, Any]]:
    """Per method, "fast" / "balanced" / "accurate": the cheapest Pareto-front point whose
    ``err_max`` is within :data:`PRESET_TOLERANCES` (else the most accurate front point)."""
    scenes = {p["scene"].get("name", ""): p["scene"] for p in points or ()}
    out: dict[str, dict[str, Any]] = {}
    for method in sorted({r["method"] for r in records}):
        front = pareto(r for r in records if r["method"] == method)
        if not front:
            continue
        out[method] = {}
        for name, tol in PRESET_TOLERANCES.items():
            ok = [r for r in front if r["err_max"] <= tol]
            r = ok[0] if ok else min(front, key=lambda r: r["err_max"])
            out[method][name] = {
                "point": r["name"],
                "study": r["study"],
                "param": r["param"],
                "value": r["value"],
                "wall_time_s": r["wall_time_s"],
                "err_max": r["err_max"],
                "tolerance": tol,
                "meets_tolerance": bool(ok),
                # the reference level itself: its error is zero by construction, not measured
                "is_reference": r["err_max"] == 0.0,
                "scene": scenes.get(r["name"]),
            }
    return out


# --------------------------------------------------------------------------- the user's scene

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
        return sc, [nx, ny], _h(nx, ny, scene.plate.width, scene.plate.height), f"{nx}x{ny}"
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
    from .runner import as_scene

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
            {**_point(param, scene.method, param, value, h, sc.replace(name=f"{base} {label}")),
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
    repeats = _check_repeats(repeats)
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
    (h2^p - h3^p), which for a constant ratio r is p = log(|q2 - q1| / |q3 - q2|) / log(r)
    (:func:`richardson`); non-uniform ratios are allowed. The extrapolated value is
    q* = q3 - (q2 - q3) h3^p / (h2^p - h3^p), and each level's error estimate q_i - q*.

    Returns a dict: ``status`` "ok" | "not in the asymptotic range" (the differences change
    sign or vanish, or p is outside [0.5, 6]: ``value`` and ``rate`` are then None, never a
    wrong number) | "not applicable" (fewer than 3 levels, no length scale, a missing value),
    ``why``, ``value``, ``rate``, ``ratios`` [r12, r23], ``constant_ratio``, ``levels`` (the
    indices of the three levels used, finest last) and ``error_estimates`` (per level, in the
    order given: {"abs": q_i - q*, "rel": |q_i - q*| / |q*|}, or None).
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


# --------------------------------------------------------------------------- outputs

CSV_KEYS: tuple[str, ...] = (
    "study", "method", "param", "value", "h", "name", "wall_time_s", "solver_time_s",
    "peak_rss_mb", "rss_before_mb", "n_dofs", "n_bonds", "n_pd_nodes", "K_I", "cmod", "sigma22",
    "peak_sigma22", "peak_step", "peak_crack_length", "n_steps",
    *(f"err_{q}" for q in QUANTITIES), *(f"err_finest_{q}" for q in QUANTITIES), "err_max",
)  # fmt: skip


def _g(v: Any, spec: str = ".4g") -> str:
    return fmt(v, spec, absent="-")


def markdown(
    records: Sequence[dict[str, Any]],
    refs: dict[str, dict[str, dict[str, Any]]],
    presets: dict[str, dict[str, Any]],
) -> str:
    lines = ["# Speed-accuracy sweep", ""]
    lines += [
        "Relative errors against the reference of each method (its refinement study: XFEM "
        "`mesh`, CCM-PD `dx`). K_I, CMOD and sigma22 at the reference load u0 = 0.01; the peak "
        "is the largest sigma22 of the load path (XFEM growth: critical states; CCM-PD: SLA "
        "steps), with its step. Time: wall time of the point in its worker (one thread). "
        "Memory: the worker's peak RSS (ru_maxrss).",
        "",
    ]
    rows = []
    for r in records:
        v = r["value"]
        val = f"1/{round(1 / v)}" if r["param"] == "dx" else str(v)
        rows.append(
            [r["method"], r["study"], val, f"{r['wall_time_s']:.3f}", f"{r['peak_rss_mb']:.0f}",
             f"{r['n_dofs']}", _g(r["n_bonds"], "d"), _g(r["K_I"], ".6g"), _g(r["cmod"], ".6g"),
             _g(r["sigma22"], ".6g"),
             f"{_g(r['peak_sigma22'], '.6g')} ({_g(r['peak_step'], 'd')}/{r['n_steps']})",
             *(_g(r[f"err_{q}"], ".2e") for q in QUANTITIES), _g(r["err_max"], ".2e")]
        )  # fmt: skip
    header = ["method", "study", "value", "time (s)", "peak RSS (MB)", "unknowns", "bonds", "K_I",
              "CMOD", "sigma22", "peak sigma22 (step)", "err K_I", "err CMOD", "err sigma22",
              "err peak", "err max"]  # fmt: skip
    lines += table(header, rows, "lll" + "r" * 13)
    lines += ["", "## References", ""]
    rows = []
    for method, qs in refs.items():
        for q, ref in qs.items():
            kind = (
                "Richardson (3 finest levels)"
                if ref["kind"] == "richardson"
                else f"finest level ({ref['why']})"
            )
            rows.append(
                [method, q, f"{ref['value']:.8g}", kind, _g(ref["rate"], ".3g"),
                 f"{ref['finest']:.8g}", f"{ref['levels']}"]
            )  # fmt: skip
    header = ["method", "quantity", "reference", "kind", "observed rate", "finest level", "levels"]
    lines += table(header, rows, "llrlrrr")
    lines += ["", "## Presets (from the Pareto front of time against err max)", ""]
    rows = []
    for method, ps in presets.items():
        for name, p in ps.items():
            tol = f"<= {p['tolerance']:g}" + ("" if p["meets_tolerance"] else " (not met)")
            if p["is_reference"]:
                tol += " (the reference level itself: error 0 by construction)"
            rows.append(
                [method, name, f"{p['point']}", f"{p['wall_time_s']:.3f}", f"{p['err_max']:.2e}",
                 tol]
            )  # fmt: skip
    header = ["method", "preset", "point", "time (s)", "err max", "tolerance"]
    lines += table(header, rows, "lllrrl")
    return "\n".join(lines) + "\n"


def plot(records: Sequence[dict[str, Any]], method: str, path: Path) -> None:
    """Log-log err max against wall time for one method, one marker per study, the Pareto front
    as a line (points with zero error, i.e. the reference itself, cannot be drawn and are
    listed in the title)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    rs = [r for r in records if r["method"] == method and r.get("err_max") is not None]
    fig, ax = plt.subplots(figsize=(6.4, 4.6))
    zero = [r["name"] for r in rs if r["err_max"] <= 0]
    for study, marker in zip(sorted({r["study"] for r in rs}), "osD^v<>"):
        pts = [r for r in rs if r["study"] == study and r["err_max"] > 0]
        if not pts:
            continue
        ax.loglog(
            [r["wall_time_s"] for r in pts], [r["err_max"] for r in pts], marker,
            label=study, alpha=0.8,
        )  # fmt: skip
        for r in pts:
            ax.annotate(str(r["value"] if r["param"] != "dx" else f"1/{round(1 / r['value'])}"),
                        (r["wall_time_s"], r["err_max"]), fontsize=7, xytext=(3, 3),
                        textcoords="offset points")  # fmt: skip
    front = [r for r in pareto(rs) if r["err_max"] > 0]
    if front:
        ax.loglog([r["wall_time_s"] for r in front], [r["err_max"] for r in front], "k-",
                  lw=0.8, label="Pareto front")  # fmt: skip
    ax.set_xlabel("wall time per point (s, one thread)")
    qs = "K_I, CMOD, sigma22, peak" if method == "xfem" else "CMOD, sigma22, peak"
    ax.set_ylabel(f"max relative error ({qs})")
    title = f"{method}: error against time"
    if zero:
        title += f"\n(zero error, not drawn: {', '.join(zero)})"
    ax.set_title(title, fontsize=9)
    ax.grid(True, which="both", alpha=0.3)
    if ax.get_legend_handles_labels()[0]:
        ax.legend(fontsize=8)
    with atomic_file(path, "wb") as f:
        fig.savefig(f, format="png", dpi=120, bbox_inches="tight")
    plt.close(fig)


#: the files of a sweep folder (one plot per method of :data:`REFINEMENT`)
FILES: tuple[str, ...] = (
    "sweep.csv", "sweep.md", *(f"sweep_{m}.png" for m in REFINEMENT), "sweep.json",
)  # fmt: skip


def write_outputs(
    out: str | Path,
    points: Sequence[dict[str, Any]],
    records: Sequence[dict[str, Any]],
    *,
    extra: dict[str, Any] | None = None,
) -> dict[str, Any]:
    """Computes the references, errors and presets of ``records`` and writes ``sweep.csv``,
    ``sweep.md``, ``sweep_<method>.png`` and ``sweep.json`` (last) into ``out`` as one unit
    (``_folder``). Returns the JSON document, which says what is missing: ``missing_points``
    (points without a record), ``missing_files`` (plots a Ctrl-C stopped) and ``complete``.

    Raises:
        OutputError: ``out`` cannot be written; the outputs were saved to the temporary folder
            it names instead (``fallback``).
        SweepInterrupted: Ctrl-C while drawing, after writing the rest (marked incomplete; the
            exception's ``doc`` is the JSON document).
    """
    return with_fallback(Path(out), lambda d: _write(d, points, records, extra or {}), "sweep")


def _write(
    out: Path,
    points: Sequence[dict[str, Any]],
    records: Sequence[dict[str, Any]],
    extra: dict[str, Any],
) -> dict[str, Any]:
    from . import __version__

    records = list(records)
    done = {r["name"] for r in records}
    names = [p["scene"].get("name", "") for p in points]
    missing_points = [n for n in names if n not in done]
    points = [p for p, n in zip(points, names) if n in done]
    refs = references(records)
    recs = errors(records, refs)
    presets = choose_presets(recs, points)
    with writing(out, owned=FILES, last="sweep.json") as w:
        rows = ([r.get(k) for k in CSV_KEYS] for r in recs)
        w.stage("sweep.csv").write_text(csv_text(CSV_KEYS, rows), encoding="utf-8")
        w.stage("sweep.md").write_text(markdown(recs, refs, presets), encoding="utf-8")
        plots = [
            (f"sweep_{m}.png", functools.partial(plot, recs, m))
            for m in sorted({r["method"] for r in recs})
        ]
        done, stopped = w.stage_each(plots)
        missing_files = [name for name, _ in plots if name not in done]
        interrupted = bool(extra.get("interrupted")) or stopped
        doc = {
            "version": __version__,
            "machine": machine(cpu=False, load_average=True),
            **extra,
            "interrupted": interrupted,
            "complete": not interrupted and not missing_points and not missing_files,
            "missing_points": missing_points,
            "missing_files": missing_files,
            "references": refs,
            "presets": presets,
            "points": recs,
            "scenes": {p["scene"].get("name", ""): p["scene"] for p in points},
        }
        w.stage("sweep.json").write_text(json.dumps(doc, indent=1), encoding="utf-8")
    if stopped:
        raise SweepInterrupted(records, doc)
    return doc


#: columns of a scene sweep's ``sweep.csv`` (``q`` is written under the quantity's name)
SCENE_CSV_KEYS: tuple[str, ...] = (
    "name", "level", "value", "h", "n_dofs", "q", "err_est", "rel_err_est", "wall_time_s",
    "wall_time_spread_s", "repeats", "solver_time_s", "peak_rss_mb",
)  # fmt: skip


def _cell(v: Any) -> Any:
    return "x".join(map(str, v)) if isinstance(v, (list, tuple)) else v


def scene_markdown(study: dict[str, Any]) -> str:
    """``sweep.md`` of a scene sweep: the levels and the Richardson extrapolation."""
    q, rich = study["quantity"], study["richardson"]
    lines = [
        f"# Sweep of {study['param']} ({study['method']}): {q}", "",
        f"{q} in the scene's units; h: element size sqrt(hx hy) (mesh) or dx (pd.dx), length "
        "units; time: the minimum wall time of the repeats in one worker (one thread), with "
        "their spread; err est: the level's value minus the Richardson value.", "",
    ]  # fmt: skip
    rows = (
        [f"{_cell(r['level'])}", f"{r['name']}", _g(r["h"], ".5g"), f"{r['n_dofs']}",
         _g(r["q"], ".10g"), _g(r["err_est"], ".3e"), _g(r["rel_err_est"], ".2e"),
         f"{r['wall_time_s']:.4f}", f"{r['wall_time_spread_s']:.4f}"]
        for r in study["levels"]
    )  # fmt: skip
    header = ["level", "point", "h", "unknowns", q, "err est", "rel. err est", "time (s)",
              "spread (s)"]  # fmt: skip
    lines += table(header, rows, "ll" + "r" * 7)
    lines += ["", "## Richardson extrapolation (three finest levels)", ""]
    if rich["status"] == "ok":
        ratios = ", ".join(f"{x:.4g}" for x in rich["ratios"])
        lines.append(
            f"{q}* = {rich['value']:.10g}, observed rate p = {rich['rate']:.4g} (refinement "
            f"ratios {ratios}{'' if rich['constant_ratio'] else ', not constant'})."
        )
    else:
        lines.append(f"{rich['status']}: {rich['why']} (no extrapolated value).")
    if study["presets"]:
        lines += ["", "## Presets (cheapest level within the estimated relative error)", ""]
        rows = (
            [name, f"{pr['tolerance']:g}", f"{pr['point'] or '(none)'}",
             _g(pr["wall_time_s"], ".4f"), _g(pr["rel_err_est"], ".2e")]
            for name, pr in study["presets"].items()
        )  # fmt: skip
        header = ["preset", "tolerance", "point", "time (s)", "rel. err est"]
        lines += table(header, rows, "lllrr")
    return "\n".join(lines) + "\n"


def write_scene_outputs(
    out: str | Path,
    points: Sequence[dict[str, Any]],
    records: Sequence[dict[str, Any]],
    quantity: str,
    *,
    extra: dict[str, Any] | None = None,
) -> dict[str, Any]:
    """Writes a scene sweep (:func:`scene_study` of ``records``) into ``out`` as one unit:
    ``sweep.csv`` (one row per level, the quantity under its name), ``sweep.md`` and
    ``sweep.json`` (last), replacing a previous sweep's files (its plots included). Returns the
    JSON document (``complete``, ``missing_points``, ``interrupted`` as :func:`write_outputs`).

    Raises:
        OutputError: as :func:`write_outputs` (the fallback folder is named).
    """
    extra = dict(extra or {})

    def write(d: Path) -> dict[str, Any]:
        from . import __version__

        study = scene_study(points, records, quantity)
        interrupted = bool(extra.get("interrupted"))
        header = [quantity if k == "q" else k for k in SCENE_CSV_KEYS]
        rows = ([_cell(r.get(k)) for k in SCENE_CSV_KEYS] for r in study["levels"])
        with writing(d, owned=FILES, last="sweep.json") as w:
            w.stage("sweep.csv").write_text(csv_text(header, rows), encoding="utf-8")
            w.stage("sweep.md").write_text(scene_markdown(study), encoding="utf-8")
            doc = {
                "version": __version__,
                "machine": machine(cpu=False, load_average=True),
                **extra,
                **study,
                "interrupted": interrupted,
                "complete": not interrupted and not study["missing_points"],
                "missing_files": [],
                "points": list(records),
                "scenes": {p["scene"].get("name", ""): p["scene"] for p in points},
            }
            w.stage("sweep.json").write_text(json.dumps(doc, indent=1), encoding="utf-8")
        return doc

    return with_fallback(Path(out), write, "sweep")
