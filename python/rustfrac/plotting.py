"""Plots of one result, for notebooks and scripts (``rf.plotting``).

Every ``plot_*`` function returns a :class:`matplotlib.figure.Figure` (a
:class:`NotebookFigure`, which Jupyter shows inline as a cell's value, pyplot or not); ``ax=``
draws into existing axes instead (the returned figure is then theirs). Figures are built with ``matplotlib.figure`` (no pyplot state), so they also work
headless. Axis labels carry units: rustfrac is unit-agnostic (any consistent set), so the labels
say "length" and "force/length^2" unless a :class:`Units` names them (``units=PAPER_UNITS``:
the paper's N, mm and MPa).

- :func:`plot_field`: the deformed mesh (FEM, XFEM) or grid nodes (PD, CCM-PD) coloured by a
  stress or displacement component;
- :func:`plot_crack_path`: the plate, the initial crack(s) and the crack path of any method
  (XFEM polylines, the PD damage ridge, the FEM seam);
- :func:`plot_load_path`: two history columns against each other (e.g. sigma22 against CMOD);
- :func:`plot_damage`: the PD nodes coloured by their damage index;
- :func:`plot_tip_deformation`: XFEM's deformed cells near the tip, magnified.
"""

from __future__ import annotations

import io
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from matplotlib.axes import Axes
from matplotlib.collections import PolyCollection
from matplotlib.figure import Figure
from matplotlib.patches import Rectangle

from .errors import InvalidParameterError, PlotDataError
from .result import Result, result_entry

__all__ = [
    "COMPONENTS",
    "DEFAULT_UNITS",
    "PAPER_UNITS",
    "NotebookFigure",
    "Units",
    "damage_ridge",
    "field_components",
    "history_quantity",
    "plot_crack_path",
    "plot_damage",
    "plot_field",
    "plot_load_path",
    "plot_tip_deformation",
    "save_damage_plot",
    "save_plot",
]


@dataclass(frozen=True)
class Units:
    """Unit names for axis labels. ``stress`` defaults to ``force/length^2``."""

    length: str = "length"
    force: str = "force"
    stress: str = ""

    @property
    def stress_unit(self) -> str:
        return self.stress or f"{self.force}/{self.length}^2"

    def of(self, quantity: str) -> str:
        """The unit of a quantity kind: "length", "force", "stress", "sif", "1"
        (dimensionless), "rad"."""
        return {
            "length": self.length,
            "force": self.force,
            "stress": self.stress_unit,
            "sif": f"{self.stress_unit} {self.length}^1/2",
            "1": "-",
            "rad": "rad",
        }[quantity]

    def label(self, name: str, quantity: str) -> str:
        return f"{name} [{self.of(quantity)}]"


#: the labels rustfrac uses unless told: "length", "force/length^2"
DEFAULT_UNITS = Units()
#: the paper's units (N, mm, MPa)
PAPER_UNITS = Units("mm", "N", "MPa")

#: field components of :func:`plot_field`: name -> quantity kind
COMPONENTS: dict[str, str] = {
    **dict.fromkeys(("s11", "s22", "s12"), "stress"),
    **dict.fromkeys(("u1", "u2"), "length"),
}
_STRESS_COLUMN = {"s11": 0, "s22": 1, "s12": 2}

#: the quantity kind of a result unit of the schema (:func:`rustfrac.result.result_schema`)
_UNIT_QUANTITY: dict[str, str] = {
    "length": "length",
    "force": "force",
    "stress": "stress",
    "stress sqrt(length)": "sif",
    "1": "1",
    "rad": "rad",
}


def history_quantity(key: str) -> str | None:
    """The quantity kind of a history column, from its unit in the result schema (a probe,
    force or mean-stress column of a general scene by its pattern), None when unknown."""
    e = result_entry("history", key)
    return None if e is None else _UNIT_QUANTITY.get(e["unit"])


def _history_label(key: str, units: Units) -> str:
    q = history_quantity(key)
    return key if q is None else units.label(key, q)


class NotebookFigure(Figure):
    """A :class:`~matplotlib.figure.Figure` that shows itself as a PNG in Jupyter (``_repr_png_``)
    without pyplot or ``%matplotlib inline`` (pyplot-free figures have no display otherwise)."""

    def _repr_png_(self) -> bytes:
        buf = io.BytesIO()
        self.savefig(buf, format="png", dpi=100, bbox_inches="tight")
        return buf.getvalue()


def _new_axes(ax: Axes | None, figsize: tuple[float, float]) -> Axes:
    return NotebookFigure(figsize=figsize).add_subplot() if ax is None else ax


