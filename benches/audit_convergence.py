"""Convergence of the energy audit (``rustfrac.energy``): XFEM against its element size, CCM-PD
under delta-, m- and delta-m-refinement (Bobaru et al. 2009), on the paper's plate under the free
displacement grips (the audit needs a work-conjugate load).

For each run: the audit's G / G0 (``rustfrac.energy.audit``) over the whole crack advance and
along the crack (``rustfrac.energy.along``, bins of the damage front fixed in space), the peak
sigma22, and the softening branch at one grid-independent point: the mean sigma22 of the SLA
states whose CMOD lies within +-SOFT_WINDOW of CMOD*, the CMOD of the finest XFEM mesh of the same
run at a = A_SOFT (XFEM's critical states interpolated in a).

Series (the PD grid must fit the plate, dx = 1/n, and the pre-crack x2 = 10.5 must pass between
node rows, which needs n odd; for n even the crack is moved to x2 = 10.5 + dx / 2, whose effect
is measured by ``offset``):

- ``m``: delta fixed at 1/4, m = 2 .. 7 (dx = 1/(4m)). The paper's delta = 4/15 fits the plate
  only for m = 4 and 8 (dx = 4/(15 m) must divide 11 and 21), so the nearest delta for which every
  m fits is used.
- ``delta``: m = 4, dx = 1/5, 1/10, 1/15, 1/20, 1/25, 1/35 (delta = 4 dx).
- ``delta_m``: delta = sqrt(dx) = 1/m: (dx, m) = (1/4, 2), (1/9, 3), (1/16, 4), (1/25, 5).
- ``offset``: the paper grid (dx = 1/15, m = 4) with the crack at 10.5 and one row higher, and
  XFEM 44 x 83 at 10.5 and 10.5 + 1/32: the size of the shift's effect.
- ``xfem``: meshes 24 x 45 .. 164 x 313 (:data:`XFEM_FULL`: the crack line mid-row and the tip
  at the same fraction of its element on every level, so the levels are similar; with the tip at
  another fraction G / G0 is not monotone in h: 0.9987, 0.9992, 1.0005 at 44 x 83, 88 x 166,
  176 x 332).

Every PD run covers the same crack advance: ``pd.stop_crack_length`` = STOP (the damage front),
with ``pd.sla_steps`` only a guard. The PD rectangle scales with delta: x1 from
max(0, a0 - 3 delta) to STOP + 4 delta, x2 within +-3 delta of the crack (the paper's rectangle
is within 0.1 delta of this one at delta = 4/15).

Rates: ``rustfrac.sweep.extrapolate`` (Richardson over the three finest levels, rate in
[0.5, 6] or "not in the asymptotic range"), the successive differences, and where a reference
exists a log-log least-squares fit |q - q_ref| = C h^p over the levels with its RMS residual in
log10 (:func:`fit_rate`). References: G / G0 -> 1 (LEFM, the value XFEM must reach); the peak and
the softening point -> XFEM's Richardson value.

Usage: python benches/audit_convergence.py [--quick] [--out benches] [--m-max M]
Writes OUT/audit_convergence.csv, OUT/audit_convergence.json and OUT/audit_convergence.png.
"""

from __future__ import annotations

import argparse
import csv
import json
import math
import platform
import time
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

import rustfrac as rf
from rustfrac import energy
from rustfrac.sweep import extrapolate

A0 = 1.1
CRACK_Y = 10.5
#: the damage front every PD run reaches (the same advance for every grid)
STOP = 2.0
#: the softening point: XFEM's CMOD at this crack length
A_SOFT = 1.5
#: half-width of the CMOD window of the softening point, relative to CMOD*
SOFT_WINDOW = 0.05
#: the bins of the ratio along the crack (crack length / damage front)
BINS = (A0, 1.4, 1.7, STOP)
#: the guard on SLA steps (the runs stop on the crack length long before)
MAX_STEPS = 100_000

