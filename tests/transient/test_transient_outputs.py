"""Outputs: result object, spectra, NetCDF round trip, checkpoint/resume, figures, CLI."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import typer
from typer.testing import CliRunner

from gearrotor.analyses.transient import (
    RK4,
    Checkpoint,
    ModalRK4,
    Save,
    load_result,
    spectrum,
    transient,
)
from gearrotor.analyses.transient.results import spectral_lines
from gearrotor.cli.transient import plot_command, transient_command

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "unity_gearbox.toml"


@pytest.fixture(scope="module")
def short_result(make_gearbox):
    return transient(make_gearbox(elements=4), t_end=0.2, integrator=ModalRK4(), save=Save(dt=2e-4))


def test_spectrum_reads_sinusoid_amplitude_in_cpm():
    dt = 1e-4
    t = np.arange(20000) * dt
    x = 3.0 * np.sin(2 * np.pi * 50.0 * t) + 0.5 * np.cos(2 * np.pi * 120.0 * t)
    for window in ("hann", "flattop"):
        f, a = spectrum(x, dt, window=window, segments=4)
        k = np.argmin(np.abs(f - 3000.0))
        tol = 0.2 if window == "hann" else 0.01
        assert abs(a[k] - 3.0) < tol * 3.0
        assert f[np.argmax(a)] == pytest.approx(3000.0, abs=f[1] - f[0])


def test_spectral_lines_finds_lines_between_bins_and_not_side_lobes():
    """Three steady lines, none on a bin (0.5 s at 8 kHz: bins of 120 cpm), spanning 1e3 in
    amplitude, on a ramp. Frequencies come back to 1e-3 of a bin (0.12 cpm; the Hann zoom on a
    noiseless signal converges far below that), amplitudes to 0.2 % (the flat-top window
    reads a line anywhere in a bin within 0.1 %; its side lobes, below -90 dB, add < 1e-4 of
    the strong line), growth rates within 0.02 1/s of zero (the halves' amplitudes agree to
    ~0.1 %: ln(1.001)/0.25 s = 0.004 1/s), end amplitudes as the mean. The strong line's lobes
    and the ramp are not reported as lines."""
    dt = 1.25e-4
    t = np.arange(4000) * dt
    lines = [(5700.0 + 37.3, 2.0), (57_114.0 + 11.1, 0.05), (182_260.0 - 44.0, 2e-3)]
    x = 1e-3 * t + sum(a * np.sin(2 * np.pi * f / 60 * t + f) for f, a in lines)
    found = spectral_lines(x, dt, count=6, relative=1e-4)
    assert len(found) == 3
    for (f, a), (fr, ar, sigma, end) in zip(lines, found, strict=True):
        assert fr == pytest.approx(f, abs=0.12)
        assert ar == pytest.approx(a, rel=2e-3)
        assert abs(sigma) < 0.02
        assert end == pytest.approx(a, rel=5e-3)
    # the relative threshold drops the weakest line; count limits the list
    assert len(spectral_lines(x, dt, relative=2e-3)) == 2
    assert len(spectral_lines(x, dt, count=1)) == 1
    assert spectral_lines(np.zeros(4000), dt) == []


def test_spectral_lines_growth_rate_and_end_amplitude():
    """A line growing as e^{19 t} (the compressor's 10x + 32x pair) beside a steady strong
    1x: the two-half estimate is exact for a pure exponential, so σ and the amplitude at the
    last sample come back to 0.5 % (measured 0.005 % and 0.13 %; the residual is the
    frequency error below and the 1x line's leakage)."""
    dt = 1.25e-4
    t = np.arange(4000) * dt
    sigma = 19.0
    x = 2.0 * np.sin(2 * np.pi * 95.0 * t) + 1e-3 * np.exp(sigma * t) * np.cos(
        2 * np.pi * 951.7 * t
    )
    (f1, *_), (f10, _, s10, end10) = spectral_lines(x, dt, count=2)
    assert f1 == pytest.approx(95.0 * 60, abs=0.12)
    # growing by e^9.5 over the record, the line is effectively seen through a window about
    # 1/σ = 0.05 s long, so the Hann zoom locates it only to a fraction of a 120 cpm bin
    assert f10 == pytest.approx(951.7 * 60, abs=0.3 * 120)
    assert s10 == pytest.approx(sigma, rel=5e-3)
    assert end10 == pytest.approx(1e-3 * np.exp(sigma * t[-1]), rel=5e-3)


def test_result_fields_and_whirl_power(short_result):
    r = short_result
    nt = len(r.time)
    assert r.status == "ok"
    assert r.shaft_speed.shape == (nt, 2)
    assert r.node_labels == ("shaft1[2]", "shaft2[2]")
    assert r.mesh_force.shape == (nt, 1) and r.contact.dtype == np.int8
    assert r.bearing_force.shape == (nt, 4, 2)
    names = r.whirl_names
    assert names[0].startswith("unbalance[0]") and "bearing:S1-B1" in names
    assert "mesh:mesh:gear" in names
    # bearings only dissipate: their mean whirl power is negative (c = 1.75e4 N·s/m)
    for k, n in enumerate(names):
        if n.startswith("bearing"):
            assert r.whirl_power[nt // 2 :, k].mean() < 0
    # the unbalance feeds the whirl
    assert r.whirl_power[nt // 2 :, 0].mean() > 0
    s = r.summary()
    assert set(s["nodes"]["shaft1[2]"]) >= {"x_1x_um", "y_1x_um", "x_lines"}
    # the strongest line at the gear node is the unbalance response at 1x; 10 %: the run is
    # 0.2 s from rest near the critical, so the 1x still changes, and the flat-top window
    # weights the middle of the run where the order fit weights all of it equally (6 %)
    line = s["nodes"]["shaft1[2]"]["x_lines"][0]
    assert line["order"] == pytest.approx(1.0, abs=0.01)
    assert line["um"] == pytest.approx(s["nodes"]["shaft1[2]"]["x_1x_um"], rel=0.1)
    assert set(s["shafts"]["shaft1"]) >= {"speed_min_rpm", "speed_max_rpm"}
    assert "wall_time_s" in s
    json.dumps(s)
    assert "speed" not in r.table().lower() or "rpm" in r.table()


def test_netcdf_round_trip_atomic(short_result, tmp_path):
    path = tmp_path / "run.nc"
    short_result.save(path)
    assert path.exists() and not (tmp_path / "run.nc.tmp").exists()
    ds = load_result(path)
    assert ds["shaft_speed"].attrs["units"] == "rad/s"
    assert ds["mesh_force"].attrs["units"] == "N"
    assert ds["x"].attrs["units"] == "m"
    model = json.loads(ds.attrs["model_json"])
    assert model["meshes"][0]["gear"]["teeth"] == 30
    np.testing.assert_array_equal(ds["x"].values, short_result.node_x)
    np.testing.assert_array_equal(ds["contact"].values, short_result.contact)


def test_checkpoint_resume_equals_uninterrupted(make_gearbox, tmp_path, monkeypatch):
    """A run interrupted after its first checkpoint resumes from it and ends bit-identical."""
    from gearrotor.analyses.transient import driver

    train = make_gearbox(elements=4)
    kw = dict(t_end=0.2, integrator=RK4(dt=2e-5), save=Save(dt=2e-4))
    ref = transient(train, **kw)
    ck = Checkpoint(tmp_path / "run.ck.npz", every=0.0)
    calls = {"n": 0}
    real = driver.kn.rk4_physical

    def interrupted(*args):
        calls["n"] += 1
        if calls["n"] == 3:
            raise KeyboardInterrupt
        return real(*args)

    monkeypatch.setattr(driver.kn, "rk4_physical", interrupted)
    with pytest.raises(KeyboardInterrupt):
        transient(train, checkpoint=ck, **kw)
    assert ck.path.exists()
    monkeypatch.setattr(driver.kn, "rk4_physical", real)
    res = transient(train, checkpoint=ck, **kw)
    assert not ck.path.exists()
    np.testing.assert_array_equal(res.final_q, ref.final_q)
    np.testing.assert_array_equal(res.node_x, ref.node_x)


def test_standard_figures(short_result, tmp_path):
    from gearrotor.analyses.transient.plots import standard_figures

    paths = standard_figures(short_result, tmp_path)
    assert len(paths) == 6
    assert all(p.stat().st_size > 10_000 for p in paths)


def _app():
    app = typer.Typer()
    app.command("transient")(transient_command)
    app.command("transient-plot")(plot_command)
    return app


def test_cli_json_summary_and_plot(tmp_path):
    out = tmp_path / "r.nc"
    res = CliRunner().invoke(
        _app(),
        [
            "transient",
            str(EXAMPLE),
            "--t-end",
            "0.6",
            "--method",
            "modal",
            "--format",
            "json",
            "--set",
            "unbalances[1].amount=360 g*mm",
            "--output",
            str(out),
            "--no-progress",
        ],
    )
    assert res.exit_code == 0, res.output
    s = json.loads(res.stdout.strip().splitlines()[-1])
    assert s["wall_time_s"] > 0
    assert {"shaft1[10]", "shaft2[10]"} <= set(s["nodes"])
    assert s["nodes"]["shaft1[10]"]["x_1x_um"] > 10
    assert s["shafts"]["shaft2"]["speed_max_rpm"] < 0
    res = CliRunner().invoke(_app(), ["transient-plot", str(out), "-o", str(tmp_path / "png")])
    assert res.exit_code == 0, res.output
    assert len(list((tmp_path / "png").glob("*.png"))) == 6


def test_cli_input_errors_exit_2(tmp_path):
    runner = CliRunner()
    res = runner.invoke(_app(), ["transient", str(tmp_path / "missing.toml")])
    assert res.exit_code == 2
    assert "model file not found" in res.output
    assert "Traceback" not in res.output
    res = runner.invoke(_app(), ["transient", str(EXAMPLE), "--set", "meshes[0].teeth"])
    assert res.exit_code == 2 and "PATH=VALUE" in res.output
    res = runner.invoke(
        _app(), ["transient", str(EXAMPLE), "--set", "meshes[0].variation.ka_ratio=-1"]
    )
    assert res.exit_code == 2 and "ka_ratio" in res.output
