"""Helpers of the fault tests (tests/test_faults.py, tests/test_files.py, tests/reliability/,
tests/static/): real faults made on purpose, and the checks of what they must leave.

* a full disk or a read-only file system: a small real tmpfs (:func:`tmpfs`; the test is skipped
  where mounting is not allowed), or an ENOSPC at the atomic writer's ``fsync``
  (:func:`full_disk_at_fsync`);
* a killed process: the pid of one that has exited (:func:`dead_pid`), for the temporaries such
  a process leaves;
* a signal at a chosen moment: the ``gearrotor`` program run in a child process that sends
  itself a real SIGINT/SIGTERM/SIGKILL when a given function is first called
  (:func:`run_signalled`; the child is forked from a server that imported the package once,
  :func:`run_program`);
* damaged result files (:func:`rewrite_netcdf`).
"""

from __future__ import annotations

import contextlib
import errno
import os
import signal
import subprocess
import sys
import time
import uuid
from collections.abc import Callable, Iterator
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from gearrotor.cli import app

SRC = Path(__file__).resolve().parents[1] / "src"
EXAMPLES = Path(__file__).resolve().parents[1] / "examples"


def invoke(*args):
    """The CLI in-process (``CliRunner``), arguments as strings."""
    return CliRunner().invoke(app, [str(a) for a in args])


def one_line_exit_2(r, *needles):
    """Exit 2 before anything was computed: nothing on stdout, one ``error:`` line on stderr
    holding every needle."""
    assert r.exit_code == 2, (r.exit_code, r.output, r.exception)
    assert r.stdout == "", r.stdout  # nothing computed, nothing printed
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: "), r.stderr
    for n in needles:
        assert n in lines[0], (n, lines[0])


def must_not_run(*args, **kwargs):
    """Monkeypatched over the first step of a computation: the test fails if it runs."""
    raise AssertionError("the computation started before the output location was checked")


# ---- the file system -------------------------------------------------------------------------
@contextlib.contextmanager
def tmpfs(base: Path, size: str, *options: str) -> Iterator[Path]:
    """A tmpfs of ``size`` mounted under ``base`` (``"ro"`` among ``options``: read-only);
    skips the test where mounting is not allowed (not root / no CAP_SYS_ADMIN)."""
    mnt = base / f"mnt-{uuid.uuid4().hex[:6]}"
    mnt.mkdir()
    opts = ",".join((f"size={size}", "mode=0777", *options))
    r = subprocess.run(
        ["mount", "-t", "tmpfs", "-o", opts, "tmpfs", str(mnt)], capture_output=True, text=True
    )
    if r.returncode != 0:
        mnt.rmdir()
        pytest.skip(f"cannot mount a tmpfs here (not root / no CAP_SYS_ADMIN): {r.stderr.strip()}")
    try:
        yield mnt
    finally:
        subprocess.run(["umount", "-l", str(mnt)], check=False)
        mnt.rmdir()


def full_disk_at_fsync(monkeypatch, after: int = 0) -> None:
    """ENOSPC from the atomic writer's ``fsync`` once ``after`` files have been synced (the
    same path as a real full disk, for machines where mount is not allowed)."""
    from gearrotor import files

    real = files.os.fsync
    count = {"n": 0}

    def fsync(fd):
        count["n"] += 1
        if count["n"] > after:
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
        real(fd)

    monkeypatch.setattr(files.os, "fsync", fsync)


def leftovers(d: Path) -> list[str]:
    """Temporaries (``*.tmp-*``) under ``d``, recursively, as paths relative to it."""
    return sorted(str(p.relative_to(d)) for p in Path(d).rglob("*") if ".tmp-" in p.name)


def files_in(folder: Path) -> set[Path]:
    return set(Path(folder).rglob("*"))