FULL: dict[str, list[tuple[int, int]]] = {
    "m": [(4 * m, m) for m in (2, 3, 4, 5, 6, 7)],
    "delta": [(n, 4) for n in (5, 10, 15, 20, 25, 35)],
    "delta_m": [(4, 2), (9, 3), (16, 4), (25, 5)],
}
QUICK: dict[str, list[tuple[int, int]]] = {
    "m": [(4 * m, m) for m in (2, 3, 4)],
    "delta": [(n, 4) for n in (5, 10, 15)],
    "delta_m": [(4, 2), (9, 3), (16, 4)],
}
#: XFEM meshes: ny odd (the crack line x2 = 10.5 mid-row), nearest nx 21 / 11 (square-ish
#: elements); nx = 4 mod 10 puts the tip a0 = 1.1 at the same fraction (0.4) of its element
XFEM_FULL = [(24, 45), (44, 83), (64, 123), (84, 161), (124, 237), (164, 313)]
XFEM_QUICK = [(24, 45), (44, 83), (84, 161)]


# --------------------------------------------------------------------------- rates


def fit_rate(hs: Sequence[float], qs: Sequence[float], ref: float) -> dict[str, Any]:
    """Least-squares fit of log|q - ref| = log C + p log h over the levels: {"p", "C",
    "residual" (RMS of the fit's residual in log10, 0 for an exact power law), "n"}; p and C
    None when fewer than two levels differ from ref."""
    h = np.asarray(hs, dtype=float)
    err = np.abs(np.asarray(qs, dtype=float) - ref)
    ok = (err > 0) & np.isfinite(err) & (h > 0)
    if np.count_nonzero(ok) < 2:
        return {"p": None, "C": None, "residual": None, "n": int(np.count_nonzero(ok))}
    x, y = np.log(h[ok]), np.log(err[ok])
    p, logc = np.polyfit(x, y, 1)
    res = y - (p * x + logc)
    return {
        "p": float(p),
        "C": float(math.exp(logc)),
        "residual": float(np.sqrt(np.mean(res**2)) / math.log(10)),
        "n": int(x.size),
    }


def rates(hs: Sequence[float], qs: Sequence[float], ref: float | None) -> dict[str, Any]:
    """The observed behaviour of one quantity along a series (levels coarse to fine):
    successive differences, the Richardson extrapolation of the three finest levels, and the
    fit against ``ref`` (None: no reference)."""
    q = [float(v) for v in qs]
    out: dict[str, Any] = {
        "differences": [b - a for a, b in zip(q[:-1], q[1:])],
        "richardson": extrapolate(list(hs), q),
    }
    out["fit"] = fit_rate(hs, q, ref) if ref is not None else None
    out["ref"] = ref
    return out


# --------------------------------------------------------------------------- runs


def crack_y(n: int) -> float:
    """The pre-crack's x2 on the grid dx = 1/n: 10.5 between node rows (n odd), else dx/2 up."""
    return CRACK_Y if n % 2 else CRACK_Y + 0.5 / n


def pd_scene(n: int, m: int, y: float | None = None) -> rf.Scene:
    """The CCM-PD scene of one level: grid dx = 1/n, horizon m dx, the rectangle of the module
    docstring, stopping at the damage front STOP."""
    dx = 1.0 / n
    delta = m * dx
    cy = crack_y(n) if y is None else y
    x0, x1 = max(0.0, A0 - 3.0 * delta), STOP + 4.0 * delta
    return rf.scenes.edge_crack_plate(
        method="ccm_pd",
        bc="free",
        dx=dx,
        m=m,
        crack_y=cy,
        pd_center=[0.5 * (x0 + x1), cy],
        pd_size=[x1 - x0, 6.0 * delta],
        sla_steps=MAX_STEPS,
        stop_crack_length=STOP,
    )


def interp_inside(x: float, xs: np.ndarray, ys: np.ndarray) -> float:
    """Linear interpolation at x inside [xs[0], xs[-1]] (xs increasing); ValueError outside
    (np.interp would return an end value)."""
    if not xs[0] <= x <= xs[-1]:
        raise ValueError(f"{x} outside the sampled range [{xs[0]}, {xs[-1]}]")
    return float(np.interp(x, xs, ys))


