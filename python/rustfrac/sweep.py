"""Speed-accuracy sweep (``rustfrac sweep --out DIR [--preset tiny|full]``).

Runs independent scenes of the paper's plate, one record per point, in a local process pool
(default) or on a dask.distributed cluster (``scheduler="tcp://..."`` or a ``distributed.Client``;
optional extra ``rustfrac[dask]``). Each worker runs with ``RAYON_NUM_THREADS=1`` (one thread per
worker, sequential solver inside), so that the numbers are identical, bit for bit, on both
backends.

Studies (method, varied parameter):

- XFEM: element size (``mesh``), sub-quads per direction (``nsub``), I-integral radius (``r_I``);
- CCM-PD: grid spacing (``dx``; 21 / dx must be odd so that the pre-crack x2 = 10.5 passes between
  grid rows), horizon factor (``m``), size of the PD rectangle (``pd_scale`` times 2.73 x 1.67).

Errors: each quantity is compared with a reference per method, taken from that method's refinement
study (XFEM ``mesh``, CCM-PD ``dx``): the Richardson extrapolation of its three finest levels when
they show a consistent observed rate (0.5 <= p <= 6, monotone differences), else the finest level
itself. ``err_finest_<q>`` is always against the finest level (0 there by construction).
"""

from __future__ import annotations

import csv
import io
import json
import math
import os
import platform
import resource
import sys
import time
from collections.abc import Callable, Iterable, Sequence
from pathlib import Path
from typing import Any

from ._folder import with_fallback, writing
from .scene import Scene
from .scenes import edge_crack_plate

__all__ = [
    "FILES",
    "QUANTITIES",
    "SweepInterrupted",
    "choose_presets",
    "define_points",
    "errors",
    "richardson",
    "run_point",
    "sweep",
    "write_outputs",
]

#: quantities compared per record (None where a method does not give it)
QUANTITIES: tuple[str, ...] = ("K_I", "cmod", "sigma22", "peak_sigma22")
#: the study of each method that defines its reference (a refinement study)
REFINEMENT: dict[str, str] = {"xfem": "mesh", "ccm_pd": "dx"}
#: keys of a record that must agree bit for bit between backends
NUMERIC_KEYS: tuple[str, ...] = (
    "K_I",
    "cmod",
    "sigma22",
    "peak_sigma22",
    "peak_step",
    "peak_crack_length",
    "n_steps",
    "n_dofs",
    "n_bonds",
    "n_pd_nodes",
)
PD_SIZE = (2.73, 1.67)

Progress = Callable[[int, int, str], Any]


class SweepInterrupted(KeyboardInterrupt):
    """Ctrl-C during :func:`sweep`: ``records`` holds the points that finished (in point order);
    raised by :func:`write_outputs` too (Ctrl-C while drawing), with ``doc`` the JSON written."""

    def __init__(
        self, records: list[dict[str, Any]], doc: dict[str, Any] | None = None
    ) -> None:
        super().__init__(f"sweep interrupted after {len(records)} points")
        self.records = records
        self.doc = doc


# --------------------------------------------------------------------------- points


def _h(nx: int, ny: int, width: float = 11.0, height: float = 21.0) -> float:
    return math.sqrt(width / nx * height / ny)


def _point(study: str, method: str, param: str, value: Any, h: float | None, scene: Scene) -> dict:
    return {
        "study": study,
        "method": method,
        "param": param,
        "value": value,
        "h": h,
        "scene": scene.to_dict(),
    }


