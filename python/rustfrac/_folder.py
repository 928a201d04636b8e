"""Output folders written as one unit (result folders, ``fig7`` and ``sweep`` outputs).

A writer stages every file of the set under a temporary name in the folder (``.NAME.PID.TOKEN.tmp``,
fsynced), then, holding an exclusive lock on the folder (``flock`` of the directory itself;
released by the kernel when a writer dies), renames them into place, its ``last`` file (the one
that names the others: ``result.json``, ``summary.json``, ``sweep.json``) last, and removes the
folder's own names that the new set lacks (a stale ``result.vtu``, a plot of an earlier run).
An owned name may be a glob pattern (``result_series/state_*.vtu``: a numbered set of files in a
subfolder); a staged name may lie in a subfolder (created when staged), which goes when a later
set empties it.
Readers (:func:`rustfrac.load`) take a shared lock, so they never see a half-renamed set; a second
writer waits for the first and then replaces its set whole (last writer wins). A writer killed
between two renames leaves a folder whose ``last`` file names checksums its neighbours no longer
have: ``rustfrac.load`` refuses it (:class:`~rustfrac.errors.InvalidResultError`). A failure
while staging (full disk, ...) changes nothing but the temporaries, which are removed.

On file systems without ``flock`` (some network mounts) and on Windows the lock is skipped; the
checksums still make a mixed folder an error rather than a result.
"""

from __future__ import annotations

import errno
import os
import secrets
import shutil
import tempfile
import time
from collections.abc import Callable, Iterable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import IO, Any, TypeVar

from .errors import OutputError

#: a writer refuses to start on a file system with less free space than this (bytes)
MIN_FREE_BYTES = 1 << 20
#: stale temporaries of dead writers older than this (seconds) are removed at the next commit
STALE_TMP_S = 3600.0

T = TypeVar("T")


def _tmp_path(path: Path) -> Path:
    return path.parent / f".{path.name}.{os.getpid()}.{secrets.token_hex(6)}.tmp"


@contextmanager
def atomic_file(path: Path, mode: str) -> Iterator[IO[Any]]:
    """Writes to a temporary file next to ``path`` and renames it over ``path`` on success."""
    # like mkstemp, but the file gets the usual permissions (0666 minus the umask), not 0600
    tmp = _tmp_path(path)
    fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666)
    try:
        with os.fdopen(fd, mode, **({} if "b" in mode else {"encoding": "utf-8"})) as f:
            yield f
            f.flush()
            os.fsync(f.fileno())
        os.replace(tmp, path)
    except BaseException:
        _unlink(tmp)
        raise


def _unlink(p: Path) -> None:
    try:
        os.unlink(p)
    except FileNotFoundError:
        pass


def why(e: OSError) -> str:
    """The reason of an OS error, for a message."""
    return e.strerror or str(e)


def check_writable(path: str | Path) -> Path:
    """Checks, before anything is computed, that the folder ``path`` can be written: it is a
    folder or can be created, a probe file can be written into it (or into its nearest existing
    ancestor) and the file system has :data:`MIN_FREE_BYTES` free. Creates nothing.

    Raises:
        OutputError: naming the path and the reason.
    """
    p = Path(path)
    if p.exists() and not p.is_dir():
        raise OutputError(f"cannot write output folder {p}: it is a file, not a folder", p)
    base = p
    while not base.exists() and base != base.parent:
        base = base.parent
    if not base.is_dir():
        raise OutputError(f"cannot create output folder {p}: {base} is a file, not a folder", p)
    probe = base / f".rustfrac-probe.{os.getpid()}.{secrets.token_hex(6)}.tmp"
    try:
        fd = os.open(probe, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o600)
        try:
            os.write(fd, b"probe")
            os.fsync(fd)
        finally:
            os.close(fd)
            _unlink(probe)
    except OSError as e:
        where = "" if base == p else f" (in {base})"
        raise OutputError(f"cannot write output folder {p}{where}: {why(e)}", p) from e
    if hasattr(os, "statvfs"):
        st = os.statvfs(base)
        free = st.f_bavail * st.f_frsize
        if free < MIN_FREE_BYTES:
            raise OutputError(
                f"cannot write output folder {p}: only {free} bytes free on its file system "
                f"(at least {MIN_FREE_BYTES} needed)",
                p,
            )
    return p