def xfem_row(mesh: tuple[int, int], y: float = CRACK_Y) -> tuple[dict[str, Any], rf.Result]:
    t = time.perf_counter()
    res = rf.run(rf.scenes.edge_crack_plate(method="xfem", mesh=mesh, crack_y=y, growth_steps=2000))
    wall = time.perf_counter() - t
    au = energy.audit(res)
    h = res.history
    a = np.asarray(h["a"], float)[1:]  # the critical states (row 0 is the unloaded origin)
    c = np.asarray(h["cmod"], float)[1:]
    s = np.asarray(h["sigma22"], float)[1:]
    row = {
        "series": "xfem",
        "nx": mesh[0],
        "ny": mesh[1],
        "h": 11.0 / mesh[0],
        "crack_y": y,
        "steps": len(a),
        "a_end": float(a[-1]),
        "G_ratio": au["ratio"],
        "G_ratio_along": energy.along(au, BINS).tolist(),
        "peak": float(np.max(h["sigma22"])),
        "cmod_soft": interp_inside(A_SOFT, a, c),
        "soft": interp_inside(A_SOFT, a, s),
        "wall_s": wall,
    }
    return row, res


def pd_row(series: str, n: int, m: int, cmod_star: float, y: float | None = None) -> dict[str, Any]:
    cy = crack_y(n) if y is None else y
    scene = pd_scene(n, m, cy)
    t = time.perf_counter()
    res = rf.run(scene)
    wall = time.perf_counter() - t
    au = energy.audit(res)
    h = res.history
    s = np.asarray(h["sigma22"], float)[1:]
    c = np.asarray(h["cmod"], float)[1:]
    win = np.abs(c / cmod_star - 1.0) <= SOFT_WINDOW
    return {
        "series": series,
        "n": n,
        "dx": 1.0 / n,
        "m": m,
        "delta": m / n,
        "crack_y": cy,
        "status": res.meta.get("status"),
        "steps": int(s.size),
        "front_end": float(h["crack_length"][-1]),
        "n_pd_nodes": res.meta["counts"]["n_pd_nodes"],
        "n_dofs": res.n_dofs,
        "G_ratio": au["ratio"],
        "G_ratio_along": energy.along(au, BINS).tolist(),
        "peak": float(np.max(s)),
        "cmod_peak": float(c[int(np.argmax(s))]),
        "soft": float(np.mean(s[win])) if np.any(win) else float("nan"),
        "soft_points": int(np.count_nonzero(win)),
        "cmod_end": float(c[-1]),
        "wall_s": wall,
    }


# --------------------------------------------------------------------------- study


