"""Threads of the BLAS/LAPACK and OpenMP libraries: one user setting, chosen per operation.

The matrices of geared trains are small for a thread pool: dense eigen solves of a few hundred
states, sparse factorisations, matrix-vector products in compiled kernels. OpenBLAS's threads
gain little there when the machine is idle, and next to any other busy process they spin
against it and cost 2–4x (docs/performance.md, ``benchmarks/threads.py``). So gearrotor runs
on **one thread** unless an operation is large enough for more to pay and the cores are free.

The setting (:func:`setting`) is ``"auto"`` (the default) or a fixed number of threads:

* ``gearrotor <command> --threads N`` (``--threads auto``), or
* the environment variable ``GEARROTOR_THREADS`` (``auto`` or ``N``); the option wins.

With a fixed N every operation runs on N threads (at most the cores this process may use).
With ``"auto"``:

* every public analysis (:func:`managed`: ``modal``, ``campbell``, ``unbalance_response``,
  ``ucs_map``, the stability audit, ``static``, ``floquet``, the report, the torsional analyses)
  and every command runs on one thread;
* an operation that declares its size (:func:`limit`) gets more only from ``CROSSOVER[kind]``
  on (measured), and never more than the cores available to the process
  (``os.sched_getaffinity``) minus those visibly busy with other work (:func:`busy_cores`).

The library's thread counts are set with threadpoolctl for the time of the call and restored
afterwards; nothing happens at import. A parametric study's workers (local processes and
Dask workers) run on one thread each. Results do not depend on the thread count beyond
round-off (the order of floating-point sums in BLAS changes with the number of threads:
``tests/test_threads.py`` bounds the change).

The thread counts are per process: calls from several Python threads at once share them.
"""

from __future__ import annotations

import contextlib
import functools
import os
import sys
import threading
from collections.abc import Callable, Iterator
from typing import TypeVar

from .errors import ModelError

__all__ = [
    "CROSSOVER",
    "ENV",
    "available_cores",
    "busy_cores",
    "current_threads",
    "processes",
    "limit",
    "managed",
    "parse_setting",
    "scope",
    "setting",
    "threads_for",
    "using",
]

#: The environment variable of the setting: ``auto`` or a number of threads.
ENV = "GEARROTOR_THREADS"

#: Size (matrix order n) from which more than one thread pays for an operation on an otherwise
#: idle machine (``benchmarks/threads.py``, 2-core AMD EPYC, OpenBLAS 0.3.30/0.3.31 pthreads;
#: docs/performance.md): the non-symmetric eigen solve (LAPACK geev) 1.04x faster on 2 threads
#: at n = 400, 1.12x at 800, 1.36x at 1600; a dense LU 1.5x at 1600. Next to one busy process
#: two threads cost 2-4x at every size, hence also :func:`busy_cores`.
CROSSOVER = {"eig": 1000, "eigh": 1000, "lu": 1000, "matmul": 1000}

F = TypeVar("F", bound=Callable)

_lock = threading.RLock()
_depth = 0  # nesting of scope(): the outermost sets the default, inner ones do nothing
_override: int | str | None = None  # set by using() (the command line's --threads)
_controller = None  # threadpoolctl's controller, rebuilt when modules were imported since
_n_modules = -1


def parse_setting(value: str | int | None, field: str = ENV) -> int | str:
    """``"auto"`` or a positive number of threads, from an option or the environment variable
    (a :class:`ModelError` naming ``field`` otherwise)."""
    if value is None:
        return "auto"
    if isinstance(value, int) and not isinstance(value, bool):
        n = value
    else:
        text = str(value).strip().lower()
        if text in ("", "auto"):
            return "auto"
        try:
            n = int(text)
        except ValueError:
            n = 0
    if n < 1:
        raise ModelError(
            "invalid number of threads",
            field=field,
            value=value,
            expected="'auto' or an integer >= 1",
        )
    return n


def setting() -> int | str:
    """The user's setting: :func:`using`'s (``--threads``), else ``GEARROTOR_THREADS``, else
    ``"auto"``."""
    if _override is not None:
        return _override
    return parse_setting(os.environ.get(ENV))


@contextlib.contextmanager
def using(value: str | int | None) -> Iterator[None]:
    """Run the block with the setting ``value`` (``"auto"``, N, or None: the environment's);
    the command line's ``--threads``."""
    global _override
    new = None if value is None else parse_setting(value, "--threads")
    old = _override
    _override = new
    try:
        yield
    finally:
        _override = old


