"""Energy audit of a load path: the energy dissipated per unit of new crack area, from the
history alone, against the fracture energy G0 (docs/design.md, "The energy audit").

The load's work at a state is 1/2 (a sigma22)(b u0) with the work-conjugate pair (a, b) the core
gives (``meta["work_conjugate"]``; the paper's grips: a = W t, b = 2, so P = sigma22 W t is the
top edge's force and D = 2 u0 the edges' relative displacement). A state on the load path is
(P, D); K = P / D is the secant stiffness of its crack.

- **XFEM** (LEFM growth, one critical state per growth step): between two critical states k and
  k + 1 the crack grows from a_k to a_k+1 and the energy dissipated is the area between their
  secants, the triangle (0, state k, state k + 1): 1/2 (P_k D_k+1 - P_k+1 D_k). Per unit of new
  crack area, G_k = that / (t (a_k+1 - a_k)); LEFM growth at K_eq = K_Ic has G = G0, so the
  ratio checks the global energy (compliance) against the local SIFs of the I-integral.
- **PD** (SLA, one bond break per step, at fixed displacement): the break at step k releases
  1/2 D_k^2 (K_k - K_k+1) (the stiffness of the state after the break is the next step's secant;
  after the last break of a separated body it is 0). The new crack area is t times the advance of
  the damage front (``crack_length``), so the ratio is an average over an advance of at least a
  few cells, not per break.

The SLA releases at least the energy of the bonds it breaks (removing a spring at fixed boundary
displacement lowers the minimum energy by at least the spring's own), so the PD ratio can exceed
the grid's discrete fracture energy: measured on a PD strip breaking across (tests/test_energy.py)
and reported on the paper's case in ``benches/RESULTS.md``.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from .errors import PlotDataError
from .result import Result, result_entry

__all__ = ["along", "audit"]


def _units(res: Result, length_key: str) -> dict[str, str]:
    """The units of the audit's entries, from the result schema (:func:`rustfrac.result_schema`):
    the dissipated energies in the unit of the FEM strain energy, G0 in that of J (energy per
    area), the crack lengths in that of the history column ``length_key``."""
    energy, per_area = (result_entry("scalars", k) for k in ("energy", "J"))
    assert energy is not None and per_area is not None  # both in the core's table
    length = res.unit(length_key) or ""
    return {
        "G0": per_area["unit"], "energy": energy["unit"], "dissipated": energy["unit"],
        "a": length, "a0": length,
    }  # fmt: skip


def _pair(res: Result) -> tuple[float, float]:
    ab = res.meta.get("work_conjugate")
    if not ab:
        raise PlotDataError(
            "the energy audit needs a load whose work the history gives (meta['work_conjugate']): "
            f"displacement grips 'free' or 'clamped'; this result ran with bc {res.meta.get('bc')!r}"
        )
    return float(ab[0]), float(ab[1])


def _g0(res: Result) -> float:
    mat = (res.meta.get("scene") or {}).get("material") or {}
    if "G0" not in mat:
        raise PlotDataError("the energy audit needs the scene's material G0 (meta['scene'])")
    return float(mat["G0"])


def audit(res: Result) -> dict[str, Any]:
    """The energy audit of a growth (XFEM) or SLA (PD, CCM-PD) result: a dict with ``G0``,
    ``energy`` (total dissipated), ``crack_area`` (thickness times the crack advance),
    ``ratio`` (energy / crack_area / G0) and, per history interval, ``a`` (crack length at its
    end), ``dissipated`` and for XFEM ``ratio_per_step``; ``a0`` (the crack length at the start)
    and ``thickness``; ``units``: the units of ``G0``, ``energy``, ``dissipated``, ``a`` and
    ``a0``, from the result schema. Raises :class:`~rustfrac.errors.PlotDataError` for a result without a load path or a
    work-conjugate load (traction grips, regions)."""
    a_, b_ = _pair(res)
    g0 = _g0(res)
    t = float((res.meta.get("scene") or {}).get("material", {}).get("thickness", 1.0))
    h = res.history
    if "sigma22" not in h or len(h["sigma22"]) < 3:
        raise PlotDataError("the energy audit needs a load path of at least two states")
    p = a_ * np.asarray(h["sigma22"], dtype=float)[1:]
    d = b_ * np.asarray(h["u0"], dtype=float)[1:]
    out: dict[str, Any] = {"G0": g0, "method": res.method}
    if res.method == "xfem":
        a = np.asarray(h["a"], dtype=float)[1:]
        e = 0.5 * (p[:-1] * d[1:] - p[1:] * d[:-1])
        da = t * np.diff(a)
        ok = da > 0
        out["ratio_per_step"] = np.where(ok, e / np.where(ok, da, 1.0) / g0, np.nan)
        out["a"], out["dissipated"] = a[1:], e
        a_start = a[0]
        advance = a[-1] - a[0]
        out["units"] = _units(res, "a")
    elif res.method in ("pd", "ccm_pd"):
        if np.any(d <= 0):
            raise PlotDataError("the energy audit needs a load displacement > 0 at every step")
        k = p / d
        k_after = np.append(k[1:], 0.0 if res.meta.get("status") == "separated" else np.nan)
        e = 0.5 * d**2 * (k - k_after)
        e = e[np.isfinite(e)]
        cl = np.asarray(h["crack_length"], dtype=float)
        out["a"], out["dissipated"] = cl[1 : 1 + e.size], e
        a_start = cl[0]
        advance = cl[e.size] - cl[0]
        out["units"] = _units(res, "crack_length")
    else:
        raise PlotDataError(f"no load path to audit for method {res.method!r}")
    energy = float(np.sum(e))
    area = t * float(advance)
    out.update(
        a0=float(a_start),
        thickness=t,
        energy=energy,
        crack_area=area,
        ratio=energy / area / g0 if area > 0 else float("nan"),
    )
    return out


def along(au: dict[str, Any], edges: Any) -> np.ndarray:
    """The audit's ratio along the crack: G / G0 over each interval ``[edges[i], edges[i+1]]``
    of the crack length (XFEM ``a``, PD the damage front; ``edges[0]`` normally the initial
    ``a0``). Each history interval's energy is spread evenly over the crack advance it made (an
    XFEM step from a_k to a_k+1; an SLA break that moves the front), or counted where the crack
    is when it made none (most SLA breaks); energy at or before ``edges[0]`` counts in the
    first interval. Each interval's energy over thickness times its length covered by the
    crack, per G0; NaN where the crack did not reach. With edges spanning the whole advance
    their length-weighted mean is :func:`audit`'s ``ratio``. ``au``: :func:`audit`'s output."""
    e = np.asarray(edges, dtype=float)
    if e.ndim != 1 or e.size < 2 or not np.all(np.diff(e) > 0):
        raise ValueError(f"edges: an increasing 1-D sequence of at least 2 crack lengths, got {e}")
    hi_a = np.asarray(au["a"], dtype=float)
    lo_a = np.concatenate([[float(au["a0"])], hi_a[:-1]])
    diss = np.asarray(au["dissipated"], dtype=float)
    moved = hi_a > lo_a
    span = np.where(moved, hi_a - lo_a, 1.0)
    front = float(np.max(hi_a)) if hi_a.size else -np.inf
    out = np.full(e.size - 1, np.nan)
    for i in range(e.size - 1):
        lo, hi = e[i], e[i + 1]
        cover = min(hi, front) - lo
        if cover <= 0:
            continue
        share = np.clip((np.minimum(hi_a, hi) - np.maximum(lo_a, lo)) / span, 0.0, 1.0)
        point = ((hi_a > lo) | (i == 0)) & (hi_a <= hi)
        w = np.where(moved, share, point.astype(float))
        if i == 0:  # advance behind edges[0] counts in the first interval
            behind = np.clip((np.minimum(hi_a, lo) - lo_a) / span, 0.0, 1.0)
            w = np.where(moved, w + behind, w)
        out[i] = float(np.sum(w * diss)) / (float(au["thickness"]) * au["G0"] * cover)
    return out
