"""Generated corpus of damaged and foreign files in a study folder (issue 17, left open there):
``study report`` (and ``study run``, ``study status``, which read the same files) refuse a case
file that is not the case's own complete result with exit 2 and one line naming the file and
what is wrong, as ``transient-plot`` refuses a hostile saved result; before, each of these was a
traceback (exit 1) from h5py, json or xarray, or (a foreign file, NaN histories) went into the
figures unnoticed.

A study of the small model (two 20 ms transient runs, one modal study) is run once; every case
copies its folder and damages one file.
"""

from __future__ import annotations

import json
import os
import shutil
from pathlib import Path

import numpy as np
import pytest

from fault_helpers import rewrite_netcdf

from .conftest import SMALL, run

TRANSIENT_STUDY = """
name = "damaged"
model = "small.toml"
output = "s.study"
[parameters]
unbalance = { path = "unbalances[0].amount", unit = "g*mm" }
[cases]
columns = ["unbalance"]
rows = [[100], [200]]
[analysis]
type = "transient"
t_end = "0.02 s"
[outputs]
window = "0.01 s"
"""

MODAL_STUDY = """
name = "damaged-modal"
model = "small.toml"
output = "s.study"
[parameters]
k = { paths = ["bearings[0].k", "bearings[1].k"], unit = "N/m" }
[cases]
columns = ["k"]
rows = [[1e7], [2e7]]
[analysis]
type = "modal"
n_modes = 4
"""


def _finished(folder: Path, text: str) -> Path:
    (folder / "small.toml").write_text(SMALL)
    (folder / "study.toml").write_text(text)
    r, _ = run("study", "run", folder / "study.toml", "--workers", "1", "--no-progress")
    assert r.exit_code == 0, (r.output, r.exception)
    return folder


@pytest.fixture(scope="module")
def transient_study(tmp_path_factory) -> Path:
    return _finished(tmp_path_factory.mktemp("transient"), TRANSIENT_STUDY)


@pytest.fixture(scope="module")
def modal_study(tmp_path_factory) -> Path:
    return _finished(tmp_path_factory.mktemp("modal"), MODAL_STUDY)


def _cases(folder: Path) -> list[Path]:
    """The case files in the order of the study's rows (study.json)."""
    doc = json.loads((folder / "s.study" / "study.json").read_text())
    return [folder / "s.study" / "cases" / f"{c['key']}.nc" for c in doc["cases"]]


def _rewrite(path: Path, change) -> None:
    rewrite_netcdf(path, path, change)


def _set(name, value):
    def change(ds):
        ds[name] = (ds[name].dims, np.full(ds[name].shape, value))
        return ds

    return change


def _attr(name, value):
    def change(ds):
        if value is None:
            del ds.attrs[name]
        else:
            ds.attrs[name] = value
        return ds

    return change


def _nan_history(ds):
    x = ds["x"].values.copy()
    x[3, 0] = np.nan
    ds["x"] = (ds["x"].dims, x)
    return ds


