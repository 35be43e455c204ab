"""``gearrotor torsional modes|campbell|response|transient``: the command line prints the numbers
of the Python API (the same quantity, the same number), checks its inputs and output locations
before running (exit 2), and writes its files."""

from __future__ import annotations

import json

import numpy as np
import pytest
from typer.testing import CliRunner

from gearrotor.analyses.torsional import torsional_modes
from gearrotor.cli import app
from gearrotor.io import load_model

RPM = np.pi / 30


@pytest.fixture(scope="module")
def model(examples):
    return examples / "motor_gearbox_compressor.toml"


def _run(*args):
    res = CliRunner().invoke(app, [str(a) for a in args])
    return res


def test_modes_json_matches_the_api_sorted_with_the_rigid_body_mode_flagged(model, tmp_path):
    res = _run("torsional", "modes", model, "--format", "json", "--plot", tmp_path / "png")
    assert res.exit_code == 0, res.output
    out = json.loads(res.stdout)
    modes = out["modes"]
    for key in ("index", "frequency_hz", "frequency_rpm", "damping_ratio", "rigid_body"):
        assert all(key in m for m in modes)
    f = [m["frequency_hz"] for m in modes]
    assert f == sorted(f)
    assert [m["rigid_body"] for m in modes].count(True) == 1 and modes[0]["rigid_body"]
    api = torsional_modes(load_model(model), n_modes=len(modes))
    np.testing.assert_allclose(f, api.frequency_hz, rtol=1e-12)
    np.testing.assert_allclose([m["frequency_rpm"] for m in modes], np.array(f) * 60, rtol=1e-12)
    assert (tmp_path / "png" / "torsional_modes.png").stat().st_size > 10_000


def test_campbell_margins_against_the_line_frequency(model, tmp_path):
    """The 60 Hz line is a fixed frequency: its margin from mode f_n is |f_n − 60| / 60."""
    res = _run(
        "torsional", "campbell", model, "--format", "json", "--margin", "0.15", "--orders",
        "motor:6", "--plot", tmp_path,
    )  # fmt: skip
    assert res.exit_code == 0, res.output
    out = json.loads(res.stdout)
    assert out["required_margin"] == 0.15
    line = [c for c in out["crossings"] if c["line"] == "line 60 Hz"]
    assert line
    for c in line:
        margin = abs(c["frequency_hz"] - 60.0) / 60.0
        assert c["margin"] == pytest.approx(margin, rel=1e-12)
        assert c["passes"] == (margin >= 0.15)
    assert any(c["line"] == "6x motor" for c in out["crossings"])
    assert out["passes"] == all(c["passes"] for c in out["crossings"])
    assert (tmp_path / "torsional_interference.png").exists()
    table = _run("torsional", "campbell", model)
    assert table.exit_code == 0 and "line 60 Hz" in table.stdout


def test_response_is_linear_in_the_torque_amplitude(model, tmp_path):
    """Steady-state response of a linear model: doubling the torque doubles every amplitude."""
    out = []
    for amp in ("5 kN*m", "10 kN*m"):
        res = _run(
            "torsional", "response", model, "--torque",
            f"shaft=motor,node=4,amplitude={amp},order=2", "--n-speeds", "30",
            "--format", "json", "--plot", tmp_path,
        )  # fmt: skip
        assert res.exit_code == 0, res.output
        out.append(json.loads(res.stdout))
    a, b = out
    assert len(a["speeds_rpm"]) == 30
    assert a["speeds_rpm"][0] == pytest.approx(900) and a["speeds_rpm"][-1] == pytest.approx(2160)
    for ea, eb in zip(a["elements"], b["elements"], strict=True):
        assert eb["max_torque_Nm"] == pytest.approx(2 * ea["max_torque_Nm"], rel=1e-9)
    assert a["meshes"][0]["contact_loss_speeds_rpm"] is not None
    assert (tmp_path / "torsional_response.png").exists()


