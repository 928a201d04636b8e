"""The numbers of a fig7 job (:mod:`rustfrac.fig7`): the summary (ours beside the paper's,
the two methods' agreement at the peak and along the curve, the energy audit, the cost) and its
markdown."""

from __future__ import annotations

from typing import Any

import numpy as np

from .. import agreement, study
from ..result import Result
from ..scene import Scene
from .presets import PAPER, Preset

__all__ = ["curve_agreement", "job_summary", "markdown", "peak", "rel", "split_line"]


def peak(res: Result) -> tuple[float, float]:
    """(peak sigma22, CMOD at the peak) of a load path."""
    s, c = res.history["sigma22"], res.history["cmod"]
    i = int(np.argmax(s))
    return float(s[i]), float(c[i])


def curve_agreement(results: dict[str, Result]) -> dict[str, Any]:
    """The CCM-PD saw-tooth against the XFEM growth curve at equal CMOD (:mod:`.agreement`)."""
    xh, ph = results["xfem_growth"].history, results["ccm_pd"].history
    return agreement.compare(xh["cmod"], xh["sigma22"], ph["cmod"], ph["sigma22"])


def rel(a: float, b: float) -> float:
    return (a - b) / b if b else float("nan")


def job_summary(
    results: dict[str, Result],
    times: dict[str, float],
    p: Preset,
    preset: str,
    bc: str,
    scenes: dict[str, Scene],
    interrupted: bool,
) -> dict[str, Any]:
    from .. import __version__

    s: dict[str, Any] = {
        "version": __version__,
        "preset": preset,
        "preset_description": p.description,
        "bc": bc,
        "interrupted": interrupted,
        "machine": study.machine(),
        "paper": PAPER,
        "scenes": {k: v.to_dict() for k, v in scenes.items()},
        "times_s": times,
        "ours": {},
    }
    ours = s["ours"]
    if "xfem" in results:
        r = results["xfem"]
        ours.update(sigma22_xfem=r.sigma22, cmod_xfem=r.cmod, K_I_displacement=r.K_I)
    if "xfem_traction" in results:
        ours["K_I_traction"] = results["xfem_traction"].K_I
    if "ccm_pd" in results:
        r = results["ccm_pd"]
        ours.update(sigma22_ccm_pd=r.sigma22, cmod_ccm_pd=r.cmod, gamma=r.gamma)
    if "xfem_growth" in results:
        r = results["xfem_growth"]
        ps, pc = peak(r)
        ours.update(
            peak_sigma22_xfem=ps,
            cmod_at_peak_xfem=pc,
            xfem_growth_status=r.meta.get("status"),
            xfem_final_a=float(r.history["a"][-1]),
        )
    if "ccm_pd" in results:
        r = results["ccm_pd"]
        ps, pc = peak(r)
        ours.update(
            peak_sigma22_ccm_pd=ps,
            cmod_at_peak_ccm_pd=pc,
            ccm_pd_status=r.meta.get("status"),
            ccm_pd_steps=len(r.history["sigma22"]) - 1,
        )
    if "peak_sigma22_xfem" in ours and "peak_sigma22_ccm_pd" in ours:
        s["agreement"] = {
            "peak_sigma22_rel_diff": rel(ours["peak_sigma22_ccm_pd"], ours["peak_sigma22_xfem"]),
            "cmod_at_peak_rel_diff": rel(ours["cmod_at_peak_ccm_pd"], ours["cmod_at_peak_xfem"]),
            "initial_cmod_rel_diff": rel(ours["cmod_ccm_pd"], ours["cmod_xfem"]),
            "initial_sigma22_rel_diff": rel(ours["sigma22_ccm_pd"], ours["sigma22_xfem"]),
        }
        cur = curve_agreement(results)
        s["agreement"]["curve"] = {k: v for k, v in cur.items() if k != "curves"}
    audits = {}
    for part, key in (("xfem_growth", "xfem"), ("ccm_pd", "ccm_pd")):
        if part in results and results[part].meta.get("work_conjugate"):
            audits[key] = study.audit(results[part])
    if audits:
        s["energy"] = audits
    s["cost"] = {
        "xfem_s": sum(v for k, v in times.items() if k.startswith("xfem_growth")),
        "ccm_pd_s": times.get("ccm_pd"),
        "paper_xfem_s": PAPER["time_xfem_s"],
        "paper_ccm_pd_s": PAPER["time_ccm_pd_s"],
    }
    return s


