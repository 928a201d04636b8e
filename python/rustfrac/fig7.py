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

import importlib
import secrets
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from functools import partial
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from . import _core, agreement, handbook, study
from ._folder import FolderWriter, check_writable, locked, why, with_fallback, writing
from ._forked import Forked
from ._log import logger
from .errors import InvalidResultError, OutputError, ResultNotFoundError
from .result import JSON_NAME, OWNED_NAMES, Result, read_json, stage_result
from .scene import Scene
from .scenes import edge_crack_plate
from .study import Log, ProgressFactory, run_logged

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from . import figures

__all__ = ["FILES", "PAPER", "PRESETS", "Fig7Interrupted", "Preset", "fig7", "load_summary"]

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


def _scenes(
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
            **_full_pd(p),
            **cal,
        ),
    }


def _full_pd(p: Preset) -> dict[str, Any]:
    """The CCM-PD options of a full-curve preset: the adaptive region (its defaults) until the
    crack reaches the core's default XFEM stop length."""
    if not p.full_pd:
        return {}
    width = edge_crack_plate("ccm_pd").plate.width
    stop = _core.scene_constants()["DEFAULT_A_STOP_FRACTION"] * width
    return dict(region="adaptive", stop_crack_length=stop)


def _peak(res: Result) -> tuple[float, float]:
    """(peak sigma22, CMOD at the peak) of a load path."""
    s, c = res.history["sigma22"], res.history["cmod"]
    i = int(np.argmax(s))
    return float(s[i]), float(c[i])


def _write_csv(path: Path, results: dict[str, Result], hb: tuple[np.ndarray, np.ndarray]) -> None:
    rows: list[list[Any]] = []
    for name in ("xfem_growth", "ccm_pd"):
        if name not in results:
            continue
        h = results[name].history
        a = h.get("a", h.get("crack_length"))
        for i in range(len(h["sigma22"])):
            rows.append(
                [
                    "xfem" if name == "xfem_growth" else "ccm_pd",
                    i,
                    None if a is None else float(a[i]),
                    float(h["load_factor"][i]),
                    float(h["u0"][i]),
                    float(h["sigma22"][i]),
                    float(h["cmod"][i]),
                ]
            )
    for i, (c, s) in enumerate(zip(*hb)):
        rows.append(["handbook", i, None, None, None, float(s), float(c)])
    header = ["method", "point", "crack_length", "load_factor", "u0", "sigma22", "cmod"]
    study.write_text(path, study.csv_text(header, rows))


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
        from .errors import InvalidParameterError

        raise InvalidParameterError(
            f"invalid preset: expected one of {', '.join(map(repr, PRESETS))}, got {preset!r}",
            "preset",
        )
    if bc not in ("free", "clamped"):
        from .errors import InvalidParameterError

        raise InvalidParameterError(
            f"invalid bc: expected 'free' or 'clamped' (displacement grips), got {bc!r}", "bc"
        )
    say: Log = log or (lambda s: None)
    outdir = check_writable(out)  # before computing: a bad --out must not cost the runs
    _import_in_background(".figures")  # matplotlib, ~0.5 s, while the runs hold no GIL
    p = PRESETS[preset]
    scenes = _scenes(p, bc, s0_calibration, surface_correction)
    t_all = time.perf_counter()
    runs = _Runs(scenes, progress, say, outdir)
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


def _import_in_background(module: str) -> None:
    """Starts importing ``module`` (of this package) in a daemon thread: the runs release the
    GIL, so the import costs no wall time while they compute. The drawing's own import then finds
    the module loaded, or waits for it under the import lock; a failed import here is silent (the
    drawing's import raises it again)."""

    def load() -> None:
        try:
            importlib.import_module(module, __package__)
        except BaseException:  # re-raised by the import where the module is used
            pass

    threading.Thread(target=load, name=f"import {module}", daemon=True).start()


