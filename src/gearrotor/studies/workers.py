"""The lifetime of a study's local worker processes and the signals of the process running it.

* How workers start (:func:`worker_processes`): where multiprocessing has the "forkserver"
  start method (Linux, macOS), a fork server of this process imports what a case needs once
  (:data:`PRELOAD`: the transient and modal analyses, the metrics, xarray; ~1.5–2 s of CPU)
  and each worker is a fork of it, ready to compute; with "spawn" (Windows, or a run while
  another run of the same process uses the fork server with another environment) every worker
  is a fresh interpreter that imports them again.
  One code path, the start method chosen by availability. The fork server is gearrotor's own
  (not multiprocessing's default one, which other libraries may use with other modules and
  another environment), started by :func:`worker_processes` in the main thread with the
  environment the workers must have (the caller's, with the one-thread variables of the run)
  and SIGINT blocked; it is kept for the next run of the same process while the environment
  and ``sys.path`` (and the folder, if ``sys.path`` has a relative entry) stay the same, and
  started again when they change (it imported its modules under them). It ends with that
  process: at its exit (:mod:`atexit`), or when the process is killed.
* A worker dies with its parent: :func:`init_worker` (the pool's initializer) asks Linux to send
  it SIGKILL when the process that started it ends (``prctl(PR_SET_PDEATHSIG)``), so a
  ``study run`` killed with SIGKILL or by the OOM killer leaves no worker computing for minutes.
  A forked worker's parent is the fork server: the server ends when the last holder of the
  write end of its "alive" pipe ends, which multiprocessing hands to every worker as well, so
  the worker closes its copy first thing (:func:`init_worker`); the process running the study
  is then the only holder, and its end (also by SIGKILL) ends the server, whose end kills the
  workers. Elsewhere (macOS, Windows) the request is skipped: the pool's own shutdown still
  ends the workers on an ordinary exit or Ctrl-C.
* A worker never sees SIGINT: Ctrl-C at a terminal goes to the whole process group, and only
  the parent should answer it (it stops the pool, :func:`stop_pool`, or the Dask cluster,
  :func:`stop_local_cluster`), not every worker with a traceback. The workers are started with
  SIGINT blocked (:func:`children_without_sigint` around what starts them; a blocked signal
  stays blocked through ``fork`` and ``exec``), so that a Ctrl-C while a worker is still
  importing gearrotor does not print a traceback either; local workers also ignore it
  (:func:`init_worker`). A Dask ``LocalCluster`` starts with the parent's signals held back
  (:func:`signals_deferred`): interrupted half started, it cannot be closed cleanly.
* The parent's SIGINT and SIGTERM are answered over the whole life of the command that runs the
  study (:class:`StopSignals`, installed when ``study run`` starts): the first one raises
  ``KeyboardInterrupt`` or :class:`Terminated` in the main thread, so the run unwinds (the pool
  is stopped, what finished is stored, the temporaries are removed) and the command says so in
  one line; later ones do not interrupt that stop. Once the command has done its work, a signal
  that still comes (while the process exits) prints the same line and ends the process with
  128 + the signal number at once.
"""

from __future__ import annotations

import atexit
import contextlib
import ctypes
import ctypes.util
import logging
import os
import signal
import sys
import threading
import time
from collections.abc import Callable, Iterator

__all__ = [
    "PRELOAD",
    "StopSignals",
    "Terminated",
    "children_without_sigint",
    "init_worker",
    "signals_deferred",
    "stop_local_cluster",
    "stop_pool",
    "start_method",
    "worker_processes",
]

try:  # not on Windows (no sending of file descriptors)
    from multiprocessing import context as _mp_context
    from multiprocessing import popen_forkserver as _popen_forkserver
except ImportError:
    _popen_forkserver = None

_PR_SET_PDEATHSIG = 1  # <linux/prctl.h>
_STOP = (signal.SIGINT, signal.SIGTERM)  # the signals that stop a study


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


