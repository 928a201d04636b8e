"""The fixed PD rectangle of a comparison (:mod:`rustfrac.compare`): where CCM-PD's PD region
goes when it is placed around a known crack path. The adaptive CCM-PD region, when it exists,
replaces :func:`pd_region` (the one function :func:`rustfrac.compare.place` calls).

Rules: the path's bounding box grown by a margin in horizons m dx; any hole that comes within
m + 1 spacings taken in whole (a hole may not cut the hybrid elements at the rectangle's
boundary: the core refuses it); edges on half-spacings (between node lines), on a free plate edge
when within m + 1 spacings of it, and at least two horizons away from loaded or supported sides
(the splice coupling's out-of-balance force breaks the bonds at a loaded PD edge first: measured
on a 4 x 8 plate under the grips, whose first SLA breaks were all on the top edge's row). Where
that clearance cuts a hole taken in whole, the side facing the hole moves back until the band
of m + 1 spacings clears it, as long as the path keeps a horizon's margin; else there is no
rectangle (None: :func:`rustfrac.compare.place` then runs the adaptive region).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

__all__ = ["DEFAULT_MARGIN_HORIZONS", "Box", "cut_hole", "held_sides", "pd_dofs", "pd_region"]

#: margin of the fixed PD rectangle around the path's bounding box, in horizons
DEFAULT_MARGIN_HORIZONS = 3.0

#: a rectangle (x0, y0, x1, y1), in the scene's lengths
Box = tuple[float, float, float, float]


def _hole_box(hole: Mapping[str, Any]) -> Box:
    shape = hole.get("shape", "circle")
    if shape == "circle":
        (cx, cy), r = hole["center"], hole["radius"]
        return (cx - r, cy - r, cx + r, cy + r)
    if shape == "rect":
        (x0, y0), (x1, y1) = hole["min"], hole["max"]
        return (x0, y0, x1, y1)
    p = np.asarray(hole["points"], dtype=float)
    return (*p.min(axis=0), *p.max(axis=0))  # type: ignore[return-value]


def _overlap(a: Box, b: Box) -> bool:
    return a[0] < b[2] and b[0] < a[2] and a[1] < b[3] and b[1] < a[3]


def cut_hole(
    box: Box, holes: Sequence[Mapping[str, Any]], plate: tuple[float, float], band: float
) -> int | None:
    """The index of the first hole that the band of width ``band`` around the boundary of the
    rectangle ``box`` crosses (the hybrid elements; the boundary's parts on the plate's edges have
    none), None when every hole lies inside the rectangle or clear of the band."""
    w, hgt = plate
    for k, hole in enumerate(holes):
        hb = _hole_box(hole)
        if not _overlap((box[0] - band, box[1] - band, box[2] + band, box[3] + band), hb):
            continue
        inside = (
            (box[0] <= 0.0 or hb[0] >= box[0] + band)
            and (box[1] <= 0.0 or hb[1] >= box[1] + band)
            and (box[2] >= w or hb[2] <= box[2] - band)
            and (box[3] >= hgt or hb[3] <= box[3] - band)
        )
        if not inside:
            return k
    return None


def held_sides(d: Mapping[str, Any]) -> set[str]:
    """The plate sides a scene dict loads or supports: the grips' top and bottom, or the sides
    of its edge / edge-part supports and loads."""
    if not d.get("support") and not isinstance(d.get("load"), list):
        return {"top", "bottom"}
    sides = set()
    for e in [*d.get("support", []), *(d.get("load") if isinstance(d.get("load"), list) else [])]:
        if e.get("region", "edge") in ("edge", "edge_part"):
            sides.add(e.get("side", "bottom"))
    return sides


def pd_region(
    path: np.ndarray,
    plate: tuple[float, float],
    dx: float,
    m: int,
    *,
    holes: Sequence[Mapping[str, Any]] = (),
    held: Sequence[str] = (),
    margin_horizons: float = DEFAULT_MARGIN_HORIZONS,
) -> Box | None:
    """The fixed PD rectangle (x0, y0, x1, y1) of a comparison: the bounding box of ``path``
    (the XFEM crack from its initial tip on) grown by ``margin_horizons`` horizons m dx; grown
    further to take in whole any hole that comes within m + 1 spacings of it (a hole may not cut
    the hybrid elements at the rectangle's boundary); edges on half-spacings (between node
    lines), on a free plate edge when within m + 1 spacings of it, and at least two horizons
    away from the ``held`` sides ("left", "right", "bottom", "top": loaded or supported; the
    splice coupling's out-of-balance force breaks bonds at a loaded PD edge first). A hole that
    clearance cuts makes the side facing it move back until the band clears the hole, while the
    path keeps a horizon m dx of margin (or what the clearance left it); None when no side can."""
    p = np.asarray(path, dtype=float).reshape(-1, 2)
    w, hgt = plate
    margin = margin_horizons * m * dx
    box: Box = (
        p[:, 0].min() - margin,
        p[:, 1].min() - margin,
        p[:, 0].max() + margin,
        p[:, 1].max() + margin,
    )
    band = (m + 1) * dx
    for _ in range(len(holes) + 1):
        grown = box
        for hole in holes:
            hb = _hole_box(hole)
            if _overlap((box[0] - band, box[1] - band, box[2] + band, box[3] + band), hb):
                grown = (
                    min(grown[0], hb[0] - band), min(grown[1], hb[1] - band),
                    max(grown[2], hb[2] + band), max(grown[3], hb[3] + band),
                )  # fmt: skip
        if grown == box:
            break
        box = grown
    keep = 2 * m * dx

    def snap(v: float, up: bool, size: float, lo_side: str, hi_side: str) -> float:
        k = math.ceil(v / dx - 0.5) if up else math.floor(v / dx - 0.5)
        v = (k + 0.5) * dx
        if lo_side in held:
            v = max(v, math.ceil(keep / dx - 0.5) * dx + 0.5 * dx)
        elif v < band:
            return 0.0
        if hi_side in held:
            v = min(v, size - math.ceil(keep / dx - 0.5) * dx - 0.5 * dx)
        elif v > size - band:
            return size
        return v

    box = (
        snap(box[0], False, w, "left", "right"),
        snap(box[1], False, hgt, "bottom", "top"),
        snap(box[2], True, w, "left", "right"),
        snap(box[3], True, hgt, "bottom", "top"),
    )
    reach = m * dx  # the path's least margin inside the rectangle
    need = (
        max(p[:, 0].min() - reach, box[0]), max(p[:, 1].min() - reach, box[1]),
        min(p[:, 0].max() + reach, box[2]), min(p[:, 1].max() + reach, box[3]),
    )  # fmt: skip
    for _ in range(4 * len(holes) + 1):
        k = cut_hole(box, holes, plate, band)
        if k is None:
            return box
        hb = _hole_box(holes[k])
        below = (math.floor((hb[0] - band) / dx - 0.5) + 0.5) * dx  # half-spacings off the band
        above = (math.ceil((hb[2] + band) / dx - 0.5) + 0.5) * dx
        lower = (math.floor((hb[1] - band) / dx - 0.5) + 0.5) * dx
        upper = (math.ceil((hb[3] + band) / dx - 0.5) + 0.5) * dx
        moved = [
            (box[0], box[1], below, box[3]),
            (above, box[1], box[2], box[3]),
            (box[0], box[1], box[2], lower),
            (box[0], upper, box[2], box[3]),
        ]
        fits = [
            b for b in moved
            if b[0] <= need[0] and b[1] <= need[1] and b[2] >= need[2] and b[3] >= need[3]
        ]  # fmt: skip
        if not fits:
            return None
        box = max(fits, key=lambda b: (b[2] - b[0]) * (b[3] - b[1]))
    return None


def pd_dofs(box: Box, dx: float) -> int:
    """Free PD dofs of a rectangle, an upper bound (nodes of holes and supports not removed)."""
    nx = math.floor((box[2] - box[0]) / dx + 1e-9) + 1
    ny = math.floor((box[3] - box[1]) / dx + 1e-9) + 1
    return 2 * nx * ny