def study(quick: bool, m_max: int | None = None, log: Any = print) -> dict[str, Any]:
    """The whole study (:data:`QUICK` or :data:`FULL` levels; ``m_max`` extends or cuts the
    m-series at delta = 1/4)."""
    t0 = time.perf_counter()
    levels = dict(QUICK if quick else FULL)
    if m_max is not None:
        levels["m"] = [(4 * m, m) for m in range(2, m_max + 1)]
    xrows = []
    for mesh in XFEM_QUICK if quick else XFEM_FULL:
        row, _ = xfem_row(mesh)
        xrows.append(row)
        log(
            f"xfem {row['nx']} x {row['ny']}: G/G0 {row['G_ratio']:.5f}, peak "
            f"{row['peak']:.4f}, sigma22(a={A_SOFT}) {row['soft']:.4f}, {row['wall_s']:.1f} s"
        )
    finest = xrows[-1]
    cmod_star = finest["cmod_soft"]
    hx = [r["h"] for r in xrows]
    xfem_rates = {
        "G_ratio": rates(hx, [r["G_ratio"] for r in xrows], 1.0),
        "peak": rates(hx, [r["peak"] for r in xrows], None),
        "soft": rates(hx, [r["soft"] for r in xrows], None),
    }
    lefm = {
        k: (
            xfem_rates[k]["richardson"]["value"]
            if xfem_rates[k]["richardson"]["status"] == "ok"
            else finest[k]
        )
        for k in ("peak", "soft")
    }
    for k in ("peak", "soft"):
        xfem_rates[k]["fit"] = fit_rate(hx, [r[k] for r in xrows], lefm[k])
        xfem_rates[k]["ref"] = lefm[k]
    # the crack's offset on even grids: its effect at the paper's grid and on XFEM
    offset: list[dict[str, Any]] = []
    for y in (CRACK_Y, CRACK_Y + 1.0 / 15.0):
        offset.append(pd_row("offset", 15, 4, cmod_star, y))
    for y in (CRACK_Y, CRACK_Y + 1.0 / 32.0):
        offset.append({**xfem_row((44, 83), y)[0], "series": "offset"})
    pd_rows: list[dict[str, Any]] = []
    for series, lv in levels.items():
        for n, m in lv:
            r = pd_row(series, n, m, cmod_star)
            pd_rows.append(r)
            log(
                f"{series:8s} dx=1/{n:<3d} m={m} delta={r['delta']:.4f}: {r['steps']} steps "
                f"({r['status']}), G/G0 {r['G_ratio']:.4f} along "
                + " ".join(f"{v:.3f}" for v in r["G_ratio_along"])
                + f", peak {r['peak']:.3f}, soft {r['soft']:.3f} ({r['soft_points']} pts), "
                f"{r['wall_s']:.1f} s"
            )
    pd_rates: dict[str, dict[str, Any]] = {}
    for series in levels:
        rows = [r for r in pd_rows if r["series"] == series]
        h = [r["dx"] for r in rows]
        refs = {"G_ratio": 1.0, "peak": lefm["peak"], "soft": lefm["soft"]}
        pd_rates[series] = {
            q: rates(h, [r[q] for r in rows], refs[q]) for q in ("G_ratio", "peak", "soft")
        }
        for i in range(len(BINS) - 1):
            pd_rates[series][f"G_ratio_bin{i}"] = rates(
                h, [r["G_ratio_along"][i] for r in rows], 1.0
            )
    return {
        "quick": quick,
        "constants": {
            "a0": A0,
            "stop": STOP,
            "a_soft": A_SOFT,
            "soft_window": SOFT_WINDOW,
            "bins": list(BINS),
            "cmod_star": cmod_star,
            "bc": "free",
        },
        "lefm": lefm,
        "xfem": xrows,
        "xfem_rates": xfem_rates,
        "pd": pd_rows,
        "pd_rates": pd_rates,
        "offset": offset,
        "machine": {"python": platform.python_version(), "node": platform.node()},
        "rustfrac": rf.__version__,
        "wall_s": time.perf_counter() - t0,
    }


# --------------------------------------------------------------------------- outputs

CSV_COLS = (
    "series", "n", "nx", "ny", "dx", "h", "m", "delta", "crack_y", "steps", "status",
    "G_ratio", "G_bin0", "G_bin1", "G_bin2", "peak", "soft", "soft_points", "wall_s",
)  # fmt: skip


def write_csv(path: Path, s: dict[str, Any]) -> None:
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=CSV_COLS, extrasaction="ignore")
        w.writeheader()
        for r in [*s["xfem"], *s["pd"], *s["offset"]]:
            row = dict(r)
            for i, v in enumerate(r["G_ratio_along"]):
                row[f"G_bin{i}"] = v
            w.writerow(row)


def _log_x(axx: Any) -> None:
    """A log h axis, refinement to the right, without the overlapping minor labels."""
    from matplotlib.ticker import NullFormatter

    axx.set_xscale("log")
    axx.invert_xaxis()
    axx.xaxis.set_minor_formatter(NullFormatter())


