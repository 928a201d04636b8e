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

__all__ = ["plot_damage", "plot_field", "save_damage_plot", "save_plot"]

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
        component: "s11" | "s22" | "s12" (from the nodal stresses).
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
    values = res.fields["nodal_stress"][:, _COMPONENTS[component]][el].mean(axis=1)
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
