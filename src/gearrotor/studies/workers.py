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
* SIGTERM of the parent becomes :class:`Terminated` (:func:`sigterm_raises`), so it unwinds like
  Ctrl-C: the pool is stopped, what finished is stored, the temporaries are removed.
"""

from __future__ import annotations

import contextlib
import ctypes
import ctypes.util
import os
import signal
import sys
import threading
from collections.abc import Iterator

__all__ = ["Terminated", "init_worker", "sigint_ignored", "sigterm_raises", "stop_pool"]

_PR_SET_PDEATHSIG = 1  # <linux/prctl.h>


class Terminated(BaseException):
    """The process received SIGTERM (raised in the main thread by :func:`sigterm_raises`)."""


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
    """Ignore SIGINT within the block (main thread only; elsewhere the block runs unchanged)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    old = signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, old)


@contextlib.contextmanager
def sigterm_raises() -> Iterator[None]:
    """Within the block, SIGTERM raises :class:`Terminated` in the main thread (outside the main
    thread, or where signals cannot be set, the block runs unchanged)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return

    def handler(signum, frame):
        raise Terminated(signum)

    old = signal.signal(signal.SIGTERM, handler)
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, old)


def stop_pool(pool) -> None:
    """Stop a ``ProcessPoolExecutor`` now: drop the queued calls and kill the running workers
    (their results would be lost anyway; the study resumes from what is stored)."""
    procs = list((getattr(pool, "_processes", None) or {}).values())
    for p in procs:
        with contextlib.suppress(OSError, ValueError, AttributeError):
            p.kill()
    pool.shutdown(wait=True, cancel_futures=True)