def plot(path: Path, s: dict[str, Any]) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(2, 4, figsize=(17, 7.5), constrained_layout=True)
    series = [("m", "m  (delta = 1/4)", "m"), ("delta", "dx  (m = 4)", "dx"),
              ("delta_m", "dx  (delta = sqrt(dx), m = 2..5)", "dx")]  # fmt: skip
    xr = s["xfem"]
    for j, (key, label, xkey) in enumerate(series):
        rows = [r for r in s["pd"] if r["series"] == key]
        x = [r[xkey] for r in rows]
        a = ax[0, j]
        a.plot(x, [r["G_ratio"] for r in rows], "o-", label=f"PD, front {A0}..{STOP}")
        for i in range(len(BINS) - 1):
            a.plot(x, [r["G_ratio_along"][i] for r in rows], ".--",
                   label=f"PD, front {BINS[i]:g}..{BINS[i + 1]:g}")  # fmt: skip
        a.axhline(1.0, color="k", lw=0.8, label="LEFM (G = G0)")
        a.axhline(xr[-1]["G_ratio"], color="C3", lw=0.8, ls=":",
                  label=f"XFEM {xr[-1]['nx']} x {xr[-1]['ny']}")  # fmt: skip
        a.set_ylabel("G / G0 (energy audit)")
        a.set_title(f"{key}-convergence")
        b = ax[1, j]
        b.plot(x, [r["peak"] for r in rows], "o-", label="PD peak sigma22")
        b.plot(x, [r["soft"] for r in rows], "s-",
               label=f"PD sigma22 at CMOD(a={A_SOFT}) +-{100 * SOFT_WINDOW:g} %")  # fmt: skip
        b.axhline(s["lefm"]["peak"], color="k", lw=0.8, label="XFEM peak (Richardson)")
        b.axhline(s["lefm"]["soft"], color="k", lw=0.8, ls="--",
                  label=f"XFEM sigma22 at a = {A_SOFT}")  # fmt: skip
        b.set_ylabel("sigma22")
        b.set_xlabel(label)
        if xkey == "dx":
            for axx in (a, b):
                _log_x(axx)
        if j == 0:
            a.legend(fontsize=7)
            b.legend(fontsize=7)
    hx = [r["h"] for r in xr]
    a, b = ax[0, 3], ax[1, 3]
    a.plot(hx, [r["G_ratio"] for r in xr], "o-", color="C3", label="XFEM, a 1.1 .. 7.7")
    for i in range(len(BINS) - 1):
        a.plot(hx, [r["G_ratio_along"][i] for r in xr], ".--",
               label=f"XFEM, a {BINS[i]:g}..{BINS[i + 1]:g}")  # fmt: skip
    a.axhline(1.0, color="k", lw=0.8)
    a.set_title("XFEM mesh convergence")
    a.legend(fontsize=7)
    b.plot(hx, [r["peak"] for r in xr], "o-", color="C3", label="XFEM peak sigma22")
    b.plot(hx, [r["soft"] for r in xr], "s-", color="C1", label=f"XFEM sigma22 at a = {A_SOFT}")
    b.axhline(s["lefm"]["peak"], color="k", lw=0.8)
    b.axhline(s["lefm"]["soft"], color="k", lw=0.8, ls="--")
    b.set_xlabel("element size h")
    b.legend(fontsize=7)
    for axx in (a, b):
        _log_x(axx)
    fig.suptitle(
        "Energy audit convergence, paper plate, free grips (CCM-PD vs XFEM/LEFM)"
        + (" [quick]" if s["quick"] else "")
    )
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _f(v: Any, spec: str = ".4f") -> str:
    return "-" if v is None or (isinstance(v, float) and not math.isfinite(v)) else format(v, spec)


def _rate_line(name: str, r: dict[str, Any]) -> str:
    rich, fit = r["richardson"], r["fit"]
    rtxt = (
        f"Richardson {_f(rich['value'])} (p = {_f(rich['rate'], '.2f')})"
        if rich["status"] == "ok"
        else f"Richardson: {rich['status']} ({rich['why']})"
    )
    ftxt = (
        f"fit |q - {_f(r['ref'])}| = C h^p: p = {_f(fit['p'], '.2f')}, "
        f"residual {_f(fit['residual'], '.2f')} (log10)"
        if fit and fit["p"] is not None
        else "no fit"
    )
    diffs = ", ".join(f"{d:+.4f}" for d in r["differences"])
    return f"- {name}: differences {diffs}; {rtxt}; {ftxt}"