def define_points(preset: str = "full") -> list[dict[str, Any]]:
    """The sweep points of a preset: "tiny" (seconds, for tests and CI) or "full".

    XFEM points run the reference load plus ``growth_steps`` critical states (the first critical
    state is the peak of the displacement-controlled load path); CCM-PD points run the SLA with
    ``sla_steps`` bond breaks (the peak is the largest sigma22 of those steps).
    """
    if preset == "tiny":
        meshes = [(44, 83), (88, 167), (176, 333)]
        nsubs, r_is, growth = [1, 4], [2.0, 3.0], 2
        dxs, ms, scales, sla, pd_base_dx = [1 / 5, 1 / 9], [3, 4], [1.0], 20, 1 / 5
    elif preset == "full":
        meshes = [(33, 62), (44, 83), (66, 125), (88, 167), (176, 333), (352, 665)]
        nsubs, r_is, growth = [1, 2, 4, 8], [1.5, 2.0, 2.5, 3.0, 3.5], 3
        dxs, ms, scales, sla, pd_base_dx = (
            [1 / 5, 1 / 9, 1 / 15, 1 / 25],
            [2, 3, 4, 5, 6],
            [0.8, 1.0, 1.2],
            500,
            1 / 15,
        )
    else:
        raise ValueError(f"unknown sweep preset {preset!r} (tiny | full)")
    pts: list[dict[str, Any]] = []
    for nx, ny in meshes:
        sc = edge_crack_plate(
            "xfem", mesh=(nx, ny), growth_steps=growth, name=f"xfem mesh {nx}x{ny}"
        )
        pts.append(_point("mesh", "xfem", "nx", nx, _h(nx, ny), sc))
    for n in nsubs:
        sc = edge_crack_plate("xfem", nsub=n, growth_steps=growth, name=f"xfem nsub {n}")
        pts.append(_point("nsub", "xfem", "nsub", n, None, sc))
    for r in r_is:
        sc = edge_crack_plate("xfem", r_I=r, growth_steps=growth, name=f"xfem r_I {r}")
        pts.append(_point("r_I", "xfem", "r_I", r, None, sc))
    for dx in dxs:
        sc = edge_crack_plate("ccm_pd", dx=dx, sla_steps=sla, name=f"ccm_pd dx 1/{round(1 / dx)}")
        pts.append(_point("dx", "ccm_pd", "dx", dx, dx, sc))
    for m in ms:
        sc = edge_crack_plate("ccm_pd", dx=pd_base_dx, m=m, sla_steps=sla, name=f"ccm_pd m {m}")
        pts.append(_point("m", "ccm_pd", "m", m, None, sc))
    for s in scales:
        size = (PD_SIZE[0] * s, PD_SIZE[1] * s)
        sc = edge_crack_plate(
            "ccm_pd", dx=pd_base_dx, pd_size=size, sla_steps=sla, name=f"ccm_pd size x{s}"
        )
        pts.append(_point("pd_size", "ccm_pd", "pd_scale", s, None, sc))
    return pts


# --------------------------------------------------------------------------- one point


def run_point(point: dict[str, Any]) -> dict[str, Any]:
    """Runs one point in this process and returns its record (no fields, numbers only).

    Sets ``RAYON_NUM_THREADS=1`` before the first solve of the process (one thread per worker).
    ``peak_rss_mb`` is this process's ``ru_maxrss`` after the run; ``rss_before_mb`` the same
    before it (a worker reused for several points reports its high-water mark: the point's own
    peak is exact when the local pool runs one point per process, as it does by default).
    """
    os.environ["RAYON_NUM_THREADS"] = "1"
    from .runner import run

    before = _maxrss_mb()
    t0 = time.perf_counter()
    res = run(Scene.from_dict(point["scene"]))
    wall = time.perf_counter() - t0
    rec: dict[str, Any] = {k: point[k] for k in ("study", "method", "param", "value", "h")}
    rec["name"] = point["scene"].get("name", "")
    rec["wall_time_s"] = wall
    rec["solver_time_s"] = float(res.wall_time_s)
    rec["rss_before_mb"] = before
    rec["peak_rss_mb"] = _maxrss_mb()
    counts = res.meta.get("counts", {})
    rec["n_dofs"] = int(res.n_dofs)
    rec["n_bonds"] = counts.get("n_bonds")
    rec["n_pd_nodes"] = counts.get("n_pd_nodes")
    rec["K_I"] = res.K_I
    rec["cmod"] = float(res.cmod)
    rec["sigma22"] = float(res.sigma22)
    h = res.history
    s = h.get("sigma22")
    if s is not None and len(s) > 1:
        i = max(range(len(s)), key=lambda j: float(s[j]))
        a = h.get("a", h.get("crack_length"))
        rec["peak_sigma22"] = float(s[i])
        rec["peak_step"] = int(i)
        rec["peak_crack_length"] = None if a is None else float(a[i])
        rec["n_steps"] = len(s) - 1
    else:
        rec.update(peak_sigma22=None, peak_step=None, peak_crack_length=None, n_steps=0)
    return rec


