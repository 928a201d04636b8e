"""The figures and CSV files of a comparison (:mod:`rustfrac.compare`): ``compare.png`` (the
paths and the PD damage), ``curves.png`` / ``curves.csv`` (the load-response curves) and
``path.csv`` (the PD ridge along the XFEM path)."""

from __future__ import annotations

from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Any

import numpy as np
from matplotlib.collections import PolyCollection
from matplotlib.figure import Figure
from matplotlib.patches import Circle, Polygon, Rectangle

from .. import figures, paths, study
from ..result import Result
from ..scene import Scene
from .plan import Plan
from .ridge import LABELS, grown_path
from .summary import ridge_of

__all__ = ["curves_csv", "curves_figure", "draw_holes", "drawings", "path_csv", "paths_figure"]


def drawings(
    p: Plan, scenes: dict[str, Scene], results: dict[str, Result], s: dict[str, Any]
) -> list[tuple[str, Callable[[Path], Any]]]:
    """(file name, writer into a path) of every file the runs ``results`` give (``s``: their
    summary)."""
    out: list[tuple[str, Callable[[Path], Any]]] = []
    if not results:
        return out
    _, ridge, mid = ridge_of(p, results)
    out.append(
        (
            "compare.png",
            lambda f: figures.save_figure(paths_figure(p, scenes, results, ridge, mid, s), f),
        )
    )
    if "curves" in s:
        out.append(("curves.png", lambda f: figures.save_figure(curves_figure(p, results, s), f)))
        out.append(("curves.csv", lambda f: study.write_text(f, curves_csv(results, s))))
    if ridge is not None:
        out.append(("path.csv", lambda f: study.write_text(f, path_csv(ridge, results["xfem"]))))
    return out


def curves_csv(results: dict[str, Result], s: dict[str, Any]) -> str:
    xk, yk = s["curves"]["x"], s["curves"]["y"]
    rows = (
        [k, i, float(a), float(b)]
        for k in results
        for i, (a, b) in enumerate(zip(results[k].history[xk], results[k].history[yk]))
    )
    return study.csv_text(["method", "point", xk, yk], rows)


def curves_figure(p: Plan, results: dict[str, Result], s: dict[str, Any]) -> Figure:
    xk, yk = s["curves"]["x"], s["curves"]["y"]
    xh, ph = results["xfem"].history, results["ccm_pd"].history
    fig = Figure(figsize=(7.0, 5.0))
    ax = fig.add_subplot()
    ax.plot(xh[xk], xh[yk], ".-", ms=4, label="XFEM (LEFM growth, critical states)")
    ax.plot(
        ph[xk], ph[yk], ".-", lw=0.4, ms=2.5, alpha=0.7, color="C1",
        label="CCM-PD (SLA, one point per bond break)",
    )  # fmt: skip
    ax.set_xlabel(LABELS.get(xk, xk))
    ax.set_ylabel(LABELS.get(yk, yk))
    ag = s["curves"].get("peak")
    title = p.source.name or "scene"
    if ag and ag.get("rel_diff") is not None:
        title += f"\npeak: CCM-PD / XFEM - 1 = {ag['rel_diff']:+.1%}"
    ax.set_title(title, fontsize=10)
    ax.legend(fontsize=8)
    ax.set_xlim(left=0.0)
    ax.set_ylim(bottom=0.0)
    return fig


