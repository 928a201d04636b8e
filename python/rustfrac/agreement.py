"""Agreement of two load paths in the sigma22-CMOD plane.

The SLA of CCM-PD gives a saw-tooth: one point per bond break, each at the load that breaks it,
so the load drops after some breaks and rises before the next. LEFM growth (XFEM) gives one
smooth curve of critical states. Comparing them at equal *crack length* would depend on how a
PD crack length is defined; comparing at equal CMOD does not. Three readings of the saw-tooth
are compared with the XFEM curve at the same CMOD:

- ``peaks``: the local maxima of sigma22 along the steps (the loads the body withstood);
- ``lower_envelope``: the local minima (the loads right after a drop);
- ``running_mean``: the centred moving average over ``window`` steps of both sigma22 and CMOD.

The XFEM curve is read by linear interpolation in CMOD, from the unloaded origin (the elastic
line below the first critical state) to its last point, over the part where its CMOD grows
(a snap-back in CMOD would make it multivalued; where it starts is reported). For each reading
the relative difference ``pd / xfem - 1`` is summarised (count, CMOD range, mean, RMS, min, max)
over the points inside that range; points beyond the XFEM curve's last CMOD are counted as
``outside``.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

__all__ = ["DEFAULT_WINDOW", "READINGS", "compare", "readings", "reference_curve"]

#: steps of the running mean (odd: centred); about the number of breaks that cross one PD cell
#: row on the paper's grid (m = 4: a crack-front node has 2 m + 1 bonds across the crack line)
DEFAULT_WINDOW = 25

#: the readings of the saw-tooth, in the order of :func:`compare`'s output
READINGS = ("peaks", "lower_envelope", "running_mean")


def _arrays(cmod: Sequence[float], sigma: Sequence[float]) -> tuple[np.ndarray, np.ndarray]:
    c = np.asarray(cmod, dtype=float)
    s = np.asarray(sigma, dtype=float)
    if c.shape != s.shape or c.ndim != 1:
        raise ValueError(f"cmod and sigma22: 1-D arrays of one length, got {c.shape} and {s.shape}")
    if not (np.all(np.isfinite(c)) and np.all(np.isfinite(s))):
        raise ValueError("cmod and sigma22: finite values")
    return c, s


def reference_curve(
    cmod: Sequence[float], sigma: Sequence[float]
) -> tuple[np.ndarray, np.ndarray, int]:
    """The reference (XFEM) curve as a function of CMOD: the origin prepended when missing, and
    the points up to the first decrease of CMOD. Returns (cmod, sigma22, points dropped)."""
    c, s = _arrays(cmod, sigma)
    if c.size == 0 or c[0] != 0.0:
        c, s = np.concatenate([[0.0], c]), np.concatenate([[0.0], s])
    grows = np.diff(c) > 0
    stop = int(np.argmin(grows)) + 1 if not np.all(grows) else c.size
    return c[:stop], s[:stop], int(c.size - stop)


def readings(
    cmod: Sequence[float], sigma: Sequence[float], window: int = DEFAULT_WINDOW
) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """The three readings of an SLA saw-tooth (rows after the unloaded origin): name ->
    (cmod, sigma22). ``window`` (odd, >= 1) is the running mean's width in steps."""
    if not (isinstance(window, int) and window >= 1 and window % 2 == 1):
        raise ValueError(f"window: an odd number of steps >= 1, got {window!r}")
    c, s = _arrays(cmod, sigma)
    if c.size and c[0] == 0.0 and s[0] == 0.0:
        c, s = c[1:], s[1:]
    out: dict[str, tuple[np.ndarray, np.ndarray]] = {}
    if c.size >= 3:
        mid = slice(1, -1)
        peak = (s[mid] >= s[:-2]) & (s[mid] > s[2:])
        trough = (s[mid] <= s[:-2]) & (s[mid] < s[2:])
        ip, it = np.flatnonzero(peak) + 1, np.flatnonzero(trough) + 1
    else:
        ip = it = np.array([], dtype=int)
    out["peaks"] = (c[ip], s[ip])
    out["lower_envelope"] = (c[it], s[it])
    if c.size >= window:
        k = np.ones(window) / window
        out["running_mean"] = (np.convolve(c, k, "valid"), np.convolve(s, k, "valid"))
    else:
        out["running_mean"] = (np.array([]), np.array([]))
    return out


def _stats(rel: np.ndarray, c: np.ndarray, outside: int) -> dict[str, Any]:
    if rel.size == 0:
        return {"n": 0, "outside": outside}
    return {
        "n": int(rel.size),
        "outside": outside,
        "cmod_range": [float(c.min()), float(c.max())],
        "mean_rel_diff": float(rel.mean()),
        "rms_rel_diff": float(np.sqrt(np.mean(rel**2))),
        "min_rel_diff": float(rel.min()),
        "max_rel_diff": float(rel.max()),
    }


def compare(
    ref_cmod: Sequence[float],
    ref_sigma: Sequence[float],
    pd_cmod: Sequence[float],
    pd_sigma: Sequence[float],
    window: int = DEFAULT_WINDOW,
) -> dict[str, Any]:
    """Each reading of the PD saw-tooth against the reference curve at the same CMOD: name ->
    summary (``n``, ``outside``, ``cmod_range``, ``mean_rel_diff``, ``rms_rel_diff``,
    ``min_rel_diff``, ``max_rel_diff``) plus ``curves`` (name -> (cmod, rel. difference), for a
    figure), ``window`` and ``reference_dropped`` (points after the reference's CMOD stops
    growing)."""
    rc, rs, dropped = reference_curve(ref_cmod, ref_sigma)
    out: dict[str, Any] = {"window": window, "reference_dropped": dropped, "curves": {}}
    for name, (c, s) in readings(pd_cmod, pd_sigma, window).items():
        inside = (c >= rc[0]) & (c <= rc[-1])
        ref = np.interp(c[inside], rc, rs)
        ok = ref > 0
        ci, rel = c[inside][ok], s[inside][ok] / ref[ok] - 1.0
        out[name] = _stats(rel, ci, int(np.count_nonzero(~inside)))
        out["curves"][name] = (ci, rel)
    return out