def _maxrss_mb() -> float:
    r = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    return r / 1024.0 / (1024.0 if sys.platform == "darwin" else 1.0)


def _init_worker() -> None:
    os.environ["RAYON_NUM_THREADS"] = "1"


# --------------------------------------------------------------------------- backends


def sweep(
    points: Sequence[dict[str, Any]],
    *,
    workers: int | None = None,
    scheduler: Any = None,
    progress: Progress | None = None,
) -> list[dict[str, Any]]:
    """Runs every point and returns their records, in the order of ``points``.

    Args:
        points: from :func:`define_points` (or dicts with ``study, method, param, value, h,
            scene``).
        workers: local processes (default: the number of cores); ignored with ``scheduler``.
        scheduler: None (local process pool), a scheduler address ``"tcp://host:port"``, or a
            ``distributed.Client``.
        progress: ``progress(done, total, message)`` after each finished point.

    Raises:
        SweepInterrupted: on Ctrl-C (a ``KeyboardInterrupt``), with the finished records; the
            points still running are cancelled.
    """
    points = list(points)
    if scheduler is not None:
        return _sweep_dask(points, scheduler, progress)
    return _sweep_local(points, workers, progress)


def _sweep_local(
    points: list[dict[str, Any]], workers: int | None, progress: Progress | None
) -> list[dict[str, Any]]:
    import multiprocessing as mp
    from concurrent.futures import ProcessPoolExecutor, as_completed

    n = max(1, min(workers or os.cpu_count() or 1, len(points) or 1))
    kw: dict[str, Any] = {"max_workers": n, "initializer": _init_worker}
    if sys.version_info >= (3, 11):
        # a fresh process per point: exact peak memory, no state carried between points
        kw.update(max_tasks_per_child=1, mp_context=mp.get_context("spawn"))
    out: list[dict[str, Any] | None] = [None] * len(points)
    ex = ProcessPoolExecutor(**kw)
    try:
        futs = {ex.submit(run_point, p): i for i, p in enumerate(points)}
        for k, f in enumerate(as_completed(futs), 1):
            i = futs[f]
            out[i] = f.result()
            if progress is not None:
                progress(k, len(points), f"sweep: {out[i]['name']}")
    except KeyboardInterrupt:
        # cancel the queued points, let the running ones end (a terminal's Ctrl-C interrupts
        # them too) and keep every point that finished
        ex.shutdown(wait=True, cancel_futures=True)
        for f, i in futs.items():
            if out[i] is None and f.done() and not f.cancelled() and f.exception() is None:
                out[i] = f.result()
        raise SweepInterrupted([r for r in out if r is not None]) from None
    ex.shutdown()
    return [r for r in out if r is not None]


def _sweep_dask(
    points: list[dict[str, Any]], scheduler: Any, progress: Progress | None
) -> list[dict[str, Any]]:
    try:
        from distributed import Client, as_completed
    except ImportError as e:
        raise ImportError(
            "sweeping on a dask cluster needs dask.distributed: pip install 'rustfrac[dask]'"
        ) from e
    own = not isinstance(scheduler, Client)
    client = Client(scheduler) if own else scheduler
    try:
        futs = client.map(run_point, points, pure=False)
        index = {f.key: i for i, f in enumerate(futs)}
        out: list[dict[str, Any] | None] = [None] * len(points)
        try:
            for k, f in enumerate(as_completed(futs), 1):
                i = index[f.key]
                out[i] = f.result()
                if progress is not None:
                    progress(k, len(points), f"sweep: {out[i]['name']}")
        except KeyboardInterrupt:
            client.cancel(futs)
            raise SweepInterrupted([r for r in out if r is not None]) from None
        return [r for r in out if r is not None]
    finally:
        if own:
            client.close()


# --------------------------------------------------------------------------- errors


