"""The numbers of a comparison (:mod:`rustfrac.compare`): the summary (the paths' distance, the
curves' agreement, the energy audits, the cost) and its markdown."""

from __future__ import annotations

from typing import Any

import numpy as np

from .. import agreement, paths, study
from ..errors import PlotDataError
from ..result import Result
from ..scene import Scene
from .plan import Plan
from .ridge import (
    RIDGE_WINDOW_SPACINGS,
    bond_midpoints,
    grown_path,
    path_agreement,
    response_pair,
    sla_broken_bonds,
    window,
)

__all__ = ["job_summary", "markdown", "ridge_of"]


def ridge_of(
    p: Plan, results: dict[str, Result]
) -> tuple[dict[str, Any], paths.Ridge | None, np.ndarray]:
    """The path statistics, the PD ridge and the broken bonds' midpoints of the runs
    ``results`` (a status only when a run is missing)."""
    xr, pr = results.get("xfem"), results.get("ccm_pd")
    if xr is None or pr is None:
        return {"status": "a run is missing"}, None, np.zeros((0, 2))
    mid = bond_midpoints(pr, sla_broken_bonds(pr))
    stats, ridge = path_agreement(grown_path(xr), mid, p.dx, p.delta, p.h)
    return stats, ridge, mid


def job_summary(
    p: Plan, scenes: dict[str, Scene], results: dict[str, Result], times: dict[str, float]
) -> dict[str, Any]:
    """The summary of a comparison's runs (without the files and the job's total time)."""
    from .. import __version__

    res = results
    s: dict[str, Any] = {
        "version": __version__,
        "scene": p.source.to_dict(),
        "scenes": {k: v.to_dict() for k, v in scenes.items()},
        "machine": study.machine(),
        "notes": list(p.notes),
        "discretisation": {"xfem_h": p.h, "pd_dx": p.dx, "pd_m": p.m, "delta": p.delta},
    }
    stats, _, _ = ridge_of(p, results)
    s["path"] = stats
    if "xfem" in res and "ccm_pd" in res:
        xk, yk = response_pair(res["xfem"])
        xh, ph = res["xfem"].history, res["ccm_pd"].history
        s["curves"] = {"x": xk, "y": yk}
        if len(xh.get(xk, [])) > 1 and len(ph.get(xk, [])) > 2:
            cur = agreement.compare(xh[xk], xh[yk], ph[xk], ph[yk], window(len(ph[xk])))
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
        row: dict[str, Any] = {"wall_time_s": times[k], "unknowns": r.n_dofs}
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


def _f(v: Any, spec: str = ".4g") -> str:
    return study.fmt(v, spec, finite=True)


def markdown(s: dict[str, Any]) -> str:
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