# ---- processes ---------------------------------------------------------------------------------
def dead_pid() -> int:
    """The pid of a process that has exited (as a killed writer's)."""
    r = subprocess.run(
        [sys.executable, "-c", "import os; print(os.getpid())"],
        capture_output=True,
        text=True,
        check=True,
    )
    return int(r.stdout)


skip_without_proc = pytest.mark.skipif(
    not Path("/proc/self/stat").exists(), reason="reads the process table from Linux /proc"
)


def children(pid: int) -> list[int]:
    """The pids of the children of ``pid`` (Linux /proc)."""
    out = []
    for stat in Path("/proc").glob("[0-9]*/stat"):
        with contextlib.suppress(OSError, IndexError, ValueError):
            fields = stat.read_text().rsplit(")", 1)[1].split()
            if int(fields[1]) == pid:
                out.append(int(stat.parent.name))
    return out


def parent_of(pid: int) -> int:
    """The parent's pid of ``pid`` (0 once it has ended; Linux /proc)."""
    try:
        return int(Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[1])
    except (OSError, IndexError, ValueError):
        return 0


def descendants(pid: int) -> list[int]:
    """The pids of the children of ``pid``, their children, and so on (Linux /proc)."""
    out, todo = [], [pid]
    while todo:
        found = children(todo.pop())
        out += found
        todo += found
    return out


def command_line(pid: int) -> str:
    """The command line of ``pid``, its arguments joined by spaces ("" once it has ended)."""
    try:
        return Path(f"/proc/{pid}/cmdline").read_bytes().replace(b"\0", b" ").decode()
    except OSError:
        return ""


def is_forkserver(pid: int) -> bool:
    """``pid`` runs multiprocessing's fork server (its forked workers share its command line:
    tell them apart by their parent)."""
    return "multiprocessing.forkserver import main" in command_line(pid)


def workers_of(pid: int) -> list[int]:
    """The worker processes of a study run by ``pid``: its children other than
    multiprocessing's resource tracker and fork server, and the fork server's children."""
    out = []
    for c in children(pid):
        if "multiprocessing.resource_tracker" in command_line(c):
            continue
        out += children(c) if is_forkserver(c) else [c]
    return out


def alive(pid: int) -> bool:
    """The process runs (not a zombie)."""
    try:
        state = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0]
    except OSError:
        return False
    return state != "Z"


def _ticks(stat: Path) -> float:
    """User + system CPU seconds of the task whose ``/proc/.../stat`` this is (0 once ended)."""
    try:
        fields = stat.read_text().rsplit(")", 1)[1].split()
    except (OSError, IndexError):
        return 0.0
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def cpu_seconds(pid: int) -> float:
    """CPU time (user + system, all threads) ``pid`` has used (Linux /proc; 0 once ended)."""
    return _ticks(Path(f"/proc/{pid}/stat"))


def thread_cpu_seconds(pid: int) -> list[float]:
    """CPU time of each thread of ``pid`` but its main thread (Linux /proc)."""
    try:
        tasks = [t for t in Path(f"/proc/{pid}/task").iterdir() if t.name != str(pid)]
    except OSError:
        return []
    return [_ticks(t / "stat") for t in tasks]


def env() -> dict[str, str]:
    """The environment of a child ``gearrotor`` process: this tree's sources."""
    return {**os.environ, "PYTHONPATH": str(SRC)}


#: The ``gearrotor`` program, sending itself signal SIG when TARGET ("module:attr" or
#: "module:Class.attr") is called for the N-th time (before the call): a real signal, delivered
#: where a user's Ctrl-C, a scheduler's SIGTERM or the OOM killer's SIGKILL can land; only the
#: moment is chosen.
_SIGNALLED = """
import importlib, os, signal, sys
target, sig, nth = sys.argv[1], signal.Signals[sys.argv[2]], int(sys.argv[3])
del sys.argv[1:4]
module, _, attr = target.partition(":")
owner = importlib.import_module(module)
*path, name = attr.split(".")
for p in path:
    owner = getattr(owner, p)
real = getattr(owner, name)
calls = [0]

def signalled(*a, **k):
    calls[0] += 1
    if calls[0] == nth:
        os.kill(os.getpid(), sig)
    return real(*a, **k)

if isinstance(owner, type) and not isinstance(owner.__dict__.get(name), staticmethod):
    def method(self, *a, **k):
        return signalled(self, *a, **k)
    setattr(owner, name, method)
else:
    setattr(owner, name, signalled)
from gearrotor.cli import main
main()
"""