def richardson(hs: Sequence[float], fs: Sequence[float]) -> tuple[float, float] | None:
    """Richardson extrapolation of three levels (h decreasing): (extrapolated value, observed
    rate p), or None when the levels show no consistent rate (non-monotone differences, or p
    outside [0.5, 6]). Solves (f1 - f2) / (f2 - f3) = (h1^p - h2^p) / (h2^p - h3^p) for p."""
    (h1, h2, h3), (f1, f2, f3) = hs, fs
    d1, d2 = f1 - f2, f2 - f3
    if d1 == 0 or d2 == 0 or (d1 > 0) != (d2 > 0) or not h1 > h2 > h3 > 0:
        return None
    target = d1 / d2

    def g(p: float) -> float:
        return (h1**p - h2**p) / (h2**p - h3**p) - target

    lo, hi = 0.5, 6.0
    if g(lo) * g(hi) > 0:
        return None
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if g(lo) * g(mid) <= 0:
            hi = mid
        else:
            lo = mid
    p = 0.5 * (lo + hi)
    c = d2 / (h2**p - h3**p)
    return f3 - c * h3**p, p


def references(records: Sequence[dict[str, Any]]) -> dict[str, dict[str, dict[str, Any]]]:
    """Per method and quantity: {"value", "finest", "kind" ("richardson" | "finest"), "rate",
    "levels"} from the method's refinement study."""
    refs: dict[str, dict[str, dict[str, Any]]] = {}
    for method, study in REFINEMENT.items():
        lv = sorted(
            (r for r in records if r["method"] == method and r["study"] == study),
            key=lambda r: -r["h"],
        )
        if not lv:
            continue
        refs[method] = {}
        for q in QUANTITIES:
            pts = [(r["h"], r[q]) for r in lv if r.get(q) is not None]
            if not pts:
                continue
            finest = pts[-1][1]
            ref = {
                "value": finest,
                "finest": finest,
                "kind": "finest",
                "rate": None,
                "levels": len(pts),
                "finest_h": pts[-1][0],
                "why": "fewer than 3 levels" if len(pts) < 3 else "no consistent rate",
            }
            if len(pts) >= 3:
                hs, fs = zip(*pts[-3:])
                rich = richardson(hs, fs)
                if rich is not None:
                    ref.update(value=rich[0], kind="richardson", rate=rich[1], why="")
            refs[method][q] = ref
    return refs


def errors(
    records: Sequence[dict[str, Any]], refs: dict[str, dict[str, dict[str, Any]]]
) -> list[dict[str, Any]]:
    """Records with ``err_<q>`` (relative error against the reference), ``err_finest_<q>``
    (against the finest level) and ``err_max`` (the largest ``err_<q>`` of the record)."""
    out = []
    for r in records:
        r = dict(r)
        worst = None
        for q in QUANTITIES:
            ref = refs.get(r["method"], {}).get(q)
            if ref is None or r.get(q) is None:
                r[f"err_{q}"] = r[f"err_finest_{q}"] = None
                continue
            e = abs(r[q] - ref["value"]) / abs(ref["value"])
            r[f"err_{q}"] = e
            r[f"err_finest_{q}"] = abs(r[q] - ref["finest"]) / abs(ref["finest"])
            worst = e if worst is None else max(worst, e)
        r["err_max"] = worst
        out.append(r)
    return out


def pareto(records: Iterable[dict[str, Any]]) -> list[dict[str, Any]]:
    """The non-dominated records in (wall time, err_max), by increasing time."""
    rs = sorted(
        (r for r in records if r.get("err_max") is not None),
        key=lambda r: (r["wall_time_s"], r["err_max"]),
    )
    front, best = [], math.inf
    for r in rs:
        if r["err_max"] < best:
            front.append(r)
            best = r["err_max"]
    return front


#: preset -> largest err_max it accepts (the cheapest front point below it is chosen)
PRESET_TOLERANCES: dict[str, float] = {"fast": 0.05, "balanced": 0.01, "accurate": 0.002}