def init_worker(parent: int, env: dict[str, str] | None = None) -> None:
    """Initializer of a local worker process: ignore SIGINT, die with ``parent`` (the pid of
    the process that started it: the one that runs the study, or its fork server), take the
    environment ``env`` (the caller's when the pool was made: a fork server's is the one it was
    started with) and run BLAS/OpenMP on one thread."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    _die_with_parent(parent)
    _leave_forkserver()
    if env is not None and dict(os.environ) != env:
        os.environ.clear()
        os.environ.update(env)
    _one_thread()


def _leave_forkserver() -> None:
    """Close this worker's copy of its fork server's "alive" pipe (none when spawned): the
    server ends once the process that runs the study, the pipe's other holder, ends, and with
    it (``PR_SET_PDEATHSIG``) this worker. Kept open, the server and its workers would wait for
    each other for ever after a SIGKILL of the study."""
    from multiprocessing import forkserver

    server = forkserver._forkserver
    fd = getattr(server, "_forkserver_alive_fd", None)
    if fd is not None and forkserver.get_inherited_fds() is not None:  # a forked worker
        with contextlib.suppress(OSError):
            os.close(fd)
        server._forkserver_alive_fd = None


def _one_thread() -> None:
    """One thread for the BLAS/OpenMP libraries already loaded (the fork server loaded numpy's
    under the one-thread variables; this holds whatever it was started with)."""
    with contextlib.suppress(ImportError):
        from threadpoolctl import threadpool_limits

        threadpool_limits(1)  # kept: called as a function, not as a context


#: Imported once by the fork server (``python -X importtime`` of a worker running a case: the
#: transient analysis 0.95 s, the study execution with the model and units 0.51 s, the metrics
#: 0.27 s, dask as xarray looks for it 0.25–0.33 s; a missing optional one is skipped).
PRELOAD = (
    "gearrotor.studies.execute",
    "gearrotor.studies.metrics",
    "gearrotor.analyses",
    "gearrotor.analyses.transient",
    "xarray",
    "dask.array",
    "threadpoolctl",
)

#: Variables that change without bearing on the workers (pytest names the running test): a
#: change of any other variable starts the fork server again.
_VOLATILE_ENV = ("PYTEST_CURRENT_TEST",)

_server_lock = threading.Lock()
_server: dict = {"server": None, "key": None, "users": 0}
_route = threading.local()  # the fork server a Process started in this thread connects to


def start_method() -> str:
    """``"forkserver"`` where multiprocessing has it (Linux, macOS) with the pieces
    :func:`worker_processes` builds on, else ``"spawn"`` (Windows). Those pieces are private
    to multiprocessing (the fork server's fields, ``Popen._launch``,
    ``connect_to_new_process``): used on the Python versions the study and fault tests ran on
    (3.11, 3.12, 3.13), spawn on later ones until they are checked."""
    import multiprocessing

    if "forkserver" not in multiprocessing.get_all_start_methods() or _popen_forkserver is None:
        return "spawn"
    if sys.version_info >= (3, 14):  # private pieces used here verified on 3.11-3.13 only
        return "spawn"  # (3.14 authenticates the connections to a fork server)
    from multiprocessing import forkserver, popen_forkserver

    needs = ("_forkserver_pid", "_forkserver_alive_fd", "_forkserver_address")
    server = getattr(forkserver, "ForkServer", lambda: None)()
    if (
        server is None
        or not all(hasattr(server, a) for a in needs)
        or not callable(getattr(forkserver, "connect_to_new_process", None))
        or not hasattr(popen_forkserver.Popen, "_launch")
    ):
        return "spawn"  # a multiprocessing whose fork server this module does not know
    return "forkserver"


@contextlib.contextmanager
def worker_processes(method: str | None = None) -> Iterator[tuple[object, int]]:
    """The multiprocessing context to start a pool's workers with, and the pid
    :func:`init_worker` checks as their parent: gearrotor's fork server's
    (:func:`start_method`) or this process's (spawn). Enter it in the main thread, with the
    environment the workers must have: a fork server started here keeps it. ``method``
    forces one (tests)."""
    import multiprocessing

    method = method or start_method()
    if method != "forkserver":
        yield multiprocessing.get_context("spawn"), os.getpid()
        return
    server = _acquire_forkserver()
    if server is None:  # another run of this process uses it, with another environment
        yield multiprocessing.get_context("spawn"), os.getpid()
        return
    try:
        yield _forkserver_context(server), server._forkserver_pid
    finally:
        with _server_lock:
            _server["users"] -= 1


def _acquire_forkserver():
    """gearrotor's fork server, running, started under the current environment and
    ``sys.path`` (and folder), having imported :data:`PRELOAD`: the one of an earlier run when
    they are the same, else a new one (the earlier one is stopped when no run uses it). Not
    multiprocessing's own: that one may be another library's (other modules, other
    environment), and a library that uses it gets what it asked for. None when another run
    of this process uses ours with another environment (that run spawns its workers)."""
    from multiprocessing import forkserver

    key = (
        tuple(sorted((k, v) for k, v in os.environ.items() if k not in _VOLATILE_ENV)),
        tuple(sys.path),
        # the modules are found from the current folder through a relative entry ("")
        os.getcwd() if not all(os.path.isabs(p) for p in sys.path) else None,
        PRELOAD,
    )
    with _server_lock:
        server = _server["server"]
        if server is None or _server["key"] != key:
            if server is not None:
                if _server["users"]:
                    return None
                _stop_forkserver(server)
            server = forkserver.ForkServer()
            server.set_forkserver_preload(list(PRELOAD))
            # ended and reaped when this process exits (it would end by itself a moment
            # later): none is left behind, and its CPU time and its workers' are this
            # process's children's in the operating system's accounting
            atexit.register(_stop_forkserver, server)
            _server.update(server=server, key=key, users=0)
        # SIGINT blocked in the server, so in every worker it forks (children_without_sigint)
        with children_without_sigint():
            server.ensure_running()  # starts it, or again if it died
        _server["users"] += 1
        return server


def _stop_forkserver(server) -> None:
    """Ask a fork server of ours to end (close our end of its "alive" pipe) and reap it; not
    waiting more than a second (a process forked from this one would hold a copy)."""
    from multiprocessing import util

    pid, fd, address = (
        server._forkserver_pid,
        server._forkserver_alive_fd,
        server._forkserver_address,
    )
    server._forkserver_pid = server._forkserver_alive_fd = server._forkserver_address = None
    if pid is None:
        return
    with contextlib.suppress(OSError):
        os.close(fd)
    if address and not util.is_abstract_socket_namespace(address):
        with contextlib.suppress(OSError):
            os.unlink(address)
    for _ in range(100):
        try:
            if os.waitpid(pid, os.WNOHANG)[0]:
                return
        except ChildProcessError:
            return
        time.sleep(0.01)


def _forkserver_context(server):
    """A "forkserver" multiprocessing context whose processes are forked by ``server``."""
    from multiprocessing import context, forkserver

    _route_connections(forkserver)
    ctx = context.ForkServerContext()
    ctx.Process = _ForkedProcess
    return ctx


if _popen_forkserver is not None:

    class _ForkedPopen(_popen_forkserver.Popen):
        """multiprocessing's forkserver ``Popen``, forked by gearrotor's fork server."""

        def _launch(self, process_obj):
            _route.server = _server["server"]
            try:
                super()._launch(process_obj)
            finally:
                _route.server = None

    class _ForkedProcess(_mp_context.ForkServerProcess):
        """A process forked by gearrotor's fork server (module level: it is pickled)."""

        @staticmethod
        def _Popen(process_obj):
            return _ForkedPopen(process_obj)


