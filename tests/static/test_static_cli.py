"""``gearrotor static`` and ``--operating-point``: JSON as in issue 11, the same numbers in the
table, JSON and figures' data, bad input checked before anything runs (exit 2, one line)."""

import json

import pytest
from typer.testing import CliRunner

from gearrotor.cli import app

STEAM = "steam_turbine_gearbox.toml"


def invoke(*args):
    return CliRunner().invoke(app, [str(a) for a in args])


def test_static_json_one_point(examples):
    r = invoke("static", examples / STEAM, "--operating-point", "LC10", "--format", "json")
    assert r.exit_code == 0, r.output
    d = json.loads(r.stdout)
    assert d["operating_point"] == "LC10"
    b = d["bearings"][0]
    for key in (
        "name",
        "shaft",
        "node",
        "force_N",
        "eccentricity_ratio",
        "attitude_deg",
        "min_film_um",
        "peak_pressure_MPa",
        "power_loss_kW",
    ):
        assert key in b
    assert len(b["force_N"]) == 3
    m = d["meshes"][0]
    for key in ("name", "tangential_N", "separating_N", "axial_N", "misalignment_um"):
        assert key in m
    s = d["shafts"][0]
    for key in ("z_m", "deflection_y_um", "moment_x_Nm", "torque_Nm", "von_mises_MPa"):
        assert key in s
    # LC10: 12.5 MW at 10,800 rpm through the 653.2/7.2 mm pinion: Ft = P/(Ω r), half per helix
    ft = 12.5e6 / (10800 * 3.141592653589793 / 30) / (0.6532 / 7.2)
    assert sum(mm["tangential_N"] for mm in d["meshes"]) == pytest.approx(ft, rel=1e-9)


def test_static_all_with_plots(examples, tmp_path):
    out = tmp_path / "figs"
    r = invoke("static", examples / STEAM, "--all", "--plot", out)
    assert r.exit_code == 0, r.output
    assert (out / "bearing_loads.png").stat().st_size > 0
    assert (out / "static_LC10.png").stat().st_size > 0
    saved = json.loads((out / "static.json").read_text())
    assert [p["operating_point"] for p in saved["operating_points"]][-1] == "LC10"
    # the table shows the number the JSON holds
    fy = saved["operating_points"][-1]["bearings"][0]["force_N"][1]
    assert f"{fy:.6g}" in r.stdout
    assert not list(out.glob("*.tmp*"))


@pytest.mark.parametrize(
    ("args", "needle"),
    [
        (("--operating-point", "LC11"), "--operating-point"),
        (("--all", "--operating-point", "LC1"), "--all"),
        (("--format", "xml"), "--format"),
        (("--set", "operating_points[0].drive.shaft=nope"), "operating_points[0].drive.shaft"),
        (("--set", "operating_points[1].speed=0 rpm"), "operating_points[1].power"),
    ],
)
def test_static_bad_input(examples, args, needle):
    r = invoke("static", examples / STEAM, *args)
    assert r.exit_code == 2, r.output
    assert r.stderr.startswith("error: ") and len(r.stderr.strip().splitlines()) == 1
    assert needle in r.stderr


def test_plot_dir_checked_before_running(examples, tmp_path):
    blocker = tmp_path / "file"
    blocker.write_text("x")
    r = invoke("static", examples / STEAM, "--plot", blocker / "sub")
    assert r.exit_code == 2 and "--plot" in r.stderr


def test_modal_operating_point_option(examples):
    r = invoke(
        "modal",
        examples / STEAM,
        "--operating-point",
        "LC10",
        "--max-frequency",
        "20000",
        "--format",
        "json",
    )
    assert r.exit_code == 0, r.output
    r = invoke("campbell", examples / STEAM, "--operating-point", "nope")
    assert r.exit_code == 2 and "--operating-point" in r.stderr
