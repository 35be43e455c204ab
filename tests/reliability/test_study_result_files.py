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
import xarray as xr

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


# ``results.nc`` is the collection when it is up to date with the case files (the SHA-256 of
# each, recorded when it was collected): it must never stand in for a case file changed since.


@pytest.mark.parametrize("which", ["transient", "modal"])
def test_results_nc_does_not_hide_a_replaced_case(transient_study, modal_study, tmp_path, which):
    """Another case's file copied under this case's name (same size), its time stamps put back:
    ``results.nc`` still names the old content, the file is read and refused (a modal report
    reads no case file for its figures)."""
    study, (case, other) = _copy(transient_study if which == "transient" else modal_study, tmp_path)
    assert case.stat().st_size == other.stat().st_size
    st = case.stat()
    shutil.copyfile(other, case)
    os.utime(case, ns=(st.st_atime_ns, st.st_mtime_ns))
    r, _ = run("study", "report", study, "--output", tmp_path / "rep", "--cases", "1")
    refused(r, str(case), "case_key", "not this case's result")


def _collect(folder: Path):
    from gearrotor.studies import collect, load_study

    return collect(load_study(folder / "study.toml"))


def test_up_to_date_results_nc_is_the_collection(
    transient_study, modal_study, tmp_path, monkeypatch
):
    """Collected anew (no results.nc) and taken from results.nc: the same Dataset; the second
    reads no case file."""
    from gearrotor.studies import collection

    for k, folder in enumerate((transient_study, modal_study)):
        copy = tmp_path / str(k)
        shutil.copytree(folder, copy)
        (copy / "s.study" / "results.nc").unlink()
        fresh = _collect(copy)
        with monkeypatch.context() as m:
            m.setattr(collection, "_read_case", lambda *a: pytest.fail("a case file was read"))
            again = _collect(copy)
        xr.testing.assert_identical(fresh, again)
        assert json.loads(again.attrs["case_files_sha256"])["sha256"].keys() == {
            c.stem for c in _cases(copy)
        }


@pytest.mark.parametrize("how", ["random-bytes", "infinite-metric", "other-settings", "older"])
def test_damaged_or_stale_results_nc_is_collected_anew(transient_study, tmp_path, how):
    """A results.nc that is not the collection of these files is never used: collected again
    from the case files and rewritten (it is derived data, not an input)."""
    study, _ = _copy(transient_study, tmp_path)
    results = tmp_path / "s.study" / "results.nc"
    genuine = _collect(tmp_path)
    if how == "random-bytes":
        results.write_bytes(os.urandom(2048))
    elif how == "infinite-metric":  # recorded digests kept, a number changed
        _rewrite(results, _set("amp_1x", np.inf))
    elif how == "other-settings":
        _rewrite(results, _attr("metric_window_s", 0.5))
    else:  # written before the digests were recorded
        _rewrite(results, _attr("case_files_sha256", None))
    again = _collect(tmp_path)
    xr.testing.assert_identical(genuine, again)
    xr.testing.assert_identical(genuine, xr.open_dataset(results, engine="h5netcdf").load())
    if how == "random-bytes":  # and the report of a model without meshes: no mesh panels
        r, _ = run("study", "report", study, "--output", tmp_path / "rep")
        assert r.exit_code == 0, (r.output, r.exception)
        assert {p.name for p in (tmp_path / "rep").glob("trend_*.png")} == {"trend_unbalance.png"}


def test_case_reader_reads_what_xarray_reads(transient_study, modal_study):
    """The case files and results.nc that ``study run`` writes are read with h5py directly; the
    Dataset is xarray's (``open_dataset(engine="h5netcdf")``): values, dtypes, attributes,
    coordinates, order, and the encoding a collection writes back."""
    from gearrotor.studies.collection import _plain_netcdf

    files = [*_cases(transient_study), *_cases(modal_study)]
    files += [f / "s.study" / "results.nc" for f in (transient_study, modal_study)]
    for path in files:
        fast = _plain_netcdf(path.read_bytes())
        assert fast is not None, path
        with xr.open_dataset(path, engine="h5netcdf") as ds:
            ref = ds.load()
        xr.testing.assert_identical(fast, ref)
        assert list(fast.variables) == list(ref.variables)
        for name, var in ref.variables.items():
            assert fast[name].dtype == var.dtype, name
            for key in ("dtype", "_FillValue"):
                assert str(fast[name].encoding.get(key)) == str(var.encoding.get(key)), name


def test_other_netcdf_layouts_are_read_by_xarray(transient_study, tmp_path):
    """A layout the direct reader does not take (here a fill value that is not NaN: xarray
    masks it) is read by xarray, as before."""
    from gearrotor.studies.collection import _plain_netcdf, _read_netcdf

    case = _cases(transient_study)[0]
    with xr.open_dataset(case, engine="h5netcdf") as ds:
        ds = ds.load()
    x = ds["x"].values.copy()
    x[0, 0] = -1.0
    ds["x"] = (ds["x"].dims, x)
    path = tmp_path / "fill.nc"
    ds.to_netcdf(path, engine="h5netcdf", encoding={"x": {"_FillValue": -1.0}})
    assert _plain_netcdf(path.read_bytes()) is None
    got = _read_netcdf(path, "test")
    assert np.isnan(got["x"].values[0, 0]) and np.isfinite(got["x"].values[1:]).all()


def test_a_huge_file_is_not_read_into_memory(transient_study, tmp_path, monkeypatch):
    """A case file is read into memory whole (one read for its digest and its checks) only when
    its header declares arrays of about its size: a 1 GiB file that is not HDF5 (sparse here)
    is refused from its first bytes, as before."""
    from gearrotor.errors import ModelError
    from gearrotor.studies.collection import _read_netcdf

    big = tmp_path / "big.nc"
    with open(big, "wb") as fh:
        fh.write(os.urandom(4096))
        fh.truncate(1024**3)
    monkeypatch.setattr(Path, "read_bytes", lambda self: pytest.fail(f"{self} read whole"))
    with pytest.raises(ModelError, match="cannot read the file as NetCDF"):
        _read_netcdf(big, "a case file")


def test_spectra_figures_from_the_results_cache(transient_study, tmp_path, monkeypatch):
    """``study report`` again into another folder: the spectra PNGs come from the results cache
    (kind ``study-spectra``, keyed by each case file's SHA-256), byte for byte those drawn the
    first time, without reading a case file; a case file whose content changed (still a valid
    case) is read and drawn again, and only the figures of its cases change."""
    from gearrotor.studies import plots

    monkeypatch.setenv("GEARROTOR_CACHE_DIR", str(tmp_path / "cache"))
    monkeypatch.setenv("GEARROTOR_CACHE", "on")
    study, (case, _) = _copy(transient_study, tmp_path / "s")

    def report(out: str) -> dict[str, bytes]:
        r, _ = run("study", "report", study, "--output", tmp_path / out)
        assert r.exit_code == 0, (r.output, r.exception)
        return {p.name: p.read_bytes() for p in (tmp_path / out).glob("spectra_*.png")}

    first = report("first")
    assert len(first) >= 2  # the probes' and the shaft speed's
    with monkeypatch.context() as m:
        m.setattr(plots, "read_case", lambda *a: pytest.fail("a case file was read"))
        assert report("again") == first

    def louder(ds):
        ds["probe_signal"] = ds["probe_signal"] * 2.0
        return ds

    _rewrite(case, louder)
    changed = report("changed")
    assert changed.keys() == first.keys()
    assert all(changed[name] != first[name] for name in first if "speed" not in name)
    assert all(changed[name] == first[name] for name in first if "speed" in name)