@contextmanager
def locked(d: Path, *, exclusive: bool) -> Iterator[None]:
    """Holds a shared or exclusive ``flock`` on the folder ``d`` (a no-op where unsupported)."""
    try:
        import fcntl
    except ImportError:  # pragma: no cover (Windows)
        yield
        return
    fd = os.open(d, os.O_RDONLY | getattr(os, "O_DIRECTORY", 0))
    try:
        try:
            fcntl.flock(fd, fcntl.LOCK_EX if exclusive else fcntl.LOCK_SH)
        except OSError:  # a file system without locks: the checksums still catch mixed sets
            pass
        yield
    finally:
        os.close(fd)  # releases the lock


class FolderWriter:
    """The pending set of files of one output folder (see the module docstring); made by
    :func:`writing`."""

    def __init__(self, path: Path, owned: Iterable[str], last: str, inner: Iterable[str]) -> None:
        self.path = path
        self.owned = frozenset(owned)
        self.last = last
        self.inner = tuple(inner)
        self._staged: dict[str, Path] = {}
        self._hooks: dict[str, Callable[[], object]] = {}
        self._synced: set[str] = set()

    def stage(self, name: str) -> Path:
        """A fresh temporary path in the folder where the caller writes the file ``name``; it is
        renamed to ``name`` at the commit."""
        if name in self._staged:
            raise ValueError(f"{name} is staged twice in {self.path}")
        target = self.path / name
        if target.parent != self.path:  # a file of a subfolder (``result_series/state_0.vtu``)
            target.parent.mkdir(parents=True, exist_ok=True)
        p = _tmp_path(target)
        self._staged[name] = p
        return p

    def discard(self, name: str) -> None:
        """Drops a staged file (e.g. a plot interrupted half-written): it is not committed."""
        p = self._staged.pop(name, None)
        self._synced.discard(name)
        if p is not None:
            _unlink(p)

    def stage_each(
        self, files: Iterable[tuple[str, Callable[[Path], object]]]
    ) -> tuple[list[str], bool]:
        """Stages the files ``(name, write(path))`` in order until a Ctrl-C: the file the
        KeyboardInterrupt interrupts is discarded and the later ones are not written. Returns the
        names staged and whether a Ctrl-C stopped it (a job then lists the others as missing)."""
        done: list[str] = []
        for name, write in files:
            try:
                write(self.stage(name))
            except KeyboardInterrupt:
                self.discard(name)
                return done, True
            done.append(name)
        return done, False

    def under_lock(self, name: str, fn: Callable[[], object]) -> None:
        """Has ``fn`` write the entry ``name`` at the commit while the folder's lock is held,
        before the renames (e.g. a result folder inside a fig7 folder)."""
        self._hooks[name] = fn

    def sync(self) -> None:
        """Flushes the files staged so far to disk (fsync; the commit does it for any not yet
        synced): a writer that stages in a worker thread syncs there too."""
        for name, p in list(self._staged.items()):
            if name in self._synced or not p.exists():
                continue
            fd = os.open(p, os.O_RDONLY)
            try:
                os.fsync(fd)
            finally:
                os.close(fd)
            self._synced.add(name)

    def commit(self) -> None:
        """Renames the staged files into place under the folder's lock (the hooks of
        :meth:`under_lock` first, the ``last`` file last) and removes the owned names the new set
        lacks; :func:`writing` calls it when its block ends."""
        self.sync()
        staged = {n: p for n, p in self._staged.items() if p.exists()}
        with locked(self.path, exclusive=True):
            for fn in self._hooks.values():
                fn()
            _remove_stale_tmps(self.path)
            # in staging order (a result's fields.npz first), the last file last
            order = sorted(staged, key=lambda n: n == self.last)
            for name in order:
                os.replace(staged[name], self.path / name)
            for name in sorted(_expand(self.path, self.owned) - set(staged) - set(self._hooks)):
                _remove_owned(self.path / name, self.inner)
                _prune(self.path, self.path / name)
            _fsync_dir(self.path)

    def abort(self) -> None:
        """Removes the staged temporaries: the folder is left as it was."""
        for p in self._staged.values():
            _unlink(p)
            _prune(self.path, p)


