"""Ready-made scenes. Every default is the paper's value (N, mm, MPa)."""

from __future__ import annotations

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
    E: float = 10000.0,
    nu: float = 0.25,
    G0: float = 0.367,
    plane: str = "strain",
    thickness: float = 1.0,
    u0: float = 0.01,
    traction: float = 9.993,
    gauss: int = 2,
    nsub: int = 4,
    r_I: float = 2.5,
    growth_steps: int = 0,
    da: float = 0.25,
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
    name: str = "",
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
        crack: "none" | "seam" (fem) | "edge" (others); default "seam" for fem, else "edge".
        nsub, r_I, growth_steps, da: XFEM sub-quads per direction, I-integral radius (element
            lengths), crack growth steps and increment.
        dx, m, pd_center, pd_size, sla_steps: PD grid spacing, horizon factor (delta = m dx),
            PD rectangle of the CCM-PD model (pure PD covers the plate), and SLA steps.
        tie_tol, refactor_every, fast, stop_crack_length, damage_at_steps: SLA options (see
            :class:`~rustfrac.scene.PdOptions`).

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
        crack=Crack(kind=crack, a0=a0, y=crack_y),
        mesh=MeshOptions(nx=nx, ny=ny, gauss=gauss),
        xfem=XfemOptions(nsub=nsub, r_I=r_I, growth_steps=growth_steps, da=da),
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
        ),
    )
