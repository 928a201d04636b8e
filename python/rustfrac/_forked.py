"""Work done in a forked child process beside the caller: figures drawn on the second core.

Matplotlib draws under the GIL, so threads cannot draw two figures at once; a child forked from
the process shares its memory (copy on write) and draws beside it, with nothing to import or
send. :class:`Forked` runs tasks (callables that write their own files) in such a child; the
caller goes on with its own work and then :meth:`Forked.wait`\\ s. Nothing is lost when the child
cannot do its part: a failed fork (no ``os.fork``: Windows; not Linux; no memory or process
left), or a child that failed, died, was killed or did not end within :data:`CHILD_TIMEOUT_S`,
leaves the tasks to :meth:`Forked.wait`, which runs them in the caller, where their errors (a full
disk, ...) are raised as they would have been.

Signals: the child ignores SIGINT (Ctrl-C reaches the whole process group: the caller handles it
and kills the child) and dies with its parent (``PR_SET_PDEATHSIG``), so a killed job leaves no
drawing process behind. The fork is made from the main thread with SIGINT blocked, so that no
KeyboardInterrupt can run in the child before it ignores SIGINT.
"""

from __future__ import annotations

import ctypes
import os
import signal
import sys
import threading
import time
import warnings
from collections.abc import Callable, Sequence

__all__ = ["Forked"]

#: Linux's prctl option: the signal the child gets when its parent dies
_PR_SET_PDEATHSIG = 1
#: seconds :meth:`Forked.wait` waits for a child before it kills it and runs its tasks here: a
#: child that hangs (a lock held by another thread at the fork, which the child never sees
#: released) must not hang the job; two figures take well under a second
CHILD_TIMEOUT_S = 120.0


def _die_with_parent(parent: int) -> None:
    """Has the kernel SIGKILL this (child) process when its parent dies; exits at once if the
    parent already died before the request."""
    try:
        libc = ctypes.CDLL(None, use_errno=True)
        libc.prctl(_PR_SET_PDEATHSIG, signal.SIGKILL, 0, 0, 0)
    except (OSError, AttributeError):  # no prctl: the child still ends with its tasks
        pass
    if os.getppid() != parent:
        os._exit(1)


class Forked:
    """Runs ``tasks`` in a forked child process (Linux, main thread) while the caller goes on;
    :meth:`wait` waits for the child and runs in the caller whatever the child did not finish.

    ``forked`` is False when no child was made (the tasks then all run at :meth:`wait`)."""

    def __init__(self, tasks: Sequence[Callable[[], object]]) -> None:
        self.tasks = list(tasks)
        self.pid: int | None = None
        if not self.tasks or not _can_fork():
            return
        parent = os.getpid()
        blocked = {signal.SIGINT}
        old = signal.pthread_sigmask(signal.SIG_BLOCK, blocked)
        try:
            with warnings.catch_warnings():
                # Python 3.12+ warns of fork() in a process with threads (the core's idle worker
                # threads here): the child runs only the tasks' Python code, then os._exit
                warnings.simplefilter("ignore", DeprecationWarning)
                pid = os.fork()
        except OSError:  # no memory or process left: the tasks run at wait()
            signal.pthread_sigmask(signal.SIG_SETMASK, old)
            return
        if pid == 0:  # the child: never returns
            code = 1
            try:
                signal.signal(signal.SIGINT, signal.SIG_IGN)
                _die_with_parent(parent)
                signal.pthread_sigmask(signal.SIG_SETMASK, old)
                for task in self.tasks:
                    task()
                code = 0
            except BaseException:  # the caller runs the tasks again and raises the error
                code = 1
            finally:
                os._exit(code)
        signal.pthread_sigmask(signal.SIG_SETMASK, old)
        self.pid = pid

    @property
    def forked(self) -> bool:
        return self.pid is not None

    def wait(self, timeout_s: float = CHILD_TIMEOUT_S) -> None:
        """Waits for the child, at most ``timeout_s`` seconds; if there was none, or it did not
        end with success in that time (then it is killed), runs the tasks here (raising their
        errors). A KeyboardInterrupt (or any exception) while waiting kills the child first."""
        if self.pid is not None:
            try:
                status = _waitpid(self.pid, timeout_s)
            except BaseException:
                self.kill()
                raise
            if status is None:  # still running: killed, its tasks done here
                self.kill()
            else:
                self.pid = None
                if os.waitstatus_to_exitcode(status) == 0:
                    return
        for task in self.tasks:
            task()

    def kill(self) -> None:
        """Kills the child, if any, and reaps it (its tasks are then not done)."""
        if self.pid is None:
            return
        try:
            os.kill(self.pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
        try:
            os.waitpid(self.pid, 0)
        except ChildProcessError:  # reaped already
            pass
        self.pid = None


def _waitpid(pid: int, timeout_s: float) -> int | None:
    """The wait status of child ``pid`` once it ends, or None if it still runs after
    ``timeout_s`` seconds (polled: a sleep of at most 10 ms between checks)."""
    deadline = time.monotonic() + timeout_s
    pause = 0.001
    while True:
        done, status = os.waitpid(pid, os.WNOHANG)
        if done:
            return status
        if time.monotonic() >= deadline:
            return None
        time.sleep(pause)
        pause = min(2 * pause, 0.01)


def _can_fork() -> bool:
    return (
        sys.platform == "linux"
        and hasattr(os, "fork")
        and threading.current_thread() is threading.main_thread()
    )
