"""LEFM and peridynamics side by side on one scene (``rustfrac compare SCENE.toml --out DIR``).

From one scene of any method, :func:`compare` derives two scenes with the same plate, material,
load, holes and pre-crack, and runs them:

1. **XFEM growth** (LEFM: critical states at G = G0, the kink criterion's direction), on the
   scene's mesh (a PD scene: a mesh of element size dx);
2. **CCM-PD** with the sequentially linear analysis (one bond break per step) in a *fixed* PD
   rectangle placed by :func:`~rustfrac.pd_region.pd_region` around the XFEM path's bounding
   box plus a margin of ``margin_horizons`` horizons (the adaptive PD region will replace that one
   function), unless the scene is a CCM-PD scene that states its own rectangle, or ``region`` is
   given. The SLA stops when the PD crack has advanced as far along the pre-crack's direction as
   the XFEM tip (``pd.stop_crack_length``).

Both use nu = 1/4 in plane strain, the only material bond-based PD represents (the scene's
values are replaced, as :mod:`rustfrac.specimens` does; the summary says so). The PD grid
spacing dx is the scene's (a PD scene), ``dx``, or by default the XFEM element size, made
coarser when the rectangle would exceed the comparison's budget of ``PD_DOFS_BUDGET`` free
PD dofs (a cost budget: the SLA runs any size, but larger regions cost minutes), so a ``dx`` or
``region`` the user gave that exceeds it is refused unless ``allow_slow``.

Compared (written into ``out`` as one unit, ``rustfrac._folder``):

- the crack paths: the PD damage ridge (:func:`rustfrac.paths.bond_ridge` of the bonds the SLA
  broke, stations every dx along the grown XFEM path) and its distance to the XFEM polyline, in
  lengths, horizons delta = m dx and XFEM element lengths (``compare.png``, ``path.csv``);
- the load-response curves in one response pair (``curves.png``, ``curves.csv``): sigma22
  against CMOD under the grips (``[load]``), the load factor (the multiplier of the scene's
  loads) against the load displacement ``u0`` with supports and loads on regions; their
  agreement at equal abscissa (``rustfrac.agreement.compare``);
- the energy audit of both (``rustfrac.energy.audit``: displacement grips only);
- the cost: wall time, unknowns, steps, PD nodes, the SLA engine;
- ``summary.md`` / ``summary.json`` (the last file written, naming the save id of the result
  folders ``xfem/`` and ``ccm_pd/``).
"""

from __future__ import annotations

import functools
import math
import secrets
import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from matplotlib.collections import PolyCollection
from matplotlib.figure import Figure
from matplotlib.patches import Circle, Polygon, Rectangle

from . import agreement, figures, paths, study
from ._folder import check_writable, with_fallback, writing
from ._log import logger
from .errors import InvalidParameterError, PlotDataError
from .pd_region import DEFAULT_MARGIN_HORIZONS, Box, cut_hole, held_sides, pd_dofs, pd_region
from .result import OWNED_NAMES, Result, save_result
from .runner import as_scene
from .scene import MAX_STEPS, METHODS, PD_NU, PdOptions, Scene
from .specimens import pd_layout
from .study import Log, ProgressFactory, run_logged

__all__ = [
    "DEFAULT_GROWTH_STEPS",
    "FILES",
    "PARTS",
    "CompareInterrupted",
    "Plan",
    "compare",
    "grown_path",
    "path_agreement",
    "place",
    "plan",
    "response_pair",
    "sla_broken_bonds",
]

#: XFEM growth steps when the scene sets none (full run, ``quick``)
DEFAULT_GROWTH_STEPS = {False: 24, True: 4}
#: XFEM edge cracks grow up to this fraction of the plate's width (height for bottom / top
#: cracks) when the scene sets no xfem.a_stop (the comparison's own stop, beyond the core's 0.7 W
#: default for a single run: the two methods are compared along a long path)
COMPARE_A_STOP_FRACTION = 0.9
#: half-width of the ridge's strip across the XFEM path, in horizons (bonds farther away are
#: counted as off the path)
RIDGE_HALF_WIDTH_HORIZONS = 3.0
#: length of the ridge's strip along the path, in grid spacings (stations are dx apart)
RIDGE_WINDOW_SPACINGS = 2.0
#: SLA steps allowed per grid spacing of crack advance, per m^3 (a crack front of m = 3 breaks
#: about 25 bonds per dx, measured on the edge crack under shear), before stop_crack_length
SLA_STEPS_PER_SPACING_M3 = 2.0
#: the comparison's cost budget: most free PD dofs of the fixed rectangle (the core's SLA runs any
#: size, its engine chosen by cost, `pd.engine`; past this a step costs more than the whole XFEM
#: growth of a typical scene, so larger rectangles need ``allow_slow``)
PD_DOFS_BUDGET = 6000