def markdown(s: dict[str, Any]) -> str:
    o, pa = s["ours"], s["paper"]
    lines = [
        "## Paper values beside ours",
        "",
        *study.table(
            ["quantity", "paper", "rustfrac"],
            [
                ["sigma22, XFEM, u0 = 0.01", pa["sigma22_xfem"], study.fmt(o.get("sigma22_xfem"))],
                ["CMOD, XFEM", pa["cmod_xfem"], study.fmt(o.get("cmod_xfem"))],
                [
                    "K_I, XFEM, displacement load",
                    pa["K_I_displacement"],
                    study.fmt(o.get("K_I_displacement")),
                ],
                ["K_I, XFEM, traction 9.993", pa["K_I_traction"], study.fmt(o.get("K_I_traction"))],
                [
                    "sigma22, CCM-PD, before any break",
                    pa["sigma22_ccm_pd"],
                    study.fmt(o.get("sigma22_ccm_pd")),
                ],
                ["CMOD, CCM-PD", pa["cmod_ccm_pd"], study.fmt(o.get("cmod_ccm_pd"))],
                ["gamma (m = 4)", "0.988895997195466", study.fmt(o.get("gamma"), ".15g")],
            ],
        ),
        "",
        "The paper's values are a comparison, not the truth: its plate is loaded through grips and "
        "its 44 x 83 mesh is not converged (see the README's validation section).",
        "",
    ]
    if "agreement" in s:
        ag = s["agreement"]
        lines += [
            "## Agreement between the two methods",
            "",
            *study.table(
                [None, "XFEM", "CCM-PD", "relative difference"],
                [
                    [
                        "peak sigma22",
                        study.fmt(o["peak_sigma22_xfem"]),
                        study.fmt(o["peak_sigma22_ccm_pd"]),
                        f"{ag['peak_sigma22_rel_diff']:+.2%}",
                    ],
                    [
                        "CMOD at the peak",
                        study.fmt(o["cmod_at_peak_xfem"]),
                        study.fmt(o["cmod_at_peak_ccm_pd"]),
                        f"{ag['cmod_at_peak_rel_diff']:+.2%}",
                    ],
                    [
                        "initial CMOD (u0 = 0.01)",
                        study.fmt(o["cmod_xfem"]),
                        study.fmt(o["cmod_ccm_pd"]),
                        f"{ag['initial_cmod_rel_diff']:+.2%}",
                    ],
                ],
            ),
            "",
        ]
        cur = ag.get("curve")
        if cur:
            lines += [
                "Along the curve, at equal CMOD (the XFEM curve interpolated; CCM-PD read three "
                f"ways, running mean over {cur['window']} steps): PD / XFEM - 1",
                "",
                *study.agreement_table(cur, "CMOD range"),
                "",
            ]
    if s.get("energy"):
        lines += [
            "## Energy audit (rustfrac.energy)",
            "",
            "Energy dissipated per unit of new crack area, from the load path alone (XFEM: between "
            "successive secants of the critical states; CCM-PD: released at each SLA break, over "
            "the damage front's advance), against G0:",
            "",
            *study.energy_table(s["energy"], ".5g", finite=False),
            "",
        ]
    c = s["cost"]
    lines += [
        "## Cost",
        "",
        *study.table(
            ["method", "paper (laptop, Mathematica / MATLAB)", "rustfrac"],
            [
                ["XFEM growth", f"{c['paper_xfem_s']} s", f"{study.fmt(c['xfem_s'], '.3f')} s"],
                ["CCM-PD, SLA", f"{c['paper_ccm_pd_s']} s", f"{study.fmt(c['ccm_pd_s'], '.3f')} s"],
            ],
        ),
        "",
        split_line(s),
        f"Whole job: {s.get('total_s', 0):.1f} s. Growth status: XFEM "
        f"{o.get('xfem_growth_status', 'n/a')} (final a = {study.fmt(o.get('xfem_final_a'))}), "
        f"CCM-PD {o.get('ccm_pd_status', 'n/a')} after {o.get('ccm_pd_steps', 'n/a')} steps.",
        "",
        "Scenes used: see `summary.json` (`scenes`).",
        "",
    ]
    lead = (
        f"rustfrac {s['version']}, preset `{s['preset']}` ({s['preset_description']}), grips "
        f"`{s['bc']}`"
    )
    return study.summary_markdown(s, "rustfrac Fig. 7 reproduction", lead, lines, platform=True)


def split_line(s: dict[str, Any]) -> str:
    """The job's time split (``time_split_s``) as one line of summary.md."""
    t = s.get("time_split_s")
    if not t:
        return ""
    return (
        f"Job time: computation {t['compute']:.2f} s (of it, figures drawn beside the CCM-PD "
        f"run {t.get('figures_beside_runs', 0.0):.2f} s), figures {t['figures']:.2f} s, result "
        f"folders {t.get('files', 0.0):.2f} s (beyond the figures, beside which they are "
        f"written), summaries {t['summaries']:.2f} s, other {t['other']:.2f} s (total "
        f"{t['total']:.2f} s; interpreter start-up, imports and the result folders' commit, "
        "after this summary, not included)."
    )