def available_cores() -> int:
    """The cores this process may run on (its CPU affinity, e.g. a container's or taskset's
    share), else the machine's."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except (AttributeError, OSError):
        return os.cpu_count() or 1


def _own_running() -> int:
    """Threads of this process that are running or runnable now (Linux; 1 elsewhere)."""
    try:
        tasks = os.listdir("/proc/self/task")
    except OSError:
        return 1
    n = 0
    for t in tasks:
        try:
            with open(f"/proc/self/task/{t}/stat", "rb") as f:
                stat = f.read()
        except OSError:
            continue
        # "pid (comm) S ...": the state follows the last ')'
        if stat[stat.rfind(b")") + 2 : stat.rfind(b")") + 3] == b"R":
            n += 1
    return max(n, 1)


def busy_cores() -> float:
    """Cores busy with other processes' work, as far as it is visible: the larger of the
    runnable tasks right now (Linux ``/proc/loadavg``) less this process's own, and the
    one-minute load average less one (this process, which is running). 0 where neither is
    known."""
    now = 0.0
    try:
        with open("/proc/loadavg") as f:
            running = int(f.read().split()[3].split("/")[0])
        now = max(0.0, running - _own_running())
    except (OSError, ValueError, IndexError):
        pass
    try:
        avg = max(0.0, os.getloadavg()[0] - 1.0)
    except (AttributeError, OSError):
        avg = 0.0
    return max(now, avg)


def threads_for(size: int, kind: str = "eig") -> int:
    """Threads for one operation of order ``size`` under the current setting: the fixed
    number (at most the available cores), or with ``"auto"`` one thread below
    ``CROSSOVER[kind]`` and above it the available cores less the busy ones (at least one)."""
    value = setting()
    cores = available_cores()
    if value != "auto":
        return min(int(value), cores)
    if size < CROSSOVER.get(kind, CROSSOVER["eig"]) or cores == 1:
        return 1
    return max(1, min(cores, int(cores - busy_cores() + 0.5)))


def processes() -> int:
    """Processes a command may run at once (the report's second process for its independent
    work): the fixed number of the setting (``--threads N``), or with ``"auto"`` the available
    cores less the busy ones (at least one)."""
    value = setting()
    cores = available_cores()
    if value != "auto":
        return max(1, min(int(value), cores))
    return max(1, min(cores, int(cores - busy_cores() + 0.5)))


def _threadpools():
    """threadpoolctl's controllers of the loaded libraries (~2 ms to build: rebuilt only when
    modules were imported since, which may have loaded another BLAS)."""
    global _controller, _n_modules
    if _controller is None or len(sys.modules) != _n_modules:
        from threadpoolctl import ThreadpoolController

        _controller = ThreadpoolController()
        _n_modules = len(sys.modules)
    return _controller.lib_controllers


def current_threads() -> dict[str, int]:
    """The thread count of each loaded BLAS/OpenMP library (file name -> threads)."""
    with _lock:
        return {os.path.basename(lib.filepath): lib.num_threads for lib in _threadpools()}


_scope_threads = 0  # the outermost scope's thread count (0: no scope)
_originals: dict[str, int] = {}  # library -> its thread count before the outermost scope


def _apply(n: int) -> None:
    """Every loaded library on ``n`` threads (each library's count before it first changed is
    kept in ``_originals``, also for libraries loaded since the scope began)."""
    for lib in _threadpools():
        if lib.filepath not in _originals:
            _originals[lib.filepath] = lib.num_threads
        if lib.num_threads != n:
            lib.set_num_threads(n)


def _restore() -> None:
    for lib in _threadpools():
        old = _originals.get(lib.filepath)
        if old is not None and lib.num_threads != old:
            lib.set_num_threads(old)
    _originals.clear()


@contextlib.contextmanager
def scope() -> Iterator[None]:
    """An analysis or a command: with ``"auto"`` one thread (N with a fixed setting) for the
    whole call, every library's count restored afterwards. A nested scope (an analysis calling
    another; a command calling an analysis) keeps the outer count, applying it to libraries
    loaded since (the command line imports the analyses inside its scope)."""
    global _depth, _scope_threads
    with _lock:
        outer = _depth == 0
        if outer:
            value = setting()
            _scope_threads = 1 if value == "auto" else min(int(value), available_cores())
        _depth += 1
        try:
            _apply(_scope_threads)
        except BaseException:
            _depth -= 1
            if outer:
                _restore()
                _scope_threads = 0
            raise
    try:
        yield
    finally:
        with _lock:
            _depth -= 1
            if outer:
                _restore()
                _scope_threads = 0


@contextlib.contextmanager
def limit(size: int, kind: str = "eig") -> Iterator[int]:
    """One operation of order ``size`` (``kind``: ``"eig"``, ``"lu"``, ``"matmul"``) on
    :func:`threads_for` threads, yielding that number; afterwards the enclosing scope's count
    (or, outside any scope, each library's own) is back."""
    n = threads_for(size, kind)
    with scope():
        if n == _scope_threads:
            yield n
            return
        with _lock:
            _apply(n)
        try:
            yield n
        finally:
            with _lock:
                _apply(_scope_threads)


def managed(fn: F) -> F:
    """Decorator of a public analysis: the call runs in a :func:`scope`."""

    @functools.wraps(fn)
    def wrapper(*args, **kwargs):
        with scope():
            return fn(*args, **kwargs)

    return wrapper  # type: ignore[return-value]