#: the files of a compare folder (the result folders xfem/ and ccm_pd/ besides)
FILES = ("compare.png", "curves.png", "curves.csv", "path.csv", "summary.md", "summary.json")
#: folder name of each run saved as a result folder
PARTS = {"xfem": "xfem", "ccm_pd": "ccm_pd"}

# ----------------------------------------------------------------------------------------------
# the two scenes


@dataclass
class Plan:
    """The two scenes of a comparison (the CCM-PD one without its rectangle until the XFEM path
    is known) and the choices made deriving them (``notes``, also in the summary)."""

    source: Scene
    xfem: Scene
    pd: dict[str, Any]  # the CCM-PD scene dict; pd.center / pd.size set by :func:`place`
    h: float  # XFEM element size (the smallest)
    dx: float
    m: int
    dx_auto: bool  # dx chosen here (may be coarsened to fit the budget PD_DOFS_BUDGET)
    region_given: Box | None
    allow_slow: bool
    margin_horizons: float
    sla_steps: int | None
    notes: list[str] = field(default_factory=list)
    #: CCM-PD on the adaptive PD region (``region="adaptive"``) instead of a fixed rectangle
    adaptive: bool = False

    @property
    def delta(self) -> float:
        return self.m * self.dx


def _element_size(d: dict[str, Any], width: float, height: float) -> float | None:
    """The smallest element size of a FEM / XFEM scene's [mesh], None without one."""
    mesh = d.get("mesh")
    if not isinstance(mesh, Mapping):
        return None
    sizes = []
    for lines, n, size in (
        (mesh.get("xs"), mesh["nx"], width),
        (mesh.get("ys"), mesh["ny"], height),
    ):
        sizes.append(float(np.min(np.diff(lines))) if lines else size / n)
    if mesh.get("refine") and mesh.get("refine_h"):
        sizes.append(float(mesh["refine_h"]))
    return min(sizes)


def _fitting_spacings(width: float, height: float, upto: float) -> list[float]:
    """Grid spacings that fit the plate (width / dx and height / dx whole numbers), from the
    largest one not above ``upto`` to coarser ones (at least 4 cells across)."""
    out = []
    for n in range(max(math.floor(width / upto + 1e-9), 1), 3, -1):
        dx = width / n
        k = height / dx
        if abs(k - round(k)) < 1e-9 * max(k, 1.0):
            out.append(dx)
    return out


def _stated_region(scene: Scene) -> Box | None:
    """A CCM-PD scene's own rectangle (center / size differing from the defaults), else None."""
    if scene.method != "ccm_pd":
        return None
    default = PdOptions()
    if scene.pd.center == default.center and scene.pd.size == default.size:
        return None
    (cx, cy), (sx, sy) = scene.pd.center, scene.pd.size
    return (cx - sx / 2, cy - sy / 2, cx + sx / 2, cy + sy / 2)


