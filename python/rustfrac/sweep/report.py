"""The sweep's report (:mod:`rustfrac.sweep`): the CSV columns, ``sweep.md`` of the paper's
sweep and of a scene sweep, and the cost-error plots."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import Any

from .._folder import atomic_file
from ..study import fmt, table
from .analysis import pareto
from .points import QUANTITIES

CSV_KEYS: tuple[str, ...] = (
    "study", "method", "param", "value", "h", "name", "wall_time_s", "solver_time_s",
    "peak_rss_mb", "rss_before_mb", "n_dofs", "n_bonds", "n_pd_nodes", "K_I", "cmod", "sigma22",
    "peak_sigma22", "peak_step", "peak_crack_length", "n_steps",
    *(f"err_{q}" for q in QUANTITIES), *(f"err_finest_{q}" for q in QUANTITIES), "err_max",
)  # fmt: skip


def _g(v: Any, spec: str = ".4g") -> str:
    return fmt(v, spec, absent="-")


def markdown(
    records: Sequence[dict[str, Any]],
    refs: dict[str, dict[str, dict[str, Any]]],
    presets: dict[str, dict[str, Any]],
) -> str:
    lines = ["# Speed-accuracy sweep", ""]
    lines += [
        "Relative errors against the reference of each method (its refinement study: XFEM "
        "`mesh`, CCM-PD `dx`). K_I, CMOD and sigma22 at the reference load u0 = 0.01; the peak "
        "is the largest sigma22 of the load path (XFEM growth: critical states; CCM-PD: SLA "
        "steps), with its step. Time: wall time of the point in its worker (one thread). "
        "Memory: the worker's peak RSS (ru_maxrss).",
        "",
    ]
    rows = []
    for r in records:
        v = r["value"]
        val = f"1/{round(1 / v)}" if r["param"] == "dx" else str(v)
        rows.append(
            [r["method"], r["study"], val, f"{r['wall_time_s']:.3f}", f"{r['peak_rss_mb']:.0f}",
             f"{r['n_dofs']}", _g(r["n_bonds"], "d"), _g(r["K_I"], ".6g"), _g(r["cmod"], ".6g"),
             _g(r["sigma22"], ".6g"),
             f"{_g(r['peak_sigma22'], '.6g')} ({_g(r['peak_step'], 'd')}/{r['n_steps']})",
             *(_g(r[f"err_{q}"], ".2e") for q in QUANTITIES), _g(r["err_max"], ".2e")]
        )  # fmt: skip
    header = ["method", "study", "value", "time (s)", "peak RSS (MB)", "unknowns", "bonds", "K_I",
              "CMOD", "sigma22", "peak sigma22 (step)", "err K_I", "err CMOD", "err sigma22",
              "err peak", "err max"]  # fmt: skip
    lines += table(header, rows, "lll" + "r" * 13)
    lines += ["", "## References", ""]
    rows = []
    for method, qs in refs.items():
        for q, ref in qs.items():
            kind = (
                "Richardson (3 finest levels)"
                if ref["kind"] == "richardson"
                else f"finest level ({ref['why']})"
            )
            rows.append(
                [method, q, f"{ref['value']:.8g}", kind, _g(ref["rate"], ".3g"),
                 f"{ref['finest']:.8g}", f"{ref['levels']}"]
            )  # fmt: skip
    header = ["method", "quantity", "reference", "kind", "observed rate", "finest level", "levels"]
    lines += table(header, rows, "llrlrrr")
    lines += ["", "## Presets (from the Pareto front of time against err max)", ""]
    rows = []
    for method, ps in presets.items():
        for name, p in ps.items():
            tol = f"<= {p['tolerance']:g}" + ("" if p["meets_tolerance"] else " (not met)")
            if p["is_reference"]:
                tol += " (the reference level itself: error 0 by construction)"
            rows.append(
                [method, name, f"{p['point']}", f"{p['wall_time_s']:.3f}", f"{p['err_max']:.2e}",
                 tol]
            )  # fmt: skip
    header = ["method", "preset", "point", "time (s)", "err max", "tolerance"]
    lines += table(header, rows, "lllrrl")
    return "\n".join(lines) + "\n"


def plot(records: Sequence[dict[str, Any]], method: str, path: Path) -> None:
    """Log-log err max against wall time for one method, one marker per study, the Pareto front
    as a line (points with zero error, i.e. the reference itself, cannot be drawn and are
    listed in the title)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    rs = [r for r in records if r["method"] == method and r.get("err_max") is not None]
    fig, ax = plt.subplots(figsize=(6.4, 4.6))
    zero = [r["name"] for r in rs if r["err_max"] <= 0]
    for study, marker in zip(sorted({r["study"] for r in rs}), "osD^v<>"):
        pts = [r for r in rs if r["study"] == study and r["err_max"] > 0]
        if not pts:
            continue
        ax.loglog(
            [r["wall_time_s"] for r in pts], [r["err_max"] for r in pts], marker,
            label=study, alpha=0.8,
        )  # fmt: skip
        for r in pts:
            ax.annotate(str(r["value"] if r["param"] != "dx" else f"1/{round(1 / r['value'])}"),
                        (r["wall_time_s"], r["err_max"]), fontsize=7, xytext=(3, 3),
                        textcoords="offset points")  # fmt: skip
    front = [r for r in pareto(rs) if r["err_max"] > 0]
    if front:
        ax.loglog([r["wall_time_s"] for r in front], [r["err_max"] for r in front], "k-",
                  lw=0.8, label="Pareto front")  # fmt: skip
    ax.set_xlabel("wall time per point (s, one thread)")
    qs = "K_I, CMOD, sigma22, peak" if method == "xfem" else "CMOD, sigma22, peak"
    ax.set_ylabel(f"max relative error ({qs})")
    title = f"{method}: error against time"
    if zero:
        title += f"\n(zero error, not drawn: {', '.join(zero)})"
    ax.set_title(title, fontsize=9)
    ax.grid(True, which="both", alpha=0.3)
    if ax.get_legend_handles_labels()[0]:
        ax.legend(fontsize=8)
    with atomic_file(path, "wb") as f:
        fig.savefig(f, format="png", dpi=120, bbox_inches="tight")
    plt.close(fig)


