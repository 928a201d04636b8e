"""The figures and the CSV of a fig7 job (:mod:`rustfrac.fig7`): Fig. 7 (the load paths beside
the LEFM handbook curve), ``fig7.csv``, Fig. 8a (CCM-PD's damage), Fig. 8b (the XFEM growth's
deformed mesh) and Fig. 6 (the two discretisations). Drawn by :mod:`rustfrac.figures`, imported
at the first drawing (matplotlib)."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from .. import _core, handbook, study
from ..result import Result
from ..scene import Scene
from .presets import PAPER, Preset
from .summary import curve_agreement

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from .. import figures

__all__ = ["drawings", "fig8b", "pd_disc", "write_csv", "xfem_disc"]


def write_csv(path: Path, results: dict[str, Result], hb: tuple[np.ndarray, np.ndarray]) -> None:
    rows: list[list[Any]] = []
    for name in ("xfem_growth", "ccm_pd"):
        if name not in results:
            continue
        h = results[name].history
        a = h.get("a", h.get("crack_length"))
        for i in range(len(h["sigma22"])):
            rows.append(
                [
                    "xfem" if name == "xfem_growth" else "ccm_pd",
                    i,
                    None if a is None else float(a[i]),
                    float(h["load_factor"][i]),
                    float(h["u0"][i]),
                    float(h["sigma22"][i]),
                    float(h["cmod"][i]),
                ]
            )
    for i, (c, s) in enumerate(zip(*hb)):
        rows.append(["handbook", i, None, None, None, float(s), float(c)])
    header = ["method", "point", "crack_length", "load_factor", "u0", "sigma22", "cmod"]
    study.write_text(path, study.csv_text(header, rows))


def drawings(
    results: dict[str, Result],
    p: Preset,
    scenes: dict[str, Scene],
    bc: str,
    preset: str,
    ahead: dict[str, figures.Rendered],
) -> list[tuple[str, Callable[[Path], Any]]]:
    """(file name, writer into a path) of every file the finished runs ``results`` give (of
    preset ``p``; ``ahead``: figures drawn already, file name -> pixels)."""
    from .. import figures

    ref = scenes["xfem"]  # the plate, material and crack every run shares
    W, mat, a0, yc = ref.plate.width, ref.material, ref.crack.a0, ref.crack.y
    # the handbook curve over the crack lengths the XFEM growth reached; without the growth
    # run, up to the core's default stop length (0.7 W, the paper's Fig. 7)
    grown = results.get("xfem_growth")
    stop = _core.scene_constants()["DEFAULT_A_STOP_FRACTION"] * W
    a_end = float(grown.history["a"].max()) if grown is not None and grown.history else stop
    a = np.linspace(a0, a_end, 120)
    hb_c, hb_s = handbook.edge_crack_curve(a, W, mat.E, mat.nu, mat.G0, mat.plane)
    hb = (np.concatenate([[0.0], hb_c]), np.concatenate([[0.0], hb_s]))
    curves: list[figures.Curve] = []
    if "xfem_growth" in results:
        h = results["xfem_growth"].history
        # on top of the PD saw-tooth, which covers it on the full curve (preset "full")
        style = {"marker": ".", "ms": 4, "zorder": 5, "color": "C0"}
        curves.append(("XFEM (LEFM growth)", h["cmod"], h["sigma22"], style))
    if "ccm_pd" in results:
        h = results["ccm_pd"].history
        # one point per SLA step (each at the load that breaks its bond): the saw-tooth of SLA
        curves.append(
            (
                "CCM-PD (SLA, one point per bond break)",
                h["cmod"],
                h["sigma22"],
                {"lw": 0.4, "alpha": 0.7, "marker": ".", "ms": 2.5, "color": "C1"},
            )
        )
    # the CMOD axis ends a little past the computed curves: the handbook's traction curve
    # reaches about twice their CMOD at a = 0.7 W and would squeeze them into half the plot
    computed = [np.max(c[1]) for c in curves if len(c[1])]
    x_max = 1.08 * float(max(computed)) if computed else None
    curves.append(
        ("LEFM handbook (long strip, traction)", hb[0], hb[1], {"ls": "--", "color": "0.4"})
    )
    title = f"edge-cracked plate, bc {bc}, preset {preset}"
    both = "xfem_growth" in results and "ccm_pd" in results
    panel = curve_agreement(results)["curves"] if both else None
    out: list[tuple[str, Callable[[Path], Any]]] = [
        (
            "fig7.png",
            lambda f: figures.save_figure(
                figures.plot_fig7(
                    curves,
                    title=title,
                    published=[
                        ("paper, initial (XFEM)", PAPER["cmod_xfem"], PAPER["sigma22_xfem"])
                    ],
                    agreement=panel,
                    x_max=x_max,
                ),
                f,
            ),
        ),
        ("fig7.csv", lambda f: write_csv(f, results, hb)),
    ]
    if "ccm_pd" in results:
        r = results["ccm_pd"]
        out.append(
            (
                "fig8a.png",
                lambda f: figures.save_figure(
                    figures.plot_damage(
                        r.fields["pd_node_xy"],
                        r.fields["damage"],
                        p.dx,
                        title=f"CCM-PD damage after {len(r.history['sigma22']) - 1} SLA steps",
                        crack_y=yc,
                    ),
                    f,
                ),
            )
        )
    # drawn beside the CCM-PD run, or now; none when the growth reached no snapshot step
    deformed = ahead.get("fig8b.png") or fig8b(results, p)
    if deformed is not None:
        out.append(("fig8b.png", lambda f: figures.save_figure(deformed, f)))
    if "xfem" in results and "ccm_pd" in results:
        out.append(
            (
                "fig6.png",
                lambda f: figures.save_figure(
                    figures.plot_discretisations(
                        xfem_disc(results["xfem"]),
                        pd_disc(results["ccm_pd"], p.dx),
                        (0.0, 2.6, 9.6, 11.4),
                    ),
                    f,
                ),
            )
        )
    return out


def fig8b(results: dict[str, Result], p: Preset) -> Figure | None:
    """Fig. 8b: the XFEM growth's deformed mesh near the tip at the preset's growth steps
    (None: no growth run, or none of those steps reached)."""
    from .. import figures
    from ..plotting import PAPER_UNITS

    g = results.get("xfem_growth")
    if g is None:
        return None
    # the paper's units (mm, MPa) of the columns' quantities in the result schema
    length, stress = (PAPER_UNITS.of(g.unit(k) or "") for k in ("a", "sigma22"))
    off = g.fields["snapshot_offsets"]
    snaps = []
    for k in p.snapshot_steps:
        if k < len(off):  # snapshot k-1: the critical state of growth step k (row k)
            rows = slice(int(off[k - 1]), int(off[k]))
            snaps.append(
                (
                    g.fields["snapshot_cells"][rows],
                    g.fields["snapshot_disp"][rows],
                    f"growth step {k}: a = {float(g.history['a'][k]):.3g} {length}, sigma22 = "
                    f"{float(g.history['sigma22'][k]):.3g} {stress}",
                )
            )
    return figures.plot_deformed_patches(snaps, scale=50.0) if snaps else None


def xfem_disc(r: Result) -> dict[str, np.ndarray]:
    f = r.fields
    return {
        "coords": f["coords"],
        "elements": f["elements"],
        "heaviside_nodes": f["heaviside_nodes"],
        "tip_nodes": f["tip_nodes"],
        "crack": f["crack"],
    }


def pd_disc(r: Result, dx: float) -> dict[str, np.ndarray]:
    from ..figures import grid_elements

    xy = r.fields["node_xy"]
    nx = round(float(xy[:, 0].max() - xy[:, 0].min()) / dx)
    ny = round(float(xy[:, 1].max() - xy[:, 1].min()) / dx)
    el = grid_elements(nx, ny)
    is_pd = np.zeros(len(xy), bool)
    is_pd[np.asarray(r.fields["pd_nodes"], int)] = True
    cells = xy[el]
    (x0, yc), (a0, _) = np.asarray(r.meta["precrack"], float)[[0, -1]]
    # FEM elements cut by the pre-crack are removed in the core (the crack is a real slit there)
    removed = (cells[:, :, 1].min(axis=1) < yc) & (cells[:, :, 1].max(axis=1) > yc)
    removed &= cells[:, :, 0].min(axis=1) < a0
    return {
        "node_xy": xy,
        "is_pd": is_pd,
        "elements": el,
        "removed": removed,
        "crack": np.array([[x0, yc], [a0, yc]]),
    }
