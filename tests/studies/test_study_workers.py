"""How a study's local workers start (issue 28, start-up): forked from a fork server of the
calling process that imported what a case needs, where multiprocessing has one (Linux, macOS),
else spawned; either way the guarantees of ``gearrotor.studies.workers`` hold. Checked here:
results bit for bit equal to spawned workers', the caller's environment at the time of the run
in every worker (also after it changed, and next to a fork server someone else started), one
BLAS thread, SIGINT blocked and ignored, numba's kernel cache used, and no fork server left
once the process that ran the study has ended. The signals and SIGKILL of ``study run`` are
tests/test_faults.py's.
"""

from __future__ import annotations

import os
import subprocess
import sys
import time
from pathlib import Path

import pytest
import xarray as xr

from fault_helpers import alive, skip_without_proc
from gearrotor.studies import THREAD_ENV, case_path, load_study, plan, run_study
from gearrotor.studies import workers as W
from gearrotor.studies.execute import _local_pool, _payload, run_case

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
MODEL = (EXAMPLES / "unity_gearbox.toml").as_posix()
SRC = Path(__file__).resolve().parents[2] / "src"

STUDY = f"""
name = "workers"
model = "{MODEL}"
output = "workers.study"
[set]
"meshes[0].variation.terms" = 5
[parameters]
ka = {{ path = "meshes[0].variation.ka_ratio" }}
backlash = {{ path = "meshes[0].backlash.value", unit = "mm" }}
[cases]
columns = ["ka", "backlash"]
rows = [[0.2, 0.0], [0.2, 0.0254]]
[analysis]
type = "transient"
t_end = "0.1 s"
[outputs]
window = "0.05 s"
"""

FORKSERVER = W.start_method() == "forkserver"
needs_forkserver = pytest.mark.skipif(not FORKSERVER, reason="no fork server here (spawn)")


def _study(folder: Path):
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / "workers.toml"
    path.write_text(STUDY)
    return load_study(path)


def _cases(st) -> list[xr.Dataset]:
    out = []
    for p in plan(st):
        with xr.open_dataset(case_path(st, p.key), engine="h5netcdf") as ds:
            out.append(ds.load())
    return out


def kernel_cache_stats() -> tuple[int, int]:
    """(hits, misses) of numba's cache over the transient kernels compiled in this process."""
    from numba.core.registry import CPUDispatcher

    from gearrotor.analyses.transient import kernels

    hits = misses = 0
    for f in vars(kernels).values():
        if isinstance(f, CPUDispatcher):
            hits += sum(f.stats.cache_hits.values())
            misses += sum(f.stats.cache_misses.values())
    return hits, misses


def run_case_and_cache_stats(payload: dict) -> tuple[str, int, int]:
    out = run_case(payload)
    return (out["status"], *kernel_cache_stats())


def signal_masks() -> tuple[int, int, int]:
    """(blocked, ignored) signal masks of this process, and its parent's pid."""
    status = Path("/proc/self/status").read_text().splitlines()
    field = {line.split(":")[0]: line.split(":")[1].strip() for line in status if ":" in line}
    return int(field["SigBlk"], 16), int(field["SigIgn"], 16), os.getppid()


@pytest.mark.slow
def test_forked_workers_give_the_spawned_workers_results_bit_for_bit(tmp_path, monkeypatch):
    """The same cases (one with backlash: the exponential scheme) on workers forked from the
    fork server and on spawned workers: every stored variable identical, bit for bit (same
    code on one thread; only the start differs). Two forked workers; one spawned worker runs
    both cases (one interpreter importing the stack, not two: its second case also shows that
    a worker carries nothing over from one case to the next)."""
    forked = _study(tmp_path / "forked")
    assert run_study(forked, workers=2, progress=False, collect_results=False).ok
    monkeypatch.setattr(W, "start_method", lambda: "spawn")
    spawned = _study(tmp_path / "spawned")
    assert run_study(spawned, workers=1, progress=False, collect_results=False).ok
    for a, b in zip(_cases(forked), _cases(spawned), strict=True):
        assert a.sizes["time"] > 0
        xr.testing.assert_identical(a.drop_attrs(), b.drop_attrs())  # exact, NaN == NaN
        assert a.attrs["worker_env"] == b.attrs["worker_env"]