def plan(
    scene: Scene | Mapping[str, Any] | str | Path,
    *,
    quick: bool = False,
    dx: float | None = None,
    m: int | None = None,
    margin_horizons: float = DEFAULT_MARGIN_HORIZONS,
    growth_steps: int | None = None,
    sla_steps: int | None = None,
    region: Box | str | None = None,
    surface_correction: str | None = None,
    allow_slow: bool = False,
) -> Plan:
    """The XFEM and CCM-PD scenes of a comparison (see the module docstring); every value is
    checked by the core when the scenes are built. ``region`` is (x0, y0, x1, y1), "auto"
    (:func:`~rustfrac.pd_region.pd_region`, also for a CCM-PD scene that states a rectangle)
    or None (a CCM-PD scene's own rectangle, else "auto"); ``surface_correction`` the CCM-PD
    scene's ``pd.surface_correction`` (None: a PD scene's, else the default)."""
    src = as_scene(scene)
    if src.method not in METHODS:  # pragma: no cover (Scene checks it)
        raise InvalidParameterError(f"invalid method {src.method!r}", "method")
    if src.extra_cracks:
        raise InvalidParameterError(
            "invalid crack: compare runs one crack (CCM-PD takes one pre-crack); the scene has "
            f"{len(src.cracks)}",
            "crack",
        )
    if src.crack.kind == "none":
        raise InvalidParameterError(
            "invalid crack: compare needs a crack, got kind 'none'", "crack"
        )
    if not (math.isfinite(margin_horizons) and margin_horizons >= 1.0):
        raise InvalidParameterError(
            f"invalid margin_horizons: expected a number >= 1 (horizons), got {margin_horizons!r}",
            "margin_horizons",
        )
    notes: list[str] = []
    d = src.to_dict()
    width, height = src.plate.width, src.plate.height
    pd_in: dict[str, Any] = dict(d.get("pd", {})) if src.method in ("pd", "ccm_pd") else {}
    h = _element_size(d, width, height)
    m = int(m if m is not None else pd_in.get("m", PdOptions().m))
    dx_auto = dx is None and "dx" not in pd_in
    if dx is None:
        if "dx" in pd_in:
            dx = float(pd_in["dx"])
        else:
            fit = _fitting_spacings(width, height, h if h is not None else PdOptions().dx)
            if not fit:
                raise InvalidParameterError(
                    f"invalid pd.dx: no grid spacing near the element size {h:g} fits the plate "
                    f"{width:g} x {height:g}; give one (--dx)",
                    "pd.dx",
                )
            dx = fit[0]
    if h is None:
        h = dx
    if src.method == "pd":
        notes.append("the pure PD scene is run as CCM-PD (PD in a rectangle around the path)")

    # common: plate, material, load, supports, holes, pre-crack; nu = 1/4, plane strain
    common = {k: v for k, v in d.items() if k not in ("method", "mesh", "xfem", "pd", "name")}
    crack = dict(common["crack"])
    if crack.get("kind") == "seam":
        crack["kind"] = "edge"
    mat = dict(common.get("material", {}))
    if mat.get("nu") != PD_NU or mat.get("plane", "strain") != "strain":
        notes.append(
            f"material: nu = {PD_NU:g}, plane strain for both methods (bond-based PD "
            f"represents no other; the scene had nu = {mat.get('nu')}, plane "
            f"{mat.get('plane', 'strain')})"
        )
    # dx and m against the core's ranges and the plate's grid rule first (a clear error naming
    # pd.dx / pd.m, not a failure in the layout below)
    Scene.from_dict(
        {"method": "pd", "plate": common.get("plate", {}), "pd": {"dx": dx, "m": m},
         "crack": {"kind": "none"}}
    )  # fmt: skip
    tmp = {"method": "pd", "pd": {"dx": dx, "m": m}, "material": dict(mat), "crack": dict(crack)}
    pd_layout(tmp)  # nu, plane, and the crack moved off a PD node row (specimens' rule)
    if tmp["crack"] != crack:
        notes.append(f"crack moved by dx/2 = {dx / 2:g} off a PD node row (both methods)")
    common["material"], common["crack"] = tmp["material"], tmp["crack"]
    name = d.get("name", "scene")

    xd: dict[str, Any] = {**common, "method": "xfem", "name": f"{name} (XFEM)"}
    xd["mesh"] = (
        dict(d["mesh"]) if "mesh" in d else {"nx": round(width / dx), "ny": round(height / dx)}
    )
    xf = dict(d.get("xfem", {})) if src.method == "xfem" else {}
    gs = (
        growth_steps
        if growth_steps is not None
        else (xf.get("growth_steps") or DEFAULT_GROWTH_STEPS[quick])
    )
    if not gs or int(gs) < 1:
        raise InvalidParameterError(
            f"invalid xfem.growth_steps: expected at least 1 for a comparison (the paths are "
            f"compared along the growth), got {gs!r}",
            "xfem.growth_steps",
        )
    xf["growth_steps"] = int(gs)
    if not xf.get("a_stop") and crack.get("kind") == "edge":
        # the path, not the core's 0.7 W default, sets how far to grow: the tip stops itself
        # 2 elements from the boundary ("ligament_used_up")
        side = width if crack.get("side", "left") in ("left", "right") else height
        xf["a_stop"] = COMPARE_A_STOP_FRACTION * side
        notes.append(
            f"XFEM growth up to a = {xf['a_stop']:g} ({COMPARE_A_STOP_FRACTION:g} of the plate)"
        )
    xd["xfem"] = xf
    pd_opts = {k: v for k, v in pd_in.items() if k not in ("center", "size")}
    pd_opts.update(dx=dx, m=m)
    if surface_correction is not None:
        pd_opts["surface_correction"] = surface_correction
    pdd: dict[str, Any] = {**common, "method": "ccm_pd", "name": f"{name} (CCM-PD)", "pd": pd_opts}
    if isinstance(region, str):
        if region not in ("auto", "adaptive"):
            raise InvalidParameterError(
                f"invalid region: expected (x0, y0, x1, y1), 'auto' or 'adaptive', got {region!r}",
                "region",
            )
        given: Box | None = None
        if region == "adaptive":
            pd_opts["region"] = "adaptive"
    elif pd_opts.get("region") == "adaptive":
        given = None  # a CCM-PD scene on the adaptive region keeps it
    elif region is not None:
        x0, y0, x1, y1 = (float(v) for v in region)
        if not (x1 > x0 and y1 > y0):
            raise InvalidParameterError(
                f"invalid region: expected (x0, y0, x1, y1) with x0 < x1, y0 < y1, got {region!r}",
                "region",
            )
        given = (x0, y0, x1, y1)
    else:
        given = _stated_region(src)
    if given is not None:
        k = cut_hole(given, common.get("hole", []), (width, height), dx)
        if k is not None:
            raise InvalidParameterError(
                f"invalid region: the PD rectangle {_fmt_box(given)} cuts hole[{k}] (the hybrid "
                "elements at its boundary would cross the hole); give a rectangle that takes the "
                "hole in whole or keeps a spacing clear of it (--region x0,y0,x1,y1; "
                "region=(x0, y0, x1, y1)), or let compare choose one (--region auto) or grow "
                "the adaptive region (--region adaptive)",
                "region",
            )
    return Plan(
        src,
        Scene.from_dict(xd),
        pdd,
        float(h),
        float(dx),
        m,
        dx_auto,
        given,
        allow_slow,
        float(margin_horizons),
        sla_steps,
        notes,
        pd_opts.get("region") == "adaptive",
    )