def choose_presets(
    records: Sequence[dict[str, Any]], points: Sequence[dict[str, Any]] | None = None
) -> dict[str, dict[str, Any]]:
    """Per method, "fast" / "balanced" / "accurate": the cheapest Pareto-front point whose
    ``err_max`` is within :data:`PRESET_TOLERANCES` (else the most accurate front point)."""
    scenes = {p["scene"].get("name", ""): p["scene"] for p in points or ()}
    out: dict[str, dict[str, Any]] = {}
    for method in sorted({r["method"] for r in records}):
        front = pareto(r for r in records if r["method"] == method)
        if not front:
            continue
        out[method] = {}
        for name, tol in PRESET_TOLERANCES.items():
            ok = [r for r in front if r["err_max"] <= tol]
            r = ok[0] if ok else min(front, key=lambda r: r["err_max"])
            out[method][name] = {
                "point": r["name"],
                "study": r["study"],
                "param": r["param"],
                "value": r["value"],
                "wall_time_s": r["wall_time_s"],
                "err_max": r["err_max"],
                "tolerance": tol,
                "meets_tolerance": bool(ok),
                # the reference level itself: its error is zero by construction, not measured
                "is_reference": r["err_max"] == 0.0,
                "scene": scenes.get(r["name"]),
            }
    return out


# --------------------------------------------------------------------------- outputs

CSV_KEYS: tuple[str, ...] = (
    "study", "method", "param", "value", "h", "name", "wall_time_s", "solver_time_s",
    "peak_rss_mb", "rss_before_mb", "n_dofs", "n_bonds", "n_pd_nodes", "K_I", "cmod", "sigma22",
    "peak_sigma22", "peak_step", "peak_crack_length", "n_steps",
    *(f"err_{q}" for q in QUANTITIES), *(f"err_finest_{q}" for q in QUANTITIES), "err_max",
)  # fmt: skip


def _fmt(v: Any) -> str:
    if v is None:
        return ""
    if isinstance(v, float):
        return repr(v)
    return str(v)


def _g(v: Any, spec: str = ".4g") -> str:
    return "-" if v is None else format(v, spec)


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
        "| method | study | value | time (s) | peak RSS (MB) | unknowns | bonds | K_I | CMOD "
        "| sigma22 | peak sigma22 (step) | err K_I | err CMOD | err sigma22 | err peak | err max |",
        "|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for r in records:
        v = r["value"]
        val = f"1/{round(1 / v)}" if r["param"] == "dx" else str(v)
        lines.append(
            f"| {r['method']} | {r['study']} | {val} | {r['wall_time_s']:.3f} | "
            f"{r['peak_rss_mb']:.0f} | {r['n_dofs']} | {_g(r['n_bonds'], 'd')} | "
            f"{_g(r['K_I'], '.6g')} | {_g(r['cmod'], '.6g')} | {_g(r['sigma22'], '.6g')} | "
            f"{_g(r['peak_sigma22'], '.6g')} ({_g(r['peak_step'], 'd')}/{r['n_steps']}) | "
            + " | ".join(_g(r[f"err_{q}"], ".2e") for q in QUANTITIES)
            + f" | {_g(r['err_max'], '.2e')} |"
        )
    lines += ["", "## References", "", "| method | quantity | reference | kind | observed rate "
              "| finest level | levels |", "|---|---|---:|---|---:|---:|---:|"]  # fmt: skip
    for method, qs in refs.items():
        for q, ref in qs.items():
            kind = (
                "Richardson (3 finest levels)"
                if ref["kind"] == "richardson"
                else f"finest level ({ref['why']})"
            )
            lines.append(
                f"| {method} | {q} | {ref['value']:.8g} | {kind} | {_g(ref['rate'], '.3g')} | "
                f"{ref['finest']:.8g} | {ref['levels']} |"
            )
    lines += ["", "## Presets (from the Pareto front of time against err max)", "",
              "| method | preset | point | time (s) | err max | tolerance |",
              "|---|---|---|---:|---:|---|"]  # fmt: skip
    for method, ps in presets.items():
        for name, p in ps.items():
            tol = f"<= {p['tolerance']:g}" + ("" if p["meets_tolerance"] else " (not met)")
            if p["is_reference"]:
                tol += " (the reference level itself: error 0 by construction)"
            lines.append(
                f"| {method} | {name} | {p['point']} | {p['wall_time_s']:.3f} | "
                f"{p['err_max']:.2e} | {tol} |"
            )
    return "\n".join(lines) + "\n"