#: A program started once that imports the libraries the programs of these tests import (numpy,
#: SciPy, numba, xarray, matplotlib...: ~1.6 s of the ~2 s the imports take, most of such a
#: program's run) and then, for each request (a JSON line on its stdin), forks a child that
#: becomes that program: the request's environment, folder, arguments and output files, its code
#: run as ``python -c`` runs it, at the top level of the interpreter (its exit, atexit callbacks
#: and signals are the interpreter's own); the server prints the child's pid, then its exit
#: status (``-N``: killed by signal N). gearrotor itself is not imported in the server: the child
#: imports it as a fresh program does, so that code which replaces one of its functions first
#: (``_SIGNALLED``) sees every module bind the replacement.
_FORK_SERVER = r"""
import json, os, signal, sys
# the signals as a program started from a terminal has them, whatever the test runner's (a
# runner started in the background by a shell without job control ignores SIGINT, and Python
# then keeps it ignored: no KeyboardInterrupt, in a fresh interpreter as well)
signal.pthread_sigmask(signal.SIG_SETMASK, [])
signal.signal(signal.SIGINT, signal.default_int_handler)
signal.signal(signal.SIGTERM, signal.SIG_DFL)
for name in json.loads(sys.argv[1]):
    try:
        __import__(name)
    except ImportError:  # an optional part (a [extra]) not installed
        pass
requests = open(0, "rb", buffering=0, closefd=False)  # unbuffered: nothing a child would see
while True:
    line = requests.readline()
    if not line:
        os._exit(0)
    pid = os.fork()
    if pid == 0:
        break
    print(pid, flush=True)
    print(os.waitstatus_to_exitcode(os.waitpid(pid, 0)[1]), flush=True)
request = json.loads(line)
del line, name, pid, requests, signal
if request["session"]:  # as Popen(start_new_session=True): a group of its own for os.killpg
    os.setsid()
os.chdir(request["cwd"])
os.environ.clear()
os.environ.update(request["env"])
for fd, path, flags in (
    (0, os.devnull, os.O_RDONLY),
    (1, request["stdout"], os.O_WRONLY | os.O_CREAT | os.O_TRUNC),
    (2, request["stderr"], os.O_WRONLY | os.O_CREAT | os.O_TRUNC),
):
    opened = os.open(path, flags, 0o600)
    os.dup2(opened, fd)
    os.close(opened)
sys.stdin = open(0, closefd=False)
sys.argv = ["-c", *request["argv"]]
code = compile(request["code"], "<string>", "exec")
del request, fd, path, flags, opened
exec(code, {"__name__": "__main__", "__builtins__": __builtins__})
"""

#: What the fork server imports: the libraries gearrotor's commands load, not gearrotor (a
#: missing optional one is skipped).
PRELOAD = (
    "numpy",
    "scipy.constants",
    "scipy.fft",
    "scipy.linalg",
    "scipy.optimize",
    "scipy.sparse.linalg",
    "scipy.spatial",
    "scipy.special",
    "numba",
    "pandas",
    "xarray",
    "dask.array",
    "h5py",
    "h5netcdf",
    "matplotlib.pyplot",
    "PIL.Image",
    "pydantic",
    "typer",
    "platformdirs",
    "threadpoolctl",
    "yaml",
    "rainflow",
)

#: Variables that change without bearing on what the server imported (pytest names the test).
_VOLATILE = ("PYTEST_CURRENT_TEST",)
_server: dict = {"proc": None, "key": None, "running": None}


