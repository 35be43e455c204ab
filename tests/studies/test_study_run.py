"""Running studies: local processes and a Dask LocalCluster give identical results; a re-run
or a resumed run recomputes nothing finished; failing cases are reported, the others complete.

Short runs (0.1 s of the SPEC 6.1 gearbox with the modal integrator) keep this module at
about half a minute on two cores.
"""

from __future__ import annotations

import json
import os
import signal
import socket
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from typer.testing import CliRunner

from gearrotor.analyses import modal
from gearrotor.cli.study import study_app
from gearrotor.io import load_model
from gearrotor.studies import (
    THREAD_ENV,
    case_path,
    collect,
    load_case,
    load_study,
    open_results,
    plan,
    run_study,
    study_status,
)

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
MODEL = (EXAMPLES / "unity_gearbox.toml").as_posix()

STUDY = f"""
name = "tiny"
model = "{MODEL}"
output = "tiny.study"

[set]
"meshes[0].variation.terms" = 5

[parameters]
unbalance = {{ paths = ["unbalances[0].amount", "unbalances[1].amount"], unit = "g*mm" }}
ka = {{ path = "meshes[0].variation.ka_ratio" }}

[cases]
columns = ["unbalance", "ka"]
# case 2: invalid value (input error); case 3: 1000 kg*m of unbalance, diverges
rows = [[360, 0.0], [720, 0.2], [720, -0.5], [1e9, 0.0]]

[analysis]
type = "transient"
t_end = "0.1 s"

[outputs]
window = "0.05 s"
"""


@pytest.fixture(scope="module")
def local_run(tmp_path_factory):
    """The study run on local processes, interrupted after case 0 and resumed."""
    path = tmp_path_factory.mktemp("local") / "tiny.toml"
    path.write_text(STUDY)
    st = load_study(path)
    first = run_study(st, cases=[0], workers=1, progress=False)
    mtime0 = case_path(st, plan(st)[0].key).stat().st_mtime_ns
    # a kill during a write leaves a temp file: it must not count as finished
    (st.folder / "cases" / f"{plan(st)[1].key}.nc.tmp-99999").write_bytes(b"partial")
    second = run_study(st, workers=1, progress=False)
    return st, first, second, mtime0


@pytest.fixture(scope="module")
def dask_run(tmp_path_factory):
    path = tmp_path_factory.mktemp("dask") / "tiny.toml"
    path.write_text(STUDY)
    st = load_study(path)
    # with distributed's default HTTP port taken, as by another cluster on the machine: the
    # run printed "UserWarning: Port 8787 is already in use" (an error here: filterwarnings)
    with socket.socket() as busy:
        try:
            busy.bind(("127.0.0.1", 8787))
            busy.listen()
        except OSError:  # taken already
            pass
        # one Dask worker (a nanny and its worker process): under ``pytest -n 2`` two would
        # put four processes on the two cores the test workers already use (issue 28)
        return st, run_study(st, scheduler="local", workers=1, progress=False)


def test_resume_recomputes_nothing_finished(local_run):
    st, first, second, mtime0 = local_run
    assert (first.executed, first.skipped) == (1, 0)
    # resumed: case 0 skipped; cases 1 and 3 run; case 2 is an input error (not run)
    assert (second.executed, second.skipped) == (2, 1)
    assert case_path(st, plan(st)[0].key).stat().st_mtime_ns == mtime0
    # a plain re-run (failed cases not retried) executes nothing
    again = run_study(st, workers=1, progress=False, retry_failed=False)
    assert (again.executed, again.skipped) == (0, 3)
    assert sorted(again.failed) == [2, 3]
    assert case_path(st, plan(st)[0].key).stat().st_mtime_ns == mtime0


def test_failing_cases_reported_others_complete(local_run):
    st, _, second, _ = local_run
    assert sorted(second.failed) == [2, 3]
    assert "meshes[0].variation.ka_ratio" in second.failed[2] and "-0.5" in second.failed[2]
    assert "SolverError" in second.failed[3] and "diverged" in second.failed[3]
    states = [s.state for s in study_status(st)]
    assert states == ["done", "done", "failed", "failed"]
    err = json.loads(case_path(st, plan(st)[3].key, error=True).read_text())
    assert "Traceback" in err["traceback"]
    res = open_results(st)
    assert list(res["status"].values) == states
    assert np.all(np.isfinite(res["amp_1x"].values[:2]))
    assert np.all(np.isnan(res["amp_1x"].values[2:]))
    assert "diverged" in str(res["error"].values[3])
    assert res["unbalance"].attrs["units"] == "g*mm"
    assert list(res["ka"].values) == [0.0, 0.2, -0.5, 0.0]
    # plausibility: 1x at the gear probes grows with the unbalance (SPEC 6.1: mainly 1x)
    assert np.all(res["amp_1x"].values[1] > 1.5 * res["amp_1x"].values[0])
    assert np.all(res["amp_1x"].values[:2] > 10 * res["amp_2x"].values[:2])


