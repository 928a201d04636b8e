"""The sweep's backends (:mod:`rustfrac.sweep`): a local process pool or a dask.distributed
cluster, each worker on one thread (``RAYON_NUM_THREADS=1``) so that both give the same numbers,
bit for bit; Ctrl-C keeps the finished records."""

from __future__ import annotations

import os
import sys
from collections.abc import Sequence
from typing import Any

from .points import Progress, check_repeats, init_worker, run_point


class SweepInterrupted(KeyboardInterrupt):
    """Ctrl-C during :func:`sweep`: ``records`` holds the points that finished (in point order);
    raised by :func:`write_outputs` too (Ctrl-C while drawing), with ``doc`` the JSON written."""

    def __init__(self, records: list[dict[str, Any]], doc: dict[str, Any] | None = None) -> None:
        super().__init__(f"sweep interrupted after {len(records)} points")
        self.records = records
        self.doc = doc


def sweep(
    points: Sequence[dict[str, Any]],
    *,
    workers: int | None = None,
    scheduler: Any = None,
    progress: Progress | None = None,
    repeats: int = 1,
) -> list[dict[str, Any]]:
    """Runs every point and returns their records, in the order of ``points``.

    Args:
        points: from :func:`define_points` (or dicts with ``study, method, param, value, h,
            scene``).
        workers: local processes (default: the number of cores); ignored with ``scheduler``.
        scheduler: None (local process pool), a scheduler address ``"tcp://host:port"``, or a
            ``distributed.Client``.
        progress: ``progress(done, total, message)`` after each finished point.
        repeats: runs per point (in its worker); the record's time is their minimum
            (:func:`run_point`).

    Raises:
        SweepInterrupted: on Ctrl-C (a ``KeyboardInterrupt``), with the finished records; the
            points still running are cancelled.
    """
    points = list(points)
    repeats = check_repeats(repeats)
    if scheduler is not None:
        return _sweep_dask(points, scheduler, progress, repeats)
    return _sweep_local(points, workers, progress, repeats)


def _sweep_local(
    points: list[dict[str, Any]], workers: int | None, progress: Progress | None, repeats: int
) -> list[dict[str, Any]]:
    import multiprocessing as mp
    from concurrent.futures import ProcessPoolExecutor, as_completed

    n = max(1, min(workers or os.cpu_count() or 1, len(points) or 1))
    kw: dict[str, Any] = {"max_workers": n, "initializer": init_worker}
    if sys.version_info >= (3, 11):
        # a fresh process per point: exact peak memory, no state carried between points
        kw.update(max_tasks_per_child=1, mp_context=mp.get_context("spawn"))
    out: list[dict[str, Any] | None] = [None] * len(points)
    ex = ProcessPoolExecutor(**kw)
    try:
        futs = {ex.submit(run_point, p, repeats): i for i, p in enumerate(points)}
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
    points: list[dict[str, Any]], scheduler: Any, progress: Progress | None, repeats: int
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
        futs = client.map(run_point, points, repeats=repeats, pure=False)
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
