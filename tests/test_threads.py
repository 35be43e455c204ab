"""Thread control (gearrotor.threads): the setting, the choice per operation, the scopes of the
analyses and commands, the study workers, and how much results move with the thread count.

The thread counts are read back from the BLAS libraries themselves (threadpoolctl), inside the
analysis, not inferred from the settings.
"""

from __future__ import annotations

import importlib
import json
import os
import subprocess
import sys

import numpy as np
import pytest
import scipy.linalg  # noqa: F401  (SciPy's OpenBLAS loaded: both libraries are checked)
from threadpoolctl import ThreadpoolController
from typer.testing import CliRunner

from gearrotor import threads
from gearrotor.cli import app
from gearrotor.errors import ModelError
from gearrotor.io import load_model

CORES = threads.available_cores()


@pytest.fixture
def two_threads_outside():
    """Every BLAS library on 2 threads before the test (as an unconfigured process on 2 cores
    would be), restored afterwards: a scope must bring them to its count and back."""
    ctl = ThreadpoolController()
    before = {lib.filepath: lib.num_threads for lib in ctl.lib_controllers}
    for lib in ctl.lib_controllers:
        lib.set_num_threads(2)
    yield
    for lib in ctl.lib_controllers:
        lib.set_num_threads(before[lib.filepath])


@pytest.fixture
def auto(monkeypatch):
    monkeypatch.delenv(threads.ENV, raising=False)


def _spy(monkeypatch, module, name):
    """Replace ``module.name`` by a wrapper that records the BLAS thread counts when called."""
    seen = []
    fn = getattr(module, name)

    def spy(*args, **kwargs):
        seen.append(set(threads.current_threads().values()))
        return fn(*args, **kwargs)

    monkeypatch.setattr(module, name, spy)
    return seen


def test_setting_parsed_and_checked(monkeypatch):
    assert threads.parse_setting(None) == "auto"
    assert threads.parse_setting(" Auto ") == "auto"
    assert threads.parse_setting("3") == 3
    for bad in ("0", "-1", "two", "1.5"):
        with pytest.raises(ModelError, match="GEARROTOR_THREADS.*'auto' or an integer >= 1"):
            threads.parse_setting(bad)
    monkeypatch.setenv(threads.ENV, "2")
    assert threads.setting() == 2
    with threads.using("auto"):  # the option wins over the environment
        assert threads.setting() == "auto"
    assert threads.setting() == 2


def test_one_thread_below_the_crossover_and_under_load(monkeypatch, auto):
    monkeypatch.setattr(threads, "available_cores", lambda: 2)
    monkeypatch.setattr(threads, "busy_cores", lambda: 0.0)
    big = threads.CROSSOVER["eig"]
    assert threads.threads_for(big - 1) == 1
    assert threads.threads_for(big) == 2
    # one neighbour busy: the second core is not free (2-4x slower, docs/performance.md)
    monkeypatch.setattr(threads, "busy_cores", lambda: 1.0)
    assert threads.threads_for(10 * big) == 1
    monkeypatch.setattr(threads, "busy_cores", lambda: 0.3)  # a light, intermittent load
    assert threads.threads_for(10 * big) == 2
    # a fixed setting holds at every size, capped at the cores available
    monkeypatch.setenv(threads.ENV, "8")
    assert threads.threads_for(10) == 2
    monkeypatch.setenv(threads.ENV, "1")
    assert threads.threads_for(10 * big) == 1


def test_busy_cores_sees_a_busy_neighbour():
    """A process spinning on a core is counted (the runnable tasks of /proc/loadavg less this
    process's own): a lower bound of 0.5, as the neighbour may be descheduled at the sample."""
    if not os.path.exists("/proc/loadavg"):
        pytest.skip("Linux only")
    proc = subprocess.Popen([sys.executable, "-c", "while True: pass"])
    try:
        import time

        time.sleep(0.3)
        seen = max(threads.busy_cores() for _ in range(20))
    finally:
        proc.kill()
        proc.wait()
    assert seen >= 1.0


def test_analysis_runs_on_one_thread_and_restores(monkeypatch, auto, two_threads_outside, examples):
    modal_mod = importlib.import_module("gearrotor.analyses.lateral.modal")

    seen = _spy(monkeypatch, modal_mod, "_classify")
    train = load_model(examples / "unity_gearbox.toml")
    modal_mod.modal(train, method="dense")
    assert seen == [{1}]
    assert set(threads.current_threads().values()) == {2}  # restored


def test_fixed_setting_and_large_operations(monkeypatch, two_threads_outside, examples):
    modal_mod = importlib.import_module("gearrotor.analyses.lateral.modal")

    seen = _spy(monkeypatch, modal_mod, "_classify")
    train = load_model(examples / "unity_gearbox.toml")
    monkeypatch.setenv(threads.ENV, "1")
    modal_mod.modal(train, method="dense")
    # a large dense solve on free cores gets them, and the scope's one thread comes back after it
    monkeypatch.delenv(threads.ENV)
    monkeypatch.setattr(threads, "available_cores", lambda: 2)
    monkeypatch.setattr(threads, "busy_cores", lambda: 0.0)
    inside = []
    with threads.scope():
        with threads.limit(threads.CROSSOVER["eig"], "eig") as n:
            inside.append(set(threads.current_threads().values()))
        inside.append(set(threads.current_threads().values()))
    assert seen == [{1}] and n == 2 and inside == [{2}, {1}]
    assert set(threads.current_threads().values()) == {2}