class _Runs:
    """The runs of a fig7 job. The CCM-PD run (the longest: its set-up and SLA) goes to a worker
    thread and the XFEM runs follow here beside it: the core releases the GIL, so they share the
    two cores. The figures that need only the XFEM runs are then drawn ahead (:meth:`draw_ahead`)
    while CCM-PD still computes.

    Ctrl-C (it reaches this thread) stops the XFEM run it meets, or the wait, and cancels the
    CCM-PD run at its next progress report (the worker's callback raises KeyboardInterrupt, as a
    Ctrl-C would); a run that finished is kept either way. Any other error of either thread is
    raised here once the worker has stopped."""

    #: the run that goes to the worker thread
    BESIDE = "ccm_pd"

    def __init__(
        self,
        scenes: dict[str, Scene],
        progress: ProgressFactory | None,
        say: Log,
        outdir: Path,
    ) -> None:
        self.scenes, self.progress, self.say, self.outdir = scenes, progress, say, outdir
        self.results: dict[str, Result] = {}
        self.times: dict[str, float] = {}
        self.interrupted = False
        #: figures drawn beside the CCM-PD run (file name -> pixels) and the time it took
        self.ahead: dict[str, figures.Rendered] = {}
        self.ahead_s = 0.0
        #: result folders staged beside the CCM-PD run (run name -> staged folder)
        self.staged: dict[str, _StagedPart] = {}
        self._cancel = threading.Event()
        self._outcome: dict[str, Any] = {}

    def run(self, p: Preset) -> None:
        """Runs every scene, and draws ahead the figures of preset ``p`` that the XFEM runs give
        (:meth:`draw_ahead`) once they are done, while the worker's run may still compute. The
        results come in the scenes' order."""
        worker = None
        if self.BESIDE in self.scenes:
            # its progress callback made here, before the XFEM runs' (the factory's order)
            inner = self.progress(self.BESIDE) if self.progress else None
            worker = threading.Thread(
                target=self._worker, args=(inner,), name="fig7 ccm_pd", daemon=True
            )
            worker.start()
        try:
            for name, scene in self.scenes.items():
                if self._worker_failed():  # raised below, without the runs left
                    break
                if name != self.BESIDE:
                    self.results[name], self.times[name] = run_logged(
                        name, scene, self.progress, self.say, _built
                    )
            if not self._worker_failed():
                self.draw_ahead(p)
            if worker is not None:
                worker.join()
        except KeyboardInterrupt:
            self.interrupted = True
        finally:
            if worker is not None:
                self._cancel.set()  # nothing to cancel once it finished
                worker.join()
        error = self._outcome.get("error")
        if isinstance(error, KeyboardInterrupt):
            self.interrupted = True
        elif error is not None:
            raise error
        if "result" in self._outcome:
            self.results[self.BESIDE], self.times[self.BESIDE] = self._outcome["result"]
        self.results = {n: self.results[n] for n in self.scenes if n in self.results}
        self.times = {n: self.times[n] for n in self.results}

    def _worker_failed(self) -> bool:
        """The worker's run raised an error (a KeyboardInterrupt, which its progress callback
        raises to cancel it, is not a failure: the XFEM runs go on and are kept)."""
        error = self._outcome.get("error")
        return error is not None and not isinstance(error, KeyboardInterrupt)

    def _worker(self, inner: Callable[[int, int, str], Any] | None) -> None:
        def report(done: int, total: int, message: str) -> None:
            if self._cancel.is_set():
                raise KeyboardInterrupt
            if inner is not None:
                inner(done, total, message)

        try:
            self._outcome["result"] = run_logged(
                self.BESIDE, self.scenes[self.BESIDE], lambda name: report, self.say, _built
            )
        except BaseException as e:  # raised again by run(), in the calling thread
            self._outcome["error"] = e

    def draw_ahead(self, p: Preset) -> None:
        """Stages the XFEM growth's result folder (worker thread) and draws Fig. 8b (the XFEM
        growth's deformed mesh: the costliest figure, and the only one that needs no CCM-PD
        result) while the CCM-PD run computes."""
        from . import figures

        t = time.perf_counter()
        name = "xfem_growth"
        if name in self.results:
            self.staged[name] = _StagedPart(
                self.results[name], self.outdir / PARTS[name], secrets.token_hex(8)
            )
        fig = _fig8b(self.results, p)
        if fig is not None:
            self.ahead["fig8b.png"] = figures.render(fig)
        self.ahead_s = time.perf_counter() - t


class Fig7Interrupted(KeyboardInterrupt):
    """Ctrl-C during :func:`fig7`: what finished was written; ``summary`` is the summary written
    (``complete`` false, ``missing`` lists the runs, folders and files that are not there)."""

    def __init__(self, summary: dict[str, Any]) -> None:
        super().__init__("fig7 interrupted")
        self.summary = summary


