"""The main job: reproduce the paper's Fig. 7 (and Figs. 6 and 8) with both methods, and report
the agreement and the cost (``rustfrac fig7 --out DIR [--preset fast|paper]``).

Runs, on the paper's plate (W = 11, L = 21, a0 = 1.1, E = 10000, nu = 0.25, G0 = 0.367, plane
strain, u2 = +-u0 on the grips, variant ``bc``):

1. XFEM at the reference load (K_I, sigma22, CMOD), under traction 9.993 (the paper's second K_I),
   and quasi-static LEFM growth from a0 to 0.7 W (its critical states give Fig. 8b's panels);
2. CCM-PD with the sequentially linear analysis (one bond break per step), in a worker thread
   beside the XFEM runs (the core releases the GIL), while Fig. 8b is drawn and the ``xfem/``
   result folder staged once those are done;
3. the LEFM handbook curve (long strip under traction: a guide, not the paper's geometry).

Once CCM-PD is done, Fig. 8a and Fig. 6 are drawn in a forked child process (:data:`BESIDE`,
``rustfrac._forked``: matplotlib draws under the GIL, so threads cannot share that work) while
this process draws Fig. 7; without a child (not Linux, no fork) they are drawn here after it.

Writes ``fig7.png``, ``fig7.csv``, ``fig8a.png``, ``fig8b.png``, ``fig6.png``, ``summary.md``,
``summary.json`` and the result folders ``xfem/`` and ``ccm_pd/``, as one unit (``_folder``; the
summary last, naming the save id of each result folder: :func:`load_summary` checks them). The
output folder is checked before anything runs; if it cannot be written at the end, the outputs go
to a temporary folder the :class:`~rustfrac.errors.OutputError` names. Ctrl-C stops cleanly: what
finished is written, and the summary says the run was interrupted (``complete`` false, ``missing``
lists the runs, result folders and files that are not there).
"""

from __future__ import annotations

import secrets
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from functools import partial
from pathlib import Path
from typing import TYPE_CHECKING, Any

from .. import study
from .._folder import FolderWriter, check_writable, with_fallback, writing
from .._forked import Forked
from .._log import logger
from ..result import OWNED_NAMES, Result
from ..scene import Scene
from ..study import Log, ProgressFactory
from .drawings import drawings, fig8b
from .folders import PARTS, StagedPart, load_summary
from .presets import PAPER, PRESETS, Preset, job_scenes
from .runs import Runs, import_in_background
from .summary import job_summary, markdown

if TYPE_CHECKING:
    from .. import figures

__all__ = ["FILES", "PAPER", "PRESETS", "Fig7Interrupted", "Preset", "fig7", "load_summary"]