def test_local_and_dask_give_identical_results(local_run, dask_run):
    st_l, _, _, _ = local_run
    st_d, summary = dask_run
    assert summary.backend == "dask-local" and summary.executed == 3
    assert sorted(summary.failed) == [2, 3]
    for i in (0, 1):
        a, b = load_case(st_l, i), load_case(st_d, i)
        for ds in (a, b):  # one BLAS/numba thread in every worker
            assert json.loads(ds.attrs["worker_env"]) == THREAD_ENV
        xr.testing.assert_identical(a.drop_attrs(), b.drop_attrs())
    ra = collect(st_l, write=False).drop_attrs().drop_vars("wall_time")
    rb = collect(st_d, write=False).drop_attrs().drop_vars("wall_time")
    xr.testing.assert_identical(ra.drop_vars("error"), rb.drop_vars("error"))


def test_identical_rows_share_one_run(tmp_path):
    path = tmp_path / "dup.toml"
    path.write_text(
        STUDY.replace(
            "rows = [[360, 0.0], [720, 0.2], [720, -0.5], [1e9, 0.0]]",
            "rows = [[360, 0.0], [360, 0.0]]",
        )
        .replace('t_end = "0.1 s"', 't_end = "0.02 s"')
        .replace('window = "0.05 s"', 'window = "0.01 s"')
    )
    st = load_study(path)
    s = run_study(st, workers=1, progress=False)
    assert (s.n_cases, s.n_runs, s.executed) == (2, 1, 1)
    res = open_results(st)
    np.testing.assert_array_equal(res["amp_1x"].values[0], res["amp_1x"].values[1])


def test_report_and_status_cli(local_run, tmp_path):
    st, *_ = local_run
    runner = CliRunner()
    res = runner.invoke(study_app, ["status", str(st.file)])
    assert res.exit_code == 0, res.output
    assert "4 cases, 2 done, 2 failed, 0 pending" in res.stdout
    out = tmp_path / "fig"
    args = ["report", str(st.file), "--output", str(out), "--probes", "gear1_x"]
    res = runner.invoke(study_app, args)
    assert res.exit_code == 0, res.output
    names = {p.name for p in out.glob("*.png")}
    assert names == {
        "trend_unbalance.png",
        "trend_ka.png",
        "spectra_gear1_x_00-01.png",
        "spectra_speed_shaft1_00-01.png",
        "spectra_speed_shaft2_00-01.png",
    }
    for p in out.glob("*.png"):
        data = p.read_bytes()
        assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 20_000


def test_modal_study_matches_modal(tmp_path):
    """A modal study gives what modal() gives on the same overridden model."""
    path = tmp_path / "modal.toml"
    path.write_text(f"""
model = "{MODEL}"
[parameters]
k = {{ paths = ["bearings[0].k", "bearings[1].k", "bearings[2].k", "bearings[3].k"], unit = "N/m" }}
[cases]
product = {{ k = [5e6, 2e7] }}
[analysis]
type = "modal"
n_modes = 4
""")
    st = load_study(path)
    s = run_study(st, workers=1, progress=False)
    assert s.ok and s.executed == 2
    res = open_results(st)
    ref = modal(load_model(MODEL, {f"bearings[{j}].k": "2e7 N/m" for j in range(4)}))
    keep = ~np.asarray(ref.overdamped, bool)
    np.testing.assert_allclose(
        res["damped_frequency"].values[1], np.asarray(ref.frequency_rpm)[keep][:4], rtol=1e-10
    )
    np.testing.assert_allclose(
        res["log_dec"].values[1], np.asarray(ref.log_dec)[keep][:4], rtol=1e-8
    )


@pytest.mark.slow
def test_killed_run_resumes(tmp_path):
    """SIGKILL the CLI (and its workers) after the first case finished; the re-run computes
    only the remaining cases and leaves the finished one untouched."""
    path = tmp_path / "kill.toml"
    path.write_text(
        STUDY.replace(
            "rows = [[360, 0.0], [720, 0.2], [720, -0.5], [1e9, 0.0]]",
            "rows = [[360, 0.0], [720, 0.0], [1080, 0.0]]",
        ).replace('t_end = "0.1 s"', 't_end = "1.0 s"')
    )
    st = load_study(path)
    code = (
        "import sys; from gearrotor.cli.study import study_app; "
        "study_app(['run', sys.argv[1], '--workers', '1', '--no-progress'])"
    )
    proc = subprocess.Popen(
        [sys.executable, "-c", code, str(path)],
        start_new_session=True,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    keys = [p.key for p in plan(st)]
    try:
        deadline = time.time() + 120
        while not case_path(st, keys[0]).exists() and time.time() < deadline:
            assert proc.poll() is None, "the run ended before it could be interrupted"
            time.sleep(0.05)
        os.killpg(proc.pid, signal.SIGKILL)
    finally:
        proc.wait(timeout=30)
    done = [k for k in keys if case_path(st, k).exists()]
    assert 1 <= len(done) < 3
    mtimes = {k: case_path(st, k).stat().st_mtime_ns for k in done}
    s = run_study(st, workers=1, progress=False)
    assert s.ok and s.executed == 3 - len(done) and s.skipped == len(done)
    assert {k: case_path(st, k).stat().st_mtime_ns for k in done} == mtimes
