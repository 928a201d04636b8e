"""Progress reports of a run: ``progress(done, total, message)`` callbacks.

- :class:`ProgressBar`: a plain-text bar on a stream (the CLI's);
- :class:`TqdmProgress`: a ``tqdm.auto`` bar (a widget in Jupyter, text in a terminal);
- :func:`callback`: what ``rf.run(scene, progress=...)`` makes of its argument (``True``: a tqdm
  bar when tqdm is installed, else a :class:`ProgressBar` on stderr).
"""

from __future__ import annotations

import sys
import time
from collections import deque
from typing import Any, Callable, TextIO

__all__ = ["LOG_INTERVAL_S", "ProgressBar", "ProgressCallback", "TqdmProgress", "callback"]

#: ``progress(done, total, message)``; called from the solver at most every ~0.1 s.
ProgressCallback = Callable[[int, int, str], Any]

#: on a stream that is not a terminal (a batch log, a pipe) each drawing of a
#: :class:`ProgressBar` is a new line: at most one every LOG_INTERVAL_S seconds (its
#: ``log_interval``), and the last report of each phase
LOG_INTERVAL_S = 5.0


class ProgressBar:
    """A plain-text progress bar on a stream; draws only once a run has lasted ``delay`` seconds
    (short runs stay quiet), at most every 0.1 s (the native side throttles too). Once two reports
    with different ``done`` counts of the same total arrived (e.g. SLA steps after the model
    setup), it also shows the estimated time left, from the rate over the recent part of the run
    (:attr:`RECENT`): the steps of an adaptive CCM-PD run grow dearer as its PD region grows, so
    the rate since the start would promise too early an end. ``clock``: seconds (tests)."""

    #: the time left is extrapolated from the rate over the last RECENT of the time since the
    #: first counted report, and over at least RECENT_MIN_S seconds
    RECENT = 0.5
    RECENT_MIN_S = 2.0

    def __init__(
        self,
        stream: TextIO | None = None,
        width: int = 30,
        delay: float = 0.5,
        clock: Callable[[], float] = time.perf_counter,
        log_interval: float = LOG_INTERVAL_S,
    ) -> None:
        # default: the sys.stderr of the moment (not of import time: redirections apply)
        self.stream = sys.stderr if stream is None else stream
        self.width, self.delay, self.clock = width, delay, clock
        self.log_interval = log_interval
        self.t0 = clock()
        self.drawn = False
        self._drawn_at = 0.0  # clock() of the last drawing
        #: the last drawing ended with a carriage return (a terminal): the bar holds the line
        self.mid_line = False
        #: (time, done) of the reports counted for the rate: those of the current total, from
        #: the first with done > 0; older ones are dropped once a newer one is older than the
        #: window
        self._seen: deque[tuple[float, int]] = deque()
        self._total: int | None = None
        self._since = 0.0  # time of the first counted report of the current total

    def __call__(self, done: int, total: int, message: str) -> None:
        now = self.clock()
        elapsed = now - self.t0
        eta = self._eta(now, done, total)
        if elapsed < self.delay and not self.drawn:
            return
        tty = self.stream.isatty()
        phase_end = total > 0 and done >= total
        if not tty and self.drawn and not phase_end and now - self._drawn_at < self.log_interval:
            return
        frac = done / total if total > 0 else 0.0
        n = round(self.width * min(max(frac, 0.0), 1.0))
        bar = "#" * n + "." * (self.width - n)
        end = "\r" if tty else "\n"
        self._drawn_at = now
        self.stream.write(f"[{bar}] {100 * frac:5.1f}% {elapsed:7.1f} s  {message}{eta}{end}")
        self.stream.flush()
        self.drawn = True
        self.mid_line = end == "\r"

    def _eta(self, now: float, done: int, total: int) -> str:
        """Counts the report and returns "  ETA ... s", or "" while the rate is unknown. A report
        that repeats the last count (the crack did not advance a thousandth since) keeps the
        estimate, less the time since that count."""
        seen = self._seen
        if total != self._total:  # a new phase: its own rate
            seen.clear()
            self._total = total
        if done > 0 and (not seen or done > seen[-1][1]):
            if not seen:
                self._since = now
            seen.append((now, done))
            window = max(self.RECENT_MIN_S, self.RECENT * (now - self._since))
            while len(seen) > 1 and now - seen[1][0] >= window:
                seen.popleft()
        if not seen or done <= 0 or done >= total:
            return ""
        (t_ref, d_ref), (t_last, d_last) = seen[0], seen[-1]
        if d_last == d_ref:
            return ""
        left = (t_last - t_ref) / (d_last - d_ref) * (total - d_last) - (now - t_last)
        return f"  ETA {max(left, 0.0):.1f} s"

    def end_line(self) -> None:
        """Ends the bar's line on a terminal (the next drawing starts a new one), e.g. before a
        log line that would otherwise overwrite it."""
        if self.mid_line:
            self.stream.write("\n")
            self.stream.flush()
            self.mid_line = False

    def close(self) -> None:
        self.end_line()


class TqdmProgress:
    """A ``tqdm.auto`` bar fed by ``(done, total, message)`` reports (the total may change
    between the phases of a run, e.g. model setup, then SLA steps). Needs tqdm."""

    def __init__(self, desc: str = "rustfrac", **tqdm_kwargs: Any) -> None:
        from tqdm.auto import tqdm  # ImportError without tqdm

        self._tqdm, self.desc, self.kwargs = tqdm, desc, tqdm_kwargs
        self.bar: Any = None  # drawn at the first report, which knows the total

    def __call__(self, done: int, total: int, message: str) -> None:
        if self.bar is None:
            self.bar = self._tqdm(total=total or None, desc=self.desc, **self.kwargs)
        b = self.bar
        if total > 0 and b.total != total:
            b.total = total
        b.n = max(0, done)
        b.set_postfix_str(message, refresh=False)
        b.refresh()

    def close(self) -> None:
        if self.bar is not None:
            self.bar.close()


def callback(
    progress: bool | ProgressCallback | None, desc: str = "rustfrac"
) -> ProgressCallback | None:
    """The callback for ``run(..., progress=...)``: None/False: none; True: a
    :class:`TqdmProgress` if tqdm is installed, else a :class:`ProgressBar` on stderr (no delay);
    a callable: itself. Bars made here have a ``close()`` the runner calls at the end."""
    if progress is None or progress is False:
        return None
    if progress is True:
        try:
            return TqdmProgress(desc)
        except ImportError:
            return ProgressBar(delay=0.0)
    if callable(progress):
        return progress
    from .errors import InvalidTypeError

    raise InvalidTypeError(
        "invalid progress: expected True, False, None or a callable progress(done, total, "
        f"message), got {type(progress).__name__}",
        "progress",
    )
