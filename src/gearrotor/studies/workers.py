"""The lifetime of a study's local worker processes and the signals of the process running it.

* A worker dies with its parent: :func:`init_worker` (the pool's initializer) asks Linux to send
  it SIGKILL when the process that started it ends (``prctl(PR_SET_PDEATHSIG)``), so a
  ``study run`` killed with SIGKILL or by the OOM killer leaves no worker computing for minutes.
  Elsewhere (macOS, Windows) the request is skipped: the pool's own shutdown still ends the
  workers on an ordinary exit or Ctrl-C.
* A worker ignores SIGINT: Ctrl-C at a terminal goes to the whole process group, and only the
  parent should answer it (it stops the pool, :func:`stop_pool`), not every worker with a
  traceback. The workers are started with SIGINT ignored (:func:`sigint_ignored` around the
  submissions, which start them; an ignored signal stays ignored through ``exec``), so that
  a Ctrl-C while a worker is still importing gearrotor does not print a traceback either.
* The parent's SIGINT and SIGTERM are answered over the whole life of the command that runs the
  study (:class:`StopSignals`, installed when ``study run`` starts): the first one raises
  ``KeyboardInterrupt`` or :class:`Terminated` in the main thread, so the run unwinds (the pool
  is stopped, what finished is stored, the temporaries are removed) and the command says so in
  one line; later ones do not interrupt that stop. Once the command has done its work, a signal
  that still comes (while the process exits) prints the same line and ends the process with
  128 + the signal number at once.
"""

from __future__ import annotations

import contextlib
import ctypes
import ctypes.util
import os
import signal
import sys
import threading
from collections.abc import Callable, Iterator

__all__ = ["StopSignals", "Terminated", "init_worker", "sigint_ignored", "stop_pool"]

_PR_SET_PDEATHSIG = 1  # <linux/prctl.h>


class Terminated(BaseException):
    """The process received SIGTERM (raised in the main thread by :class:`StopSignals`)."""


def _die_with_parent(parent: int) -> bool:
    """Ask the kernel for SIGKILL when the parent ends; False where that is not available."""
    if not sys.platform.startswith("linux"):
        return False
    try:
        libc = ctypes.CDLL(ctypes.util.find_library("c") or "libc.so.6", use_errno=True)
        if libc.prctl(_PR_SET_PDEATHSIG, signal.SIGKILL, 0, 0, 0) != 0:
            return False
    except (OSError, AttributeError):
        return False
    if os.getppid() != parent:  # the parent ended before the request: end now
        os._exit(1)
    return True


def init_worker(parent: int) -> None:
    """Initializer of a local worker process: die with ``parent`` (the pid of the process that
    runs the study), ignore SIGINT."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    _die_with_parent(parent)


@contextlib.contextmanager
def sigint_ignored() -> Iterator[None]:
    """Ignore SIGINT within the block (main thread only; elsewhere the block runs unchanged).
    A Ctrl-C within it (the few milliseconds in which the workers are spawned) is dropped:
    blocking it instead would not hold it back, since the kernel hands a process-directed
    signal to any thread that does not block it (numpy's BLAS threads), which drops it too."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    old = signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, old)


class StopSignals:
    """SIGINT and SIGTERM of a command that runs a study, from its start to the process's exit.

    ``line(signum)`` is the one line the command prints when a signal stops it. Use::

        stop = StopSignals(line).install()
        try:
            ...  # the whole command; KeyboardInterrupt / Terminated: print line(), exit 128 + sig
        finally:
            stop.finish()  # as a program, until the process exits; else stop.restore()

    While the command works (after :meth:`install`), the first signal raises
    ``KeyboardInterrupt`` (SIGINT) or :class:`Terminated` (SIGTERM) in the main thread; the
    command unwinds and prints ``line``. Later signals are ignored: the stop the first one
    started (killing workers, removing temporaries, closing a Dask cluster) is not itself cut
    short, which is what leaves a temporary or a traceback behind.

    After :meth:`finish` the work is done and its output printed; a signal that comes while the
    process exits (an ``atexit`` callback, a library's finaliser) cannot unwind anything, and
    Python would print "Exception ignored" with a traceback (SIGINT) or die silently (SIGTERM):
    it prints ``line`` and ends the process with status 128 + the signal number at once
    (``os._exit``, after flushing stdout), unless the command already stopped on a signal.
    Only a process that is the ``gearrotor`` program should call :meth:`finish`; a command run
    inside another program (a test runner) calls :meth:`restore`, which puts the previous
    handlers back.

    Outside the main thread (where Python cannot set handlers) nothing is installed.
    """

    SIGNALS = (signal.SIGINT, signal.SIGTERM)

    def __init__(self, line: Callable[[int], str]) -> None:
        self.line = line
        self.received: int | None = None  #: the first signal received, if any
        self.finished = False
        self._old: dict[int, object] = {}

    def install(self) -> StopSignals:
        if threading.current_thread() is threading.main_thread():
            for sig in self.SIGNALS:
                self._old[sig] = signal.signal(sig, self._handle)
        return self

    def finish(self) -> None:
        """The command's work is done: a signal from now on ends the process at once."""
        self.finished = True

    def restore(self) -> None:
        """Put back the handlers :meth:`install` replaced."""
        for sig, old in self._old.items():
            signal.signal(sig, signal.SIG_DFL if old is None else old)
        self._old.clear()

    def _handle(self, signum: int, frame) -> None:
        if self.received is not None:  # already stopping on an earlier signal
            return
        self.received = signum
        if not self.finished:
            if signum == signal.SIGINT:
                raise KeyboardInterrupt
            raise Terminated(signum)
        with contextlib.suppress(Exception):  # the main thread may be inside a write to stdout
            sys.stdout.flush()
        with contextlib.suppress(Exception):
            os.write(2, (self.line(signum) + "\n").encode())
        os._exit(128 + signum)


def stop_pool(pool) -> None:
    """Stop a ``ProcessPoolExecutor`` now: drop the queued calls and kill the running workers
    (their results would be lost anyway; the study resumes from what is stored)."""
    procs = list((getattr(pool, "_processes", None) or {}).values())
    for p in procs:
        with contextlib.suppress(OSError, ValueError, AttributeError):
            p.kill()
    pool.shutdown(wait=True, cancel_futures=True)