# ----------------------------------------------------------------------------------------------
# the PD rectangle


def place(p: Plan, xfem_path: np.ndarray, final_tip: Sequence[float] | None) -> Scene:
    """The CCM-PD scene of plan ``p`` with its rectangle (the stated one, or
    :func:`~rustfrac.pd_region.pd_region` around ``xfem_path``), its SLA steps and its stop length.
    Coarsens an automatic dx to keep the budget ``PD_DOFS_BUDGET``; refuses a given dx / rectangle
    beyond it unless ``p.allow_slow``."""
    if p.adaptive:
        p.notes.append(
            "adaptive PD region: squares around the tip grown ahead of the crack (pd.adapt_margin, "
            "pd.adapt_size); no rectangle budget"
        )
        return _with_sla_length(p, p.dx, final_tip)
    w, hgt = p.source.plate.width, p.source.plate.height
    holes = p.pd.get("hole", [])
    cands = [p.dx]
    if p.dx_auto and p.region_given is None:
        cands += [v for v in _fitting_spacings(w, hgt, p.dx * (1 - 1e-9)) if v > p.dx]
    box: Box | None = p.region_given
    for dx in cands:
        box = p.region_given or pd_region(
            xfem_path,
            (w, hgt),
            dx,
            p.m,
            holes=holes,
            held=sorted(held_sides(p.pd)),
            margin_horizons=p.margin_horizons,
        )
        if box is None:
            return _adaptive_instead(p, final_tip)
        if pd_dofs(box, dx) <= PD_DOFS_BUDGET:
            break
    assert box is not None
    n = pd_dofs(box, dx)
    if dx != p.dx:
        p.notes.append(
            f"PD grid coarsened from dx = {p.dx:.6g} (the XFEM element size) to {dx:.6g} to keep "
            f"the rectangle under the comparison's budget of {PD_DOFS_BUDGET} free PD dofs"
        )
        p.dx = dx
        p.pd["pd"]["dx"] = dx
        tmp = {"method": "pd", "pd": {"dx": dx, "m": p.m}, "crack": dict(p.xfem.crack.to_dict())}
        pd_layout(tmp)
        if tmp["crack"] != p.xfem.crack.to_dict():
            p.pd["crack"] = tmp["crack"]
            p.notes.append(f"PD pre-crack moved by dx/2 = {dx / 2:g} off a node row (XFEM's not)")
    if n > PD_DOFS_BUDGET:
        msg = (
            f"the PD rectangle {_fmt_box(box)} at dx = {dx:.6g} holds about {n} free PD dofs, "
            f"above the comparison's budget of {PD_DOFS_BUDGET} (compare.PD_DOFS_BUDGET): the SLA "
            "would take minutes"
        )
        if not p.allow_slow:
            param = "pd.dx" if p.region_given is None else "pd.size"
            raise InvalidParameterError(
                f"invalid {param}: {msg}; choose a coarser dx or a smaller rectangle, or allow "
                "it (allow_slow=True, --allow-slow)",
                param,
            )
        logger.warning("compare: %s (allowed)", msg)
        p.notes.append(msg + " (allowed)")
    if p.region_given is not None:
        p.notes.append(f"PD rectangle {_fmt_box(box)} as given")
    else:
        p.notes.append(
            f"fixed PD rectangle {_fmt_box(box)}: the XFEM path's bounding box plus "
            f"{p.margin_horizons:g} horizons (adaptive CCM-PD not used)"
        )
    opts = p.pd["pd"]
    opts["center"] = [(box[0] + box[2]) / 2, (box[1] + box[3]) / 2]
    opts["size"] = [box[2] - box[0], box[3] - box[1]]
    return _with_sla_length(p, dx, final_tip)


def _adaptive_instead(p: Plan, final_tip: Sequence[float] | None) -> Scene:
    """The CCM-PD scene of ``p`` on the adaptive region, where no fixed rectangle around the path
    keeps clear of the holes (:func:`~rustfrac.pd_region.pd_region`), with a note saying so."""
    p.adaptive = True
    p.pd["pd"]["region"] = "adaptive"
    p.notes.append(
        "no fixed PD rectangle around the XFEM path keeps clear of the holes (a hole taken in "
        "whole, or its hybrid band clear of it) and two horizons off the loaded or supported "
        "sides: the adaptive PD region instead; give a rectangle with --region x0,y0,x1,y1 "
        "(region=(x0, y0, x1, y1)) to choose one"
    )
    return _with_sla_length(p, p.dx, final_tip)


