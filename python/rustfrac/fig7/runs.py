"""The runs of a fig7 job (:mod:`rustfrac.fig7`): CCM-PD in a worker thread beside the XFEM
runs, and the work drawn or staged ahead while CCM-PD still computes."""

from __future__ import annotations

import importlib
import secrets
import threading
import time
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any

from ..result import Result
from ..scene import Scene
from ..study import Log, ProgressFactory, run_logged
from .drawings import fig8b
from .folders import PARTS, StagedPart
from .presets import Preset

if TYPE_CHECKING:
    from .. import figures

__all__ = ["Runs", "built", "import_in_background"]


def import_in_background(module: str) -> None:
    """Starts importing ``module`` (relative to this package: "..figures") in a daemon thread:
    the runs release the GIL, so the import costs no wall time while they compute. The drawing's own import then finds
    the module loaded, or waits for it under the import lock; a failed import here is silent (the
    drawing's import raises it again)."""

    def load() -> None:
        try:
            importlib.import_module(module, __package__)
        except BaseException:  # re-raised by the import where the module is used
            pass

    threading.Thread(target=load, name=f"import {module}", daemon=True).start()


class Runs:
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
        self.staged: dict[str, StagedPart] = {}
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
                        name, scene, self.progress, self.say, built
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
                self.BESIDE, self.scenes[self.BESIDE], lambda name: report, self.say, built
            )
        except BaseException as e:  # raised again by run(), in the calling thread
            self._outcome["error"] = e

    def draw_ahead(self, p: Preset) -> None:
        """Stages the XFEM growth's result folder (worker thread) and draws Fig. 8b (the XFEM
        growth's deformed mesh: the costliest figure, and the only one that needs no CCM-PD
        result) while the CCM-PD run computes."""
        from .. import figures

        t = time.perf_counter()
        name = "xfem_growth"
        if name in self.results:
            self.staged[name] = StagedPart(
                self.results[name], self.outdir / PARTS[name], secrets.token_hex(8)
            )
        fig = fig8b(self.results, p)
        if fig is not None:
            self.ahead["fig8b.png"] = figures.render(fig)
        self.ahead_s = time.perf_counter() - t


def built(res: Result) -> str:
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
