"""The Fig. 7 job's paper values, presets and scenes (:mod:`rustfrac.fig7`): the paper's plate
under the four runs (XFEM at the reference load, under traction and in growth; CCM-PD with the
SLA) at a preset's discretisation."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from .. import _core
from ..scene import Scene
from ..scenes import edge_crack_plate

__all__ = ["PAPER", "PRESETS", "Preset", "full_pd", "job_scenes"]

#: the paper's published values (section 3) and run times
PAPER: dict[str, float] = {
    "sigma22_xfem": 9.993,
    "sigma22_ccm_pd": 9.992,
    "cmod_xfem": 0.005317,
    "cmod_ccm_pd": 0.005374,
    "K_I_displacement": 19.85,
    "K_I_traction": 20.71,
    "K_I_analytical": 20.79,
    "traction": 9.993,
    "time_xfem_s": 1919.62,
    "time_ccm_pd_s": 1999.71,
}


@dataclass(frozen=True)
class Preset:
    """Discretisation of one Fig. 7 run."""

    mesh: tuple[int, int]  # XFEM elements (nx, ny)
    dx: float  # PD grid spacing
    sla_steps: int  # bond breaks
    snapshot_steps: tuple[int, int]  # XFEM growth steps shown in Fig. 8b
    description: str
    #: CCM-PD on the adaptive PD region until the crack reaches the XFEM growth's end (0.7 W):
    #: both full curves (``sla_steps`` is then only a bound)
    full_pd: bool = False


#: the job's presets by name (``rustfrac fig7 --preset NAME``)
PRESETS: dict[str, Preset] = {
    "paper": Preset((44, 83), 1.0 / 15.0, 500, (2, 8), "the paper's settings"),
    "fast": Preset((44, 83), 1.0 / 5.0, 120, (2, 8), "XFEM as the paper, coarse PD grid: seconds"),
    "full": Preset(
        (44, 83),
        1.0 / 15.0,
        20000,
        (2, 8),
        "the paper's settings, CCM-PD on the adaptive PD region to a = 0.7 W (both full "
        "curves; minutes)",
        full_pd=True,
    ),
}


def job_scenes(
    p: Preset, bc: str, s0_calibration: str | None = None, surface_correction: str | None = None
) -> dict[str, Scene]:
    growth = dict(growth_steps=400)  # until a_stop = 0.7 W (or the ligament is used up)
    # the scene states pd.s0_calibration and pd.surface_correction only when asked (the default
    # scene stays as it was)
    cal = {} if s0_calibration is None else {"s0_calibration": s0_calibration}
    if surface_correction is not None:
        cal["surface_correction"] = surface_correction
    return {
        "xfem": edge_crack_plate("xfem", mesh=p.mesh, bc=bc, name="xfem reference load"),
        "xfem_traction": edge_crack_plate(
            "xfem", mesh=p.mesh, bc="traction", traction=PAPER["traction"], name="xfem traction"
        ),
        "xfem_growth": edge_crack_plate("xfem", mesh=p.mesh, bc=bc, name="xfem growth", **growth),
        "ccm_pd": edge_crack_plate(
            "ccm_pd",
            dx=p.dx,
            sla_steps=p.sla_steps,
            bc=bc,
            name="ccm_pd SLA",
            **full_pd(p),
            **cal,
        ),
    }


def full_pd(p: Preset) -> dict[str, Any]:
    """The CCM-PD options of a full-curve preset: the adaptive region (its defaults) until the
    crack reaches the core's default XFEM stop length."""
    if not p.full_pd:
        return {}
    width = edge_crack_plate("ccm_pd").plate.width
    stop = _core.scene_constants()["DEFAULT_A_STOP_FRACTION"] * width
    return dict(region="adaptive", stop_crack_length=stop)
