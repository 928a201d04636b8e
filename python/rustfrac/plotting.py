"""Minimal matplotlib helpers (no pyplot state: figures are built with ``matplotlib.figure``,
so they work headless, like the Agg backend)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
from matplotlib.axes import Axes
from matplotlib.collections import PolyCollection
from matplotlib.figure import Figure

from .result import Result

__all__ = ["plot_damage", "plot_field", "plot_load_path", "plot_tip_deformation", "save_damage_plot", "save_plot"]

_COMPONENTS = {"s11": 0, "s22": 1, "s12": 2}


def plot_field(
    res: Result,
    component: str = "s22",
    *,
    scale: float | None = None,
    ax: Axes | None = None,
    cmap: str = "viridis",
) -> Axes:
    """Draws the deformed mesh coloured by an element-mean stress component.

    Args:
        component: "s11" | "s22" | "s12" (from the nodal stresses; results without nodal
            stresses, e.g. XFEM, are coloured by u2).
        scale: displacement magnification; default: max displacement = 2 % of the plate size.
        ax: axes to draw in; default: a new figure.
    """
    if component not in _COMPONENTS:
        raise ValueError(f"component must be one of {', '.join(_COMPONENTS)}, got {component!r}")
    xy = np.asarray(res.coords, dtype=float)
    u = res.displacement
    size = float(np.ptp(xy, axis=0).max())
    umax = float(np.abs(u).max()) if u.size else 0.0
    if scale is None:
        scale = 0.02 * size / umax if umax > 0 else 1.0
    xyd = xy + scale * u
    el = np.asarray(res.elements)
    if "nodal_stress" in res.fields:
        values = res.fields["nodal_stress"][:, _COMPONENTS[component]][el].mean(axis=1)
    else:  # XFEM results carry displacements only: colour by u2
        component = "u2"
        values = u[:, 1][el].mean(axis=1)
    if ax is None:
        ax = Figure(figsize=(5, 8)).add_subplot()
    pc = PolyCollection(xyd[el], array=values, cmap=cmap, edgecolors="k", linewidths=0.1)
    ax.add_collection(pc)
    ax.autoscale_view()
    ax.set_aspect("equal")
    ax.set_xlabel("x1")
    ax.set_ylabel("x2")
    ax.set_title(f"{res.method}: {component} (displacements x {scale:.3g})")
    ax.figure.colorbar(pc, ax=ax, label=component)
    return ax


def save_plot(res: Result, path: str | Path, **kwargs: Any) -> Path:
    """:func:`plot_field` into a new figure saved to ``path`` (format from the suffix)."""
    ax = plot_field(res, **kwargs)
    p = Path(path)
    ax.figure.savefig(p, dpi=150, bbox_inches="tight")
    return p


def plot_tip_deformation(res: Result, *, scale: float = 50.0, ax: Axes | None = None) -> Axes:
    """XFEM: the deformed cells near the crack tip magnified ``scale`` times (Fig. 8b; from
    ``fields["deformed_cells"]`` and ``fields["deformed_disp"]``, the enriched displacement
    evaluated inside each cell, so the crack opens as a gap) over the initial crack line."""
    cells = res.fields.get("deformed_cells")
    disp = res.fields.get("deformed_disp")
    if cells is None or disp is None:
        raise ValueError(f"{res.method} result has no deformed tip patch (XFEM results only)")
    if ax is None:
        ax = Figure(figsize=(6, 6)).add_subplot()
    pc = PolyCollection(
        np.asarray(cells) + scale * np.asarray(disp),
        facecolors="none",
        edgecolors="k",
        linewidths=0.3,
    )
    ax.add_collection(pc)
    crack = res.fields.get("crack_initial", res.fields.get("crack"))
    if crack is not None:
        ax.plot(crack[:, 0], crack[:, 1], "r-", lw=0.8, label="crack (undeformed)")
    ax.autoscale_view()
    ax.set_aspect("equal")
    ax.set_xlabel("x1")
    ax.set_ylabel("x2")
    ax.set_title(f"deformed mesh near the tip (displacements x {scale:g})")
    return ax


def plot_load_path(
    res: Result, *, x: str = "u0", y: str = "sigma22", ax: Axes | None = None
) -> Axes:
    """A load path from ``res.history`` (e.g. sigma22 against u0 or cmod, as in Fig. 7)."""
    if not res.history:
        raise ValueError("result has no history (run with growth_steps > 0)")
    for k in (x, y):
        if k not in res.history:
            raise ValueError(f"history has no {k!r}; available: {', '.join(res.history)}")
    if ax is None:
        ax = Figure(figsize=(6, 4.5)).add_subplot()
    ax.plot(res.history[x], res.history[y], "o-", ms=3, label=res.method)
    ax.set_xlabel(x)
    ax.set_ylabel(y)
    ax.legend()
    return ax


def plot_damage(res: Result, *, ax: Axes | None = None, cmap: str = "viridis") -> Axes:
    """Draws the PD nodes (PD and CCM-PD results) coloured by their final damage index."""
    xy = np.asarray(res.fields["pd_node_xy"], dtype=float)
    if ax is None:
        ax = Figure(figsize=(6, 5)).add_subplot()
    sc = ax.scatter(xy[:, 0], xy[:, 1], c=res.damage, s=4, cmap=cmap, vmin=0.0, vmax=1.0)
    ax.set_aspect("equal")
    ax.set_xlabel("x1")
    ax.set_ylabel("x2")
    ax.set_title(f"{res.method}: damage after {res.meta.get('sla_steps_done', '?')} SLA steps")
    ax.figure.colorbar(sc, ax=ax, label="damage")
    return ax


def save_damage_plot(res: Result, path: str | Path, **kwargs: Any) -> Path:
    """:func:`plot_damage` into a new figure saved to ``path``."""
    ax = plot_damage(res, **kwargs)
    p = Path(path)
    ax.figure.savefig(p, dpi=150, bbox_inches="tight")
    return p