def test_transient_outputs_agree_with_the_printed_summary(model, tmp_path):
    pytest.importorskip("xarray")
    js, nc = tmp_path / "run.json", tmp_path / "run.nc"
    res = _run(
        "torsional", "transient", model, "--t-end", "0.05", "--format", "json", "-o", js,
        "--sn-stress", "100 MPa",
    )  # fmt: skip
    assert res.exit_code == 0, res.output
    out = json.loads(res.stdout)
    saved = json.loads(js.read_text())
    assert saved["sections"] == out["sections"]
    assert saved["fatigue"] == out["fatigue"]
    hist = saved["histories"]
    assert hist["time_s"][-1] == pytest.approx(0.05)
    # the peak of the saved history is within the exact per-step peak
    peak = max(abs(np.array(v)).max() for k, v in hist["element_torque_Nm"].items())
    top = max(s["peak_torque_Nm"] for s in out["sections"])
    assert peak <= top * (1 + 1e-12) and peak > 0.9 * top
    res = _run(
        "torsional", "transient", model, "--t-end", "0.05", "-o", nc, "--plot", tmp_path,
        "--sn-stress", "100 MPa",
    )  # fmt: skip
    assert res.exit_code == 0, res.output
    assert "allowable events" in res.stdout
    import xarray as xr

    with xr.open_dataset(nc, engine="h5netcdf") as ds:
        np.testing.assert_allclose(ds["time"].values, hist["time_s"])
        assert json.loads(ds.attrs["fatigue_json"]) == out["fatigue"]
    for name in ("torsional_transient.png", "torsional_fatigue.png"):
        assert (tmp_path / name).exists()


@pytest.mark.parametrize(
    ("args", "needle"),
    [
        (["modes", "{m}", "--mesh", "stiff"], "--mesh"),
        (["modes", "{m}", "--format", "xml"], "--format"),
        (["campbell", "{m}", "--orders", "motor"], "--orders"),
        (["campbell", "{m}", "--min-speed", "2000", "--max-speed", "1000"], "--min-speed"),
        (["response", "{m}", "--torque", "shaft=motor,node=4"], "--torque[0]"),
        (["response", "{m}", "--torque", "motor 4 5 kN*m"], "--torque[0]"),
        (["transient", "{m}", "--sn-m", "-3"], "--sn-m"),
        (["transient", "{m}", "-o", "{tmp}/missing/run.nc"], "--output"),
        (["transient", "{m}", "-o", "{tmp}/run.csv"], "--output"),
        (["transient", "{m}", "--plot", "{tmp}/afile"], "--plot"),
        (["transient", "{m}", "--t-end", "0"], "--t-end"),
        (["transient", "{m}", "--t-end", "nan"], "--t-end"),
        (["transient", "{m}", "--initial-speed", "-5"], "--initial-speed"),
        (
            [
                "response",
                "{m}",
                "--torque",
                "shaft=motor,node=4,amplitude=1,order=1",
                "--n-speeds",
                "100000000",
            ],
            "--n-speeds",
        ),  # fmt: skip
        (["campbell", "{m}", "--margin", "1.5"], "--margin"),
        (["campbell", "{m}", "--line-frequency", "-60"], "--line-frequency"),
        (["modes", "{m}", "--n-modes", "0"], "--n-modes"),
    ],
)
def test_bad_input_exits_2_before_running(model, tmp_path, args, needle):
    (tmp_path / "afile").write_text("x")
    argv = ["torsional"] + [a.format(m=model, tmp=tmp_path) for a in args]
    res = _run(*argv)
    assert res.exit_code == 2, res.output
    assert needle in res.stderr and "Traceback" not in res.output
    assert len(res.stderr.strip().splitlines()) == 1  # one line, no usage box
    assert not list(tmp_path.glob("*.nc")) and not list(tmp_path.glob("*.png"))


@pytest.mark.parametrize("sub", ["modes", "campbell", "response", "transient"])
def test_help_states_the_exit_codes_and_a_missing_model_exits_2(sub, tmp_path):
    r = _run("torsional", sub, "--help")
    assert r.exit_code == 0, r.output
    text = " ".join(r.output.split())
    assert "Exit status: 0 done; 2 invalid input" in text and "3 solver failure" in text
    extra = ["--torque", "shaft=motor,node=4,amplitude=1,order=1"] if sub == "response" else []
    r = _run("torsional", sub, tmp_path / "nope.toml", *extra)
    assert r.exit_code == 2 and "nope.toml" in r.stderr