def _figure(ax: Axes) -> Figure:
    fig = ax.get_figure()
    assert isinstance(fig, Figure)
    return fig


def _xy_labels(ax: Axes, units: Units) -> None:
    ax.set_xlabel(units.label("x1", "length"))
    ax.set_ylabel(units.label("x2", "length"))


def _save(fig: Figure, path: str | Path) -> Path:
    p = Path(path)
    fig.savefig(p, dpi=150, bbox_inches="tight")
    return p


# ----------------------------------------------------------------------------------------------
# fields


def _nodes(res: Result) -> tuple[np.ndarray, np.ndarray | None]:
    """(node coordinates (n, 2), Q4 connectivity or None): the mesh of FEM / XFEM, the grid
    nodes (no cells) of PD / CCM-PD."""
    if "coords" in res.fields and "elements" in res.fields:
        return np.asarray(res.coords, dtype=float), np.asarray(res.elements)
    if "node_xy" in res.fields:
        return np.asarray(res.fields["node_xy"], dtype=float), None
    raise PlotDataError(
        f"{res.method} result has neither a mesh (fields coords, elements) nor grid nodes "
        "(node_xy): nothing to draw"
    )


def field_components(res: Result) -> list[str]:
    """The components :func:`plot_field` can draw for ``res``: s11, s22, s12 where the result
    has nodal stresses (FEM), u1, u2 where it has nodal displacements (every method)."""
    out = []
    if "nodal_stress" in res.fields:
        out += list(_STRESS_COLUMN)
    if "u" in res.fields:
        out += ["u1", "u2"]
    return out


def _component_values(res: Result, component: str | None) -> tuple[str, np.ndarray]:
    """(component, nodal values); None picks s22, or u2 without nodal stresses."""
    valid = field_components(res)
    if component is None:
        component = "s22" if "s22" in valid else "u2"
    if component not in COMPONENTS:
        raise InvalidParameterError(
            f"invalid component: expected one of {', '.join(COMPONENTS)}, got {component!r}",
            "component",
        )
    if component not in valid:
        raise InvalidParameterError(
            f"invalid component: a {res.method} result has no {component!r} field (no "
            f"{'nodal stresses' if component in _STRESS_COLUMN else 'displacements'}); valid for "
            f"it: {', '.join(valid) or 'none'}",
            "component",
        )
    if component in _STRESS_COLUMN:
        return component, res.fields["nodal_stress"][:, _STRESS_COLUMN[component]]
    return component, res.displacement[:, 0 if component == "u1" else 1]


def plot_field(
    res: Result,
    component: str | None = None,
    *,
    scale: float | None = None,
    ax: Axes | None = None,
    cmap: str = "viridis",
    units: Units = DEFAULT_UNITS,
) -> Figure:
    """The deformed mesh (FEM, XFEM: element means of the nodal values) or the deformed grid nodes
    (PD, CCM-PD: one dot per node, displacements at the reference load) coloured by a component.

    Args:
        component: "s11" | "s22" | "s12" (nodal stresses: FEM) or "u1" | "u2" (every method);
            default "s22", or "u2" for results without nodal stresses (XFEM, PD, CCM-PD). A
            component the result lacks raises :class:`~rustfrac.errors.InvalidParameterError`
            listing the valid ones (:func:`field_components`).
        scale: displacement magnification; default: max displacement = 2 % of the plate size.
        ax: axes to draw in; default: a new figure.
        units: unit names of the labels.
    """
    component, values = _component_values(res, component)
    xy, el = _nodes(res)
    u = res.displacement
    size = float(np.ptp(xy, axis=0).max())
    umax = float(np.abs(u).max()) if u.size else 0.0
    if scale is None:
        scale = 0.02 * size / umax if umax > 0 else 1.0
    xyd = xy + scale * u
    ax = _new_axes(ax, (5, 8))
    if el is not None:
        art: Any = PolyCollection(
            xyd[el], array=values[el].mean(axis=1), cmap=cmap, edgecolors="k", linewidths=0.1
        )
        ax.add_collection(art)
        ax.autoscale_view()
    else:
        art = ax.scatter(xyd[:, 0], xyd[:, 1], c=values, s=2, cmap=cmap, linewidths=0)
    ax.set_aspect("equal")
    _xy_labels(ax, units)
    ax.set_title(f"{res.method}: {component} (displacements x {scale:.3g})")
    _figure(ax).colorbar(art, ax=ax, label=units.label(component, COMPONENTS[component]))
    return _figure(ax)


def save_plot(res: Result, path: str | Path, **kwargs: Any) -> Path:
    """:func:`plot_field` into a new figure saved to ``path`` (format from the suffix)."""
    return _save(plot_field(res, **kwargs), path)


