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

The user's own scene (:func:`sweep_scene`, ``rustfrac sweep SCENE.toml --param P --levels ...``):
one knob (``mesh``, ``pd.dx`` or any ``section.key``) at the given levels, any scalar response as
the quantity (:func:`quantities_of`), the same backends, and :func:`extrapolate` (Richardson with
a status) of the three finest levels. Every point is timed ``repeats`` times, the minimum kept.
"""

from __future__ import annotations

import functools
import json
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from .._folder import with_fallback, writing
from ..study import csv_text, machine

# "X as X": names kept where they were before the package (rustfrac.sweep.X)
from .analysis import PRESET_TOLERANCES as PRESET_TOLERANCES
from .analysis import RATE_RANGE as RATE_RANGE
from .analysis import choose_presets, errors, references, richardson
from .analysis import pareto as pareto
from .backends import SweepInterrupted, sweep
from .points import NUMERIC_KEYS as NUMERIC_KEYS
from .points import PD_SIZE as PD_SIZE
from .points import QUANTITIES, REFINEMENT, define_points, quantities_of, run_point
from .points import Progress as Progress
from .report import CSV_KEYS, SCENE_CSV_KEYS, cell, markdown, plot, scene_markdown
from .user_scene import ASPECT_TOL as ASPECT_TOL
from .user_scene import (
    DEFAULT_REPEATS,
    SCENE_PARAMS,
    check_quantity,
    extrapolate,
    run_scene_points,
    scene_points,
    scene_study,
    sweep_scene,
)

__all__ = [
    "DEFAULT_REPEATS",
    "FILES",
    "QUANTITIES",
    "SCENE_PARAMS",
    "SweepInterrupted",
    "check_quantity",
    "choose_presets",
    "define_points",
    "errors",
    "extrapolate",
    "quantities_of",
    "richardson",
    "run_point",
    "run_scene_points",
    "scene_points",
    "scene_study",
    "sweep",
    "sweep_scene",
    "write_outputs",
    "write_scene_outputs",
]

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
    from .. import __version__

    records = list(records)
    done = {r["name"] for r in records}
    names = [p["scene"].get("name", "") for p in points]
    missing_points = [n for n in names if n not in done]
    points = [p for p, n in zip(points, names) if n in done]
    refs = references(records)
    recs = errors(records, refs)
    presets = choose_presets(recs, points)
    with writing(out, owned=FILES, last="sweep.json") as w:
        rows = ([r.get(k) for k in CSV_KEYS] for r in recs)
        w.stage("sweep.csv").write_text(csv_text(CSV_KEYS, rows), encoding="utf-8")
        w.stage("sweep.md").write_text(markdown(recs, refs, presets), encoding="utf-8")
        plots = [
            (f"sweep_{m}.png", functools.partial(plot, recs, m))
            for m in sorted({r["method"] for r in recs})
        ]
        done, stopped = w.stage_each(plots)
        missing_files = [name for name, _ in plots if name not in done]
        interrupted = bool(extra.get("interrupted")) or stopped
        doc = {
            "version": __version__,
            "machine": machine(cpu=False, load_average=True),
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


def write_scene_outputs(
    out: str | Path,
    points: Sequence[dict[str, Any]],
    records: Sequence[dict[str, Any]],
    quantity: str,
    *,
    extra: dict[str, Any] | None = None,
) -> dict[str, Any]:
    """Writes a scene sweep (:func:`scene_study` of ``records``) into ``out`` as one unit:
    ``sweep.csv`` (one row per level, the quantity under its name), ``sweep.md`` and
    ``sweep.json`` (last), replacing a previous sweep's files (its plots included). Returns the
    JSON document (``complete``, ``missing_points``, ``interrupted`` as :func:`write_outputs`).

    Raises:
        OutputError: as :func:`write_outputs` (the fallback folder is named).
    """
    extra = dict(extra or {})

    def write(d: Path) -> dict[str, Any]:
        from .. import __version__

        study = scene_study(points, records, quantity)
        interrupted = bool(extra.get("interrupted"))
        header = [quantity if k == "q" else k for k in SCENE_CSV_KEYS]
        rows = ([cell(r.get(k)) for k in SCENE_CSV_KEYS] for r in study["levels"])
        with writing(d, owned=FILES, last="sweep.json") as w:
            w.stage("sweep.csv").write_text(csv_text(header, rows), encoding="utf-8")
            w.stage("sweep.md").write_text(scene_markdown(study), encoding="utf-8")
            doc = {
                "version": __version__,
                "machine": machine(cpu=False, load_average=True),
                **extra,
                **study,
                "interrupted": interrupted,
                "complete": not interrupted and not study["missing_points"],
                "missing_files": [],
                "points": list(records),
                "scenes": {p["scene"].get("name", ""): p["scene"] for p in points},
            }
            w.stage("sweep.json").write_text(json.dumps(doc, indent=1), encoding="utf-8")
        return doc

    return with_fallback(Path(out), write, "sweep")
