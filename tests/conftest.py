import os
import sys
from pathlib import Path

import pytest

import cli_cache  # noqa: F401  (the command line's click command built once per process)


def _one_thread_per_worker() -> None:
    """Under pytest-xdist (``-n N``) every worker runs its BLAS/OpenMP libraries on its share
    of the cores (one thread on 2 cores with ``-n 2``): the workers would otherwise each start
    a pool of as many threads as cores and spin against each other. The environment variables
    reach the processes the tests start (command-line runs, study workers); threadpoolctl sets
    the libraries this worker has already loaded (numpy's and SciPy's OpenBLAS)."""
    workers = int(os.environ.get("PYTEST_XDIST_WORKER_COUNT") or 0)
    if not os.environ.get("PYTEST_XDIST_WORKER") or workers < 1:
        return
    try:
        cores = len(os.sched_getaffinity(0))
    except (AttributeError, OSError):
        cores = os.cpu_count() or 1
    n = str(max(1, cores // workers))
    for var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "GEARROTOR_THREADS"):
        os.environ.setdefault(var, n)
    import numpy  # noqa: F401  (the BLAS libraries the tests use, loaded now to be limited)
    import scipy.linalg  # noqa: F401
    from threadpoolctl import threadpool_limits

    threadpool_limits(int(os.environ["OPENBLAS_NUM_THREADS"]))


_one_thread_per_worker()


def pytest_configure(config) -> None:
    """``-n N`` distributes by the groups of :func:`pytest_collection_modifyitems`
    (``--dist loadgroup``; an explicit ``--dist`` is kept).

    One results cache (``gearrotor.cache``: the fluid-film tables) for the whole run, fresh
    and shared: set by the controlling process before pytest-xdist starts its workers, so that
    they and every command line a test runs use the same folder, and a table solved by one is
    read by the others; removed when the run ends. A cache directory set by the caller (or
    ``GEARROTOR_CACHE=off``) is kept."""
    if getattr(config.option, "dist", None) == "load":  # `-n N` without a --dist of its own
        config.option.dist = "loadgroup"  # the groups of pytest_collection_modifyitems
        os.environ["GEARROTOR_TEST_LOADGROUP"] = "1"  # for the workers, started after this
    if os.environ.get("PYTEST_XDIST_WORKER"):
        return
    _compile_sources()
    if os.environ.get("GEARROTOR_CACHE_DIR"):
        return
    import tempfile

    folder = tempfile.mkdtemp(prefix="gearrotor-test-cache-")
    os.environ["GEARROTOR_CACHE_DIR"] = folder
    config._gearrotor_cache = folder


def _compile_sources() -> None:
    """Byte-compile the package once, before the workers start. Under
    ``PYTHONDONTWRITEBYTECODE`` (set on the test machines) nothing writes the ``.pyc`` files
    of a fresh checkout, so every process the suite starts (hundreds: command lines, study
    workers, scripts) compiled gearrotor's sources again: ~45 s of CPU of a ~1,100-s run,
    measured with py-spy over the whole suite. ``compileall`` writes them whatever that
    setting (~1 s); a source folder that cannot be written is left as it is."""
    import compileall

    compileall.compile_dir(ROOT / "src" / "gearrotor", quiet=2, workers=1)


#: Module- and session-scoped fixtures too cheap to keep their tests on one worker.
_CHEAP_FIXTURES = {"examples", "doc_workspaces", "make_gearbox"}
_SCOPE_RANK = {"session": 0, "package": 1, "module": 2, "class": 3}


#: ``GEARROTOR_TESTS=all`` runs the slow cross-checks with the rest (CI: ``.ci/run``).
_ALL = "all"


def _slow_left_out(config) -> bool:
    """Whether this run leaves out the tests marked slow: when no ``-m`` is given and
    ``GEARROTOR_TESTS`` is not ``all``."""
    return not config.option.markexpr and os.environ.get("GEARROTOR_TESTS", "").strip() != _ALL


def _named(config) -> list[str]:
    """The node ids named on the command line (``FILE::TEST``), relative to the root folder as
    pytest writes them."""
    out = []
    for arg in config.args:
        if "::" not in arg:
            continue
        path, rest = arg.split("::", 1)
        try:
            rel = Path(path).resolve().relative_to(config.rootpath).as_posix()
        except ValueError:
            continue
        out.append(f"{rel}::{rest}")
    return out


def _leave_out_slow(config, items) -> None:
    """The default run (the README's ``python3 -m pytest -n 2 -q``) leaves out the long
    cross-checks marked slow, as pytest's own recipe for slow tests and SciPy's test runner do:
    every area's checks and the docs' quick commands stay in it. ``-m slow`` runs them alone,
    ``GEARROTOR_TESTS=all`` with the rest (CI runs the whole suite so: ``.ci/run``), and a
    slow test named on the command line (``FILE::TEST``) runs."""
    if not _slow_left_out(config):
        return
    named = _named(config)
    keep, out = [], []
    for item in items:
        wanted = any(
            item.nodeid == n or item.nodeid.startswith((f"{n}[", f"{n}::", f"{n}@")) for n in named
        )
        (out if item.get_closest_marker("slow") and not wanted else keep).append(item)
    if out:
        config.hook.pytest_deselected(items=out)
        items[:] = keep


def pytest_terminal_summary(terminalreporter, exitstatus, config) -> None:
    """Says that the slow tests were left out (under ``-n N`` the workers deselect them and
    the summary line of the controlling process does not count them)."""
    if _slow_left_out(config) and not os.environ.get("PYTEST_XDIST_WORKER"):
        terminalreporter.write_line(
            "the long cross-checks marked slow are left out of this run: `-m slow` runs them, "
            "`GEARROTOR_TESTS=all` runs the whole suite (as CI does)"
        )


@pytest.hookimpl(tryfirst=True)
def pytest_collection_modifyitems(config, items) -> None:
    """The tests that share a module- or session-scoped fixture of this suite (a computed
    report, an example's doc commands, a solved model) go to one pytest-xdist worker (``-n N``
    runs as ``--dist loadgroup``: :func:`pytest_configure`): spread over two workers, each
    worker computed the fixture again. The group is the widest such fixture a test uses;
    tests without one are distributed freely. Runs before pytest-xdist's own hook reads the
    groups (a worker is told the controller's ``--dist`` only as "no": the variable says it is
    ``loadgroup``). pytest 9.2 broke pytest-xdist's grouping (its group suffix of the node id
    no longer takes: pytest-xdist issue #1386), so the test extra asks for pytest < 9.2."""
    if os.environ.get("PYTEST_XDIST_WORKER") and os.environ.get("GEARROTOR_TEST_LOADGROUP"):
        config.option.loadgroup = True
    _leave_out_slow(config, items)
    for item in items:
        if item.get_closest_marker("xdist_group"):
            continue
        info = getattr(item, "_fixtureinfo", None)
        if info is None:
            continue
        best = None
        for name in info.names_closure:
            defs = info.name2fixturedefs.get(name)
            if not defs or name in _CHEAP_FIXTURES:
                continue
            fd = defs[-1]
            scope = str(getattr(fd, "scope", "function"))
            if scope not in _SCOPE_RANK or not fd.baseid:  # function scope, pytest's own
                continue
            key = (_SCOPE_RANK[scope], f"{fd.baseid}::{name}")
            best = key if best is None else min(best, key)
        if best is not None:
            item.add_marker(pytest.mark.xdist_group(best[1]))


def pytest_unconfigure(config) -> None:
    import shutil

    folder = getattr(config, "_gearrotor_cache", None)
    if folder:
        shutil.rmtree(folder, ignore_errors=True)
        os.environ.pop("GEARROTOR_CACHE_DIR", None)


ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = ROOT / "examples"


@pytest.fixture(scope="session")
def examples() -> Path:
    return EXAMPLES


@pytest.fixture(autouse=True)
def _close_figures():
    """Close the pyplot figures a test leaves open: figure functions return their figure for the
    test to inspect, and with ``filterwarnings = error`` matplotlib's warning at more than 20
    open figures would fail whichever later test in the same worker opens the 21st."""
    yield
    plt = sys.modules.get("matplotlib.pyplot")
    if plt is not None:
        plt.close("all")
