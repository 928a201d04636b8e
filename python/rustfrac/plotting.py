"""Plots of one result, for notebooks and scripts (``rf.plotting``).

Every ``plot_*`` function returns a :class:`matplotlib.figure.Figure` (a
:class:`NotebookFigure`, which Jupyter shows inline as a cell's value, pyplot or not); ``ax=``
draws into existing axes instead (the returned figure is then theirs). Figures are built with ``matplotlib.figure`` (no pyplot state), so they also work
headless. Axis labels carry units: rustfrac is unit-agnostic (any consistent set), so the labels
say "length" and "force/length^2" unless a :class:`Units` names them (``units=PAPER_UNITS``:
the paper's N, mm and MPa).

- :func:`plot_field`: the deformed mesh (FEM; XFEM with its cut cells, of the single solve or of
  any kept growth state) or grid nodes (PD, CCM-PD) coloured by a stress (s11, s22, s12, von
  Mises) or displacement component;
- :func:`plot_crack_path`: the plate with its holes, notches, supports and loads (as the scene
  lays them out), the initial crack(s) and the crack path of any method (XFEM polylines, the PD
  damage ridge, the FEM seam);
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
from matplotlib.patches import Circle, FancyArrow, Polygon, Rectangle

from . import _vtk
from .errors import InvalidParameterError, PlotDataError
from .result import Result, result_entry
from .scene import Scene

__all__ = [
    "COMPONENTS",
    "DEFAULT_UNITS",
    "PAPER_UNITS",
    "NotebookFigure",
    "Units",
    "damage_ridge",
    "draw_layout",
    "field_components",
    "history_quantity",
    "plot_crack_path",
    "plot_damage",
    "plot_field",
    "plot_load_path",
    "plot_tip_deformation",
    "save_damage_plot",
    "save_plot",
    "von_mises",
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

#: field components of :func:`plot_field`: name -> what it is (its unit is that of the result
#: field it is read from, in the result schema)
COMPONENTS: dict[str, str] = {
    "s11": "stress s11",
    "s22": "stress s22",
    "s12": "shear stress s12",
    "von_mises": "von Mises equivalent stress",
    "u1": "displacement u1",
    "u2": "displacement u2",
}
_STRESS_COLUMN = {"s11": 0, "s22": 1, "s12": 2}
_STRESSES = (*_STRESS_COLUMN, "von_mises")

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


def von_mises(stress: Any, nu: float, plane: str) -> np.ndarray:
    """The von Mises equivalent stress of in-plane stresses ``stress`` (k, 3) [s11, s22, s12]:
    sqrt(((s11 - s22)^2 + (s22 - s33)^2 + (s33 - s11)^2) / 2 + 3 s12^2), with s33 = nu (s11 +
    s22) in plane strain and s33 = 0 in plane stress (``plane`` "strain" | "stress")."""
    s = np.asarray(stress, dtype=float).reshape(-1, 3)
    if plane not in ("strain", "stress"):
        raise InvalidParameterError(
            f"invalid plane: expected 'strain' or 'stress', got {plane!r}", "plane"
        )
    s11, s22, s12 = s[:, 0], s[:, 1], s[:, 2]
    s33 = nu * (s11 + s22) if plane == "strain" else np.zeros_like(s11)
    return np.sqrt(0.5 * ((s11 - s22) ** 2 + (s22 - s33) ** 2 + (s33 - s11) ** 2) + 3 * s12**2)


def field_components(res: Result) -> list[str]:
    """The components :func:`plot_field` can draw for ``res``: s11, s22, s12 and von_mises where
    the result has stresses (FEM: nodal stresses; XFEM: the element and cut-cell stresses),
    u1, u2 where it has nodal displacements (every method)."""
    out = []
    xfem = _is_xfem(res)
    if "nodal_stress" in res.fields or (xfem and "gauss_stress" in res.fields):
        out += list(_STRESSES)
    if "u" in res.fields:
        out += ["u1", "u2"]
    return out


def _is_xfem(res: Result) -> bool:
    return "coords" in res.fields and "cut_offsets" in res.fields


def _checked_component(res: Result, component: str | None) -> str:
    """``component`` (None: s22, or u2 without stresses), refused when unknown or absent."""
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
            f"{'stresses' if component in _STRESSES else 'displacements'}); valid for "
            f"it: {', '.join(valid) or 'none'}",
            "component",
        )
    return component


def _material(res: Result) -> tuple[float, str]:
    """(nu, plane) of the scene that ran (``meta["scene"]``), for the von Mises stress."""
    scene = res.meta.get("scene")
    if not isinstance(scene, Mapping):
        raise PlotDataError(
            f"{res.method} result without its scene (meta['scene']): nu and the plane of the "
            "von Mises stress are unknown"
        )
    m = Scene.from_dict(dict(scene)).material
    return float(m.nu), str(m.plane)


def _stress_values(res: Result, component: str, stress: np.ndarray) -> np.ndarray:
    if component == "von_mises":
        return von_mises(stress, *_material(res))
    return stress[:, _STRESS_COLUMN[component]]


def _quantity(res: Result, field: str) -> str:
    """The quantity kind of a result field, from its unit in the result schema."""
    return _UNIT_QUANTITY.get(res.unit(field, "fields") or "", "1")


def _xfem_state(res: Result, state: int | None) -> _vtk.XfemState:
    """The XFEM state ``state`` (a history row of a kept growth state, see
    ``fields["state_rows"]``; None: the last kept state, else the single solve)."""
    states = _vtk.xfem_states(res)
    if state is None:
        return states[-1] if states else _vtk.initial_state(res)
    rows = [st.row for st in states]
    if states and state == 0 and rows[0] == 1:
        return states[0].unloaded()
    if state not in rows:
        raise InvalidParameterError(
            f"invalid state: expected the history row of a kept growth state "
            f"({', '.join(map(str, rows)) or 'none: a single solve, or xfem.state_every = 0'}), "
            f"got {state!r}",
            "state",
        )
    return states[rows.index(state)]


def _xfem_cells(
    res: Result, component: str, state: int | None
) -> tuple[list[np.ndarray], list[np.ndarray], np.ndarray, list[np.ndarray], str, _vtk.XfemState]:
    """An XFEM state's cells for :func:`plot_field`: (cell polygons (reference), their
    displacements, their values, the crack lines, the unit field, the state)."""
    st = _xfem_state(res, state)
    points, blocks, pdata, cdata, _ = _vtk.xfem_parts(res, st)
    disp = pdata["displacement"][:, :2]
    xy = points[:, :2]
    polys, vals, shift, lines = [], [], [], []
    for (ctype, conn), stress in zip(blocks, cdata.get("stress", [None] * len(blocks))):
        if ctype == "line":
            lines += [xy[seg] for seg in conn]
            continue
        if component in _STRESSES:
            if stress is None:
                raise PlotDataError(f"{res.method} result has no stresses of this state")
            vals.append(_stress_values(res, component, stress))
        else:
            vals.append(disp[conn, 0 if component == "u1" else 1].mean(axis=1))
        polys += list(xy[conn])
        shift += list(disp[conn])
    field = ("state_stress" if st.row else "gauss_stress") if component in _STRESSES else "u"
    return polys, shift, np.concatenate(vals), lines, field, st


def plot_field(
    res: Result,
    component: str | None = None,
    *,
    state: int | None = None,
    scale: float | None = None,
    ax: Axes | None = None,
    cmap: str = "viridis",
    units: Units = DEFAULT_UNITS,
) -> Figure:
    """The deformed mesh (FEM; XFEM with its cut cells, each crack face with its own
    displacement and stress) or the deformed grid nodes (PD, CCM-PD: one dot per node,
    displacements at the reference load) coloured by a component.

    FEM colours each element by the mean of its nodal values. XFEM draws what ``result.vtu``
    holds (``rustfrac._vtk``): the standard elements coloured by their element stress (the mean
    of their Gauss-point stresses) and the cut cells by the stress of their own side, the
    cracks as red lines; by default of the last kept growth state (a single solve: the
    reference load), ``state=`` another history row of a kept state (``fields["state_rows"]``;
    0: the unloaded origin).

    Args:
        component: "s11" | "s22" | "s12" | "von_mises" (FEM, XFEM; von Mises with s33 of the
            scene's plane, :func:`von_mises`) or "u1" | "u2" (every method); default "s22", or
            "u2" for results without stresses (PD, CCM-PD). A component the result lacks raises
            :class:`~rustfrac.errors.InvalidParameterError` listing the valid ones
            (:func:`field_components`).
        state: XFEM growth runs: the history row of the state to draw (default: the last).
        scale: displacement magnification; default: max displacement = 2 % of the plate size.
        ax: axes to draw in; default: a new figure.
        units: unit names of the labels.
    """
    component = _checked_component(res, component)
    if state is not None and not _is_xfem(res):
        raise InvalidParameterError(
            f"invalid state: only XFEM growth results have states, not {res.method}", "state"
        )
    ax = _new_axes(ax, (5, 8))
    if _is_xfem(res):
        polys, shift, values, lines, field, st = _xfem_cells(res, component, state)
        xy = np.asarray(res.coords, dtype=float)
        umax = max((float(np.abs(d).max()) for d in shift), default=0.0)
        size = float(np.ptp(xy, axis=0).max())
        if scale is None:
            scale = 0.02 * size / umax if umax > 0 else 1.0
        cells = [p + scale * d for p, d in zip(polys, shift)]
        art: Any = PolyCollection(cells, array=values, cmap=cmap, edgecolors="k", linewidths=0.05)
        ax.add_collection(art)
        for seg in lines:
            ax.plot(seg[:, 0], seg[:, 1], "-", color="C3", lw=1.0)
        ax.autoscale_view()
        where = f", row {st.row}" if st.row or _vtk.xfem_states(res) else ""
    else:
        if component in _STRESSES:
            values = _stress_values(res, component, np.asarray(res.fields["nodal_stress"]))
            field = "nodal_stress"
        else:
            values, field = res.displacement[:, 0 if component == "u1" else 1], "u"
        xy, el = _nodes(res)
        u = res.displacement
        size = float(np.ptp(xy, axis=0).max())
        umax = float(np.abs(u).max()) if u.size else 0.0
        if scale is None:
            scale = 0.02 * size / umax if umax > 0 else 1.0
        xyd = xy + scale * u
        if el is not None:
            art = PolyCollection(
                xyd[el], array=values[el].mean(axis=1), cmap=cmap, edgecolors="k", linewidths=0.1
            )
            ax.add_collection(art)
            ax.autoscale_view()
        else:
            art = ax.scatter(xyd[:, 0], xyd[:, 1], c=values, s=2, cmap=cmap, linewidths=0)
        where = ""
    ax.set_aspect("equal")
    _xy_labels(ax, units)
    ax.set_title(f"{res.method}: {component}{where} (displacements x {scale:.3g})")
    _figure(ax).colorbar(art, ax=ax, label=units.label(component, _quantity(res, field)))
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


def _scene_of(res: Result) -> Scene | None:
    scene = res.meta.get("scene")
    return Scene.from_dict(dict(scene)) if isinstance(scene, Mapping) else None


def _edge(side: str, lo: float, hi: float, w: float, h: float) -> np.ndarray:
    """The segment of side ``side`` from ``lo`` to ``hi`` along it (x1 on bottom / top, x2 on
    left / right)."""
    if side in ("bottom", "top"):
        y = 0.0 if side == "bottom" else h
        return np.array([[lo, y], [hi, y]])
    x = 0.0 if side == "left" else w
    return np.array([[x, lo], [x, hi]])


def _region_line(r: Any, w: float, h: float) -> np.ndarray | None:
    """An edge or edge-part region's segment, None for points and boxes."""
    if r.region == "edge":
        return _edge(r.side, 0.0, w if r.side in ("bottom", "top") else h, w, h)
    if r.region == "edge_part":
        return _edge(r.side, r.from_, r.to, w, h)
    return None


#: length of a load arrow of :func:`draw_layout`, a fraction of the plate's larger side
ARROW = 0.05


def _draw_layout(ax: Axes, res: Result, w: float, h: float) -> None:
    """The scene's holes, notches, supports and loads (``meta["scene"]``), if it has them."""
    scene = _scene_of(res)
    if scene is not None:
        draw_layout(ax, scene, w, h)


def draw_layout(ax: Axes, scene: Scene, w: float, h: float) -> None:
    """Draws the holes (circles, rectangles, polygons) and notches (slots of ``width`` x
    ``depth`` cut from their side at ``at``) of ``scene`` in grey, its supports in green
    (a point support as a triangle, an edge, edge part or box as a thick line or box) and its
    loads on regions in blue (a point force as an arrow, an edge load as a thick line with an
    arrow of its traction's direction), on a plate ``w`` x ``h``, in the scene's coordinates."""
    grey = {"fc": "0.85", "ec": "0.3", "lw": 0.6}
    for k, hole in enumerate(scene.holes):
        label = "hole / notch" if k == 0 else None
        if hole.shape == "circle":
            ax.add_patch(Circle(tuple(hole.center), hole.radius, label=label, **grey))
        elif hole.shape == "rect":
            (x0, y0), (x1, y1) = hole.min, hole.max
            ax.add_patch(Rectangle((x0, y0), x1 - x0, y1 - y0, label=label, **grey))
        else:
            ax.add_patch(Polygon(np.asarray(hole.points, dtype=float), label=label, **grey))
    for k, n in enumerate(scene.notches):
        label = "hole / notch" if k == 0 and not scene.holes else None
        lo, d = n.at - 0.5 * n.width, n.depth
        x0, y0, dx, dy = {
            "bottom": (lo, 0.0, n.width, d),
            "top": (lo, h - d, n.width, d),
            "left": (0.0, lo, d, n.width),
            "right": (w - d, lo, d, n.width),
        }[n.side]
        ax.add_patch(Rectangle((x0, y0), dx, dy, label=label, **grey))
    size = max(w, h)
    for k, sup in enumerate(scene.supports):
        label = "support" if k == 0 else None
        line = _region_line(sup, w, h)
        if line is not None:
            ax.plot(line[:, 0], line[:, 1], "-", color="C2", lw=3.0, label=label)
        elif sup.region == "point":
            ax.plot(*sup.point, "^", color="C2", ms=8, label=label)
        elif len(sup.box) == 4:
            x0, y0, x1, y1 = sup.box
            ax.add_patch(
                Rectangle((x0, y0), x1 - x0, y1 - y0, fill=False, ec="C2", lw=1.5, label=label)
            )
    for k, load in enumerate(scene.loads):
        label = "load" if k == 0 else None
        line = _region_line(load, w, h)
        if line is not None:
            ax.plot(line[:, 0], line[:, 1], "-", color="C0", lw=3.0, label=label)
            t = line[1] - line[0]
            t = t / (np.linalg.norm(t) or 1.0)
            outward = {"bottom": (0, -1), "top": (0, 1), "left": (-1, 0), "right": (1, 0)}
            f = load.normal * np.asarray(outward[load.side], dtype=float) + load.shear * t
            at = line.mean(axis=0)
        else:
            f, at = np.asarray(load.force, dtype=float), np.asarray(load.point, dtype=float)
            ax.plot(*at, "o", color="C0", ms=4, label=label)
        norm = float(np.linalg.norm(f))
        if norm > 0:
            d = ARROW * size * f / norm
            ax.add_patch(
                FancyArrow(*(at - d), *d, width=0.005 * size, length_includes_head=True, color="C0")
            )


def plot_crack_path(
    res: Result,
    *,
    ax: Axes | None = None,
    threshold: float = 0.25,
    units: Units = DEFAULT_UNITS,
) -> Figure:
    """The plate outline with the scene's holes and notches (grey), supports (green triangles:
    points; green lines: edges, edge parts and boxes) and loads on regions (blue arrows and
    lines), in the scene's own coordinates (:func:`draw_layout`), the initial crack(s) (dashed)
    and the crack path of the result: XFEM's final crack polylines (:attr:`Result.crack_polylines`), the damage ridge of PD / CCM-PD
    (:func:`damage_ridge`, ``threshold`` its damage index) with the CCM-PD rectangle, the seam of
    FEM (which does not grow)."""
    w, h = _plate(res)
    ax = _new_axes(ax, (5, 8))
    ax.add_patch(Rectangle((0.0, 0.0), w, h, fill=False, ec="k", lw=1.0, label="plate"))
    _draw_layout(ax, res, w, h)
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
    pad = (ARROW + 0.01) * max(w, h)  # room for the load arrows outside the plate
    ax.set_xlim(-pad, w + pad)
    ax.set_ylim(-pad, h + pad)
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
