"""Bearing input files, coefficient tables, the CLI function and plots."""

import json
import math
from pathlib import Path

import numpy as np
import pytest

from gearrotor.bearings import (
    BearingTable,
    Grid,
    SolverOptions,
    coefficients_table,
    load_bearing,
    load_table,
    parse_bearing,
    plain,
    save_table,
)
from gearrotor.cli.bearing import bearing_command, parse_load, parse_speed
from gearrotor.errors import ModelError

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "bearings"
SPEC_LOADS = [
    (2, -826),
    (100, -588),
    (995, 1605),
    (1991, 4043),
    (4978, 11352),
    (8959, 21098),
    (12940, 30848),
    (16921, 40594),
    (20902, 50341),
    (24883, 60087),
]
DEG = math.pi / 180


@pytest.mark.parametrize("path", sorted(EXAMPLES.glob("*.toml")), ids=lambda p: p.name)
def test_examples_load(path):
    case = load_bearing(path)
    assert case.bearing.pads and case.speed is not None and case.loads


def test_pressure_dam_example_is_spec_6_2():
    case = load_bearing(EXAMPLES / "pinion_3lobe_dam.toml")
    b = case.bearing
    assert (b.diameter, b.length, b.clearance) == pytest.approx((0.140, 0.130, 152.4e-6))
    assert b.viscosity == pytest.approx(0.0152)
    assert case.speed == pytest.approx(10800 * math.pi / 30)
    assert [p.reference_angle / DEG for p in b.pads] == pytest.approx([52.5, 172.5, 292.5])
    assert all(
        p.arc == pytest.approx(97 * DEG) and p.preload == 0.33 and p.offset == 0.5 for p in b.pads
    )
    assert b.pads[0].pocket is None
    for p in b.pads[1:]:
        assert (p.pocket.arc, p.pocket.width, p.pocket.depth) == pytest.approx(
            (60 * DEG, 0.090, 0.22e-3)
        )
    assert case.loads == tuple((float(a), float(b_)) for a, b_ in SPEC_LOADS)
    v = load_bearing(EXAMPLES / "pinion_3lobe_dam_minclearance.toml").bearing
    assert (v.diameter, v.clearance, v.pads[0].preload) == pytest.approx((0.13975, 119.9e-6, 0.39))
    assert v.pads[1].pocket.depth == pytest.approx(0.18e-3)


def _doc(**over):
    d = {
        "name": "t",
        "type": "multilobe",
        "diameter": "100 mm",
        "length": "50 mm",
        "clearance": "100 um",
        "viscosity": "0.02 Pa*s",
        "speed": "3000 rpm",
        "pivots": ["90 deg", "270 deg"],
        "arc": "150 deg",
        "preload": 0.2,
    }
    d.update(over)
    return {"bearing": d}


@pytest.mark.parametrize(
    "over, field, words",
    [
        ({"diamter": "1 m"}, "bearing.diamter", "unknown key"),
        ({"diameter": "100 kg"}, "bearing.diameter", "length"),
        ({"arc": 150}, "bearing.arc", "deg"),
        ({"type": "lemon"}, "bearing.type", "offset_halves | elliptical"),
        (
            {"pockets": [{"pads": [3], "arc": "30 deg", "width": "20 mm", "depth": "0.1 mm"}]},
            "bearing.pockets[0].pads",
            "pad numbers 1..2",
        ),
        (
            {"pockets": [{"pads": [1], "arc": "30 deg", "width": "80 mm", "depth": "0.1 mm"}]},
            "bearing.pads[0].pocket.width",
            "length",
        ),
        ({"preload": 1.2}, "bearing.preload", "preload"),
    ],
)
def test_input_errors_name_file_field_value_expected(over, field, words):
    with pytest.raises(ModelError) as info:
        parse_bearing(_doc(**over), "my.toml")
    err = info.value
    assert err.file == "my.toml"
    assert err.field.startswith(field), err.field
    text = str(err)
    assert "my.toml" in text and words in text, text


