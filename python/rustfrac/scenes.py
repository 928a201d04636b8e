"""Ready-made scenes. Every default is the paper's value (N, mm, MPa), as the core defines it."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

from .errors import InvalidTypeError, UnknownParameterError
from .scene import METHOD_SECTIONS, Crack, Scene, keys

__all__ = ["edge_crack_plate"]

#: keyword names of :func:`edge_crack_plate` that differ from their scene key
_ALIASES: dict[str, tuple[str, str]] = {
    "crack": ("crack", "kind"),
    "crack_y": ("crack", "y"),
    "crack_angle": ("crack", "angle"),
    "crack_x": ("crack", "x"),
    "crack_side": ("crack", "side"),
    "pd_center": ("pd", "center"),
    "pd_size": ("pd", "size"),
}
#: the sections of the paper's plate (the methods' tables, not the general scene's lists)
_PLATE_SECTIONS = set().union(*METHOD_SECTIONS.values()) - {"crack"}
#: every other keyword is the scene key of that name (the key names are unique across these
#: sections)
_KEYS: dict[str, tuple[str, str]] = {
    **{k["key"]: (k["section"], k["key"]) for k in keys() if k["section"] in _PLATE_SECTIONS},
    **{k["key"]: ("crack", k["key"]) for k in keys("crack") if k["key"] == "a0"},
    **_ALIASES,
}


def edge_crack_plate(
    method: str = "fem",
    *,
    mesh: tuple[int, int] | None = None,
    cracks: Sequence[Crack | Mapping[str, Any]] | None = None,
    name: str = "",
    **overrides: Any,
) -> Scene:
    """The paper's edge-cracked plate (section 3).

    Plate W x L = 11 x 21 (x1 x x2), edge crack along x2 = 10.5 from x1 = 0 to a0 = 1.1,
    E = 10000, nu = 0.25, plane strain, thickness 1, G0 = 0.367; u2 = +-u0 = +-0.01 on the top
    and bottom edges (``bc="free"``: u1 free; ``"clamped"``: u1 = 0; ``"traction"``: uniform
    stress ``traction`` = 9.993).

    Args:
        method: "fem" (plain Q4; ``crack`` "seam" or "none"), "xfem", "pd" or "ccm_pd".
        a0: crack length. mesh: (nx, ny) Q4 elements (FEM/XFEM; the paper's XFEM mesh 44 x 83).
        bc: "free" | "clamped" | "traction".
        crack: "none" | "seam" (fem), "edge" | "center" (xfem), "none" | "edge" (pd, ccm_pd);
            default "seam" for fem, else "edge".
        crack_y, crack_angle, crack_x: height of the crack (its centre for "center"), its angle
            in degrees from x1 (xfem only; 0 elsewhere), centre x1 of a "center" crack.
        nsub, tip_nsub, r_I, fixed_area_radius, area_threshold, growth_steps, da, a_stop: XFEM
            options (see :class:`~rustfrac.scene.XfemOptions`: sub-quads per direction (4), in
            tip elements (0 = nsub), I-integral radius in element lengths (2.5), fixed-area tip
            enrichment radius (0 = off), small-area threshold (1e-4), growth steps (0 = the
            reference load only), extension per step (0 = one element length), stop length
            (0 = 0.7 width)). Growth uses ``G0``.
        kink_rule: XFEM growth direction: "hoop" (the maximum hoop stress criterion at the tip,
            one solve per step; the default) or "predictor_corrector" (a trial extension and the
            bisector of the two hoop directions, two solves per step, no zig-zag on curving
            paths).
        dx, m, pd_center, pd_size, sla_steps: PD grid spacing, horizon factor (delta = m dx),
            PD rectangle of the CCM-PD model (pure PD covers the plate), and SLA steps.
        fem_grading, fem_coarse: CCM-PD graded FEM grid: growth ratio away from the PD
            rectangle (1 = uniform dx, the default) and largest element in dx (8).
        tie_tol, refactor_every, fast, engine, stop_crack_length: SLA options (see
            :class:`~rustfrac.scene.PdOptions`).
        s0_calibration: the critical stretch: "continuum" (eq. 48, the paper's; default),
            "grid" or "sla" (s0 rescaled so that the grid's discrete fracture energy, or the
            SLA's release in a reference strip, is G0; ``meta["s0_calibration"]``).
        damage_at_steps, checkpoint_every, checkpoint_path, resume_from: SLA outputs and
            checkpoints (see :class:`~rustfrac.scene.PdOptions`).
        cracks: XFEM only: several cracks, each a :class:`~rustfrac.scene.Crack` or a dict of
            its keys (e.g. ``{"kind": "edge", "side": "right", "a0": 1.1, "y": 10.5}``), in place
            of the single crack that ``crack``, ``a0``, ``crack_y``, ``crack_angle`` and
            ``crack_x`` describe; the first is the primary crack (CMOD, history ``a``).

    Every value is validated; bad ones raise :class:`~rustfrac.errors.InvalidParameterError`.
    """
    sections: dict[str, dict[str, Any]] = {}
    for kw, v in overrides.items():
        if kw not in _KEYS:
            raise UnknownParameterError(
                f"unknown keyword {kw!r} of edge_crack_plate; allowed: mesh, cracks, name, "
                + ", ".join(sorted(_KEYS)),
                kw,
            )
        sec, key = _KEYS[kw]
        sections.setdefault(sec, {})[key] = v
    if mesh is not None:
        try:
            nx, ny = mesh
        except (TypeError, ValueError):
            raise InvalidTypeError(f"mesh must be a pair (nx, ny), got {mesh!r}", "mesh") from None
        sections.setdefault("mesh", {}).update(nx=nx, ny=ny)
    d: dict[str, Any] = {"method": method, "name": name, **sections}
    if cracks is not None:
        d["crack"] = [c.to_dict() if isinstance(c, Crack) else c for c in cracks]
    return Scene.from_dict(d)
