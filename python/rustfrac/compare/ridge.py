"""What a comparison compares along the crack (:mod:`rustfrac.compare`): the grown XFEM path, the
bonds the SLA broke and the PD ridge's distance to the path (:mod:`rustfrac.paths`), and the
load-response pair both methods define alike."""

from __future__ import annotations

from typing import Any

import numpy as np

from .. import agreement, paths
from ..result import Result

__all__ = [
    "LABELS",
    "RIDGE_HALF_WIDTH_HORIZONS",
    "RIDGE_WINDOW_SPACINGS",
    "bond_midpoints",
    "grown_path",
    "path_agreement",
    "response_pair",
    "sla_broken_bonds",
    "window",
]

#: half-width of the ridge's strip across the XFEM path, in horizons (bonds farther away are
#: counted as off the path)
RIDGE_HALF_WIDTH_HORIZONS = 3.0
#: length of the ridge's strip along the path, in grid spacings (stations are dx apart)
RIDGE_WINDOW_SPACINGS = 2.0


def grown_path(res: Result) -> np.ndarray:
    """The primary XFEM crack from its initial tip on (the part that grew), (k, 2)."""
    line = np.asarray(res.crack_polylines[0], dtype=float)
    k0 = len(res.meta.get("crack_initial") or [])
    return line[max(k0 - 1, 0) :]


def sla_broken_bonds(res: Result) -> np.ndarray:
    """The bonds the SLA broke (not the pre-crack's), as indices into ``fields["bond_nodes"]``."""
    b = np.asarray(res.history.get("bond", []), dtype=int)
    return np.unique(b[b >= 0])


def bond_midpoints(res: Result, bonds: np.ndarray) -> np.ndarray:
    xy = np.asarray(res.fields["node_xy"], dtype=float)
    ij = np.asarray(res.fields["bond_nodes"], dtype=int)[bonds]
    return 0.5 * (xy[ij[:, 0]] + xy[ij[:, 1]])


def path_agreement(
    xfem_path: np.ndarray, midpoints: np.ndarray, dx: float, delta: float, h: float
) -> tuple[dict[str, Any], paths.Ridge | None]:
    """The PD ridge of the broken bonds' ``midpoints`` along ``xfem_path`` and its distance to
    it: ``n_stations``, ``covered`` (fraction with bonds), ``covered_length`` (arc length up to
    the last covered station) of ``path_length``, ``mean`` / ``max`` distance (length) and the
    same in horizons (``*_horizons``) and XFEM element lengths (``*_elements``), and
    ``off_path_bonds`` (fraction of broken bonds farther than the strip's half-width from the
    XFEM path: a PD crack elsewhere)."""
    out: dict[str, Any] = {"n_bonds": len(midpoints)}
    if len(xfem_path) < 2 or paths.path_length(xfem_path) < dx:
        out["status"] = "the XFEM crack did not grow: no path to compare"
        return out, None
    if len(midpoints) == 0:
        out["status"] = "the SLA broke no bond"
        return out, None
    half = RIDGE_HALF_WIDTH_HORIZONS * delta
    ridge = paths.bond_ridge(midpoints, xfem_path, dx, half, window=RIDGE_WINDOW_SPACINGS * dx)
    dist = paths.distance_to_polyline(ridge.points(), xfem_path)
    far = paths.distance_to_polyline(midpoints, xfem_path) > half
    total = paths.path_length(xfem_path)
    out.update(
        status="ok" if ridge.covered.any() else "no broken bond near the XFEM path",
        n_stations=len(ridge.s),
        covered=float(np.mean(ridge.covered)),
        path_length=total,
        covered_length=float(ridge.s[ridge.covered].max()) if ridge.covered.any() else 0.0,
        strip_half_width=half,
        off_path_bonds=float(np.mean(far)),
    )
    if dist.size:
        for k, v in (("mean", float(dist.mean())), ("max", float(dist.max()))):
            out[k] = v
            out[f"{k}_horizons"] = v / delta
            out[f"{k}_elements"] = v / h
    return out, ridge


def response_pair(res: Result) -> tuple[str, str]:
    """(x, y) history columns both methods define alike: (cmod, sigma22) under the grips,
    (u0, load_factor) with supports and loads on regions (u0 is then the load displacement; the
    load factor multiplies the scene's loads)."""
    if res.meta.get("bc") == "regions":
        return "u0", "load_factor"
    return "cmod", "sigma22"


LABELS = {
    "cmod": "CMOD",
    "sigma22": "sigma22 (mean normal stress on the loaded edge)",
    "u0": "load displacement u0",
    "load_factor": "load factor (x the scene's loads)",
}


def window(n: int) -> int:
    w = min(agreement.DEFAULT_WINDOW, max(n // 4, 1))
    return w if w % 2 else max(w - 1, 1)