def paths_figure(
    p: Plan,
    scenes: dict[str, Scene],
    results: dict[str, Result],
    ridge: paths.Ridge | None,
    mid: np.ndarray,
    s: dict[str, Any],
) -> Figure:
    """compare.png: the plate with the paths, the PD region zoomed with the damage, and the
    ridge's distance to the XFEM path along it."""
    res = results
    w, hgt = p.source.plate.width, p.source.plate.height
    fig = Figure(figsize=(15.0, 6.0), layout="constrained")
    ax, zx, dx_ax = fig.subplots(1, 3, gridspec_kw={"width_ratios": [1, 1.3, 1.2]})
    pr = res.get("ccm_pd")
    boxes = []
    if pr is not None and isinstance(pr.meta.get("pd_regions"), list):
        boxes = pr.meta["pd_regions"]  # several for an adaptive region
    for a, zoom in ((ax, False), (zx, True)):
        a.add_patch(Rectangle((0, 0), w, hgt, fill=False, ec="k", lw=1.0))
        draw_holes(a, scenes["xfem"].to_dict(), w, hgt)
        for k, box in enumerate(boxes):
            a.add_patch(
                Rectangle(
                    (box[0], box[1]), box[2] - box[0], box[3] - box[1], fill=False,
                    ec="#2ca02c", lw=0.8, ls="-.", label="PD region" if k == 0 else None,
                )
            )  # fmt: skip
        if pr is not None:
            xy = np.asarray(pr.fields["pd_node_xy"], dtype=float)
            dmg = np.asarray(pr.damage, dtype=float)
            on = dmg > 0 if not zoom else np.ones(len(dmg), bool)
            hd = p.dx / 2
            sq = np.stack(
                [
                    xy[on] + [-hd, -hd],
                    xy[on] + [hd, -hd],
                    xy[on] + [hd, hd],
                    xy[on] + [-hd, hd],
                ],
                axis=1,
            )
            pc = PolyCollection(sq, array=dmg[on], cmap="viridis", edgecolors="none")
            pc.set_clim(0.0, 1.0)
            a.add_collection(pc)
            pre = np.asarray(pr.meta.get("precrack", []), dtype=float)
            if len(pre):
                a.plot(pre[:, 0], pre[:, 1], "--", color="0.6", lw=1.6, label="PD pre-crack")
            if zoom:
                fig.colorbar(pc, ax=a, label="PD damage index", shrink=0.8)
                if len(mid):
                    a.plot(
                        mid[:, 0],
                        mid[:, 1],
                        ".",
                        color="w",
                        ms=1.2,
                        alpha=0.8,
                        label="bonds the SLA broke (midpoints)",
                    )
        if "xfem" in res:
            x0 = np.asarray(res["xfem"].meta.get("crack_initial", []), dtype=float)
            if len(x0):
                a.plot(x0[:, 0], x0[:, 1], ":", color="k", lw=1.2, label="XFEM initial crack")
            line = np.asarray(res["xfem"].crack_polylines[0], dtype=float)
            a.plot(line[:, 0], line[:, 1], "-", color="C3", lw=1.6, label="XFEM path")
        if ridge is not None:
            rp = ridge.points()
            a.plot(rp[:, 0], rp[:, 1], "-", color="C1", lw=1.4, label="PD ridge")
        a.set_aspect("equal")
        a.set_xlabel("x1")
        a.set_ylabel("x2")
        if zoom and boxes:
            a.set_xlim(min(b[0] for b in boxes), max(b[2] for b in boxes))
            a.set_ylim(min(b[1] for b in boxes), max(b[3] for b in boxes))
        else:
            a.set_xlim(-0.03 * w, 1.03 * w)
            a.set_ylim(-0.03 * hgt, 1.03 * hgt)
    ax.set_title(p.source.name or "scene", fontsize=10)
    zx.set_title(
        f"adaptive PD region ({len(boxes)} rectangle{'s' if len(boxes) != 1 else ''})"
        if p.adaptive
        else "PD rectangle",
        fontsize=10,
    )
    fig.legend(*zx.get_legend_handles_labels(), loc="outside lower center", ncol=4, fontsize=7)
    st = s.get("path", {})
    if ridge is not None and ridge.covered.any():
        d = paths.distance_to_polyline(ridge.xy[ridge.covered], grown_path(res["xfem"]))
        dx_ax.plot(ridge.s[ridge.covered], d / p.delta, ".-", color="C1")
        dx_ax.set_xlabel("arc length along the XFEM path (from the initial tip)")
        dx_ax.set_ylabel("PD ridge to XFEM path (horizons delta = m dx)")
        sec = dx_ax.secondary_yaxis(
            "right", functions=(lambda v: v * p.delta / p.h, lambda v: v * p.h / p.delta)
        )
        sec.set_ylabel("(XFEM element lengths)")
        dx_ax.set_title(
            f"mean {st.get('mean_horizons', float('nan')):.2f}, max "
            f"{st.get('max_horizons', float('nan')):.2f} horizons; covered "
            f"{st.get('covered', 0):.0%} of the stations",
            fontsize=9,
        )
        dx_ax.set_ylim(bottom=0.0)
    else:
        dx_ax.text(0.5, 0.5, st.get("status", "no path"), ha="center", transform=dx_ax.transAxes)
    return fig


def draw_holes(ax: Any, d: Mapping[str, Any], w: float, hgt: float) -> None:
    style: dict[str, Any] = {"fc": "0.85", "ec": "k", "lw": 0.6}
    for hole in d.get("hole", []):
        shape = hole.get("shape", "circle")
        if shape == "circle":
            ax.add_patch(Circle(tuple(hole["center"]), hole["radius"], **style))
        elif shape == "rect":
            (x0, y0), (x1, y1) = hole["min"], hole["max"]
            ax.add_patch(Rectangle((x0, y0), x1 - x0, y1 - y0, **style))
        else:
            ax.add_patch(Polygon(np.asarray(hole["points"]), closed=True, **style))
    for n in d.get("notch", []):
        side, at, wd, dp = n.get("side", "bottom"), n["at"], n["width"], n["depth"]
        x0, y0, sx, sy = {
            "bottom": (at - wd / 2, 0.0, wd, dp),
            "top": (at - wd / 2, hgt - dp, wd, dp),
            "left": (0.0, at - wd / 2, dp, wd),
            "right": (w - dp, at - wd / 2, dp, wd),
        }[side]
        ax.add_patch(Rectangle((x0, y0), sx, sy, **style))


def path_csv(ridge: paths.Ridge, xr: Result) -> str:
    d = np.full(len(ridge.s), np.nan)
    if ridge.covered.any():
        d[ridge.covered] = paths.distance_to_polyline(ridge.xy[ridge.covered], grown_path(xr))
    rows = (
        [float(v) for v in (ridge.s[k], *ridge.station_xy[k])]
        + [int(ridge.n_bonds[k])]
        + [float(v) for v in (*ridge.xy[k], ridge.offset[k], d[k])]
        for k in range(len(ridge.s))
    )
    header = [
        "s",
        "station_x1",
        "station_x2",
        "bonds",
        "ridge_x1",
        "ridge_x2",
        "offset",
        "distance",
    ]
    return study.csv_text(header, rows)