def _with_sla_length(p: Plan, dx: float, final_tip: Sequence[float] | None) -> Scene:
    """The CCM-PD scene of ``p`` with its stop length (the XFEM tip's reach along the pre-crack)
    and its SLA steps."""
    opts = p.pd["pd"]
    pre = np.asarray(
        Scene.from_dict({**p.pd, "method": "pd", "pd": {"dx": dx, "m": p.m}}).crack_polylines()[0],
        dtype=float,
    )
    advance = 0.0
    if final_tip is not None and not opts.get("stop_crack_length"):
        t = (pre[-1] - pre[0]) / np.linalg.norm(pre[-1] - pre[0])
        reach = float((np.asarray(final_tip) - pre[0]) @ t)
        advance = reach - float(np.linalg.norm(pre[-1] - pre[0]))
        if advance > 0:
            opts["stop_crack_length"] = reach
    if p.sla_steps is not None:
        opts["sla_steps"] = int(p.sla_steps)
    elif "sla_steps" not in opts:  # a PD scene's own sla_steps stays the limit
        cells = max(advance / dx, 1.0)
        opts["sla_steps"] = int(min(SLA_STEPS_PER_SPACING_M3 * p.m**3 * cells + 50, MAX_STEPS))
    return Scene.from_dict(p.pd)


def _fmt_box(b: Box) -> str:
    return f"[{b[0]:.4g}, {b[2]:.4g}] x [{b[1]:.4g}, {b[3]:.4g}]"


# ----------------------------------------------------------------------------------------------
# what is compared


def grown_path(res: Result) -> np.ndarray:
    """The primary XFEM crack from its initial tip on (the part that grew), (k, 2)."""
    line = np.asarray(res.crack_polylines[0], dtype=float)
    k0 = len(res.meta.get("crack_initial") or [])
    return line[max(k0 - 1, 0) :]


def sla_broken_bonds(res: Result) -> np.ndarray:
    """The bonds the SLA broke (not the pre-crack's), as indices into ``fields["bond_nodes"]``."""
    b = np.asarray(res.history.get("bond", []), dtype=int)
    return np.unique(b[b >= 0])


def _bond_midpoints(res: Result, bonds: np.ndarray) -> np.ndarray:
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


_LABELS = {
    "cmod": "CMOD",
    "sigma22": "sigma22 (mean normal stress on the loaded edge)",
    "u0": "load displacement u0",
    "load_factor": "load factor (x the scene's loads)",
}


