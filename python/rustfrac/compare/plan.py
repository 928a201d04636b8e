"""The two scenes of a comparison (:mod:`rustfrac.compare`): from one scene of any method, the
XFEM growth scene and the CCM-PD scene (without its rectangle until the XFEM path is known), and
the choices made deriving them."""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import InvalidParameterError
from ..pd_region import DEFAULT_MARGIN_HORIZONS, Box, cut_hole
from ..runner import as_scene
from ..scene import METHODS, PD_NU, PdOptions, Scene
from ..specimens import pd_layout

__all__ = [
    "COMPARE_A_STOP_FRACTION",
    "DEFAULT_GROWTH_STEPS",
    "PD_DOFS_BUDGET",
    "SLA_STEPS_PER_SPACING_M3",
    "Plan",
    "element_size",
    "fitting_spacings",
    "fmt_box",
    "plan",
    "stated_region",
]

#: XFEM growth steps when the scene sets none (full run, ``quick``)
DEFAULT_GROWTH_STEPS = {False: 24, True: 4}
#: XFEM edge cracks grow up to this fraction of the plate's width (height for bottom / top
#: cracks) when the scene sets no xfem.a_stop (the comparison's own stop, beyond the core's 0.7 W
#: default for a single run: the two methods are compared along a long path)
COMPARE_A_STOP_FRACTION = 0.9
#: SLA steps allowed per grid spacing of crack advance, per m^3 (a crack front of m = 3 breaks
#: about 25 bonds per dx, measured on the edge crack under shear), before stop_crack_length
SLA_STEPS_PER_SPACING_M3 = 2.0
#: the comparison's cost budget: most free PD dofs of the fixed rectangle (the core's SLA runs any
#: size, its engine chosen by cost, `pd.engine`; past this a step costs more than the whole XFEM
#: growth of a typical scene, so larger rectangles need ``allow_slow``)
PD_DOFS_BUDGET = 6000


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


def element_size(d: dict[str, Any], width: float, height: float) -> float | None:
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


def fitting_spacings(width: float, height: float, upto: float) -> list[float]:
    """Grid spacings that fit the plate (width / dx and height / dx whole numbers), from the
    largest one not above ``upto`` to coarser ones (at least 4 cells across)."""
    out = []
    for n in range(max(math.floor(width / upto + 1e-9), 1), 3, -1):
        dx = width / n
        k = height / dx
        if abs(k - round(k)) < 1e-9 * max(k, 1.0):
            out.append(dx)
    return out


def stated_region(scene: Scene) -> Box | None:
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
    h = element_size(d, width, height)
    m = int(m if m is not None else pd_in.get("m", PdOptions().m))
    dx_auto = dx is None and "dx" not in pd_in
    if dx is None:
        if "dx" in pd_in:
            dx = float(pd_in["dx"])
        else:
            fit = fitting_spacings(width, height, h if h is not None else PdOptions().dx)
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
        given = stated_region(src)
    if given is not None:
        k = cut_hole(given, common.get("hole", []), (width, height), dx)
        if k is not None:
            raise InvalidParameterError(
                f"invalid region: the PD rectangle {fmt_box(given)} cuts hole[{k}] (the hybrid "
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


def fmt_box(b: Box) -> str:
    """A rectangle (x0, y0, x1, y1) as "[x0, x1] x [y0, y1]" for messages and notes."""
    return f"[{b[0]:.4g}, {b[2]:.4g}] x [{b[1]:.4g}, {b[3]:.4g}]"