def test_load_bearing_file_errors(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text('[bearing]\ntype = "plain"\ndiameter = "0.1 m"\n')
    with pytest.raises(ModelError, match="bad.toml") as info:
        load_bearing(bad)
    assert info.value.field.startswith("bearing.")
    with pytest.raises(ModelError, match="not found"):
        load_bearing(tmp_path / "missing.toml")


@pytest.mark.parametrize("suffix", [".csv", ".toml"])
def test_coefficients_table_roundtrip_and_rotor_table(tmp_path, suffix):
    b = plain(0.1, 0.05, 1e-4, 0.02, name="plain, test")
    opts = SolverOptions(grid=Grid(24, 6))
    table = coefficients_table(b, (0.0, -2000.0), [3000.0, 6000.0, 9000.0], options=opts)
    assert isinstance(table, BearingTable) and table.speed_rpm.tolist() == [3000, 6000, 9000]
    assert np.all(table.kxx > 0) and np.all(table.cyy > 0)
    # higher speed → lower eccentricity
    assert np.all(np.diff(table.eccentricity_ratio) < 0)
    path = save_table(table, tmp_path / f"t{suffix}")
    back = load_table(path)
    np.testing.assert_array_equal(back.values(), table.values())
    np.testing.assert_array_equal(back.speed_rpm, table.speed_rpm)
    assert back.load == (0.0, -2000.0) and back.name == "plain, test"
    rotor = back.to_coefficient_table()
    np.testing.assert_allclose(rotor.at(6000 * math.pi / 30), table.values()[1])


def test_cli_parsers():
    assert parse_load("2,-826") == (2.0, -826.0)
    assert parse_load("2 kN, -3 kN") == (2000.0, -3000.0)
    assert parse_speed("10800") == pytest.approx(10800 * math.pi / 30)
    assert parse_speed("-50 Hz") == pytest.approx(-100 * math.pi)
    with pytest.raises(ModelError, match="--load"):
        parse_load("1,2,3")


def test_bearing_command_json_and_plots(tmp_path, capsys):
    res = bearing_command(
        EXAMPLES / "plain_ld1.toml", load="0,-5000", speed="3000", fmt="json", plot=tmp_path
    )
    doc = json.loads(capsys.readouterr().out)
    assert doc["cases"][0]["fy_N"] == -5000.0
    assert doc["cases"][0]["kxx_N_per_m"] == pytest.approx(res[0].K[0, 0])
    assert (tmp_path / "pressure_case01.png").stat().st_size > 10_000
    assert (tmp_path / "locus.png").stat().st_size > 10_000


def test_bearing_command_all_cases_table(capsys):
    res = bearing_command(EXAMPLES / "pinion_3lobe_dam.toml", fmt="table")
    out = capsys.readouterr().out
    assert len(res) == 10 and "kxx N/m" in out and out.count("\n") > 20
    ecc = [r.equilibrium.eccentricity_ratio for r in res]
    assert ecc[-1] > ecc[2] > 0  # heavier generator load → larger eccentricity


def test_load_speed_sweep_and_mixed_sign_table():
    from gearrotor.bearings import load_speed_sweep

    b = plain(0.1, 0.05, 1e-4, 0.02)
    opts = SolverOptions(grid=Grid(24, 6))
    light, heavy = load_speed_sweep(b, [(0.0, -1000.0), (0.0, -3000.0)], [3000, 6000], options=opts)
    assert light.load == (0.0, -1000.0) and np.all(heavy.kyy > light.kyy)
    both = coefficients_table(b, (0.0, -1000.0), [-3000, 3000], options=opts)
    # reversed rotation mirrors a plain bearing: kxy changes sign, kxx does not
    assert both.kxy[0] == pytest.approx(-both.kxy[1], rel=1e-6)
    assert both.kxx[0] == pytest.approx(both.kxx[1], rel=1e-6)
    with pytest.raises(ModelError, match="one sign"):
        both.to_coefficient_table()
