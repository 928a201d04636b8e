"""Work in a forked child beside the caller (``rustfrac._forked``): the child's files, its
failures and deaths (the tasks then run in the caller), Ctrl-C while waiting, and a child that
dies with its parent."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import pytest

from rustfrac import _forked
from rustfrac._forked import Forked

pytestmark = pytest.mark.skipif(sys.platform != "linux", reason="the child is forked on Linux")


def _writer(path: Path, text: str) -> object:
    def write() -> None:
        path.write_text(f"{text} {os.getpid()}")

    return write


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    stat = Path(f"/proc/{pid}/stat")
    return stat.exists() and stat.read_text().split(")")[-1].split()[0] != "Z"


def test_the_tasks_run_in_a_child_beside_the_caller(tmp_path: Path) -> None:
    a, b = tmp_path / "a", tmp_path / "b"
    f = Forked([_writer(a, "A"), _writer(b, "B")])
    assert f.forked
    f.wait()
    assert not f.forked
    for p, t in ((a, "A"), (b, "B")):
        text, pid = p.read_text().split()
        assert text == t and int(pid) not in (os.getpid(), 0)  # written by the child


def test_a_failed_child_leaves_its_tasks_to_the_caller(tmp_path: Path) -> None:
    parent = os.getpid()
    out = tmp_path / "out"

    def fails_in_the_child() -> None:
        if os.getpid() != parent:
            raise OSError("no space left in the child")
        out.write_text("caller")

    f = Forked([fails_in_the_child])
    assert f.forked
    f.wait()
    assert out.read_text() == "caller"


def test_a_killed_child_leaves_its_tasks_to_the_caller(tmp_path: Path) -> None:
    parent = os.getpid()
    out = tmp_path / "out"

    def killed_in_the_child() -> None:
        if os.getpid() != parent:
            os.kill(os.getpid(), signal.SIGKILL)
        out.write_text("caller")

    f = Forked([killed_in_the_child])
    f.wait()
    assert out.read_text() == "caller"


def test_the_error_of_a_task_is_raised_in_the_caller(tmp_path: Path) -> None:
    def fails() -> None:
        raise OSError(28, "No space left on device")

    f = Forked([fails])
    with pytest.raises(OSError, match="No space left"):
        f.wait()
    assert not f.forked


def test_without_a_fork_the_tasks_run_at_wait(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(_forked, "_can_fork", lambda: False)
    out = tmp_path / "out"
    f = Forked([_writer(out, "X")])
    assert not f.forked and not out.exists()
    f.wait()
    assert int(out.read_text().split()[1]) == os.getpid()


def test_a_failed_fork_leaves_the_tasks_to_wait(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    def no_memory() -> int:
        raise OSError(12, "Cannot allocate memory")

    monkeypatch.setattr(os, "fork", no_memory)
    out = tmp_path / "out"
    f = Forked([_writer(out, "X")])
    assert not f.forked
    f.wait()
    assert out.read_text().startswith("X")
    assert not signal.pthread_sigmask(signal.SIG_BLOCK, set())  # SIGINT not left blocked


def test_ctrl_c_while_waiting_kills_the_child() -> None:
    f = Forked([lambda: time.sleep(60)])
    pid = f.pid
    assert pid is not None

    def interrupt(*a: object) -> None:
        raise KeyboardInterrupt

    old = signal.signal(signal.SIGALRM, interrupt)
    try:
        signal.setitimer(signal.ITIMER_REAL, 0.2)
        t = time.perf_counter()
        with pytest.raises(KeyboardInterrupt):
            f.wait()
        assert time.perf_counter() - t < 10
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, old)
    assert not f.forked and not _alive(pid)  # killed and reaped


def test_the_child_ignores_sigint_sent_to_the_process_group(tmp_path: Path) -> None:
    out = tmp_path / "out"

    def slow() -> None:
        time.sleep(0.5)
        out.write_text(str(os.getpid()))

    f = Forked([slow])
    assert f.pid is not None
    os.kill(f.pid, signal.SIGINT)  # as Ctrl-C reaches every process of the group
    f.wait()
    assert int(out.read_text()) != os.getpid()  # the child finished: not drawn again here


def test_the_child_dies_with_its_parent(tmp_path: Path) -> None:
    """A parent killed with SIGKILL (no chance to kill its child) takes the child with it."""
    pidfile = tmp_path / "child.pid"
    script = textwrap.dedent(
        f"""
        import os, time
        from pathlib import Path
        from rustfrac._forked import Forked
        def task():
            Path({str(pidfile)!r}).write_text(str(os.getpid()))
            time.sleep(60)
        f = Forked([task])
        time.sleep(60)
        """
    )
    proc = subprocess.Popen([sys.executable, "-c", script], env=dict(os.environ))
    try:
        deadline = time.monotonic() + 30
        while not (pidfile.exists() and pidfile.read_text()) and time.monotonic() < deadline:
            time.sleep(0.02)
        child = int(pidfile.read_text())
        assert _alive(child)
    finally:
        proc.kill()
        proc.wait()
    deadline = time.monotonic() + 10
    while _alive(child) and time.monotonic() < deadline:
        time.sleep(0.02)
    assert not _alive(child)


def test_a_child_that_hangs_is_killed_and_its_tasks_run_here(tmp_path: Path) -> None:
    """A child that does not end (a lock it never sees released) must not hang the job: after
    the timeout it is killed and its tasks run in the caller."""
    parent = os.getpid()
    out = tmp_path / "out"

    def hangs_in_the_child() -> None:
        if os.getpid() != parent:
            time.sleep(60)
        out.write_text("caller")

    f = Forked([hangs_in_the_child])
    pid = f.pid
    assert pid is not None
    t = time.perf_counter()
    f.wait(timeout_s=0.3)
    assert 0.3 <= time.perf_counter() - t < 10
    assert out.read_text() == "caller"
    assert not f.forked and not _alive(pid)  # killed and reaped
