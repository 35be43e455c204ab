"""Issue 14 item 15: `study run` starts the longest cases (backlash) first and estimates the
time left from the work left, not from the number of cases."""

from __future__ import annotations

import io
import shutil

import pytest

from gearrotor.studies import execute
from gearrotor.studies.cases import plan
from gearrotor.studies.spec import load_study

pytest.importorskip("xarray")
pytest.importorskip("h5netcdf")


@pytest.fixture()
def seed(examples, tmp_path):
    for name in ("unity_gearbox_study.toml", "unity_gearbox.toml"):
        shutil.copy(examples / name, tmp_path / name)
    return load_study(tmp_path / "unity_gearbox_study.toml")


def test_backlash_cases_weigh_more_and_run_first(seed, monkeypatch):
    planned = plan(seed)
    weights = [execute._case_weight(p) for p in planned]
    # SPEC 6.1 matrix: the rows with backlash are the slow ones (5x in the seed study's run)
    for p, w in zip(planned, weights, strict=True):
        assert (w == execute.BACKLASH_COST) == (p.case.values["backlash"] > 0)
    seen = []
    monkeypatch.setattr(execute, "_execute_local", lambda payloads, n, done: seen.extend(payloads))
    execute.run_study(seed, progress=False, collect_results=False)
    order = {p.key: execute._case_weight(p) for p in planned}
    run_weights = [order[q["key"]] for q in seen]
    assert run_weights == sorted(run_weights, reverse=True)  # longest first
    assert len(seen) == len({p.key for p in planned})  # every distinct case, once


def test_eta_from_the_work_left(monkeypatch):
    # 2 backlash cases (weight 5) and 8 plain ones (1): after the first backlash case took
    # 10 s, 13 of 18 units are left: ~26 s, not 9 cases × 10 s = 90 s
    clock = iter([0.0, 10.0])
    monkeypatch.setattr(execute.time, "perf_counter", lambda: next(clock))
    out = io.StringIO()
    bar = execute._Progress(10, enabled=True, stream=out, total_weight=18.0)
    bar.update("case 0 ok", weight=5.0)
    assert "~26 s left" in out.getvalue()