@pytest.mark.skipif(CORES < 2, reason="needs 2 cores")
def test_cli_threads_option_reaches_the_analysis(monkeypatch, auto, two_threads_outside, examples):
    modal_mod = importlib.import_module("gearrotor.analyses.lateral.modal")

    seen = _spy(monkeypatch, modal_mod, "_classify")
    model = str(examples / "unity_gearbox.toml")
    r = CliRunner().invoke(app, ["modal", model, "--threads", "2", "--format", "json"])
    assert r.exit_code == 0, r.output
    r = CliRunner().invoke(app, ["modal", model, "--format", "json"])
    assert r.exit_code == 0, r.output
    assert seen == [{2}, {1}]
    monkeypatch.setenv(threads.ENV, "many")
    r = CliRunner().invoke(app, ["modal", model])
    assert r.exit_code == 2 and "error: GEARROTOR_THREADS: invalid number of threads" in r.output
    r = CliRunner().invoke(app, ["torsional", "modes", model, "--threads", "0"])
    assert r.exit_code == 2 and "--threads" in r.output


def test_study_case_runs_on_one_thread(monkeypatch, auto, two_threads_outside, examples):
    """A study case (local process or Dask worker, also one started without THREAD_ENV) runs in
    a one-thread scope."""
    from gearrotor.model import Train
    from gearrotor.studies import execute

    seen = []

    def fake(train, settings):
        seen.append(set(threads.current_threads().values()))
        raise RuntimeError("stop here")

    monkeypatch.setattr(execute, "_run_modal", fake)
    train = load_model(examples / "unity_gearbox.toml")
    out = execute.run_case(
        {
            "key": "k",
            "index": 0,
            "model_json": Train.model_dump_json(train),
            "analysis": {"type": "modal"},
            "window": None,
            "histories": [],
            "values": {},
            "study": "s",
        }
    )
    assert out["status"] == "failed" and "stop here" in out["error"]
    assert seen == [{1}]


def test_xdist_workers_share_the_cores():
    """Under ``pytest -n N`` each worker's BLAS libraries run on cores // N threads
    (tests/conftest.py); without xdist nothing is set."""
    workers = int(os.environ.get("PYTEST_XDIST_WORKER_COUNT") or 0)
    if not os.environ.get("PYTEST_XDIST_WORKER"):
        pytest.skip("not under pytest-xdist")
    want = max(1, CORES // workers) if "OPENBLAS_NUM_THREADS" not in os.environ else None
    counts = set(ThreadpoolController().info()[i]["num_threads"] for i in range(2))
    assert counts == {want or int(os.environ["OPENBLAS_NUM_THREADS"])}


def test_no_side_effects_at_import():
    """``import gearrotor`` (and the analyses) neither imports threadpoolctl nor changes a
    library's thread count (STYLE.md)."""
    code = (
        "import json, sys, numpy, scipy.linalg\n"
        "from threadpoolctl import ThreadpoolController as T\n"
        "before = [l.num_threads for l in T().lib_controllers]\n"
        "import gearrotor, gearrotor.analyses, gearrotor.cli\n"
        "after = [l.num_threads for l in T().lib_controllers]\n"
        "print(json.dumps([before, after]))\n"
    )
    env = {k: v for k, v in os.environ.items() if not k.endswith("_NUM_THREADS")}
    env.pop(threads.ENV, None)
    out = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, env=env, check=True
    )
    before, after = json.loads(out.stdout)
    assert before == after
    code = "import sys, gearrotor, gearrotor.analyses; print('threadpoolctl' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env)
    assert out.stdout.strip() == "False"


@pytest.mark.skipif(CORES < 2, reason="needs 2 cores")
def test_results_move_by_round_off_with_the_thread_count(monkeypatch, examples):
    """The same analyses on 1 and 2 threads (every operation, ``GEARROTOR_THREADS``): BLAS sums
    in another order, so results may differ in the last digits and no more. Measured on the
    steam turbine (docs/performance.md): damped frequencies 2.3e-12 relative, log decrements
    2.7e-11 absolute (dense solve), Campbell 5e-12, unbalance response 0 (the sparse LU is not
    threaded). Bounds: 50x those (the eigen solve's backward error ~1e-15 ‖A‖ times the modes'
    condition numbers; another BLAS or CPU may order its sums differently)."""
    from gearrotor.analyses import campbell, modal, unbalance_response

    train = load_model(examples / "steam_turbine_gearbox.toml")
    out = {}
    for n in ("1", "2"):
        monkeypatch.setenv(threads.ENV, n)
        w = abs(train.speed)
        m = modal(train, method="dense")
        c = campbell(train, speeds=np.linspace(0.8, 1.1, 4) * w, max_frequency=3 * w)
        u = unbalance_response(train, speeds=np.linspace(0.8, 1.1, 3) * w)
        out[n] = (m, c, u)
    (m1, c1, u1), (m2, c2, u2) = out["1"], out["2"]
    ok = ~m1.overdamped
    assert np.allclose(m1.damped_frequency[ok], m2.damped_frequency[ok], rtol=1e-10, atol=0)
    assert np.allclose(m1.log_dec[ok], m2.log_dec[ok], rtol=0, atol=1.5e-9)
    f1, f2 = c1.damped_frequency, c2.damped_frequency
    fin = np.isfinite(f1)
    assert np.array_equal(fin, np.isfinite(f2))
    assert np.allclose(f1[fin], f2[fin], rtol=2.5e-10, atol=0)
    a1, a2 = np.abs(u1.response), np.abs(u2.response)
    assert np.max(np.abs(a1 - a2)) <= 1e-11 * a1.max()