def _stop_server() -> None:
    proc = _server["proc"]
    if proc is not None:
        proc.stdin.close()  # it exits at the end of its input (after the child it waits for)
        try:
            proc.wait(timeout=10)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait()
        proc.stdout.close()
    _server.update(proc=None, running=None)


def _fork_server(environ: dict[str, str]) -> subprocess.Popen:
    """The fork server (started at the first use, and again when the environment changed: it
    imported its modules under the one it was started with)."""
    key = {k: v for k, v in environ.items() if k not in _VOLATILE}
    proc = _server["proc"]
    if proc is None or proc.poll() is not None or _server["key"] != key:
        _stop_server()
        import atexit
        import json

        proc = subprocess.Popen(
            [sys.executable, "-c", _FORK_SERVER, json.dumps(PRELOAD)],
            stdin=subprocess.PIPE,
            stdout=subprocess.PIPE,
            bufsize=0,
            env=environ,
        )
        if _server["key"] is None:
            atexit.register(_stop_server)
        _server.update(proc=proc, key=key)
    return proc


def _read_line(proc: subprocess.Popen, deadline: float) -> str | None:
    """One line of the fork server's output, read a byte at a time (nothing buffered past
    it); None at the deadline (at once if it has passed and nothing is there)."""
    import select

    out = b""
    while not out.endswith(b"\n"):
        left = max(deadline - time.monotonic(), 0.0)
        if not select.select([proc.stdout], [], [], left)[0]:
            if not out:
                return None
            continue  # the rest of a line being written
        byte = os.read(proc.stdout.fileno(), 1)
        if not byte:
            raise AssertionError("the fork server of the tests ended")
        out += byte
    return out.decode()


class Program:
    """A program forked by the server (:func:`start_program`), with the parts of
    ``subprocess.Popen`` the tests use; its output goes to files, read when it has ended."""

    def __init__(self, server: subprocess.Popen, args: list[str], folder: Path, pid: int):
        self.args, self.pid, self.returncode = args, pid, None
        self._server, self._folder = server, folder

    def poll(self) -> int | None:
        if self.returncode is None:
            status = _read_line(self._server, 0.0)
            if status is not None:
                self.returncode = int(status)
                _server["running"] = None
        return self.returncode

    def wait(self, timeout: float | None = None) -> int:
        if self.returncode is None:
            deadline = time.monotonic() + (1e9 if timeout is None else timeout)
            status = _read_line(self._server, deadline)
            if status is None:
                raise subprocess.TimeoutExpired(self.args, timeout)
            self.returncode = int(status)
            _server["running"] = None
        return self.returncode

    def communicate(self, timeout: float | None = None) -> tuple[str, str]:
        """Its stdout and stderr, once it has ended (within ``timeout`` s)."""
        self.wait(timeout)
        out = (self._folder / "stdout").read_text(errors="replace")
        err = (self._folder / "stderr").read_text(errors="replace")
        import shutil

        shutil.rmtree(self._folder, ignore_errors=True)
        return out, err

    def send_signal(self, sig: int) -> None:
        if self.poll() is None:
            os.kill(self.pid, sig)

    def kill(self) -> None:
        self.send_signal(signal.SIGKILL)


def start_program(code: str, *args, new_session: bool = False) -> Program:
    """``python -c CODE ARGS`` with :func:`env`, in the current folder, started: forked from a
    server that has imported the libraries (:data:`_FORK_SERVER`), for tests about what a
    program does after it started, not about its start. ``new_session``: in a session (and
    process group) of its own, as ``Popen(start_new_session=True)``."""
    import json
    import tempfile

    environ = env()
    argv = [str(a) for a in args]
    proc = _fork_server(environ)
    running = _server.get("running")
    if running is not None and running.poll() is None:  # left by a failed test: the server
        running.kill()  # waits for it before it reads the next request
        running.wait(60)
    folder = Path(tempfile.mkdtemp(prefix="gearrotor-test-run-"))
    request = {"code": code, "argv": argv, "env": environ, "cwd": os.getcwd()}
    request.update(stdout=str(folder / "stdout"), stderr=str(folder / "stderr"))
    request.update(session=new_session)
    data = json.dumps(request).encode() + b"\n"
    while data:  # a raw pipe may take a part of it
        data = data[proc.stdin.write(data) :]
    pid = int(_read_line(proc, time.monotonic() + 60) or 0)
    assert pid > 0, "the fork server of the tests did not answer"
    program = Program(proc, [sys.executable, "-c", code, *argv], folder, pid)
    _server["running"] = program
    return program