#: the files of a fig7 folder (the result folders xfem/ and ccm_pd/ besides)
FILES = ("fig7.png", "fig7.csv", "fig8a.png", "fig8b.png", "fig6.png", "summary.md", "summary.json")
#: folder name of each run saved as a result folder
PARTS = {"xfem_growth": "xfem", "ccm_pd": "ccm_pd"}
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
    #: figures drawn beside the CCM-PD run (:meth:`_Runs.draw_ahead`), and their wall time
    #: (inside ``compute_s``)
    ahead: dict[str, figures.Rendered] = field(default_factory=dict)
    ahead_s: float = 0.0
    #: result folders staged beside the CCM-PD run, in the output folder (run name -> staged)
    staged_ahead: dict[str, _StagedPart] = field(default_factory=dict)

    def write(self, outdir: Path) -> dict[str, Any]:
        """Writes every output into ``outdir`` (summary.json last, naming the save id of each
        result folder) and returns the summary. The result folders are staged in worker threads
        while the figures draw (:class:`_StagedPart`) and committed under the folder's lock. A
        Ctrl-C while drawing stops the drawing; the summary then lists the files not drawn."""
        staged: list[_StagedPart] = []
        try:
            return self._write(outdir, staged)
        except BaseException:
            for part in [*staged, *self.staged_ahead.values()]:
                part.abort()
            self.staged_ahead.clear()
            raise

    def _write(self, outdir: Path, staged: list[_StagedPart]) -> dict[str, Any]:
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
            summary = _summary(
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
            study.write_summary(w, summary, _markdown(summary))
        return summary

    def _draw(
        self,
        w: FolderWriter,
        drawings: list[tuple[str, Callable[[Path], Any]]],
        staged: list[_StagedPart],
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
                    ahead = _StagedPart(self.results[name], outdir / part, secrets.token_hex(8))
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
        from . import figures

        results, p = self.results, self.p
        ref = self.scenes["xfem"]  # the plate, material and crack every run shares
        W, mat, a0, yc = ref.plate.width, ref.material, ref.crack.a0, ref.crack.y
        # the handbook curve over the crack lengths the XFEM growth reached; without the growth
        # run, up to the core's default stop length (0.7 W, the paper's Fig. 7)
        grown = results.get("xfem_growth")
        stop = _core.scene_constants()["DEFAULT_A_STOP_FRACTION"] * W
        a_end = float(grown.history["a"].max()) if grown is not None and grown.history else stop
        a = np.linspace(a0, a_end, 120)
        hb_c, hb_s = handbook.edge_crack_curve(a, W, mat.E, mat.nu, mat.G0, mat.plane)
        hb = (np.concatenate([[0.0], hb_c]), np.concatenate([[0.0], hb_s]))
        curves: list[figures.Curve] = []
        if "xfem_growth" in results:
            h = results["xfem_growth"].history
            # on top of the PD saw-tooth, which covers it on the full curve (preset "full")
            style = {"marker": ".", "ms": 4, "zorder": 5, "color": "C0"}
            curves.append(("XFEM (LEFM growth)", h["cmod"], h["sigma22"], style))
        if "ccm_pd" in results:
            h = results["ccm_pd"].history
            # one point per SLA step (each at the load that breaks its bond): the saw-tooth of SLA
            curves.append(
                (
                    "CCM-PD (SLA, one point per bond break)",
                    h["cmod"],
                    h["sigma22"],
                    {"lw": 0.4, "alpha": 0.7, "marker": ".", "ms": 2.5, "color": "C1"},
                )
            )
        # the CMOD axis ends a little past the computed curves: the handbook's traction curve
        # reaches about twice their CMOD at a = 0.7 W and would squeeze them into half the plot
        computed = [np.max(c[1]) for c in curves if len(c[1])]
        x_max = 1.08 * float(max(computed)) if computed else None
        curves.append(
            ("LEFM handbook (long strip, traction)", hb[0], hb[1], {"ls": "--", "color": "0.4"})
        )
        title = f"edge-cracked plate, bc {self.bc}, preset {self.preset}"
        both = "xfem_growth" in results and "ccm_pd" in results
        panel = _curve_agreement(results)["curves"] if both else None
        out: list[tuple[str, Callable[[Path], Any]]] = [
            (
                "fig7.png",
                lambda f: figures.save_figure(
                    figures.plot_fig7(
                        curves,
                        title=title,
                        published=[
                            ("paper, initial (XFEM)", PAPER["cmod_xfem"], PAPER["sigma22_xfem"])
                        ],
                        agreement=panel,
                        x_max=x_max,
                    ),
                    f,
                ),
            ),
            ("fig7.csv", lambda f: _write_csv(f, results, hb)),
        ]
        if "ccm_pd" in results:
            r = results["ccm_pd"]
            out.append(
                (
                    "fig8a.png",
                    lambda f: figures.save_figure(
                        figures.plot_damage(
                            r.fields["pd_node_xy"],
                            r.fields["damage"],
                            p.dx,
                            title=f"CCM-PD damage after {len(r.history['sigma22']) - 1} SLA steps",
                            crack_y=yc,
                        ),
                        f,
                    ),
                )
            )
        # drawn beside the CCM-PD run, or now; none when the growth reached no snapshot step
        fig8b = self.ahead.get("fig8b.png") or _fig8b(results, p)
        if fig8b is not None:
            out.append(("fig8b.png", lambda f: figures.save_figure(fig8b, f)))
        if "xfem" in results and "ccm_pd" in results:
            out.append(
                (
                    "fig6.png",
                    lambda f: figures.save_figure(
                        figures.plot_discretisations(
                            _xfem_disc(results["xfem"]),
                            _pd_disc(results["ccm_pd"], p.dx),
                            (0.0, 2.6, 9.6, 11.4),
                        ),
                        f,
                    ),
                )
            )
        return out


def _fig8b(results: dict[str, Result], p: Preset) -> Figure | None:
    """Fig. 8b: the XFEM growth's deformed mesh near the tip at the preset's growth steps
    (None: no growth run, or none of those steps reached)."""
    from . import figures

    g = results.get("xfem_growth")
    if g is None:
        return None
    off = g.fields["snapshot_offsets"]
    snaps = []
    for k in p.snapshot_steps:
        if k < len(off):  # snapshot k-1: the critical state of growth step k (row k)
            rows = slice(int(off[k - 1]), int(off[k]))
            snaps.append(
                (
                    g.fields["snapshot_cells"][rows],
                    g.fields["snapshot_disp"][rows],
                    f"growth step {k}: a = {float(g.history['a'][k]):.3g} mm, sigma22 = "
                    f"{float(g.history['sigma22'][k]):.3g} MPa",
                )
            )
    return figures.plot_deformed_patches(snaps, scale=50.0) if snaps else None


class _StagedPart:
    """A result folder (``xfem/``, ``ccm_pd/``) of a fig7 folder, staged in a worker thread (its
    arrays compressed, hashed and fsynced: work that releases the GIL, beside the figures'
    drawing) and committed by :meth:`commit` under the fig7 folder's lock, as
    :meth:`Result.save` would write it."""

    def __init__(self, res: Result, d: Path, save_id: str) -> None:
        self.d = d
        self.save_id = save_id
        self._made = not d.exists()
        self._w: FolderWriter | None = None
        self._error: BaseException | None = None
        self._done = False
        self._thread = threading.Thread(
            target=self._stage_files, args=(res, save_id), name=f"stage {d.name}", daemon=True
        )
        self._thread.start()

    def _stage_files(self, res: Result, save_id: str) -> None:
        try:
            self.d.mkdir(parents=True, exist_ok=True)
            self._w = FolderWriter(self.d, OWNED_NAMES, JSON_NAME, ())
            stage_result(res, self._w, vtu=True, save_id=save_id)
            self._w.sync()
        except BaseException as e:  # raised again by commit(), in the main thread
            self._error = e

    def wait(self) -> None:
        """Waits for the staging to finish."""
        self._thread.join()

    def commit(self) -> None:
        """Renames the staged files into place (the staging's error, if any, raised here).

        Raises:
            OutputError: the result folder could not be written (naming it and the reason).
        """
        self.wait()
        try:
            if self._error is not None:
                raise self._error
            assert self._w is not None
            self._w.commit()
            self._done = True
        except OSError as e:
            if isinstance(e, OutputError):
                raise
            raise OutputError(f"cannot write output folder {self.d}: {why(e)}", self.d) from e

    def abort(self) -> None:
        """Removes what was staged (after the staging ends) and the folder if it made it."""
        self.wait()
        if self._done:
            return
        if self._w is not None:
            self._w.abort()
        if self._made:
            try:
                self.d.rmdir()
            except OSError:  # not empty (or gone)
                pass


def load_summary(out: str | Path) -> dict[str, Any]:
    """Reads the ``summary.json`` of a fig7 folder, checking that its result folders are the ones
    it was written with (each ``xfem/`` and ``ccm_pd/`` save id against the summary's ``parts``).

    Raises:
        ResultNotFoundError: no summary.json.
        InvalidResultError: not valid, or a result folder of another run (naming it).
    """
    d = Path(out)
    path = d / "summary.json"
    try:
        with locked(d, exclusive=False):
            data = path.read_bytes()
            ids = {}
            for part in PARTS.values():
                try:
                    ids[part] = read_json(
                        d / part / "result.json", (d / part / "result.json").read_bytes()
                    ).get("save_id")
                except FileNotFoundError:
                    ids[part] = None
    except FileNotFoundError as e:
        raise ResultNotFoundError(
            f"{e.filename}: no such file (not a fig7 folder?)", e.filename
        ) from e
    summary = read_json(path, data)
    parts = summary.get("parts")
    if not isinstance(parts, dict):
        raise InvalidResultError(
            f"invalid parts in {path}: expected an object of save ids", path, "parts"
        )
    for part in PARTS.values():
        if parts.get(part) != ids[part]:
            raise InvalidResultError(
                f"{d / part} does not belong to {path}: its save id is {ids[part]}, the summary's "
                f"{parts.get(part)} (a result of another run, or an interrupted write)",
                d / part,
                "parts",
            )
    return summary


def _built(res: Result) -> str:
    m = res.meta
    if res.method == "xfem":
        en = m.get("enrichment", {})
        return (
            f"{res.n_dofs} unknowns, {en.get('n_heaviside_nodes', '?')} Heaviside and "
            f"{en.get('n_tip_nodes', '?')} tip nodes, status {m.get('status', '?')}"
        )
    if res.method in ("pd", "ccm_pd"):
        c, t = m.get("counts", {}), m.get("timings", {})
        return (
            f"{res.n_dofs} unknowns, {c.get('n_pd_nodes', '?')} PD nodes, "
            f"{c.get('n_bonds', '?')} bonds, gamma {res.gamma:.15g}, status "
            f"{m.get('status', '?')} after {m.get('sla_steps_done', '?')} steps "
            f"(setup {t.get('setup_s', float('nan')):.2f} s, SLA {t.get('sla_s', float('nan')):.2f} s)"
        )
    return f"{res.n_dofs} unknowns"


def _xfem_disc(r: Result) -> dict[str, np.ndarray]:
    f = r.fields
    return {
        "coords": f["coords"],
        "elements": f["elements"],
        "heaviside_nodes": f["heaviside_nodes"],
        "tip_nodes": f["tip_nodes"],
        "crack": f["crack"],
    }


def _pd_disc(r: Result, dx: float) -> dict[str, np.ndarray]:
    from .figures import grid_elements

    xy = r.fields["node_xy"]
    nx = round(float(xy[:, 0].max() - xy[:, 0].min()) / dx)
    ny = round(float(xy[:, 1].max() - xy[:, 1].min()) / dx)
    el = grid_elements(nx, ny)
    is_pd = np.zeros(len(xy), bool)
    is_pd[np.asarray(r.fields["pd_nodes"], int)] = True
    cells = xy[el]
    (x0, yc), (a0, _) = np.asarray(r.meta["precrack"], float)[[0, -1]]
    # FEM elements cut by the pre-crack are removed in the core (the crack is a real slit there)
    removed = (cells[:, :, 1].min(axis=1) < yc) & (cells[:, :, 1].max(axis=1) > yc)
    removed &= cells[:, :, 0].min(axis=1) < a0
    return {
        "node_xy": xy,
        "is_pd": is_pd,
        "elements": el,
        "removed": removed,
        "crack": np.array([[x0, yc], [a0, yc]]),
    }


def _curve_agreement(results: dict[str, Result]) -> dict[str, Any]:
    """The CCM-PD saw-tooth against the XFEM growth curve at equal CMOD (:mod:`.agreement`)."""
    xh, ph = results["xfem_growth"].history, results["ccm_pd"].history
    return agreement.compare(xh["cmod"], xh["sigma22"], ph["cmod"], ph["sigma22"])


def _rel(a: float, b: float) -> float:
    return (a - b) / b if b else float("nan")


def _summary(
    results: dict[str, Result],
    times: dict[str, float],
    p: Preset,
    preset: str,
    bc: str,
    scenes: dict[str, Scene],
    interrupted: bool,
) -> dict[str, Any]:
    from . import __version__

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
        ps, pc = _peak(r)
        ours.update(
            peak_sigma22_xfem=ps,
            cmod_at_peak_xfem=pc,
            xfem_growth_status=r.meta.get("status"),
            xfem_final_a=float(r.history["a"][-1]),
        )
    if "ccm_pd" in results:
        r = results["ccm_pd"]
        ps, pc = _peak(r)
        ours.update(
            peak_sigma22_ccm_pd=ps,
            cmod_at_peak_ccm_pd=pc,
            ccm_pd_status=r.meta.get("status"),
            ccm_pd_steps=len(r.history["sigma22"]) - 1,
        )
    if "peak_sigma22_xfem" in ours and "peak_sigma22_ccm_pd" in ours:
        s["agreement"] = {
            "peak_sigma22_rel_diff": _rel(ours["peak_sigma22_ccm_pd"], ours["peak_sigma22_xfem"]),
            "cmod_at_peak_rel_diff": _rel(ours["cmod_at_peak_ccm_pd"], ours["cmod_at_peak_xfem"]),
            "initial_cmod_rel_diff": _rel(ours["cmod_ccm_pd"], ours["cmod_xfem"]),
            "initial_sigma22_rel_diff": _rel(ours["sigma22_ccm_pd"], ours["sigma22_xfem"]),
        }
        cur = _curve_agreement(results)
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


def _fmt(v: Any, spec: str = ".6g") -> str:
    return study.fmt(v, spec)


def _markdown(s: dict[str, Any]) -> str:
    o, pa = s["ours"], s["paper"]
    lines = [
        "## Paper values beside ours",
        "",
        *study.table(
            ["quantity", "paper", "rustfrac"],
            [
                ["sigma22, XFEM, u0 = 0.01", pa["sigma22_xfem"], _fmt(o.get("sigma22_xfem"))],
                ["CMOD, XFEM", pa["cmod_xfem"], _fmt(o.get("cmod_xfem"))],
                [
                    "K_I, XFEM, displacement load",
                    pa["K_I_displacement"],
                    _fmt(o.get("K_I_displacement")),
                ],
                ["K_I, XFEM, traction 9.993", pa["K_I_traction"], _fmt(o.get("K_I_traction"))],
                [
                    "sigma22, CCM-PD, before any break",
                    pa["sigma22_ccm_pd"],
                    _fmt(o.get("sigma22_ccm_pd")),
                ],
                ["CMOD, CCM-PD", pa["cmod_ccm_pd"], _fmt(o.get("cmod_ccm_pd"))],
                ["gamma (m = 4)", "0.988895997195466", _fmt(o.get("gamma"), ".15g")],
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
                        _fmt(o["peak_sigma22_xfem"]),
                        _fmt(o["peak_sigma22_ccm_pd"]),
                        f"{ag['peak_sigma22_rel_diff']:+.2%}",
                    ],
                    [
                        "CMOD at the peak",
                        _fmt(o["cmod_at_peak_xfem"]),
                        _fmt(o["cmod_at_peak_ccm_pd"]),
                        f"{ag['cmod_at_peak_rel_diff']:+.2%}",
                    ],
                    [
                        "initial CMOD (u0 = 0.01)",
                        _fmt(o["cmod_xfem"]),
                        _fmt(o["cmod_ccm_pd"]),
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
                ["XFEM growth", f"{c['paper_xfem_s']} s", f"{_fmt(c['xfem_s'], '.3f')} s"],
                ["CCM-PD, SLA", f"{c['paper_ccm_pd_s']} s", f"{_fmt(c['ccm_pd_s'], '.3f')} s"],
            ],
        ),
        "",
        _split_line(s),
        f"Whole job: {s.get('total_s', 0):.1f} s. Growth status: XFEM "
        f"{o.get('xfem_growth_status', 'n/a')} (final a = {_fmt(o.get('xfem_final_a'))}), "
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


def _split_line(s: dict[str, Any]) -> str:
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