def _route_connections(forkserver) -> None:
    """Have ``multiprocessing.forkserver.connect_to_new_process`` (what a forkserver Process
    calls to be forked) go to the server a Process started in this thread asked for
    (:data:`_route`), else, as before, to multiprocessing's own."""
    if getattr(forkserver.connect_to_new_process, "_gearrotor", False):
        return
    default = forkserver.connect_to_new_process

    def connect_to_new_process(fds):
        server = getattr(_route, "server", None)
        return default(fds) if server is None else server.connect_to_new_process(fds)

    connect_to_new_process._gearrotor = True
    forkserver.connect_to_new_process = connect_to_new_process


@contextlib.contextmanager
def children_without_sigint() -> Iterator[None]:
    """The processes (and threads) started within the block never see SIGINT: it is blocked in
    the calling thread meanwhile, and a blocked signal stays blocked in the threads it starts
    and through ``fork`` and ``exec`` in the processes. Ctrl-C at a terminal goes to the whole
    process group; a worker that is still importing would answer it with a traceback.

    The caller keeps its own handler: a SIGINT is still delivered to one of its other threads
    (numpy's BLAS threads, for instance) and answered by the main thread, or stays pending
    until the block ends. (Ignoring SIGINT in the caller, which the children would inherit as
    well, drops a Ctrl-C that comes meanwhile.) Where threads cannot block signals (outside
    POSIX), or outside the main thread, the block runs unchanged."""
    if threading.current_thread() is not threading.main_thread() or not hasattr(
        signal, "pthread_sigmask"
    ):
        yield
        return
    # multiprocessing's resource tracker, when it starts, unblocks SIGINT in the thread that
    # starts it (SIG_UNBLOCK, not the previous mask): start it first, or the first queue a
    # thread started here creates (Dask's event loop does) would undo the block
    from multiprocessing import resource_tracker

    resource_tracker.ensure_running()
    mask = signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT})
    try:
        yield
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, mask)


