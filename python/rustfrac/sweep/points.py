"""The paper's sweep points and one point's run (:mod:`rustfrac.sweep`): the studies of each
method on the paper's plate, a point run ``repeats`` times in one process (the minimum time
kept), and the scalar quantities a record compares."""

from __future__ import annotations

import math
import os
import resource
import sys
import time
from collections.abc import Callable
from typing import Any

from ..errors import InvalidParameterError
from ..scene import Scene
from ..scenes import edge_crack_plate

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
#: the paper's PD rectangle (width, height), scaled by the ``pd_size`` study
PD_SIZE = (2.73, 1.67)
#: a progress callback (done, total, message)
Progress = Callable[[int, int, str], Any]


def element_size(nx: int, ny: int, width: float = 11.0, height: float = 21.0) -> float:
    return math.sqrt(width / nx * height / ny)


def make_point(
    study: str, method: str, param: str, value: Any, h: float | None, scene: Scene
) -> dict:
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
        pts.append(make_point("mesh", "xfem", "nx", nx, element_size(nx, ny), sc))
    for n in nsubs:
        sc = edge_crack_plate("xfem", nsub=n, growth_steps=growth, name=f"xfem nsub {n}")
        pts.append(make_point("nsub", "xfem", "nsub", n, None, sc))
    for r in r_is:
        sc = edge_crack_plate("xfem", r_I=r, growth_steps=growth, name=f"xfem r_I {r}")
        pts.append(make_point("r_I", "xfem", "r_I", r, None, sc))
    for dx in dxs:
        sc = edge_crack_plate("ccm_pd", dx=dx, sla_steps=sla, name=f"ccm_pd dx 1/{round(1 / dx)}")
        pts.append(make_point("dx", "ccm_pd", "dx", dx, dx, sc))
    for m in ms:
        sc = edge_crack_plate("ccm_pd", dx=pd_base_dx, m=m, sla_steps=sla, name=f"ccm_pd m {m}")
        pts.append(make_point("m", "ccm_pd", "m", m, None, sc))
    for s in scales:
        size = (PD_SIZE[0] * s, PD_SIZE[1] * s)
        sc = edge_crack_plate(
            "ccm_pd", dx=pd_base_dx, pd_size=size, sla_steps=sla, name=f"ccm_pd size x{s}"
        )
        pts.append(make_point("pd_size", "ccm_pd", "pd_scale", s, None, sc))
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
    from ..runner import run

    repeats = check_repeats(repeats)
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


def check_repeats(repeats: Any) -> int:
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


def init_worker() -> None:
    os.environ["RAYON_NUM_THREADS"] = "1"
