"""The paper's figures, drawn from run results (matplotlib, no pyplot state, headless).

- :func:`plot_fig7`: CMOD against sigma22 for XFEM and CCM-PD on one plot (paper Fig. 7), each
  curve from the origin (its linear loading branch), plus the LEFM handbook curve labelled as such;
- :func:`plot_damage`: the damage map of the PD nodes (Fig. 8a);
- :func:`plot_deformed_patches`: the XFEM deformed mesh near the tip, magnified (Fig. 8b);
- :func:`plot_discretisations`: both discretisations near the tip (Fig. 6b, 6c).

Every ``save_*`` writes atomically (temporary file, then rename).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import matplotlib as mpl
import numpy as np
from matplotlib.axes import Axes
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.collections import PolyCollection
from matplotlib.figure import Figure
from matplotlib.image import imsave
from matplotlib.patches import Rectangle

from ._folder import atomic_file
from .plotting import PAPER_UNITS
from .result import result_entry

__all__ = [
    "Curve",
    "Rendered",
    "plot_damage",
    "plot_deformed_patches",
    "plot_discretisations",
    "plot_fig7",
    "render",
    "save_figure",
]

#: (label, cmod array, sigma22 array, matplotlib style dict)
Curve = tuple[str, np.ndarray, np.ndarray, dict[str, Any]]


#: zlib level of the PNGs: 1, the fastest (Pillow's default 6 takes 1.7x as long for files
#: 10 % smaller: 0.14 s against 0.085 s for the four PNGs of a fig7 job)
PNG_LEVEL = 1


def _paper_label(name: str, group: str, key: str) -> str:
    """The axis label ``name [unit]`` in the paper's units (N, mm, MPa), the quantity's unit
    that of the result key ``key`` of ``group`` in the result schema."""
    e = result_entry(group, key)
    assert e is not None, key  # a key of the core's table
    return PAPER_UNITS.label(name, e["unit"])


#: the axis labels of the paper's figures
_CMOD, _SIGMA22 = _paper_label("CMOD", "history", "cmod"), _paper_label("σ₂₂", "history", "sigma22")
_X1, _X2 = (_paper_label(n, "fields", "coords") for n in ("x1", "x2"))


@dataclass(frozen=True)
class Rendered:
    """A figure drawn ahead of its file (:func:`render`): its pixels cropped to its ink, or None
    when its ink leaves the canvas (then ``savefig(bbox_inches="tight")`` draws it again)."""

    fig: Figure
    dpi: int
    rgba: np.ndarray | None


def render(fig: Figure, dpi: int = 150) -> Rendered:
    """Draws a figure (Agg) now, for :func:`save_figure` to write later: e.g. while a run still
    computes (the core releases the GIL), so the drawing costs no wall time."""
    return Rendered(fig, dpi, _drawn_tight(fig, dpi))


def save_figure(fig: Figure | Rendered, path: str | Path, dpi: int = 150) -> Path:
    """Saves a figure (or one :func:`render` drew, at its own dpi) as PNG atomically, cropped
    to its ink (``bbox_inches="tight"``).

    Drawn once: ``savefig(bbox_inches="tight")`` lays the figure out twice (once to measure, once
    to draw), a third of a figure's time. Here the figure is drawn on its canvas, its tight box
    measured from that drawing and the pixels cropped to it (the padding
    ``savefig.pad_inches``, cut at the canvas's edge). A figure with ink outside its canvas
    (which only a larger canvas shows) goes through ``savefig(bbox_inches="tight")``."""
    p = Path(path)
    r = fig if isinstance(fig, Rendered) else render(fig, dpi)
    with atomic_file(p, "wb") as f:
        if r.rgba is None:
            r.fig.savefig(f, format="png", dpi=r.dpi, bbox_inches="tight")
        else:
            meta = {"Software": f"Matplotlib version{mpl.__version__}, https://matplotlib.org/"}
            imsave(
                f, r.rgba, format="png", origin="upper", dpi=r.dpi, metadata=meta,
                pil_kwargs={"compress_level": PNG_LEVEL},
            )  # fmt: skip
    return p


def _drawn_tight(fig: Figure, dpi: int) -> np.ndarray | None:
    """The figure drawn at ``dpi`` (Agg) and cropped to its padded tight box, as RGBA rows from
    the top; None when its tight box leaves the canvas."""
    old_canvas, old_dpi = fig.canvas, fig.dpi
    try:
        canvas = FigureCanvasAgg(fig)
        fig.dpi = dpi
        canvas.draw()
        renderer = canvas.get_renderer()
        ink = fig.get_tightbbox(renderer)
        rows = np.asarray(canvas.buffer_rgba())
    finally:
        fig.dpi = old_dpi
        fig.set_canvas(old_canvas)
    h, w = rows.shape[:2]
    x0, x1, y0, y1 = ink.x0 * dpi, ink.x1 * dpi, h - ink.y1 * dpi, h - ink.y0 * dpi
    if x0 < -0.5 or y0 < -0.5 or x1 > w + 0.5 or y1 > h + 0.5:
        return None
    pad = mpl.rcParams["savefig.pad_inches"] * dpi
    c0, c1 = max(int(np.floor(x0 - pad)), 0), min(int(np.ceil(x1 + pad)), w)
    r0, r1 = max(int(np.floor(y0 - pad)), 0), min(int(np.ceil(y1 + pad)), h)
    return rows[r0:r1, c0:c1]


def plot_fig7(
    curves: Sequence[Curve],
    *,
    title: str = "",
    published: Sequence[tuple[str, float, float]] = (),
    agreement: Mapping[str, tuple[np.ndarray, np.ndarray]] | None = None,
    x_max: float | None = None,
) -> Figure:
    """CMOD (x) against sigma22 (y) for each curve; ``published`` marks single (label, cmod,
    sigma22) points such as the paper's initial values. ``agreement`` (reading -> (cmod,
    relative difference), :func:`rustfrac.agreement.compare`'s ``curves``) adds a panel below:
    the PD readings against the XFEM curve at the same CMOD, in percent; each reading is drawn
    as points (a reading along the SLA steps goes back and forth in CMOD, so a line through them
    would zigzag). ``x_max``: the right end of the CMOD axis (None: every curve whole), e.g. to
    let a reference curve run beyond the computed ones."""
    fig = Figure(figsize=(7.0, 7.0 if agreement else 5.0))
    if agreement:
        ax, bx = fig.subplots(2, 1, sharex=True, gridspec_kw={"height_ratios": [3, 1.3]})
        for (name, (c, rel)), style in zip(
            agreement.items(),
            ({"marker": "^", "ms": 3}, {"marker": "v", "ms": 3}, {"marker": ".", "ms": 2}),
        ):
            bx.plot(c, 100 * np.asarray(rel), label=name.replace("_", " "), ls="none", **style)
        bx.axhline(0.0, color="0.4", lw=0.6)
        bx.set_xlabel(_CMOD)
        bx.set_ylabel("CCM-PD / XFEM - 1 [%]", fontsize=8)
        bx.grid(alpha=0.3)
        bx.legend(fontsize=7)
    else:
        ax = fig.add_subplot()
    for label, cmod, sigma, style in curves:
        ax.plot(cmod, sigma, label=label, **style)
    for label, c, s in published:
        ax.plot([c], [s], "k*", ms=9, label=label)
    if not agreement:
        ax.set_xlabel(_CMOD)
    # plain text, not mathtext: the mathtext parser costs 0.13 s at its first use
    ax.set_ylabel(_SIGMA22)
    ax.set_xlim(left=0, right=x_max)
    ax.set_ylim(bottom=0)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    if title:
        ax.set_title(title, fontsize=10)
    return fig


def plot_damage(
    xy: np.ndarray, damage: np.ndarray, dx: float, *, title: str = "", crack_y: float | None = None
) -> Figure:
    """Damage index (eq. 53) of the PD nodes as dx-sized squares coloured from 0 to 1."""
    fig = Figure(figsize=(7.0, 4.2))
    ax = fig.add_subplot()
    h = dx / 2
    polys = np.stack(
        [
            np.column_stack([xy[:, 0] - h, xy[:, 1] - h]),
            np.column_stack([xy[:, 0] + h, xy[:, 1] - h]),
            np.column_stack([xy[:, 0] + h, xy[:, 1] + h]),
            np.column_stack([xy[:, 0] - h, xy[:, 1] + h]),
        ],
        axis=1,
    )
    pc = PolyCollection(polys, array=damage, cmap="jet", edgecolors="none")
    pc.set_clim(0.0, 1.0)
    ax.add_collection(pc)
    ax.autoscale_view()
    ax.set_aspect("equal")
    if crack_y is not None:
        ax.axhline(crack_y, color="w", lw=0.6, ls=":")
    fig.colorbar(pc, ax=ax, label="damage index", shrink=0.8)
    ax.set_xlabel(_X1)
    ax.set_ylabel(_X2)
    if title:
        ax.set_title(title, fontsize=10)
    return fig


def _patch_axes(ax: Axes, cells: np.ndarray, disp: np.ndarray, scale: float, title: str) -> None:
    ax.add_collection(PolyCollection(cells, facecolors="none", edgecolors="0.75", linewidths=0.4))
    ax.add_collection(
        PolyCollection(cells + scale * disp, facecolors="none", edgecolors="C0", linewidths=0.6)
    )
    ax.autoscale_view()
    ax.set_aspect("equal")
    ax.set_title(title, fontsize=9)
    ax.set_xlabel(_X1)


def plot_deformed_patches(
    patches: Sequence[tuple[np.ndarray, np.ndarray, str]], *, scale: float = 50.0
) -> Figure:
    """Undeformed (grey) and deformed (blue, displacements x ``scale``) cells near the tip, one
    panel per (cells (c,4,2), displacements (c,4,2), title)."""
    fig = Figure(figsize=(4.0 * len(patches), 4.0))
    for i, (cells, disp, title) in enumerate(patches):
        ax = fig.add_subplot(1, len(patches), i + 1)
        _patch_axes(ax, np.asarray(cells), np.asarray(disp), scale, title)
        if i == 0:
            ax.set_ylabel(_X2)
    fig.suptitle(f"XFEM deformed mesh near the tip (displacements x{scale:g})", fontsize=10)
    return fig


def plot_discretisations(
    xfem: dict[str, np.ndarray],
    pd: dict[str, np.ndarray],
    window: tuple[float, float, float, float],
) -> Figure:
    """Fig. 6 (b, c): the XFEM mesh with its enriched nodes and the crack, and the CCM-PD grid with
    PD nodes, FEM and hybrid elements, in ``window`` = (x0, x1, y0, y1).

    ``xfem``: coords (n,2), elements (m,4), heaviside_nodes, tip_nodes, crack (k,2).
    ``pd``: node_xy (N,2) of the structured grid, is_pd (N,) bool, elements (M,4) of the grid,
    removed (M,) bool, crack (k,2)."""
    x0, x1, y0, y1 = window
    tol = 1e-9 * max(x1 - x0, y1 - y0)  # relative to the window: the plots are unit-agnostic
    fig = Figure(figsize=(11.0, 4.8))

    ax = fig.add_subplot(1, 2, 1)
    xy, el = xfem["coords"], xfem["elements"]
    cells = xy[el]
    inside = _cells_inside(cells, (x0, y0, x1, y1), tol)
    hv = np.zeros(len(xy), bool)
    hv[np.asarray(xfem["heaviside_nodes"], int)] = True
    tp = np.zeros(len(xy), bool)
    tp[np.asarray(xfem["tip_nodes"], int)] = True
    enriched = (hv | tp)[el]
    el_tip = tp[el].all(axis=1)  # the element holding the tip
    el_split = enriched.all(axis=1) & ~el_tip  # cut through by the crack
    el_blend = enriched.any(axis=1) & ~enriched.all(axis=1)  # partly enriched (blending)
    colours = np.where(
        el_tip, "#ffb347", np.where(el_split, "#a6d8ff", np.where(el_blend, "#eeeeee", "none"))
    )
    ax.add_collection(
        PolyCollection(cells[inside], facecolors=colours[inside], edgecolors="0.5", linewidths=0.5)
    )
    sel = (xy[:, 0] >= x0) & (xy[:, 0] <= x1) & (xy[:, 1] >= y0) & (xy[:, 1] <= y1)
    ax.plot(*xy[sel & hv].T, "s", ms=4, mfc="none", mec="C0", label="Heaviside nodes")
    ax.plot(*xy[sel & tp].T, "o", ms=5, mfc="C3", mec="C3", label="crack-tip nodes")
    c = np.asarray(xfem["crack"])
    ax.plot(c[:, 0], c[:, 1], "k-", lw=1.5, label="crack")
    _finish_panel(
        ax, (x0, y0, x1, y1), "XFEM: split (blue), tip (orange) and blending (grey) elements"
    )

    ax = fig.add_subplot(1, 2, 2)
    nxy, is_pd, gel = pd["node_xy"], np.asarray(pd["is_pd"], bool), pd["elements"]
    removed = np.asarray(pd.get("removed", np.zeros(len(gel), bool)), bool)
    gcells = nxy[gel]
    ginside = _cells_inside(gcells, (x0, y0, x1, y1), tol)
    npd = is_pd[gel].sum(axis=1)
    fem_el = (npd < 4) & ~removed
    hybrid = fem_el & (npd > 0)
    for mask, fc, ec, lab in (
        (fem_el & ~hybrid & ginside, "none", "#5fa8d3", "FEM elements"),
        (hybrid & ginside, "#fff3a0", "#c9a800", "hybrid elements"),
    ):
        ax.add_collection(
            PolyCollection(gcells[mask], facecolors=fc, edgecolors=ec, linewidths=0.5, label=lab)
        )
    sel = (nxy[:, 0] >= x0) & (nxy[:, 0] <= x1) & (nxy[:, 1] >= y0) & (nxy[:, 1] <= y1)
    ax.plot(*nxy[sel & is_pd].T, "o", ms=2.5, mfc="#2ca02c", mec="none", label="PD nodes")
    c = np.asarray(pd["crack"])
    ax.plot(c[:, 0], c[:, 1], "k-", lw=1.5, label="pre-crack")
    ax.add_patch(Rectangle((x0, y0), x1 - x0, y1 - y0, fill=False, lw=0))
    _finish_panel(ax, (x0, y0, x1, y1), "CCM-PD: PD nodes, FEM and hybrid elements")
    return fig


def grid_elements(nx: int, ny: int) -> np.ndarray:
    """Q4 connectivity of a structured (nx x ny cells) grid numbered row by row from (0, 0)."""
    i, j = np.meshgrid(np.arange(nx), np.arange(ny))
    n0 = (j * (nx + 1) + i).ravel()
    return np.column_stack([n0, n0 + 1, n0 + nx + 2, n0 + nx + 1])


def _cells_inside(
    cells: np.ndarray, box: tuple[float, float, float, float], tol: float
) -> np.ndarray:
    """Which cells (n, 4, 2 corner coordinates) lie inside the box (x0, y0, x1, y1), within tol."""
    x0, y0, x1, y1 = box
    x, y = cells[:, :, 0], cells[:, :, 1]
    return np.all((x >= x0 - tol) & (x <= x1 + tol) & (y >= y0 - tol) & (y <= y1 + tol), axis=1)


def _finish_panel(ax: Axes, box: tuple[float, float, float, float], title: str) -> None:
    """Limits (the box), equal aspect, title, legend and axis labels of a discretisation panel."""
    x0, y0, x1, y1 = box
    ax.set_xlim(x0, x1)
    ax.set_ylim(y0, y1)
    ax.set_aspect("equal")
    ax.set_title(title, fontsize=9)
    ax.legend(fontsize=7, loc="upper right")
    ax.set_xlabel(_X1)
    ax.set_ylabel(_X2)