@contextlib.contextmanager
def signals_deferred() -> Iterator[None]:
    """SIGINT and SIGTERM are held back within the block and answered at its end: the
    previous handlers are put back and the first signal that came is raised again
    (``signal.raise_signal``), so it is answered as it would have been, once the block is done.
    For a step that cannot be cut short cleanly: a Dask ``LocalCluster`` interrupted while it
    starts leaves workers half started, which its ``atexit`` callback then fails to close with a
    traceback. Main thread only (elsewhere the block runs unchanged)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    came: list[int] = []
    old = {sig: signal.signal(sig, lambda signum, frame: came.append(signum)) for sig in _STOP}
    try:
        yield
    finally:
        for sig, handler in old.items():
            signal.signal(sig, signal.SIG_DFL if handler is None else handler)
        if came:
            signal.raise_signal(came[0])


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

    SIGNALS = (signal.SIGINT, signal.SIGTERM)  # == _STOP

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
    (their results would be lost anyway; the study resumes from what is stored).

    A worker killed while it sends its result (a case's dataset: megabytes through a pipe)
    leaves half a message in the pool's result pipe, and the pool's manager thread would wait
    for the rest for ever: this process holds the pipe's write end as well, so the reader never
    sees the end of the file. Once the workers are dead that end is closed here: the manager
    thread's read then fails, it takes the pool for broken, and the shutdown completes."""
    procs = list((getattr(pool, "_processes", None) or {}).values())
    for p in procs:
        with contextlib.suppress(OSError, ValueError, AttributeError):
            p.kill()
    for p in procs:
        with contextlib.suppress(OSError, ValueError, AttributeError, AssertionError):
            p.join(10)
    if procs and not any(_alive(p) for p in procs):
        writer = getattr(getattr(pool, "_result_queue", None), "_writer", None)
        with contextlib.suppress(OSError, AttributeError):
            writer.close()
    pool.shutdown(wait=True, cancel_futures=True)


def _alive(process) -> bool:
    try:
        return process.is_alive()
    except (ValueError, AssertionError):  # closed, or not a child of this process
        return False


def stop_local_cluster(cluster, close: Callable[[], None]) -> None:
    """Stop a Dask ``LocalCluster`` of ours now (the study was interrupted), then ``close()``
    it (the client and the cluster).

    Its worker processes are killed, as :func:`stop_pool` kills the local ones: asked to close,
    a worker inside a compiled kernel does not answer, and after 4 s the nanny logs "Worker
    process still alive after 4.0 seconds, killing" (once per worker) and kills it anyway.
    Each nanny is first told the stop is deliberate (``close_gracefully``), so that it does not
    restart the worker it loses; the cluster's own log lines about workers it loses are
    silenced (they are ours, not news to the user), and stay silenced once it is closed: its
    event loop may still log the connections it closed ("Batched Comm Closed" with a
    traceback) after ``close()`` returns, after the interrupted study's one line had it been
    restored then. Dask's log lines below CRITICAL stay off in this process afterwards."""
    log = logging.getLogger("distributed")
    log.setLevel(logging.CRITICAL)
    for handler in log.handlers:
        handler.setLevel(logging.CRITICAL)
    for nanny in list(getattr(cluster, "workers", {}).values()):
        with contextlib.suppress(Exception):
            nanny.close_gracefully(reason="gearrotor study interrupted")
        pid = getattr(nanny, "pid", None)
        if pid:
            with contextlib.suppress(OSError):
                os.kill(pid, signal.SIGKILL)
    close()
