"""The PD region of a comparison's CCM-PD scene (:mod:`rustfrac.compare`), once the XFEM path is
known: the stated rectangle, :func:`~rustfrac.pd_region.pd_region` around the path within the
comparison's budget, or the adaptive region; its SLA steps and stop length."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from .._log import logger
from ..errors import InvalidParameterError
from ..pd_region import Box, held_sides, pd_dofs, pd_region
from ..scene import MAX_STEPS, Scene
from ..specimens import pd_layout
from .plan import PD_DOFS_BUDGET, SLA_STEPS_PER_SPACING_M3, Plan, fitting_spacings, fmt_box

__all__ = ["adaptive_instead", "place", "with_sla_length"]


def _held_path(p: Plan, xfem_path: np.ndarray) -> np.ndarray:
    """What the rectangle must hold: the grown XFEM path and, when it is inclined, the whole
    pre-crack (the core refuses a CCM-PD pre-crack whose inclined part leaves the rectangle: in
    the FEM part it would cut the elements into a staircase that leaves nodes without
    stiffness)."""
    lines = p.xfem.crack_polylines()
    if not lines:
        return xfem_path
    pre = np.asarray(lines[0], dtype=float)
    d = np.abs(np.diff(pre, axis=0))
    inclined = bool(np.any((d[:, 1] > 1e-12 * d[:, 0]) & (d[:, 0] > 1e-12 * d[:, 1])))
    return np.vstack([pre, xfem_path]) if inclined else xfem_path


def place(p: Plan, xfem_path: np.ndarray, final_tip: Sequence[float] | None) -> Scene:
    """The CCM-PD scene of plan ``p`` with its rectangle (the stated one, or
    :func:`~rustfrac.pd_region.pd_region` around ``xfem_path``, an inclined pre-crack included),
    its SLA steps and its stop length.
    Coarsens an automatic dx to keep the budget ``PD_DOFS_BUDGET``; refuses a given dx / rectangle
    beyond it unless ``p.allow_slow``."""
    if p.adaptive:
        p.notes.append(
            "adaptive PD region: squares around the tip grown ahead of the crack (pd.adapt_margin, "
            "pd.adapt_size); no rectangle budget"
        )
        return with_sla_length(p, p.dx, final_tip)
    w, hgt = p.source.plate.width, p.source.plate.height
    holes = p.pd.get("hole", [])
    cands = [p.dx]
    if p.dx_auto and p.region_given is None:
        cands += [v for v in fitting_spacings(w, hgt, p.dx * (1 - 1e-9)) if v > p.dx]
    box: Box | None = p.region_given
    held_path = _held_path(p, xfem_path)
    for dx in cands:
        box = p.region_given or pd_region(
            held_path,
            (w, hgt),
            dx,
            p.m,
            holes=holes,
            held=sorted(held_sides(p.pd)),
            margin_horizons=p.margin_horizons,
        )
        if box is None:
            return adaptive_instead(p, final_tip)
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
            f"the PD rectangle {fmt_box(box)} at dx = {dx:.6g} holds about {n} free PD dofs, "
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
        p.notes.append(f"PD rectangle {fmt_box(box)} as given")
    else:
        p.notes.append(
            f"fixed PD rectangle {fmt_box(box)}: the XFEM path's bounding box plus "
            f"{p.margin_horizons:g} horizons"
            + ("; holes taken in whole or kept clear of its boundary" if holes else "")
            + " (adaptive CCM-PD not used)"
        )
    opts = p.pd["pd"]
    opts["center"] = [(box[0] + box[2]) / 2, (box[1] + box[3]) / 2]
    opts["size"] = [box[2] - box[0], box[3] - box[1]]
    return with_sla_length(p, dx, final_tip)


def adaptive_instead(p: Plan, final_tip: Sequence[float] | None) -> Scene:
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
    return with_sla_length(p, p.dx, final_tip)


def with_sla_length(p: Plan, dx: float, final_tip: Sequence[float] | None) -> Scene:
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