def markdown(s: dict[str, Any]) -> str:
    """The tables and rates of a study, as in benches/RESULTS.md."""
    nb = len(s["constants"]["bins"]) - 1
    bins = " | ".join(
        f"G/G0 {s['constants']['bins'][i]:g}..{s['constants']['bins'][i + 1]:g}" for i in range(nb)
    )
    out = [
        f"| series | dx | m | delta | steps | G/G0 | {bins} | peak | sigma22 at CMOD* (pts) | s |",
        "|---|---|---|---|---:|---:|" + "---:|" * nb + "---:|---:|---:|",
    ]
    for r in s["pd"]:
        along = " | ".join(_f(v, ".3f") for v in r["G_ratio_along"])
        out.append(
            f"| {r['series']} | 1/{r['n']} | {r['m']} | {r['delta']:.4f} | {r['steps']} | "
            f"{r['G_ratio']:.4f} | {along} | {r['peak']:.3f} | {_f(r['soft'], '.3f')} "
            f"({r['soft_points']}) | {r['wall_s']:.1f} |"
        )
    out += ["", "| XFEM mesh | h | steps | G/G0 | " + bins + " | peak | sigma22 at a* | s |"]
    out.append("|---|---:|---:|---:|" + "---:|" * nb + "---:|---:|---:|")
    for r in s["xfem"]:
        along = " | ".join(_f(v, ".5f") for v in r["G_ratio_along"])
        out.append(
            f"| {r['nx']} x {r['ny']} | {r['h']:.4f} | {r['steps']} | {r['G_ratio']:.5f} | "
            f"{along} | {r['peak']:.4f} | {r['soft']:.4f} | {r['wall_s']:.1f} |"
        )
    out += ["", "Rates (levels coarse to fine; h = dx, XFEM h = 11 / nx):"]
    for q, r in s["xfem_rates"].items():
        out.append(_rate_line(f"xfem {q}", r))
    for series, rr in s["pd_rates"].items():
        for q, r in rr.items():
            out.append(_rate_line(f"{series} {q}", r))
    out += ["", "Offset of the crack line (x2):"]
    for r in s["offset"]:
        mesh = f"PD 1/{r['n']}, m {r['m']}" if "n" in r else f"XFEM {r['nx']} x {r['ny']}"
        out.append(
            f"- {mesh}, x2 = {r['crack_y']:.5f}: G/G0 {r['G_ratio']:.5f}, peak "
            f"{r['peak']:.4f}, sigma22 at CMOD* / a* {_f(r['soft'])}"
        )
    c = s["constants"]
    out.append(
        f"\nCMOD* = {c['cmod_star']:.6f} (finest XFEM at a = {c['a_soft']}); LEFM references: "
        f"peak {s['lefm']['peak']:.4f}, sigma22 at a* {s['lefm']['soft']:.4f}; "
        f"study wall time {s['wall_s']:.0f} s"
    )
    return "\n".join(out)


def main(argv: Sequence[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--quick", action="store_true", help="3 levels a series (about 30 s)")
    ap.add_argument("--out", default=str(Path(__file__).resolve().parent), help="output folder")
    ap.add_argument(
        "--m-max",
        type=int,
        default=None,
        help="m-series up to this m (full: 7, about half the study's time)",
    )
    args = ap.parse_args(argv)
    if args.m_max is not None and not 3 <= args.m_max <= 12:
        ap.error(f"--m-max: an integer in 3..12, got {args.m_max}")
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    s = study(args.quick, args.m_max, log=lambda m: print(m, flush=True))
    (out / "audit_convergence.json").write_text(json.dumps(s, indent=1, default=str))
    write_csv(out / "audit_convergence.csv", s)
    plot(out / "audit_convergence.png", s)
    print(markdown(s))
    print(f"wrote {out}/audit_convergence.{{csv,json,png}} in {s['wall_s']:.0f} s")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