def plot(records: Sequence[dict[str, Any]], method: str, path: Path) -> None:
    """Log-log err max against wall time for one method, one marker per study, the Pareto front
    as a line (points with zero error, i.e. the reference itself, cannot be drawn and are
    listed in the title)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from .result import _atomic

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
    with _atomic(path, "wb") as f:
        fig.savefig(f, format="png", dpi=120, bbox_inches="tight")
    plt.close(fig)


#: the files of a sweep folder (one plot per method of :data:`REFINEMENT`)
FILES: tuple[str, ...] = (
    "sweep.csv", "sweep.md", *(f"sweep_{m}.png" for m in REFINEMENT), "sweep.json",
)  # fmt: skip


def write_outputs(
    out: str | Path,
    points: Sequence[dict[str, Any]],
    records: Sequence[dict[str, Any]],
    *,
    extra: dict[str, Any] | None = None,
) -> dict[str, Any]:
    """Computes the references, errors and presets of ``records`` and writes ``sweep.csv``,
    ``sweep.md``, ``sweep_<method>.png`` and ``sweep.json`` (last) into ``out`` as one unit
    (``_folder``). Returns the JSON document, which says what is missing: ``missing_points``
    (points without a record), ``missing_files`` (plots a Ctrl-C stopped) and ``complete``.

    Raises:
        OutputError: ``out`` cannot be written; the outputs were saved to the temporary folder
            it names instead (``fallback``).
        SweepInterrupted: Ctrl-C while drawing, after writing the rest (marked incomplete; the
            exception's ``doc`` is the JSON document).
    """
    return with_fallback(Path(out), lambda d: _write(d, points, records, extra or {}), "sweep")


def _write(
    out: Path,
    points: Sequence[dict[str, Any]],
    records: Sequence[dict[str, Any]],
    extra: dict[str, Any],
) -> dict[str, Any]:
    from . import __version__

    records = list(records)
    done = {r["name"] for r in records}
    names = [p["scene"].get("name", "") for p in points]
    missing_points = [n for n in names if n not in done]
    points = [p for p, n in zip(points, names) if n in done]
    refs = references(records)
    recs = errors(records, refs)
    presets = choose_presets(recs, points)
    with writing(out, owned=FILES, last="sweep.json") as w:
        buf = io.StringIO()
        csv_w = csv.writer(buf)
        csv_w.writerow(CSV_KEYS)
        for r in recs:
            csv_w.writerow([_fmt(r.get(k)) for k in CSV_KEYS])
        w.stage("sweep.csv").write_text(buf.getvalue(), encoding="utf-8")
        w.stage("sweep.md").write_text(markdown(recs, refs, presets), encoding="utf-8")
        missing_files, stopped = [], False
        for method in sorted({r["method"] for r in recs}):
            name = f"sweep_{method}.png"
            if stopped:
                missing_files.append(name)
                continue
            try:
                plot(recs, method, w.stage(name))
            except KeyboardInterrupt:
                w.discard(name)
                missing_files.append(name)
                stopped = True
        interrupted = bool(extra.get("interrupted")) or stopped
        doc = {
            "version": __version__,
            "machine": {
                "platform": platform.platform(),
                "cores": os.cpu_count(),
                "python": platform.python_version(),
                "load_average": list(os.getloadavg()) if hasattr(os, "getloadavg") else None,
            },
            **extra,
            "interrupted": interrupted,
            "complete": not interrupted and not missing_points and not missing_files,
            "missing_points": missing_points,
            "missing_files": missing_files,
            "references": refs,
            "presets": presets,
            "points": recs,
            "scenes": {p["scene"].get("name", ""): p["scene"] for p in points},
        }
        w.stage("sweep.json").write_text(json.dumps(doc, indent=1), encoding="utf-8")
    if stopped:
        raise SweepInterrupted(records, doc)
    return doc
