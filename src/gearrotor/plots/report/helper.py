"""A second process for the report's independent work (issue 28: the flagship report on two
idle cores).

The report's analyses and figures are single-threaded; much of the work does not depend on
the rest: the Campbell sweep on the modal and unbalance analyses, each PNG file on the page's
HTML. :class:`Helper` runs such jobs in a forked copy of the process, one job per fork, while
this process goes on; a job's value comes back pickled (a PNG job writes its file into the
report's temporary folder and returns None). The same code runs in both processes on the same
data, so the report is the same file for file, with or without the helper (tested).

Used only where a fork exists and the thread setting allows two processes
(:func:`gearrotor.threads.processes`: ``auto`` with a second core not busy, or ``--threads
2`` or more); otherwise every job runs here at once, as before. A job that fails in the helper
(an error, a signal, a value that does not pickle) is run again here, so its error is raised
as it would be without the helper; an exception here kills the helper.
"""

from __future__ import annotations

import os
import pickle
import signal
import warnings
from collections.abc import Callable, Hashable
from typing import Any

__all__ = ["Helper"]


class Helper:
    """Jobs ``key -> fn()`` run in a forked helper process (one at a time) or here."""

    def __init__(self, enabled: bool):
        self.enabled = bool(enabled) and hasattr(os, "fork")
        self._fns: dict[Hashable, Callable[[], Any]] = {}
        self._queue: list[Hashable] = []  # submitted, not started
        self._running: tuple[int, int, Hashable] | None = None  # (pid, read fd, key)
        self._done: dict[Hashable, Any] = {}

    # --- jobs ----------------------------------------------------------------------------
    def submit(self, key: Hashable, fn: Callable[[], Any]) -> None:
        """Run ``fn`` for ``key``: in the helper when it is idle (else queued for it or for
        :meth:`finish`), or here and now when the helper is not enabled."""
        if key in self._fns:
            raise ValueError(f"job {key!r} submitted twice")
        self._fns[key] = fn
        if not self.enabled:
            self._here(key)
            return
        self._queue.append(key)
        self._poll()

    def result(self, key: Hashable) -> Any:
        """The value of job ``key``, waiting for the helper if it runs it, running it here if
        it has not started (or failed in the helper)."""
        if key not in self._done:
            if key in self._queue:
                self._queue.remove(key)
                self._here(key)
            elif self._running is not None and self._running[2] == key:
                self._collect()
            if key not in self._done:  # failed in the helper: here, to raise its error
                self._here(key)
        self._poll()
        return self._done[key]

    def finish(self) -> None:
        """Run every submitted job to its end: this process takes the queue from its end while
        the helper takes it from its start, one job per fork."""
        while self._queue:
            self._poll()
            if self._queue:
                self._here(self._queue.pop())
        if self._running is not None:
            self._collect()
        for key in list(self._fns):
            if key not in self._done:
                self._here(key)

    def _here(self, key: Hashable) -> None:
        """Run job ``key`` in this process; one that raises is not run again."""
        fn = self._fns[key]
        try:
            self._done[key] = fn()
        except BaseException:
            del self._fns[key]
            raise

    def close(self) -> None:
        """Stop a running helper (after an exception here); nothing if none runs."""
        if self._running is None:
            return
        pid, fd, _ = self._running
        self._running = None
        try:
            os.kill(pid, signal.SIGKILL)
        except OSError:
            pass
        os.close(fd)
        try:
            os.waitpid(pid, 0)
        except ChildProcessError:
            pass

    # --- the helper process --------------------------------------------------------------
    def _poll(self) -> None:
        """Collect a helper that has finished, start one on the queue's first job if idle."""
        if self._running is not None:
            pid = self._running[0]
            try:
                got, status = os.waitpid(pid, os.WNOHANG)
            except ChildProcessError:
                got, status = pid, 1
            if got != 0:
                self._collect(status)
        if self._running is None and self._queue:
            self._start(self._queue.pop(0))

    def _start(self, key: Hashable) -> None:
        r, w = os.pipe()
        with warnings.catch_warnings():
            # (Python >= 3.12 warns about forking a process with threads: the BLAS library's
            # idle pool; the helper uses it single-threaded, as this process does)
            warnings.simplefilter("ignore", DeprecationWarning)
            parent = os.getpid()
            pid = os.fork()
        if pid == 0:  # the helper: run the job, send its value, leave without cleaning up
            code = 1
            try:
                os.close(r)
                _helper_setup(parent)
                data = pickle.dumps(self._fns[key](), protocol=pickle.HIGHEST_PROTOCOL)
                view = memoryview(data)
                while view:
                    view = view[os.write(w, view) :]
                code = 0
            except BaseException:  # noqa: BLE001 (the parent runs the job again)
                pass
            finally:
                os._exit(code)
        os.close(w)
        self._running = (pid, r, key)

    def _collect(self, status: int | None = None) -> None:
        """Read the running helper's value (until it closes the pipe), reap it (``status``:
        already reaped with it), keep the value if it succeeded."""
        pid, fd, key = self._running
        self._running = None
        chunks = []
        try:
            while chunk := os.read(fd, 1 << 20):
                chunks.append(chunk)
        finally:
            os.close(fd)
        if status is None:
            try:
                status = os.waitpid(pid, 0)[1]
            except ChildProcessError:
                status = 1
        if status == 0 and chunks:
            try:
                self._done[key] = pickle.loads(b"".join(chunks))
            except Exception:  # noqa: BLE001 (run again here)
                pass


def _helper_setup(parent: int) -> None:
    """In the forked helper: files written at once (not staged in an output set of the parent,
    whose end runs only there), the default Ctrl-C (the parent handles it), and no life of its
    own: killed with the parent (Linux's parent-death signal; a parent already gone ends it
    here), so a killed report leaves no orphan process."""
    from ... import files

    files._SET.set(None)
    signal.signal(signal.SIGINT, signal.SIG_DFL)
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    _die_with_parent()
    if os.getppid() != parent:
        os._exit(1)


def _die_with_parent() -> None:
    """SIGKILL this process when its parent exits (prctl PR_SET_PDEATHSIG; Linux only,
    elsewhere nothing)."""
    import ctypes

    try:
        ctypes.CDLL(None).prctl(1, signal.SIGKILL, 0, 0, 0)  # PR_SET_PDEATHSIG = 1
    except (OSError, AttributeError):
        pass
