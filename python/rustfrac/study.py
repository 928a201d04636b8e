"""What the studies share (:mod:`~rustfrac.fig7`, :mod:`~rustfrac.compare`,
:mod:`~rustfrac.sweep`): one logged run, the machine a study ran on, the summary files
(``summary.md`` and ``summary.json``, written atomically), the CSV and markdown tables they hold,
and the blocks of those tables two studies print alike (the curve agreement, the energy audit).
"""

from __future__ import annotations

import csv
import io
import json
import math
import os
import platform
import time
from collections.abc import Callable, Iterable, Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any, Optional

import numpy as np

from . import agreement, energy
from ._folder import FolderWriter, atomic_file
from .runner import run

if TYPE_CHECKING:
    from .result import Result
    from .scene import Scene

__all__ = [
    "AUDIT_KEYS",
    "agreement_table",
    "audit",
    "csv_text",
    "energy_table",
    "fmt",
    "json_default",
    "machine",
    "missing",
    "run_logged",
    "summary_markdown",
    "table",
    "write_summary",
    "write_text",
]

#: a line logger
Log = Callable[[str], None]
#: a factory ``progress(name)`` of the progress callback of one run (or None: no progress)
ProgressFactory = Callable[[str], Optional[Callable[[int, int, str], Any]]]
#: the numbers of an energy audit (:func:`rustfrac.energy.audit`) a summary keeps
AUDIT_KEYS = ("G0", "energy", "crack_area", "ratio")


# ----------------------------------------------------------------------------------------------
# runs


def run_logged(
    name: str,
    scene: Scene,
    progress: ProgressFactory | None,
    say: Log,
    built: Callable[[Result], str],
) -> tuple[Result, float]:
    """One run of a job (fig7, compare): logged before and after (``built`` describes the
    result), with its progress callback from the factory ``progress(name)``; returns the result
    and its wall time."""
    say(f"run     {name}: {scene.describe()}")
    t0 = time.perf_counter()
    res = run(scene, progress=progress(name) if progress else None)
    seconds = time.perf_counter() - t0
    say(f"        {built(res)}; {seconds:.2f} s")
    return res, seconds


def machine(*, cpu: bool = True, load_average: bool = False) -> dict[str, Any]:
    """The machine a study ran on: the processor's name (``cpu``, from /proc/cpuinfo where
    there is one), the cores, the platform and the Python version, and with ``load_average`` the
    system's 1, 5 and 15 minute load averages (None where the system has none)."""
    out: dict[str, Any] = {}
    if cpu:
        name = platform.processor() or ""
        try:
            for line in Path("/proc/cpuinfo").read_text().splitlines():
                if line.startswith("model name"):
                    name = line.split(":", 1)[1].strip()
                    break
        except OSError:
            pass
        out["cpu"] = name
    out.update(cores=os.cpu_count(), platform=platform.platform())
    out["python"] = platform.python_version()
    if load_average:
        out["load_average"] = list(os.getloadavg()) if hasattr(os, "getloadavg") else None
    return out


def audit(res: Result) -> dict[str, Any]:
    """The energy audit of a load path (:func:`rustfrac.energy.audit`) as a summary keeps it
    (:data:`AUDIT_KEYS`)."""
    au = energy.audit(res)
    return {k: au[k] for k in AUDIT_KEYS}


def missing(
    runs: Iterable[str],
    parts: Mapping[str, str],
    files: Iterable[str],
    results: Mapping[str, Any],
    written: Sequence[str],
) -> list[str]:
    """What a job's folder lacks: each of ``runs`` without a result, the result folder
    (``parts``: run -> folder) of each, and each of ``files`` not ``written``."""
    return (
        [f"run {n}" for n in runs if n not in results]
        + [f"{part}/" for n, part in parts.items() if n not in results]
        + [f for f in files if f not in written]
    )


# ----------------------------------------------------------------------------------------------
# files


def json_default(v: Any) -> Any:
    """``json.dumps``'s ``default`` for a summary: numpy scalars and arrays as Python values."""
    if isinstance(v, np.generic):
        return v.item()
    if isinstance(v, np.ndarray):
        return v.tolist()
    raise TypeError(f"not JSON serialisable: {type(v).__name__}")


def write_text(path: Path, text: str) -> None:
    """Writes ``text`` (UTF-8) to ``path`` atomically (a temporary file renamed over it)."""
    with atomic_file(path, "w") as f:
        f.write(text)


