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
import secrets
import time
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from .. import study
from .._folder import check_writable, with_fallback, writing
from .._log import logger
from ..pd_region import DEFAULT_MARGIN_HORIZONS, Box
from ..result import OWNED_NAMES, Result, save_result
from ..scene import Scene
from ..study import Log, ProgressFactory, run_logged
from .drawings import drawings
from .place import place

# "X as X": names kept where they were before the package (rustfrac.compare.X)
from .plan import COMPARE_A_STOP_FRACTION as COMPARE_A_STOP_FRACTION
from .plan import DEFAULT_GROWTH_STEPS, Plan, fitting_spacings, plan
from .plan import PD_DOFS_BUDGET as PD_DOFS_BUDGET
from .plan import SLA_STEPS_PER_SPACING_M3 as SLA_STEPS_PER_SPACING_M3
from .ridge import RIDGE_HALF_WIDTH_HORIZONS as RIDGE_HALF_WIDTH_HORIZONS
from .ridge import RIDGE_WINDOW_SPACINGS as RIDGE_WINDOW_SPACINGS
from .ridge import bond_midpoints, grown_path, path_agreement, response_pair, sla_broken_bonds
from .summary import job_summary, markdown

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

#: the comparison's helpers under the names its tests know
_bond_midpoints = bond_midpoints
_fitting_spacings = fitting_spacings

#: the files of a compare folder (the result folders xfem/ and ccm_pd/ besides)
FILES = ("compare.png", "curves.png", "curves.csv", "path.csv", "summary.md", "summary.json")
#: folder name of each run saved as a result folder
PARTS = {"xfem": "xfem", "ccm_pd": "ccm_pd"}


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
            s = job_summary(self.p, self.scenes, self.results, self.times)
            files, stopped = w.stage_each(drawings(self.p, self.scenes, self.results, s))
            interrupted = self.interrupted or stopped
            s["interrupted"] = interrupted
            s["total_s"] = time.perf_counter() - self.t_all
            s["files"] = [*files, "summary.md", "summary.json"]
            s["parts"] = parts
            s["missing"] = study.missing(PARTS, PARTS, FILES, self.results, s["files"])
            s["complete"] = not interrupted and not s["missing"]
            study.write_summary(w, s, markdown(s))
        return s