def fig7(
    out: str | Path,
    *,
    preset: str = "paper",
    bc: str = "free",
    s0_calibration: str | None = None,
    surface_correction: str | None = None,
    log: Log | None = logger.info,
    progress: ProgressFactory | None = None,
) -> dict[str, Any]:
    """Runs the Fig. 7 job into ``out`` and returns the summary dict (also written as JSON).

    Args:
        preset: "paper" (the paper's discretisations), "fast" (coarse, seconds) or "full" (the
            paper's, with CCM-PD on the adaptive PD region to a = 0.7 W: both full curves).
        bc: grip variant of the displacement load: "free" or "clamped".
        s0_calibration: CCM-PD's critical stretch, scene key ``pd.s0_calibration``
            ("continuum", the paper's eq. 48; "grid"; "sla"); None: the scene's default.
        surface_correction: the CCM-PD run's ``pd.surface_correction`` ("none" or "energy");
            None: the scene's default ("none", the paper's).
        log: line logger (default: ``logging.getLogger("rustfrac").info``; None: silent).
        progress: factory ``progress(name)`` returning a progress callback for one run, or None.
    """
    if preset not in PRESETS:
        from ..errors import InvalidParameterError

        raise InvalidParameterError(
            f"invalid preset: expected one of {', '.join(map(repr, PRESETS))}, got {preset!r}",
            "preset",
        )
    if bc not in ("free", "clamped"):
        from ..errors import InvalidParameterError

        raise InvalidParameterError(
            f"invalid bc: expected 'free' or 'clamped' (displacement grips), got {bc!r}", "bc"
        )
    say: Log = log or (lambda s: None)
    outdir = check_writable(out)  # before computing: a bad --out must not cost the runs
    import_in_background("..figures")  # matplotlib, ~0.5 s, while the runs hold no GIL
    p = PRESETS[preset]
    scenes = job_scenes(p, bc, s0_calibration, surface_correction)
    t_all = time.perf_counter()
    runs = Runs(scenes, progress, say, outdir)
    try:
        runs.run(p)
    except BaseException:
        for part in runs.staged.values():
            part.abort()
        raise
    if runs.interrupted:
        say("interrupted: writing what finished")
    compute_s = time.perf_counter() - t_all
    job = _Job(
        runs.results, runs.times, p, preset, bc, scenes, runs.interrupted, t_all, compute_s,
        runs.ahead, runs.ahead_s, runs.staged,
    )  # fmt: skip
    summary = with_fallback(outdir, job.write, "fig7")
    commit_s = time.perf_counter() - t_all - summary["total_s"]
    say(
        f"saved   {outdir}/ ({', '.join(summary['files'])}; the result folders and the commit "
        f"{commit_s:.2f} s after the summary)"
    )
    if summary["missing"]:
        say(f"missing {', '.join(summary['missing'])}")
    if summary["interrupted"]:
        raise Fig7Interrupted(summary)
    return summary


class Fig7Interrupted(KeyboardInterrupt):
    """Ctrl-C during :func:`fig7`: what finished was written; ``summary`` is the summary written
    (``complete`` false, ``missing`` lists the runs, folders and files that are not there)."""

    def __init__(self, summary: dict[str, Any]) -> None:
        super().__init__("fig7 interrupted")
        self.summary = summary


#: the job's scenes and its Fig. 8b under the names its tests and benches know
_scenes = job_scenes
_fig8b = fig8b

#: the files of a fig7 folder (the result folders xfem/ and ccm_pd/ besides)
FILES = ("fig7.png", "fig7.csv", "fig8a.png", "fig8b.png", "fig6.png", "summary.md", "summary.json")
#: the figures drawn in a child process (:class:`~rustfrac._forked.Forked`) while this process
#: draws the others: the two that need the CCM-PD result besides fig7.png
BESIDE = ("fig8a.png", "fig6.png")


