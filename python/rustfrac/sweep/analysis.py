"""The sweep's errors (:mod:`rustfrac.sweep`): the reference of each method (the Richardson
extrapolation of its refinement study, or its finest level), each record's errors, the
cost-error Pareto front and the presets chosen on it."""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from typing import Any

from .points import QUANTITIES, REFINEMENT

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