def write_summary(w: FolderWriter, s: dict[str, Any], markdown: str) -> None:
    """Stages a job's ``summary.md`` (the text ``markdown``) and ``summary.json`` (``s``) into
    the pending folder ``w``."""
    write_text(w.stage("summary.md"), markdown)
    write_text(w.stage("summary.json"), json.dumps(s, indent=2, default=json_default))


def _csv_cell(v: Any) -> str:
    if v is None:
        return ""
    if isinstance(v, float):
        return repr(v)
    return str(v)


def csv_text(header: Sequence[str], rows: Iterable[Sequence[Any]]) -> str:
    """A CSV file's text: the header, then the rows (None an empty cell, a float its repr: the
    shortest text that reads back to the same bits)."""
    buf = io.StringIO()
    w = csv.writer(buf)
    w.writerow(header)
    for row in rows:
        w.writerow([_csv_cell(v) for v in row])
    return buf.getvalue()


# ----------------------------------------------------------------------------------------------
# markdown


def fmt(v: Any, spec: str = ".6g", *, absent: str = "n/a", finite: bool = False) -> str:
    """``v`` formatted with ``spec`` for a summary's text; ``absent`` for None (and, with
    ``finite``, for a float that is not finite)."""
    if v is None or (finite and isinstance(v, float) and not math.isfinite(v)):
        return absent
    return format(v, spec)


def table(
    header: Sequence[str | None], rows: Iterable[Sequence[str | None]], align: str | None = None
) -> list[str]:
    """A markdown table's lines: the header, the rule (``align``: one letter per column, "l"
    left, "r" right; default all left), the rows; a cell None is left blank."""

    def line(cells: Sequence[str | None]) -> str:
        return "|" + "|".join(" " if c is None else f" {c} " for c in cells) + "|"

    rule = "|" + "".join("---:|" if a == "r" else "---|" for a in align or "l" * len(header))
    return [line(header), rule, *(line(r) for r in rows)]


def summary_markdown(
    s: dict[str, Any], title: str, lead: str, body: Sequence[str], *, platform: bool = False
) -> str:
    """A job's ``summary.md``: the title, the ``lead`` line (marked when the job was
    interrupted), what is missing, the machine (with ``platform``, its platform too), then the
    ``body`` lines."""
    m = s["machine"]
    lines = [
        f"# {title}",
        "",
        lead + (" -- **interrupted: partial results**" if s.get("interrupted") else ""),
        *([f"**Missing:** {', '.join(s['missing'])}"] if s.get("missing") else []),
        f"Machine: {m['cpu']}, {m['cores']} cores" + (f", {m['platform']}" if platform else ""),
        "",
        *body,
    ]
    return "\n".join(lines)


def agreement_table(cur: dict[str, Any], range_label: str | None = None) -> list[str]:
    """The table of a curve agreement (:func:`rustfrac.agreement.compare`): one row per CCM-PD
    reading, PD / XFEM - 1 in per cent; with ``range_label`` a column of each reading's abscissa
    range under that name."""
    rng = [range_label] if range_label else []
    rows: list[list[str | None]] = []
    for k in agreement.READINGS:
        v = cur[k]
        if not v["n"]:
            rows.append([k, "0", *(["n/a"] if rng else []), None, None, None, None])
            continue
        span = [f"{v['cmod_range'][0]:.5g} .. {v['cmod_range'][1]:.5g}"] if rng else []
        rel = [f"{v['mean_rel_diff']:+.2%}", f"{v['rms_rel_diff']:.2%}"]
        rel += [f"{v['min_rel_diff']:+.2%}", f"{v['max_rel_diff']:+.2%}"]
        rows.append([k, str(v["n"]), *span, *rel])
    return table(["CCM-PD reading", "points", *rng, "mean", "RMS", "min", "max"], rows)


def energy_table(audits: dict[str, Any], spec: str = ".4g", *, finite: bool = True) -> list[str]:
    """The table of the energy audits (:func:`audit` of each method, or ``not_available``: why
    not), the energies and areas formatted with ``spec`` (:func:`fmt` with ``finite``)."""
    rows: list[list[str | None]] = []
    for k, v in audits.items():
        if "not_available" in v:
            rows.append([k, f"n/a: {v['not_available']}", None, None])
        else:
            num = [fmt(v[q], spec, finite=finite) for q in ("energy", "crack_area")]
            rows.append([k, *num, fmt(v["ratio"], ".4f", finite=finite)])
    return table(["method", "dissipated", "new crack area", "G / G0"], rows)