@skip_without_proc
@pytest.mark.parametrize("method", ["forkserver", "spawn"])
def test_workers_get_the_environment_of_the_run_and_never_see_sigint(monkeypatch, method):
    """A variable the user sets before a run (GEARROTOR_CACHE_DIR) is in the workers, also
    when it changes between two runs of the same process (the fork server, which imported
    gearrotor under the first value, is not reused); one BLAS thread in each; SIGINT blocked
    and ignored; the worker's parent the fork server (or this process when spawned)."""
    if method == "forkserver" and not FORKSERVER:
        pytest.skip("no fork server here")
    import threadpoolctl

    sigint = 1 << (2 - 1)
    for value in ("/tmp/gearrotor-a", "/tmp/gearrotor-b"):
        monkeypatch.setenv("GEARROTOR_CACHE_DIR", value)
        with _local_pool(1, method) as pool:
            with W.children_without_sigint():  # as the study's submissions (they start workers)
                first = pool.submit(os.getenv, "GEARROTOR_CACHE_DIR")
            assert first.result() == value
            env = {k: pool.submit(os.getenv, k).result() for k in THREAD_ENV}
            assert env == THREAD_ENV
            info = pool.submit(threadpoolctl.threadpool_info).result()
            assert info and all(i["num_threads"] == 1 for i in info), info
            blocked, ignored, parent = pool.submit(signal_masks).result()
            assert blocked & sigint and ignored & sigint
            server = W._server["server"] if method == "forkserver" else None
            assert parent == (server._forkserver_pid if server else os.getpid())


@needs_forkserver
def test_multiprocessing_s_own_fork_server_is_neither_used_nor_changed(monkeypatch):
    """multiprocessing's own fork server, started by something else in the process (other
    modules, another environment: here 4 BLAS threads; the test suite's doc-example runner
    has one), neither forks the study's workers nor is touched by them; the workers have the
    run's environment and one thread; and a process started on it afterwards still gets
    that server's environment and modules."""
    import multiprocessing
    from multiprocessing import forkserver

    import threadpoolctl

    monkeypatch.setenv("OPENBLAS_NUM_THREADS", "4")
    theirs = forkserver._forkserver
    # started by an earlier test of this process under another environment (the doc
    # examples' runner, under the suite's one BLAS thread): started again under this one
    theirs._stop()
    saved = theirs._preload_modules
    theirs.set_forkserver_preload(["numpy"])
    theirs.ensure_running()
    theirs._preload_modules = saved
    foreign = theirs._forkserver_pid
    monkeypatch.delenv("OPENBLAS_NUM_THREADS")
    try:
        with _local_pool(1) as pool:
            assert pool.submit(os.getppid).result() == W._server["server"]._forkserver_pid
            assert pool.submit(os.getppid).result() != foreign
            assert pool.submit(os.getenv, "OPENBLAS_NUM_THREADS").result() == "1"
            info = pool.submit(threadpoolctl.threadpool_info).result()
            assert info and all(i["num_threads"] == 1 for i in info), info
        assert theirs._forkserver_pid == foreign  # still running
        ctx = multiprocessing.get_context("forkserver")
        with ctx.Pool(1) as other:
            assert other.apply(os.getppid) == foreign
            assert other.apply(os.getenv, ("OPENBLAS_NUM_THREADS",)) == "4"
    finally:
        theirs._stop()


@needs_forkserver
def test_the_numba_kernel_cache_is_used_by_forked_workers(tmp_path):
    """A worker forked after the kernels were cached loads them from numba's cache (hits, no
    misses) instead of compiling them (~45 s of CPU)."""
    st = _study(tmp_path)
    payload = _payload(st, plan(st)[1])  # the backlash case: the exponential scheme's kernels
    with _local_pool(1) as pool:  # fills the cache if it was empty
        assert pool.submit(run_case_and_cache_stats, payload).result()[0] == "ok"
    with _local_pool(1) as pool:  # a new worker
        status, hits, misses = pool.submit(run_case_and_cache_stats, payload).result()
    assert status == "ok" and hits > 0 and misses == 0, (hits, misses)


_RUN_AND_PRINT_SERVER = """
import sys
from gearrotor.studies import load_study, run_study, workers
if __name__ == "__main__":
    run_study(load_study(sys.argv[1]), workers=1, cases=[0], progress=False)
    print(workers._server["server"]._forkserver_pid, flush=True)
"""


@needs_forkserver
@skip_without_proc
def test_no_fork_server_is_left_after_a_study(tmp_path):
    """The fork server of a process that ran a study ends when that process ends (it is not
    a daemon of its own: its "alive" pipe's only holder left is that process)."""
    st = _study(tmp_path)
    r = subprocess.run(
        [sys.executable, "-c", _RUN_AND_PRINT_SERVER, str(st.file)],
        capture_output=True,
        text=True,
        timeout=300,
        env={**os.environ, "PYTHONPATH": str(SRC)},
    )
    assert r.returncode == 0 and r.stderr == "", r.stderr
    pid = int(r.stdout.split()[-1])
    deadline = time.time() + 10
    while alive(pid) and time.time() < deadline:
        time.sleep(0.05)
    assert not alive(pid), f"the fork server {pid} outlived its process"


def test_spawn_on_pythons_whose_fork_server_is_not_checked(monkeypatch):
    """The fork server is driven through pieces private to multiprocessing, checked on the
    Python versions the suite runs on; a later Python (3.14 authenticates the connections to
    a fork server) spawns its workers until it is checked."""
    monkeypatch.setattr(sys, "version_info", (3, 14, 0, "final", 0))
    assert W.start_method() == "spawn"
