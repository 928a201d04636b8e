"""Ready-made scenes. Every default is the paper's value (N, mm, MPa)."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

from .scene import (
    Crack,
    Load,
    Material,
    MeshOptions,
    PdOptions,
    Plate,
    Scene,
    XfemOptions,
)

__all__ = ["edge_crack_plate"]


def edge_crack_plate(
    method: str = "fem",
    *,
    a0: float = 1.1,
    mesh: tuple[int, int] = (44, 83),
    bc: str = "free",
    crack: str | None = None,
    width: float = 11.0,
    height: float = 21.0,
    crack_y: float = 10.5,
    crack_angle: float = 0.0,
    crack_x: float = 5.5,
    E: float = 10000.0,
    nu: float = 0.25,
    G0: float = 0.367,
    plane: str = "strain",
    thickness: float = 1.0,
    u0: float = 0.01,
    traction: float = 9.993,
    gauss: int = 2,
    nsub: int = 4,
    tip_nsub: int = 0,
    r_I: float = 2.5,
    fixed_area_radius: float = 0.0,
    area_threshold: float = 1e-4,
    growth_steps: int = 0,
    da: float = 0.0,
    a_stop: float = 0.0,
    dx: float = 1.0 / 15.0,
    m: int = 4,
    pd_center: tuple[float, float] = (1.70, 10.5),
    pd_size: tuple[float, float] = (2.73, 1.67),
    sla_steps: int = 500,
    tie_tol: float = 0.0,
    refactor_every: int = 0,
    fast: bool = True,
    stop_crack_length: float = 0.0,
    damage_at_steps: tuple[int, ...] | list[int] = (),
    checkpoint_every: int = 0,
    checkpoint_path: str = "",
    resume_from: str = "",
    name: str = "",
    cracks: Sequence[Crack | Mapping[str, Any]] | None = None,
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
        dx, m, pd_center, pd_size, sla_steps: PD grid spacing, horizon factor (delta = m dx),
            PD rectangle of the CCM-PD model (pure PD covers the plate), and SLA steps.
        tie_tol, refactor_every, fast, stop_crack_length, damage_at_steps, checkpoint_every,
            checkpoint_path, resume_from: SLA options (see :class:`~rustfrac.scene.PdOptions`).
        cracks: XFEM only: several cracks, each a :class:`~rustfrac.scene.Crack` or a dict of
            its keys (e.g. ``{"kind": "edge", "side": "right", "a0": 1.1, "y": 10.5}``), in place
            of the single crack that ``crack``, ``a0``, ``crack_y``, ``crack_angle`` and
            ``crack_x`` describe; the first is the primary crack (CMOD, history ``a``).

    Every value is validated; bad ones raise :class:`~rustfrac.errors.InvalidParameterError`.
    """
    if crack is None:
        crack = "seam" if method == "fem" else "edge"
    try:
        nx, ny = mesh
    except (TypeError, ValueError):
        from .errors import InvalidTypeError

        raise InvalidTypeError(f"mesh must be a pair (nx, ny), got {mesh!r}", "mesh") from None
    return Scene(
        method=method,
        name=name,
        plate=Plate(width=width, height=height),
        material=Material(E=E, nu=nu, plane=plane, thickness=thickness, G0=G0),
        load=Load(bc=bc, u0=u0, traction=traction),
        crack=(
            Crack(kind=crack, a0=a0, y=crack_y, angle=crack_angle, x=crack_x)
            if cracks is None
            else list(cracks)  # type: ignore[arg-type]  # Scene splits and validates the list
        ),
        mesh=MeshOptions(nx=nx, ny=ny, gauss=gauss),
        xfem=XfemOptions(
            nsub=nsub,
            tip_nsub=tip_nsub,
            r_I=r_I,
            fixed_area_radius=fixed_area_radius,
            area_threshold=area_threshold,
            growth_steps=growth_steps,
            da=da,
            a_stop=a_stop,
        ),
        pd=PdOptions(
            dx=dx,
            m=m,
            center=pd_center,
            size=pd_size,
            sla_steps=sla_steps,
            tie_tol=tie_tol,
            refactor_every=refactor_every,
            fast=fast,
            stop_crack_length=stop_crack_length,
            damage_at_steps=damage_at_steps,
            checkpoint_every=checkpoint_every,
            checkpoint_path=checkpoint_path,
            resume_from=resume_from,
        ),
    )