def _window(n: int) -> int:
    w = min(agreement.DEFAULT_WINDOW, max(n // 4, 1))
    return w if w % 2 else max(w - 1, 1)


# ----------------------------------------------------------------------------------------------
# the job


class CompareInterrupted(KeyboardInterrupt):
    """Ctrl-C during :func:`compare`: what finished was written; ``summary`` is the summary
    (``complete`` false, ``missing`` lists what is not there)."""

    def __init__(self, summary: dict[str, Any]) -> None:
        super().__init__("compare interrupted")
        self.summary = summary


def compare(
    scene: Scene | Mapping[str, Any] | str | Path,
    out: str | Path,
    *,
    quick: bool = False,
    dx: float | None = None,
    m: int | None = None,
    margin_horizons: float = DEFAULT_MARGIN_HORIZONS,
    growth_steps: int | None = None,
    sla_steps: int | None = None,
    region: Box | str | None = None,
    surface_correction: str | None = None,
    allow_slow: bool = False,
    vtu: bool = False,
    log: Log | None = logger.info,
    progress: ProgressFactory | None = None,
) -> dict[str, Any]:
    """Runs XFEM growth and CCM-PD on ``scene`` (a Scene, dict or TOML path) and writes the
    comparison into ``out``; returns the summary (also ``summary.json``).

    Args:
        quick: fewer XFEM growth steps when the scene sets none (4 instead of 24).
        dx: PD grid spacing (default: a PD scene's, else the XFEM element size, coarsened to
            stay within PD_DOFS_BUDGET).
        m: PD horizon factor (default: a PD scene's, else 4).
        margin_horizons: margin of the PD rectangle around the XFEM path, in horizons.
        growth_steps: XFEM growth steps (default: the scene's, else 24, 4 with ``quick``).
        sla_steps: most SLA steps (default: a PD scene's, else enough for the XFEM path; the
            SLA stops when the PD crack has advanced as far as the XFEM tip).
        region: the PD rectangle (x0, y0, x1, y1); "auto":
            :func:`~rustfrac.pd_region.pd_region` around the XFEM path; "adaptive": the core's
            adaptive PD region (``pd.region``), grown where the PD crack goes; None (default): a
            CCM-PD scene's own rectangle or adaptive region if it states one, else "auto". allow_slow: run even when the PD
            rectangle exceeds the budget ``PD_DOFS_BUDGET``.
        surface_correction: the CCM-PD run's ``pd.surface_correction`` ("none" or "energy";
            None: a PD scene's, else "none").
        vtu: also write the ParaView files of the two result folders.
        log: line logger (None: silent).
        progress: factory ``progress(name)`` of a progress callback for each run, or None.

    Raises:
        InvalidParameterError: a scene or option the comparison cannot run (naming it).
        CompareInterrupted: Ctrl-C; what finished was written.
    """
    say: Log = log or (lambda s: None)
    p = plan(
        scene, quick=quick, dx=dx, m=m, margin_horizons=margin_horizons,
        growth_steps=growth_steps, sla_steps=sla_steps, region=region,
        surface_correction=surface_correction, allow_slow=allow_slow,
    )  # fmt: skip
    outdir = check_writable(out)
    results: dict[str, Result] = {}
    times: dict[str, float] = {}
    scenes: dict[str, Scene] = {"xfem": p.xfem}
    interrupted = False
    t_all = time.perf_counter()
    try:
        for name in PARTS:
            if name == "ccm_pd":
                if "xfem" in results:
                    gp = grown_path(results["xfem"])
                    tip = gp[-1]
                else:  # pragma: no cover (XFEM failed before)
                    gp, tip = np.asarray(p.xfem.crack_polylines()[0])[-1:], None
                scenes["ccm_pd"] = place(p, gp, tip)
            results[name], times[name] = run_logged(name, scenes[name], progress, say, _built)
    except KeyboardInterrupt:
        interrupted = True
        say("interrupted: writing what finished")
    for n in p.notes:
        say(f"note    {n}")
    job = _Job(p, scenes, results, times, interrupted, t_all, vtu)
    summary = with_fallback(outdir, job.write, "compare")
    say(f"saved   {outdir}/ ({', '.join(summary['files'])})")
    if summary["missing"]:
        say(f"missing {', '.join(summary['missing'])}")
    if interrupted:
        raise CompareInterrupted(summary)
    return summary


def _built(res: Result) -> str:
    m = res.meta
    if res.method == "xfem":
        return (
            f"{res.n_dofs} unknowns, {len(res.history.get('a', [])) - 1} growth steps, status "
            f"{m.get('status')}"
        )
    c = m.get("counts", {})
    return (
        f"{res.n_dofs} unknowns, {c.get('n_pd_nodes')} PD nodes, {c.get('n_bonds')} bonds, "
        f"{m.get('sla_steps_done')} SLA steps, status {m.get('status')}, solver {m.get('solver')}"
    )


@dataclass
class _Job:
    """The outputs of one comparison, written as one folder (``rustfrac._folder``)."""

    p: Plan
    scenes: dict[str, Scene]
    results: dict[str, Result]
    times: dict[str, float]
    interrupted: bool
    t_all: float
    vtu: bool

    def write(self, outdir: Path) -> dict[str, Any]:
        owned = (*FILES, *PARTS.values())
        with writing(outdir, owned=owned, last="summary.json", inner=OWNED_NAMES) as w:
            parts: dict[str, str] = {}
            for name, part in PARTS.items():
                if name in self.results:
                    parts[part] = secrets.token_hex(8)
                    w.under_lock(
                        part,
                        functools.partial(
                            save_result, self.results[name], outdir / part, vtu=self.vtu,
                            save_id=parts[part],
                        ),
                    )  # fmt: skip
            s = self.summary()
            files, stopped = w.stage_each(self._drawings(s))
            interrupted = self.interrupted or stopped
            s["interrupted"] = interrupted
            s["total_s"] = time.perf_counter() - self.t_all
            s["files"] = [*files, "summary.md", "summary.json"]
            s["parts"] = parts
            s["missing"] = study.missing(PARTS, PARTS, FILES, self.results, s["files"])
            s["complete"] = not interrupted and not s["missing"]
            study.write_summary(w, s, _markdown(s))
        return s

    # -- numbers ----------------------------------------------------------------------------

    def _ridge(self) -> tuple[dict[str, Any], paths.Ridge | None, np.ndarray]:
        xr, pr, p = self.results.get("xfem"), self.results.get("ccm_pd"), self.p
        if xr is None or pr is None:
            return {"status": "a run is missing"}, None, np.zeros((0, 2))
        mid = _bond_midpoints(pr, sla_broken_bonds(pr))
        stats, ridge = path_agreement(grown_path(xr), mid, p.dx, p.delta, p.h)
        return stats, ridge, mid

    def summary(self) -> dict[str, Any]:
        from . import __version__

        p, res = self.p, self.results
        s: dict[str, Any] = {
            "version": __version__,
            "scene": p.source.to_dict(),
            "scenes": {k: v.to_dict() for k, v in self.scenes.items()},
            "machine": study.machine(),
            "notes": list(p.notes),
            "discretisation": {"xfem_h": p.h, "pd_dx": p.dx, "pd_m": p.m, "delta": p.delta},
        }
        stats, _, _ = self._ridge()
        s["path"] = stats
        if "xfem" in res and "ccm_pd" in res:
            xk, yk = response_pair(res["xfem"])
            xh, ph = res["xfem"].history, res["ccm_pd"].history
            s["curves"] = {"x": xk, "y": yk}
            if len(xh.get(xk, [])) > 1 and len(ph.get(xk, [])) > 2:
                cur = agreement.compare(xh[xk], xh[yk], ph[xk], ph[yk], _window(len(ph[xk])))
                s["curves"]["agreement"] = {k: v for k, v in cur.items() if k != "curves"}
                px, py = int(np.argmax(xh[yk])), int(np.argmax(ph[yk]))
                s["curves"]["peak"] = {
                    "xfem": [float(xh[xk][px]), float(xh[yk][px])],
                    "ccm_pd": [float(ph[xk][py]), float(ph[yk][py])],
                    "rel_diff": float(ph[yk][py] / xh[yk][px] - 1.0) if xh[yk][px] else None,
                }
        s["energy"] = {}
        for k, r in res.items():
            try:
                s["energy"][k] = study.audit(r)
            except PlotDataError as e:
                s["energy"][k] = {"not_available": str(e)}
        s["cost"] = {}
        for k, r in res.items():
            row: dict[str, Any] = {"wall_time_s": self.times[k], "unknowns": r.n_dofs}
            if k == "xfem":
                row["steps"] = max(len(r.history.get("a", [])) - 1, 0)
                row["status"] = r.meta.get("status")
            else:
                c = r.meta.get("counts", {})
                row.update(
                    steps=r.meta.get("sla_steps_done"), status=r.meta.get("status"),
                    pd_nodes=c.get("n_pd_nodes"), bonds=c.get("n_bonds"),
                    solver=r.meta.get("solver"), pd_region=r.meta.get("pd_regions"),
                )  # fmt: skip
            s["cost"][k] = row
        return s

    # -- files ------------------------------------------------------------------------------

    def _drawings(self, s: dict[str, Any]) -> list[tuple[str, Callable[[Path], Any]]]:
        out: list[tuple[str, Callable[[Path], Any]]] = []
        if not self.results:
            return out
        _, ridge, mid = self._ridge()
        out.append(
            ("compare.png", lambda f: figures.save_figure(self._paths_figure(ridge, mid, s), f))
        )
        if "curves" in s:
            out.append(("curves.png", lambda f: figures.save_figure(self._curves_figure(s), f)))
            out.append(("curves.csv", lambda f: study.write_text(f, self._curves_csv(s))))
        if ridge is not None:
            out.append(
                ("path.csv", lambda f: study.write_text(f, _path_csv(ridge, self.results["xfem"])))
            )
        return out

    def _curves_csv(self, s: dict[str, Any]) -> str:
        xk, yk = s["curves"]["x"], s["curves"]["y"]
        rows = (
            [k, i, float(a), float(b)]
            for k in PARTS
            for i, (a, b) in enumerate(
                zip(self.results[k].history[xk], self.results[k].history[yk])
            )
        )
        return study.csv_text(["method", "point", xk, yk], rows)

    def _curves_figure(self, s: dict[str, Any]) -> Figure:
        xk, yk = s["curves"]["x"], s["curves"]["y"]
        xh, ph = self.results["xfem"].history, self.results["ccm_pd"].history
        fig = Figure(figsize=(7.0, 5.0))
        ax = fig.add_subplot()
        ax.plot(xh[xk], xh[yk], ".-", ms=4, label="XFEM (LEFM growth, critical states)")
        ax.plot(
            ph[xk], ph[yk], ".-", lw=0.4, ms=2.5, alpha=0.7, color="C1",
            label="CCM-PD (SLA, one point per bond break)",
        )  # fmt: skip
        ax.set_xlabel(_LABELS.get(xk, xk))
        ax.set_ylabel(_LABELS.get(yk, yk))
        ag = s["curves"].get("peak")
        title = self.p.source.name or "scene"
        if ag and ag.get("rel_diff") is not None:
            title += f"\npeak: CCM-PD / XFEM - 1 = {ag['rel_diff']:+.1%}"
        ax.set_title(title, fontsize=10)
        ax.legend(fontsize=8)
        ax.set_xlim(left=0.0)
        ax.set_ylim(bottom=0.0)
        return fig

    def _paths_figure(
        self, ridge: paths.Ridge | None, mid: np.ndarray, s: dict[str, Any]
    ) -> Figure:
        p, res = self.p, self.results
        w, hgt = p.source.plate.width, p.source.plate.height
        fig = Figure(figsize=(15.0, 6.0), layout="constrained")
        ax, zx, dx_ax = fig.subplots(1, 3, gridspec_kw={"width_ratios": [1, 1.3, 1.2]})
        pr = res.get("ccm_pd")
        boxes = []
        if pr is not None and isinstance(pr.meta.get("pd_regions"), list):
            boxes = pr.meta["pd_regions"]  # several for an adaptive region
        for a, zoom in ((ax, False), (zx, True)):
            a.add_patch(Rectangle((0, 0), w, hgt, fill=False, ec="k", lw=1.0))
            _draw_holes(a, self.scenes["xfem"].to_dict(), w, hgt)
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
            dx_ax.text(
                0.5, 0.5, st.get("status", "no path"), ha="center", transform=dx_ax.transAxes
            )
        return fig


def _draw_holes(ax: Any, d: Mapping[str, Any], w: float, hgt: float) -> None:
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


def _path_csv(ridge: paths.Ridge, xr: Result) -> str:
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


def _f(v: Any, spec: str = ".4g") -> str:
    return study.fmt(v, spec, finite=True)


def _markdown(s: dict[str, Any]) -> str:
    d = s["discretisation"]
    lines = [
        "## Choices made",
        "",
        *(f"- {n}" for n in s["notes"]),
        "",
        "## Crack paths",
        "",
    ]
    st = s.get("path", {})
    if "mean" in st:
        lines += [
            "The PD ridge (the centroid, across the XFEM path, of the midpoints of the bonds the "
            f"SLA broke, in strips {RIDGE_WINDOW_SPACINGS:g} dx long every dx) against the grown "
            "XFEM path:",
            "",
            *study.table(
                ["distance", "length", "horizons", "XFEM elements"],
                (
                    [k, _f(st[k]), _f(st[k + "_horizons"], ".3f"), _f(st[k + "_elements"], ".3f")]
                    for k in ("mean", "max")
                ),
            ),
            "",
            f"Stations: {st['n_stations']}, covered by broken bonds: {st['covered']:.0%} (up to "
            f"s = {_f(st['covered_length'])} of the XFEM path's {_f(st['path_length'])}); "
            f"broken bonds farther than {_f(st['strip_half_width'])} from the XFEM path: "
            f"{st['off_path_bonds']:.1%} of {st['n_bonds']}.",
            "",
        ]
    else:
        lines += [f"No comparison: {st.get('status', 'n/a')}.", ""]
    cur = s.get("curves")
    if cur:
        lines += [f"## Load-response curves: {cur['y']} against {cur['x']}", ""]
        pk = cur.get("peak")
        if pk:
            lines += [
                *study.table(
                    [None, "XFEM", "CCM-PD", "CCM-PD / XFEM - 1"],
                    [
                        [
                            f"peak {cur['y']}",
                            _f(pk["xfem"][1]),
                            _f(pk["ccm_pd"][1]),
                            _f(pk["rel_diff"], "+.2%"),
                        ],
                        [f"{cur['x']} at the peak", _f(pk["xfem"][0]), _f(pk["ccm_pd"][0]), None],
                    ],
                ),
                "",
            ]
        ag = cur.get("agreement")
        if ag:
            lines += [
                f"Along the curve, at equal {cur['x']} (XFEM interpolated; the SLA saw-tooth read "
                f"three ways, running mean over {ag['window']} steps): PD / XFEM - 1",
                "",
                *study.agreement_table(ag),
                "",
            ]
    lines += [
        "## Energy audit (rustfrac.energy)",
        "",
        *study.energy_table(s.get("energy", {})),
        "",
        "## Cost",
        "",
        *study.table(
            ["method", "wall time (s)", "unknowns", "steps", "status", "PD nodes", "solver"],
            (
                [
                    k,
                    f"{v['wall_time_s']:.3f}",
                    f"{v['unknowns']}",
                    f"{v.get('steps')}",
                    f"{v.get('status')}",
                    f"{v.get('pd_nodes', '')}",
                    f"{v.get('solver', '')}",
                ]
                for k, v in s.get("cost", {}).items()
            ),
        ),
    ]
    lines += ["", f"Whole job: {s.get('total_s', 0):.1f} s. Scenes: `summary.json` (`scenes`).", ""]
    lead = (
        f"rustfrac {s['version']}; XFEM element size h = {_f(d['xfem_h'])}, PD dx = "
        f"{_f(d['pd_dx'])}, m = {d['pd_m']} (horizon delta = {_f(d['delta'])})"
    )
    title = f"rustfrac compare: {s['scene'].get('name', 'scene')}"
    return study.summary_markdown(s, title, lead, lines)