def _damage(case: Path, other: Path, how: str) -> None:
    if how == "random-bytes":
        case.write_bytes(os.urandom(4096))
    elif how == "truncated":
        case.write_bytes(case.read_bytes()[: case.stat().st_size // 2])
    elif how == "empty":
        case.write_bytes(b"")
    elif how == "directory":
        case.unlink()
        case.mkdir()
    elif how == "foreign":  # another case's result under this case's name
        shutil.copyfile(other, case)
    elif how == "no-metrics":
        _rewrite(case, _attr("metrics", None))
    elif how == "metrics-not-json":
        _rewrite(case, _attr("metrics", "[amp_1x"))
    elif how == "missing-metric":
        _rewrite(case, lambda ds: ds.drop_vars("amp_1x"))
    elif how == "text-metric":
        _rewrite(case, _set("amp_1x", "a"))
    elif how == "infinite-metric":
        _rewrite(case, _set("amp_1x", np.inf))
    elif how == "nan-history":
        _rewrite(case, _nan_history)
    elif how == "reversed-time":
        _rewrite(case, lambda ds: ds.assign_coords(time=ds["time"].values[::-1].copy()))
    elif how == "model-not-json":
        _rewrite(case, _attr("model_json", "{not json"))
    elif how == "probe-on-no-shaft":
        _rewrite(case, _set("probe_shaft", 7))
    elif how == "solver-stats-not-json":
        _rewrite(case, _attr("solver_stats", "{"))
    else:
        raise AssertionError(how)


CASES = [
    ("random-bytes", ["cannot read the file as NetCDF"]),
    ("truncated", ["cannot read the file as NetCDF"]),
    ("empty", ["cannot read the file as NetCDF"]),
    ("directory", ["a directory, not a file"]),
    ("foreign", ["case_key", "not this case's result"]),
    ("no-metrics", ["metrics", "not a JSON list"]),
    ("metrics-not-json", ["metrics", "not valid JSON"]),
    ("missing-metric", ["metrics", "missing ['amp_1x']"]),
    ("text-metric", ["amp_1x", "not numeric"]),
    ("infinite-metric", ["amp_1x", "infinite"]),
    ("nan-history", ["x: ", "not finite"]),
    ("reversed-time", ["time", "increasing"]),
    ("model-not-json", ["model_json", "not valid JSON"]),
    ("probe-on-no-shaft", ["probe_shaft", "shaft indices"]),
    ("solver-stats-not-json", ["solver_stats", "not valid JSON"]),
]


def refused(r, *needles) -> None:
    """Exit 2; the one error line (the last on stderr; before it only the report's progress
    lines, "[  0.1 s] collecting ...") names the file and what is wrong; no traceback."""
    assert r.exit_code == 2, (r.exit_code, r.output, r.exception)
    assert "Traceback" not in r.output, r.output
    lines = r.stderr.strip().splitlines()
    assert lines[-1].startswith("error: ") and all(x.startswith("[") for x in lines[:-1]), lines
    for n in needles:
        assert n in lines[-1], (n, lines[-1])


def _copy(study: Path, tmp_path: Path) -> tuple[Path, list[Path]]:
    shutil.copytree(study, tmp_path, dirs_exist_ok=True)
    return tmp_path / "study.toml", _cases(tmp_path)


@pytest.mark.parametrize("how, needles", CASES, ids=[c[0] for c in CASES])
def test_damaged_case_refused_by_study_report(transient_study, tmp_path, how, needles):
    study, (case, other) = _copy(transient_study, tmp_path)
    _damage(case, other, how)
    r, _ = run("study", "report", study, "--output", tmp_path / "rep")
    refused(r, str(case), *needles)
    assert not (tmp_path / "rep").exists()


def test_damaged_case_refused_by_study_run(transient_study, tmp_path):
    """``study run`` skips a case whose file exists, then collects: the damaged file is named,
    with what to do."""
    study, (case, other) = _copy(transient_study, tmp_path)
    _damage(case, other, "truncated")
    r, _ = run("study", "run", study, "--no-progress")
    refused(r, str(case), "delete it to run the case again")


def test_damaged_modal_case(modal_study, tmp_path):
    study, (case, other) = _copy(modal_study, tmp_path)
    _rewrite(case, _set("mode_type", 1.0))
    r, _ = run("study", "report", study, "--output", tmp_path / "rep")
    refused(r, str(case), "mode_type", "text expected")


@pytest.mark.parametrize("content", [b"{not json", b"\xff\xfe", b'{"error": 3}', b"[]"])
def test_damaged_failed_case_file(transient_study, tmp_path, content):
    """A failed case's ``<key>.error.json`` is read by ``status``, ``run`` and ``report``."""
    study, (case, _) = _copy(transient_study, tmp_path)
    error = case.with_name(case.name.replace(".nc", ".error.json"))
    case.unlink()
    error.write_bytes(content)
    for args in (("status", study), ("report", study), ("run", study, "--no-retry-failed")):
        r, _ = run("study", *args)
        refused(r, str(error))


def test_genuine_cases_still_read(transient_study, modal_study):
    """The check passes what ``study run`` writes (both analyses; the transient one with its
    embedded model), and the collected metrics are those of the files."""
    from gearrotor.studies import collect, load_case, load_study

    for folder in (transient_study, modal_study):
        st = load_study(folder / "study.toml")
        ds = collect(st, write=False)
        assert list(ds["status"].values) == ["done", "done"]
        first = load_case(st, 0)
        for name in json.loads(first.attrs["metrics"]):
            np.testing.assert_array_equal(ds[name].values[0], first[name].values)
