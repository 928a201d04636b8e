"""The result folders of a fig7 folder (:mod:`rustfrac.fig7`): ``xfem/`` and ``ccm_pd/``,
staged beside the job's other work and committed with it, and :func:`load_summary`, which reads
the summary back and checks that its result folders are the ones it was written with."""

from __future__ import annotations

import threading
from pathlib import Path
from typing import Any

from .._folder import FolderWriter, locked, why
from ..errors import InvalidResultError, OutputError, ResultNotFoundError
from ..result import JSON_NAME, OWNED_NAMES, Result, read_json, stage_result

__all__ = ["PARTS", "StagedPart", "load_summary"]

#: folder name of each run saved as a result folder
PARTS = {"xfem_growth": "xfem", "ccm_pd": "ccm_pd"}


class StagedPart:
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