# ----------------------------------------------------------------------------------------------
# crack paths


def _plate(res: Result) -> tuple[float, float]:
    """(width, height) of the plate: from the scene in ``meta``, else the nodes' extent."""
    plate = res.meta.get("scene", {}).get("plate")
    if isinstance(plate, Mapping) and "width" in plate and "height" in plate:
        return float(plate["width"]), float(plate["height"])
    xy, _ = _nodes(res)
    hi = xy.max(axis=0)
    return float(hi[0]), float(hi[1])


def _initial_cracks(res: Result) -> list[np.ndarray]:
    """The cracks before any growth: the scene's (as the solvers see them), if ``meta`` has it."""
    scene = res.meta.get("scene")
    if not isinstance(scene, Mapping):
        return []
    from . import _core

    return [np.asarray(c, dtype=float) for c in _core.crack_polylines(dict(scene))]


def _damage(res: Result) -> np.ndarray:
    """The damage index of the PD nodes (``fields["pd_node_xy"]``), or a PlotDataError."""
    if res.damage is None or "pd_node_xy" not in res.fields:
        raise PlotDataError(f"{res.method} result has no damage field (PD and CCM-PD results only)")
    return np.asarray(res.damage, dtype=float)


def damage_ridge(res: Result, threshold: float = 0.25) -> list[np.ndarray]:
    """The crack path of a PD / CCM-PD result, read from its damage field: column by column along
    x1 (PD cracks run along x1), the damage-weighted mean x2 of the band of consecutive nodes
    around the column's most damaged node whose damage index reaches ``threshold`` (with m = 4 a
    node beside a fully broken crack line has lost about 0.4 of its bonds). Columns more
    than 1.5 spacings apart start a new polyline; each polyline is (k, 2)."""
    d = _damage(res)
    if not 0.0 < threshold <= 1.0:
        raise InvalidParameterError(
            f"invalid threshold: expected a damage index in (0, 1], got {threshold!r}", "threshold"
        )
    xy = np.asarray(res.fields["pd_node_xy"], dtype=float)
    xs = np.unique(xy[:, 0])
    dx = float(np.min(np.diff(xs))) if len(xs) > 1 else 1.0
    tol = 1e-9 * dx
    pts = []
    for x in xs:
        col = np.abs(xy[:, 0] - x) <= tol
        order = np.argsort(xy[col, 1])
        dc, yc = d[col][order], xy[col, 1][order]
        i = int(np.argmax(dc))
        if dc[i] < threshold:
            continue
        lo, hi = i, i  # the band of consecutive nodes at or above the threshold around the peak
        while lo > 0 and dc[lo - 1] >= threshold and yc[lo] - yc[lo - 1] <= 1.5 * dx + tol:
            lo -= 1
        while (
            hi + 1 < len(dc) and dc[hi + 1] >= threshold and yc[hi + 1] - yc[hi] <= 1.5 * dx + tol
        ):
            hi += 1
        pts.append((x, float(np.average(yc[lo : hi + 1], weights=dc[lo : hi + 1]))))
    lines: list[list[tuple[float, float]]] = []
    for p in pts:
        if lines and p[0] - lines[-1][-1][0] <= 1.5 * dx + tol:
            lines[-1].append(p)
        else:
            lines.append([p])
    return [np.asarray(line) for line in lines]


def plot_crack_path(
    res: Result,
    *,
    ax: Axes | None = None,
    threshold: float = 0.25,
    units: Units = DEFAULT_UNITS,
) -> Figure:
    """The plate outline, the initial crack(s) (dashed) and the crack path of the result: XFEM's
    final crack polylines (:attr:`Result.crack_polylines`), the damage ridge of PD / CCM-PD
    (:func:`damage_ridge`, ``threshold`` its damage index) with the CCM-PD rectangle, the seam of
    FEM (which does not grow)."""
    w, h = _plate(res)
    ax = _new_axes(ax, (5, 8))
    ax.add_patch(Rectangle((0.0, 0.0), w, h, fill=False, ec="k", lw=1.0, label="plate"))
    regions = res.meta.get("pd_regions")  # CCM-PD: [[x0, y0, x1, y1]]; pure PD: a string
    for k, (x0, y0, x1, y1) in enumerate(regions if isinstance(regions, list) else []):
        ax.add_patch(
            Rectangle(
                (x0, y0),
                x1 - x0,
                y1 - y0,
                fill=True,
                fc="#e8f4e8",
                ec="#2ca02c",
                lw=0.6,
                label="PD region" if k == 0 else None,
            )
        )
    initial = _initial_cracks(res)
    for k, c in enumerate(initial):
        ax.plot(
            c[:, 0],
            c[:, 1],
            "--",
            color="0.4",
            lw=1.2,
            label=("seam crack" if res.method == "fem" else "initial crack") if k == 0 else None,
        )
    if res.method == "xfem":
        paths, label = res.crack_polylines, "crack path (XFEM)"
    elif res.damage is not None:
        paths, label = damage_ridge(res, threshold), f"damage ridge (damage >= {threshold:g})"
    else:
        paths, label = [], ""
    for k, c in enumerate(paths):
        ax.plot(c[:, 0], c[:, 1], "-", color="C3", lw=1.8, label=label if k == 0 else None)
    ax.set_xlim(-0.03 * w, 1.03 * w)
    ax.set_ylim(-0.03 * h, 1.03 * h)
    ax.set_aspect("equal")
    _xy_labels(ax, units)
    what = "uncracked" if not initial and not paths else "crack path"
    ax.set_title(f"{res.method}: {what}")
    ax.legend(fontsize=7, loc="upper right")
    return _figure(ax)


