"""The audit commands ``gearrotor ucs`` and ``gearrotor stability``: JSON keys, agreement with
the library and the closed forms, verdicts on crafted models, bad input (exit 2, one line)."""

from __future__ import annotations

import json

import pytest
from cli_models import RPM, uniform_toml
from test_ucs import timoshenko_pinned_forward
from typer.testing import CliRunner

from gearrotor.analyses import ucs_map
from gearrotor.cli import app
from gearrotor.io import load_model


def invoke(*args):
    return CliRunner().invoke(app, [str(a) for a in args])


def ok_json(r) -> dict:
    assert r.exit_code == 0, (r.output, r.exception)
    return json.loads(r.stdout)


def one_line_error(r, *needles):
    assert r.exit_code == 2, (r.exit_code, r.output, r.exception)
    assert "Traceback" not in r.output
    assert r.stderr.startswith("error: ") and len(r.stderr.strip().splitlines()) == 1, r.stderr
    for n in needles:
        assert n in r.stderr, (n, r.stderr)


@pytest.fixture
def uniform(tmp_path):
    p = tmp_path / "uniform.toml"
    p.write_text(uniform_toml())
    return p


def test_ucs_json_is_the_library_map_and_meets_the_closed_form(uniform, tmp_path):
    """The command is a thin layer: its JSON is ucs_map's to_dict (same sweep); the rigid
    limit is the pinned-pinned Timoshenko forward critical (mesh of 10 elements: 1e-3, the
    cubic elements' discretisation error on the first mode is ~1e-5); the operating range and
    MCS come from the model, and the options override them."""
    png = tmp_path / "out" / "map.png"
    d = ok_json(
        invoke(
            "ucs",
            uniform,
            "--min-stiffness",
            "1e5 N/m",
            "--max-stiffness",
            "1e10",
            "--n-points",
            6,
            "--n-modes",
            2,
            "--format",
            "json",
            "--plot",
            png,
        )
    )
    lib = ucs_map(load_model(uniform), stiffness=(1e5, 1e10), n_stiffness=6, n_modes=2)
    want = lib.to_dict()
    for key in ("stiffness_N_per_m", "shafts", "intersections", "bearings"):
        assert d[key] == want[key]
    assert d["operating_range_rpm"] == pytest.approx([2700, 3000])
    assert d["max_continuous_speed_rpm"] == pytest.approx(3150)
    rigid = d["shafts"][0]["rigid_critical_speeds_rpm"][0] * RPM
    assert rigid == pytest.approx(timoshenko_pinned_forward(1.0, 0.05, 1), rel=1e-3)
    # the constant bearings meet every branch at their own stiffness, 1e7 N/m
    assert {x["stiffness_N_per_m"] for x in d["intersections"]} == {1e7}
    assert png.stat().st_size > 10_000
    d2 = ok_json(
        invoke(
            "ucs",
            uniform,
            "--n-points",
            3,
            "--n-modes",
            1,
            "--format",
            "json",
            "--operating-range",
            "1000,2000",
            "--mcs",
            "2100",
        )
    )
    assert d2["operating_range_rpm"] == pytest.approx([1000, 2000])
    assert d2["max_continuous_speed_rpm"] == pytest.approx(2100)


def test_ucs_table(uniform):
    r = invoke("ucs", uniform, "--n-points", 3, "--n-modes", 1)
    assert r.exit_code == 0, r.output
    assert "operating range 2700..3000 rpm" in r.stdout
    assert "maximum continuous speed 3150 rpm" in r.stdout
    assert "intersections" in r.stdout


@pytest.mark.parametrize(
    "args, needles",
    [
        (["--min-stiffness", "-1e6", "--max-stiffness", "1e9"], ["--min-stiffness"]),
        (["--min-stiffness", "1e6"], ["--min-stiffness/--max-stiffness"]),
        (["--min-stiffness", "1e9", "--max-stiffness", "1e6"], ["--max-stiffness"]),
        (["--min-stiffness", "3 m", "--max-stiffness", "1e9"], ["--min-stiffness", "3 m"]),
        (["--operating-range", "3000"], ["--operating-range"]),
        (["--operating-range", "3000,2000"], ["--operating-range"]),
        (["--operating-range", "2000,3500"], ["--operating-range", "MCS 3150"]),
        (["--mcs", "2900"], ["--mcs"]),
        (["--plot", "map.svg"], ["--plot", "map.svg"]),
        (["--format", "xml"], ["--format"]),
        (["--n-points", "1"], ["--n-points"]),
    ],
)
def test_ucs_bad_input(uniform, args, needles):
    one_line_error(invoke("ucs", uniform, *args), *needles)


def test_ucs_unwritable_plot_is_checked_first(uniform, tmp_path):
    """A figure path under a file: refused before the map is computed (no output)."""
    blocker = tmp_path / "a_file"
    blocker.write_text("")
    r = invoke("ucs", uniform, "--plot", blocker / "map.png")
    one_line_error(r, "--plot")
    assert r.stdout == ""