@dataclass
class _Job:
    """The outputs of one fig7 job, written as one folder (see :mod:`rustfrac._folder`)."""

    results: dict[str, Result]
    times: dict[str, float]
    p: Preset
    preset: str
    bc: str
    scenes: dict[str, Scene]
    interrupted: bool
    t_all: float
    #: wall time of the runs (the job's computation)
    compute_s: float = 0.0
    #: figures drawn beside the CCM-PD run (:meth:`Runs.draw_ahead`), and their wall time
    #: (inside ``compute_s``)
    ahead: dict[str, figures.Rendered] = field(default_factory=dict)
    ahead_s: float = 0.0
    #: result folders staged beside the CCM-PD run, in the output folder (run name -> staged)
    staged_ahead: dict[str, StagedPart] = field(default_factory=dict)

    def write(self, outdir: Path) -> dict[str, Any]:
        """Writes every output into ``outdir`` (summary.json last, naming the save id of each
        result folder) and returns the summary. The result folders are staged in worker threads
        while the figures draw (:class:`StagedPart`) and committed under the folder's lock. A
        Ctrl-C while drawing stops the drawing; the summary then lists the files not drawn."""
        staged: list[StagedPart] = []
        try:
            return self._write(outdir, staged)
        except BaseException:
            for part in [*staged, *self.staged_ahead.values()]:
                part.abort()
            self.staged_ahead.clear()
            raise

    def _write(self, outdir: Path, staged: list[StagedPart]) -> dict[str, Any]:
        owned = (*FILES, *PARTS.values())
        with writing(outdir, owned=owned, last="summary.json", inner=OWNED_NAMES) as w:
            t_fig = time.perf_counter()
            drawings = self._drawings()
            # some figures are drawn in a child process on the other core (forked before the
            # result folders' staging threads start: a fork copies only the calling thread)
            beside = [(f, make, w.stage(f)) for f, make in drawings if f in BESIDE]
            child = Forked([partial(make, path) for _, make, path in beside])
            try:
                files, stopped = self._draw(w, drawings, staged, outdir, child, beside)
            finally:
                child.kill()  # an error here: the child's files are not needed
            figures_s = time.perf_counter() - t_fig
            t_files = time.perf_counter()
            for part in staged:  # the result folders' staging, if the figures drew faster
                part.wait()
            files_s = time.perf_counter() - t_files
            interrupted = self.interrupted or stopped
            t_sum = time.perf_counter()
            summary = job_summary(
                self.results, self.times, self.p, self.preset, self.bc, self.scenes, interrupted
            )
            summary["total_s"] = time.perf_counter() - self.t_all
            # the job's own wall time by phase: the runs, the figures (fig7.csv included: it is
            # written among them), the result folders xfem/ and ccm_pd/ ("files": the wait for
            # their staging, which runs beside the figures; their renames at the folder's commit,
            # after this summary is staged, are not in it: fig7() logs that time), the summaries;
            # "other" is the rest
            summary["time_split_s"] = split = {
                "compute": self.compute_s,
                "figures": figures_s,
                # not a part of the sum: the figures drawn beside the CCM-PD run, inside compute
                "figures_beside_runs": self.ahead_s,
                "files": files_s,
                "summaries": time.perf_counter() - t_sum,
                "total": summary["total_s"],
            }
            split["other"] = max(
                0.0,
                split["total"]
                - split["compute"]
                - split["figures"]
                - split["files"]
                - split["summaries"],
            )
            summary["files"] = [*files, "summary.md", "summary.json"]
            summary["parts"] = {part.d.name: part.save_id for part in staged}
            summary["missing"] = study.missing(
                self.scenes, PARTS, FILES, self.results, summary["files"]
            )
            summary["complete"] = not interrupted and not summary["missing"]
            study.write_summary(w, summary, markdown(summary))
        return summary

    def _draw(
        self,
        w: FolderWriter,
        drawings: list[tuple[str, Callable[[Path], Any]]],
        staged: list[StagedPart],
        outdir: Path,
        child: Forked,
        beside: list[tuple[str, Callable[[Path], Any], Path]],
    ) -> tuple[list[str], bool]:
        """Stages the result folders (worker threads), draws the figures not ``beside`` (in the
        child) here, then waits for the child; returns the files drawn, in the drawings' order,
        and whether a Ctrl-C stopped the drawing (the files not drawn are then discarded)."""
        for name, part in PARTS.items():
            if name in self.results:
                ahead = self.staged_ahead.pop(name, None)
                if ahead is None or ahead.d != outdir / part:  # none, or not in this folder
                    if ahead is not None:
                        ahead.abort()
                    ahead = StagedPart(self.results[name], outdir / part, secrets.token_hex(8))
                staged.append(ahead)
                w.under_lock(part, ahead.commit)
        here, stopped = w.stage_each((f, make) for f, make in drawings if f not in BESIDE)
        done = set(here)
        try:
            if stopped:
                child.kill()
            else:
                child.wait()  # the child's figures, or drawn here if the child failed
                done.update(f for f, _, _ in beside)
        except KeyboardInterrupt:
            stopped = True
        for fname, _, _ in beside:
            if fname not in done:
                w.discard(fname)
        return [f for f, _ in drawings if f in done], stopped

    def _drawings(self) -> list[tuple[str, Callable[[Path], Any]]]:
        """(file name, writer into a path) of every file the finished runs give."""
        return drawings(self.results, self.p, self.scenes, self.bc, self.preset, self.ahead)