#: columns of a scene sweep's ``sweep.csv`` (``q`` is written under the quantity's name)
SCENE_CSV_KEYS: tuple[str, ...] = (
    "name", "level", "value", "h", "n_dofs", "q", "err_est", "rel_err_est", "wall_time_s",
    "wall_time_spread_s", "repeats", "solver_time_s", "peak_rss_mb",
)  # fmt: skip


def cell(v: Any) -> Any:
    return "x".join(map(str, v)) if isinstance(v, (list, tuple)) else v


def scene_markdown(study: dict[str, Any]) -> str:
    """``sweep.md`` of a scene sweep: the levels and the Richardson extrapolation."""
    q, rich = study["quantity"], study["richardson"]
    lines = [
        f"# Sweep of {study['param']} ({study['method']}): {q}", "",
        f"{q} in the scene's units; h: element size sqrt(hx hy) (mesh) or dx (pd.dx), length "
        "units; time: the minimum wall time of the repeats in one worker (one thread), with "
        "their spread; err est: the level's value minus the Richardson value.", "",
    ]  # fmt: skip
    rows = (
        [f"{cell(r['level'])}", f"{r['name']}", _g(r["h"], ".5g"), f"{r['n_dofs']}",
         _g(r["q"], ".10g"), _g(r["err_est"], ".3e"), _g(r["rel_err_est"], ".2e"),
         f"{r['wall_time_s']:.4f}", f"{r['wall_time_spread_s']:.4f}"]
        for r in study["levels"]
    )  # fmt: skip
    header = ["level", "point", "h", "unknowns", q, "err est", "rel. err est", "time (s)",
              "spread (s)"]  # fmt: skip
    lines += table(header, rows, "ll" + "r" * 7)
    lines += ["", "## Richardson extrapolation (three finest levels)", ""]
    if rich["status"] == "ok":
        ratios = ", ".join(f"{x:.4g}" for x in rich["ratios"])
        lines.append(
            f"{q}* = {rich['value']:.10g}, observed rate p = {rich['rate']:.4g} (refinement "
            f"ratios {ratios}{'' if rich['constant_ratio'] else ', not constant'})."
        )
    else:
        lines.append(f"{rich['status']}: {rich['why']} (no extrapolated value).")
    if study["presets"]:
        lines += ["", "## Presets (cheapest level within the estimated relative error)", ""]
        rows = (
            [name, f"{pr['tolerance']:g}", f"{pr['point'] or '(none)'}",
             _g(pr["wall_time_s"], ".4f"), _g(pr["rel_err_est"], ".2e")]
            for name, pr in study["presets"].items()
        )  # fmt: skip
        header = ["preset", "tolerance", "point", "time (s)", "rel. err est"]
        lines += table(header, rows, "lllrr")
    return "\n".join(lines) + "\n"