@contextmanager
def writing(
    path: str | Path, *, owned: Iterable[str], last: str, inner: Iterable[str] = ()
) -> Iterator[FolderWriter]:
    """Writes an output folder as one unit: the caller writes each file to ``w.stage(name)``;
    when the block ends, the set is committed (see the module docstring). ``owned`` are the names
    the folder's kind writes (removed when the new set lacks them; an owned subfolder loses the
    ``inner`` names only, and goes if then empty), ``last`` the file renamed last. An exception
    in the block, or a failure to write, leaves the folder as it was.

    Raises:
        OutputError: the folder cannot be created or written (naming it and the reason).
    """
    d = Path(path)
    try:
        d.mkdir(parents=True, exist_ok=True)
    except OSError as e:
        raise OutputError(f"cannot create output folder {d}: {why(e)}", d) from e
    w = FolderWriter(d, owned, last, inner)
    try:
        yield w
        w.commit()
    except OutputError:
        w.abort()
        raise
    except OSError as e:
        w.abort()
        name = Path(e.filename).name if isinstance(e.filename, str) else None
        raise OutputError(
            f"cannot write output folder {d}: {why(e)}"
            + (f" (writing {name})" if name else "")
            + "; the folder was left as it was",
            d,
        ) from e
    except BaseException:
        w.abort()
        raise


def with_fallback(out: Path, write: Callable[[Path], T], what: str) -> T:
    """``write(out)``; if that raises :class:`OutputError`, writes into a fresh temporary folder
    instead and raises an :class:`OutputError` naming both (``fallback`` holds the new folder),
    so that a finished computation is not lost to a full or read-only disk."""
    try:
        return write(out)
    except OutputError as e:
        try:
            fb = Path(tempfile.mkdtemp(prefix=f"rustfrac-{what}-"))
            write(fb)
        except OSError as e2:  # OutputError included
            raise OutputError(f"{e}; writing to a temporary folder failed too ({e2})", out) from e
        raise OutputError(f"{e}; the {what} output was saved to {fb} instead", out, fb) from e


def _is_glob(name: str) -> bool:
    return any(c in name for c in "*?[")


def _expand(d: Path, names: Iterable[str]) -> set[str]:
    """``names`` with each glob pattern replaced by the matching files in ``d`` (relative)."""
    out: set[str] = set()
    for n in names:
        if _is_glob(n):
            out.update(p.relative_to(d).as_posix() for p in d.glob(n) if p.is_file())
        else:
            out.add(n)
    return out


def _prune(d: Path, p: Path) -> None:
    """Removes the now empty subfolders of ``d`` between ``p`` and ``d`` (none of ``d``)."""
    q = p.parent
    while q != d and d in q.parents:
        try:
            q.rmdir()
        except OSError:  # not empty (or gone)
            return
        q = q.parent


def _remove_owned(p: Path, inner: tuple[str, ...]) -> None:
    """Removes a name of the folder's kind: a file, or a subfolder's ``inner`` files (names or
    glob patterns), then the subfolder if empty (nothing else of the user's is deleted)."""
    if p.is_dir() and not p.is_symlink():
        for n in sorted(_expand(p, inner)):
            if (p / n).is_file():
                _unlink(p / n)
                _prune(p, p / n)
        try:
            p.rmdir()
        except OSError:
            pass
    elif p.exists() or p.is_symlink():
        _unlink(p)


def _remove_stale_tmps(d: Path) -> None:
    """Removes temporaries of writers that died (pid gone, older than :data:`STALE_TMP_S`)."""
    now = time.time()
    for p in [*d.glob(".*.tmp"), *d.glob("*/.*.tmp")]:
        parts = p.name.rsplit(".", 3)
        if len(parts) != 4 or not parts[1].isdigit():
            continue
        try:
            os.kill(int(parts[1]), 0)
            continue  # alive
        except ProcessLookupError:
            pass
        except OSError:
            continue
        try:
            if now - p.stat().st_mtime > STALE_TMP_S:
                shutil.rmtree(p) if p.is_dir() else _unlink(p)
        except OSError:
            pass


def _fsync_dir(d: Path) -> None:
    try:
        fd = os.open(d, os.O_RDONLY | getattr(os, "O_DIRECTORY", 0))
    except OSError:  # pragma: no cover
        return
    try:
        os.fsync(fd)
    except OSError as e:  # pragma: no cover (some file systems refuse directory fsync)
        if e.errno not in (errno.EINVAL, errno.EBADF):
            raise
    finally:
        os.close(fd)