# ----------------------------------------------------------------------------------------------
# load paths, damage, tip


def plot_load_path(
    res: Result,
    *,
    x: str = "u0",
    y: str = "sigma22",
    ax: Axes | None = None,
    units: Units = DEFAULT_UNITS,
) -> Figure:
    """A load path: two columns of ``res.history`` against each other, e.g. sigma22 against u0
    or cmod as in Fig. 7, or for a general scene ``x="load_displacement"`` (the load point's
    displacement along its force), ``"probe:<name>:<k>"`` (component k = 1, 2 of a probe),
    ``"force:<region>:<k>"`` (a region's force, e.g. ``"force:load[0]:2"``) or
    ``"mean_stress:<region>"``. The axis labels carry the columns' units (``units``).

    Raises:
        PlotDataError: the result has no history (a single solve: run with growth_steps > 0
            or sla_steps > 0).
        InvalidParameterError: ``x`` or ``y`` is not a column (``param`` "x" / "y"; the
            message lists the available ones).
    """
    if not res.history:
        raise PlotDataError(
            f"{res.method} result has no history (run with growth_steps > 0 or sla_steps > 0)"
        )
    for name, k in (("x", x), ("y", y)):
        if k not in res.history:
            raise InvalidParameterError(
                f"invalid {name}: the history has no {k!r}; valid: {', '.join(res.history)}", name
            )
    ax = _new_axes(ax, (6, 4.5))
    ax.plot(res.history[x], res.history[y], "o-", ms=3, label=res.method)
    ax.set_xlabel(_history_label(x, units))
    ax.set_ylabel(_history_label(y, units))
    ax.legend()
    return _figure(ax)


def plot_damage(
    res: Result, *, ax: Axes | None = None, cmap: str = "viridis", units: Units = DEFAULT_UNITS
) -> Figure:
    """Draws the PD nodes (PD and CCM-PD results) coloured by their final damage index."""
    d = _damage(res)
    xy = np.asarray(res.fields["pd_node_xy"], dtype=float)
    ax = _new_axes(ax, (6, 5))
    sc = ax.scatter(xy[:, 0], xy[:, 1], c=d, s=4, cmap=cmap, vmin=0.0, vmax=1.0)
    ax.set_aspect("equal")
    _xy_labels(ax, units)
    ax.set_title(f"{res.method}: damage after {res.meta.get('sla_steps_done', '?')} SLA steps")
    _figure(ax).colorbar(sc, ax=ax, label=units.label("damage index", "1"))
    return _figure(ax)


def save_damage_plot(res: Result, path: str | Path, **kwargs: Any) -> Path:
    """:func:`plot_damage` into a new figure saved to ``path``."""
    return _save(plot_damage(res, **kwargs), path)


def plot_tip_deformation(
    res: Result, *, scale: float = 50.0, ax: Axes | None = None, units: Units = DEFAULT_UNITS
) -> Figure:
    """XFEM: the deformed cells near the crack tip magnified ``scale`` times (Fig. 8b; from
    ``fields["deformed_cells"]`` and ``fields["deformed_disp"]``, the enriched displacement
    evaluated inside each cell, so the crack opens as a gap) over the initial crack line."""
    cells = res.fields.get("deformed_cells")
    disp = res.fields.get("deformed_disp")
    if cells is None or disp is None:
        raise PlotDataError(f"{res.method} result has no deformed tip patch (XFEM results only)")
    ax = _new_axes(ax, (6, 6))
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
    _xy_labels(ax, units)
    ax.set_title(f"deformed mesh near the tip (displacements x {scale:g})")
    return _figure(ax)