def run_program(code: str, *args, timeout: float = 300) -> subprocess.CompletedProcess:
    """``python -c CODE ARGS`` run to its end by :func:`start_program`, its output captured
    (as ``subprocess.run(..., capture_output=True, text=True)``)."""
    program = start_program(code, *args)
    try:
        program.wait(timeout)
    except subprocess.TimeoutExpired:
        program.kill()
        program.communicate(60)
        raise
    out, err = program.communicate()
    return subprocess.CompletedProcess(program.args, program.returncode, out, err)


def run_signalled(
    target: str, sig: str, *args, nth: int = 1, timeout: float = 300
) -> subprocess.CompletedProcess:
    """``gearrotor ARGS`` in a child process that receives ``sig`` ("SIGINT", "SIGKILL", ...)
    when ``target`` is called the ``nth`` time (see ``_SIGNALLED``; run by
    :func:`run_program`)."""
    return run_program(_SIGNALLED, target, sig, nth, *args, timeout=timeout)


# ---- damaged files -------------------------------------------------------------------------------
#: Datasets read by :func:`rewrite_netcdf`, by the SHA-256 of their file (xarray takes ~0.3 s to
#: open one case file: the tests damage copies of the same few files again and again).
_READ: dict = {}


def rewrite_netcdf(src: Path, dst: Path, change: Callable) -> None:
    """Read the NetCDF ``src``, apply ``change`` (Dataset -> Dataset, given a deep copy) and
    write ``dst`` (which may be ``src``) without the package's checks, as a foreign or damaged
    file would be."""
    import hashlib

    import xarray as xr

    key = hashlib.sha256(Path(src).read_bytes()).hexdigest()
    if key not in _READ:  # the same content in another copy of a study: read once
        if len(_READ) > 16:
            _READ.clear()
        with xr.open_dataset(src, engine="h5netcdf") as ds:
            _READ[key] = ds.load()
        xr.backends.file_manager.FILE_CACHE.clear()
    ds = change(_READ[key].copy(deep=True))
    if Path(dst).exists():
        Path(dst).unlink()
    ds.to_netcdf(dst, engine="h5netcdf")
    xr.backends.file_manager.FILE_CACHE.clear()


def netcdf_bomb(src: Path, dst: Path, shape: tuple[int, ...], *, coordinate: bool = False) -> int:
    """Copy the NetCDF ``src`` to ``dst`` with one more variable, ``bomb``, of ``shape`` float64,
    chunked and compressed, none of its chunks written: the file grows by a few kB, and a reader
    that loads it unpacks ``prod(shape) * 8`` bytes of fill values (a decompression bomb).
    ``coordinate``: a 1-D dimension coordinate (read when the file is opened). Returns the
    bytes declared."""
    import shutil

    import h5netcdf

    shutil.copyfile(src, dst)
    dims = ("bomb",) if coordinate else tuple(f"bomb_{k}" for k in range(len(shape)))
    with h5netcdf.File(dst, "a") as f:
        for d, n in zip(dims, shape, strict=True):
            f.dimensions[d] = n
        chunks = tuple(min(n, 1000) for n in shape)
        f.create_variable("bomb", dims, "f8", chunks=chunks, compression="gzip")
    return int(np.prod(shape, dtype=np.float64)) * 8
