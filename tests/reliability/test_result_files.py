"""Generated corpus of hostile transient result files (issue 17) for ``transient-plot`` and
``report --transient``: what is read is checked (NetCDF, the variables used, an increasing
finite time axis, finite values, the embedded model's JSON depth and types) and refused with
exit 2 and one line naming the file, before anything is drawn or written."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from fault_helpers import netcdf_bomb, rewrite_netcdf

from .conftest import SMALL, check_refused, files_in, run


@pytest.fixture(scope="module")
def saved(tmp_path_factory) -> Path:
    """A genuine result: 10 ms of the small model (RK4)."""
    import tomllib

    from gearrotor.analyses.transient import RK4, transient
    from gearrotor.io import model_from_dict

    folder = tmp_path_factory.mktemp("result")
    res = transient(model_from_dict(tomllib.loads(SMALL)), t_end=0.01, integrator=RK4(dt=2e-5))
    return res.save(folder / "run.nc")


def _tamper(src: Path, dst: Path, how: str) -> None:
    rewrite_netcdf(src, dst, lambda ds: _tampered(ds, how))


def _tampered(ds, how: str):
    model = json.loads(ds.attrs["model_json"])
    if how == "deep-json":
        ds.attrs["model_json"] = "[" * 100000 + "]" * 100000
    elif how == "nested-json":
        ds.attrs["model_json"] = json.dumps({"name": "x", "a": json.loads("[" * 40 + "]" * 40)})
    elif how == "bad-json":
        ds.attrs["model_json"] = "{not json"
    elif how == "wrong-type":
        model["probes"][0]["node"] = 1e308
        ds.attrs["model_json"] = json.dumps(model)
    elif how == "string-number":
        model["materials"]["steel"]["E"] = "10**10**10 Pa"
        ds.attrs["model_json"] = json.dumps(model)
    elif how == "constant-time":
        ds = ds.assign_coords(time=np.zeros(ds.sizes["time"]))
    elif how == "reversed-time":
        ds = ds.assign_coords(time=ds["time"].values[::-1].copy())
    elif how == "nan-speed":
        sp = ds["shaft_speed"].values.copy()
        sp[3, 0] = np.nan
        ds["shaft_speed"] = (ds["shaft_speed"].dims, sp)
    elif how == "missing-variable":
        ds = ds.drop_vars("x")
    elif how == "one-sample":
        ds = ds.isel(time=[0])
    return ds


CASES = [
    ("deep-json", ["model_json", "not valid JSON"]),
    ("nested-json", ["model_json", "nested"]),
    ("bad-json", ["model_json", "not valid JSON"]),
    ("wrong-type", ["model_json", "probes[0].node"]),
    ("string-number", ["model_json", "10**10**10"]),
    ("constant-time", ["time", "increasing"]),
    ("reversed-time", ["time", "increasing"]),
    ("nan-speed", ["shaft_speed", "not finite"]),
    ("missing-variable", ["missing x"]),
    ("one-sample", ["time", "2 samples"]),
]


@pytest.mark.parametrize("how, needles", CASES, ids=[c[0] for c in CASES])
def test_hostile_result_refused_by_transient_plot(saved, tmp_path, how, needles):
    bad = tmp_path / "bad.nc"
    _tamper(saved, bad, how)
    before = files_in(tmp_path)
    r, dt = run("transient-plot", bad, "-o", tmp_path / "figs")
    check_refused(r, dt, "bad.nc", *needles)
    assert files_in(tmp_path) == before


@pytest.mark.parametrize(
    "content", [b"", b"\x89HDF\r\n\x1a\n" + bytes(200), bytes(range(256)) * 4, None]
)
def test_not_a_result_file(tmp_path, content):
    bad = tmp_path / "bad.nc"
    if content is None:
        bad.mkdir()
    else:
        bad.write_bytes(content)
    before = files_in(tmp_path)
    r, dt = run("transient-plot", bad, "-o", tmp_path / "figs")
    check_refused(r, dt, "bad.nc")
    assert files_in(tmp_path) == before


def test_hostile_result_refused_by_report(saved, small, tmp_path):
    bad = tmp_path / "bad.nc"
    _tamper(saved, bad, "nan-speed")
    r, dt = run("report", small, "-o", tmp_path / "rep", "--analyses", "modal", "--transient", bad)
    check_refused(r, dt, "bad.nc", "shaft_speed")
    assert not (tmp_path / "rep").exists()


BOMBS = [
    ("data-7TiB", (10**6, 10**6), False),
    ("coordinate-7TiB", (10**12,), True),
]


@pytest.mark.parametrize("shape, coordinate", [b[1:] for b in BOMBS], ids=[b[0] for b in BOMBS])
def test_decompression_bomb_refused_from_the_header(saved, tmp_path, shape, coordinate):
    """Issue 23: a NetCDF of a few kB that unpacks to terabytes (chunks never written read as
    fill values) crashed ``transient-plot`` and ``report --transient`` (SIGSEGV under a memory
    limit; a MemoryError traceback without). Its arrays' sizes come from the header: one line,
    exit 2, before any data (or the coordinates xarray reads on opening) is read."""
    bomb = tmp_path / "bomb.nc"
    declared = netcdf_bomb(saved, bomb, shape, coordinate=coordinate)
    assert bomb.stat().st_size < 100_000 and declared > 8 * 1024**3
    before = files_in(tmp_path)
    r, dt = run("transient-plot", bomb, "-o", tmp_path / "figs")
    check_refused(r, dt, "bomb.nc", "GiB of memory once unpacked", "nothing was read")
    assert files_in(tmp_path) == before


def test_decompression_bomb_refused_by_report(saved, small, tmp_path):
    bomb = tmp_path / "bomb.nc"
    netcdf_bomb(saved, bomb, (10**6, 10**6))
    r, dt = run("report", small, "-o", tmp_path / "rep", "--analyses", "modal", "--transient", bomb)
    check_refused(r, dt, "bomb.nc", "once unpacked")
    assert not (tmp_path / "rep").exists()


def test_result_larger_than_any_transient_writes(saved, tmp_path, monkeypatch):
    """Below what the machine could allocate, the cap (the largest result a transient writes)
    refuses it too; lowered here to 100 MB so that the 800 MB bomb costs nothing where the
    check is missing."""
    from gearrotor.analyses.transient import results

    monkeypatch.setattr(results, "MAX_RESULT_BYTES", 100 * 1024**2)
    bomb = tmp_path / "bomb.nc"
    netcdf_bomb(saved, bomb, (10**4, 10**4))
    r, dt = run("transient-plot", bomb, "-o", tmp_path / "figs")
    check_refused(r, dt, "bomb.nc", "0.0977 GiB (the largest result a transient writes)")


def test_result_larger_than_the_memory_left(saved, tmp_path, monkeypatch):
    """Below the cap, the memory this process can still get decides (a memory limit, ulimit -v
    or a cgroup's): a result needing more than half of it is refused, naming why."""
    from gearrotor.analyses.transient import results

    need = results.check_sizes(saved)
    monkeypatch.setattr(results, "memory_available", lambda: need)  # half of it is too little
    r, dt = run("transient-plot", saved, "-o", tmp_path / "figs")
    check_refused(r, dt, "run.nc", "half the memory available")
    monkeypatch.setattr(results, "memory_available", lambda: 2 * need)
    r, _ = run("transient-plot", saved, "-o", tmp_path / "figs")
    assert r.exit_code == 0, (r.output, r.exception)


def test_genuine_result_still_reads(saved):
    from gearrotor.analyses.transient import load_result

    ds = load_result(saved)
    assert ds.sizes["time"] > 2
