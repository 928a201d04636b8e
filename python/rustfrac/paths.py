"""Crack paths of two methods compared: stations along a polyline, the ridge of a set of broken
bonds along it, and the distance between the ridge and the polyline.

A PD crack is a set of broken bonds, an XFEM crack a polyline. To compare them no PD crack line
is guessed from the damage map alone: the XFEM polyline gives the stations, and the PD crack is
read across it.

- **Stations** (:func:`stations`): points every ``spacing`` of arc length along the polyline
  (its first point, then s = spacing, 2 spacing, ..., and its last point), each with the unit
  tangent t of its segment and the normal n = (-t2, t1).
- **Ridge** (:func:`bond_ridge`): at station k (point p, tangent t, normal n), the bonds whose
  midpoints x lie in the strip ``|t . (x - p)| <= window / 2``, ``|n . (x - p)| <= half_width``
  (``window`` = ``spacing`` unless given); the ridge point is ``p + c n`` with ``c`` the
  (weighted) mean of ``n . (x - p)`` over them, the centroid of
  the broken bonds' midpoints in the normal direction. A station without such bonds has no ridge
  point (``covered`` False): the PD crack stopped short of it, or runs elsewhere.
- **Distance** (:func:`distance_to_polyline`): the shortest distance from each ridge point to the
  polyline's segments (not only ``|c|``, which measures along one station's normal).

Validated on a straight pre-crack at an angle (``tests/test_compare.py``): the ridge of the bonds
the core pre-breaks across it lies on it within dx / 2.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from .errors import InvalidParameterError

__all__ = ["Ridge", "bond_ridge", "distance_to_polyline", "path_length", "stations"]


def _polyline(line: Any, name: str = "polyline") -> np.ndarray:
    p = np.asarray(line, dtype=float)
    if p.ndim != 2 or p.shape[1] != 2 or len(p) < 2 or not np.all(np.isfinite(p)):
        raise InvalidParameterError(f"invalid {name}: expected (k >= 2, 2) finite points", name)
    seg = np.linalg.norm(np.diff(p, axis=0), axis=1)
    p = np.concatenate([p[:1], p[1:][seg > 0]])  # repeated points carry no direction
    if len(p) < 2:
        raise InvalidParameterError(f"invalid {name}: its points coincide (no length)", name)
    return p


def _positive(v: float, name: str) -> float:
    if not (np.isfinite(v) and v > 0):
        raise InvalidParameterError(f"invalid {name}: expected a length > 0, got {v!r}", name)
    return float(v)


def path_length(line: Any) -> float:
    """Arc length of a polyline (k, 2)."""
    p = _polyline(line)
    return float(np.sum(np.linalg.norm(np.diff(p, axis=0), axis=1)))


def stations(line: Any, spacing: float) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Stations every ``spacing`` of arc length along ``line`` (k, 2), its ends included.
    Returns (s, points, tangents, normals): arc lengths (n,), points (n, 2), unit tangents of the
    segment each station lies on (n, 2) and the normals n = (-t2, t1) (n, 2)."""
    p = _polyline(line)
    spacing = _positive(spacing, "spacing")
    d = np.diff(p, axis=0)
    seg = np.linalg.norm(d, axis=1)
    cum = np.concatenate([[0.0], np.cumsum(seg)])
    total = cum[-1]
    n = int(np.floor(total / spacing + 1e-9))
    s = np.arange(n + 1) * spacing
    if total - s[-1] > 1e-9 * spacing:
        s = np.append(s, total)
    k = np.clip(np.searchsorted(cum, s, side="right") - 1, 0, len(seg) - 1)
    t = d[k] / seg[k, None]
    pts = p[k] + (s - cum[k])[:, None] * t
    normals = np.column_stack([-t[:, 1], t[:, 0]])
    return s, pts, t, normals


@dataclass(frozen=True)
class Ridge:
    """The ridge of a set of bond midpoints along a polyline (:func:`bond_ridge`).

    Attributes:
        s: arc length of every station (n,).
        station_xy: the stations on the polyline (n, 2).
        covered: whether a station has bonds in its strip (n,).
        offset: the centroid's signed offset along the station's normal (n,; NaN where not
            covered).
        xy: the ridge points (n, 2; NaN where not covered).
        n_bonds: bonds in each station's strip (n,).
    """

    s: np.ndarray
    station_xy: np.ndarray
    covered: np.ndarray
    offset: np.ndarray
    xy: np.ndarray
    n_bonds: np.ndarray

    def points(self) -> np.ndarray:
        """The ridge points of the covered stations, in path order (k, 2)."""
        return self.xy[self.covered]


def bond_ridge(
    midpoints: Any,
    line: Any,
    spacing: float,
    half_width: float,
    weights: Any = None,
    window: float | None = None,
) -> Ridge:
    """The ridge of bonds (their ``midpoints`` (b, 2), optional ``weights`` (b,) >= 0) along the
    polyline ``line`` (k, 2): at each of its :func:`stations` every ``spacing``, the weighted
    centroid of the midpoints in the station's strip (``window`` long along the path, default
    ``spacing``; ``2 half_width`` wide across it) in the normal direction (see the module
    docstring)."""
    spacing = _positive(spacing, "spacing")
    half_width = _positive(half_width, "half_width")
    window = spacing if window is None else _positive(window, "window")
    x = np.asarray(midpoints, dtype=float).reshape(-1, 2)
    w = np.ones(len(x)) if weights is None else np.asarray(weights, dtype=float).reshape(-1)
    if w.shape != (len(x),) or np.any(~np.isfinite(w)) or np.any(w < 0):
        raise InvalidParameterError(
            f"invalid weights: expected {len(x)} finite values >= 0", "weights"
        )
    s, pts, t, nrm = stations(line, spacing)
    n = len(s)
    offset = np.full(n, np.nan)
    count = np.zeros(n, dtype=int)
    for k in range(n):
        r = x - pts[k]
        along, across = r @ t[k], r @ nrm[k]
        sel = (np.abs(along) <= 0.5 * window) & (np.abs(across) <= half_width)
        sel &= w > 0
        count[k] = int(np.count_nonzero(sel))
        if count[k]:
            offset[k] = float(np.average(across[sel], weights=w[sel]))
    covered = count > 0
    xy = pts + np.where(covered, offset, np.nan)[:, None] * nrm
    return Ridge(s, pts, covered, offset, xy, count)


def distance_to_polyline(points: Any, line: Any) -> np.ndarray:
    """The shortest distance from each of ``points`` (q, 2) to the segments of ``line`` (k, 2)."""
    q = np.asarray(points, dtype=float).reshape(-1, 2)
    p = _polyline(line)
    a, b = p[:-1], p[1:]
    ab = b - a
    # (q, segments): the parameter of the closest point on each segment, clipped to [0, 1]
    t = np.einsum("qsk,sk->qs", q[:, None, :] - a[None], ab) / np.sum(ab * ab, axis=1)
    t = np.clip(t, 0.0, 1.0)
    closest = a[None] + t[..., None] * ab[None]
    return np.min(np.linalg.norm(q[:, None, :] - closest, axis=2), axis=1)
