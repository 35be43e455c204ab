"""Seal files and the ``gearrotor seal`` command: the example files, the JSON keys of the issue,
one-line errors naming file, field, value and expectation (exit 2) for bad inputs."""

from __future__ import annotations

import json
import math
import shutil

import pytest
from typer.testing import CliRunner

from doc_examples import ROOT, doc_commands
from gearrotor.cli import app
from gearrotor.errors import ModelError
from gearrotor.seals import (
    COEFFICIENT_KEYS,
    AnnularSeal,
    LabyrinthSeal,
    coolprop_available,
    load_seal,
    parse_seal,
)

EXAMPLES = ROOT / "examples" / "seals"
LAB_FILE = EXAMPLES / "labyrinth_interlocking.toml"
LAB_DOC = {
    "type": "labyrinth",
    "shaft_diameter": "145 mm",
    "radial_clearance": "0.3 mm",
    "n_teeth": 16,
    "pitch": "3.175 mm",
    "tooth_height": "3.175 mm",
    "tooth_width": "0.1524 mm",
    "teeth_on": "stator",
    "inlet_pressure": "3.08 bar",
    "outlet_pressure": "94.3 kPa",
    "inlet_temperature": "10 degC",
    "preswirl": 0.5,
    "gas": {"molar_mass": 28.97, "gamma": 1.4, "viscosity": "1.8e-5 Pa*s"},
}


def invoke(*args):
    return CliRunner().invoke(app, [str(a) for a in args])


@pytest.mark.parametrize("path", sorted(EXAMPLES.glob("*.toml")), ids=lambda p: p.name)
def test_example_files_load(path):
    doc = path.read_text()
    if "shafts" in doc:  # the rotor model of the example
        return
    if "composition" in doc and not coolprop_available():
        pytest.skip("CoolProp (the seals extra) is not installed")
    assert isinstance(load_seal(path), LabyrinthSeal | AnnularSeal)


def test_units_and_plain_numbers():
    seal = parse_seal(LAB_DOC)
    assert seal.inlet_pressure == pytest.approx(308000.0)
    assert seal.inlet_temperature == pytest.approx(283.15)
    assert seal.fluid.molar_mass == 28.97  # kg/kmol
    assert seal.shaft_diameter == pytest.approx(0.145)


def test_json_has_the_issue_keys():
    r = invoke("seal", LAB_FILE, "--speed", "8000", "--format", "json")
    assert r.exit_code == 0, r.output
    doc = json.loads(r.stdout)
    assert (
        set(doc["coefficients"])
        == set(COEFFICIENT_KEYS)
        == {
            "kxx_N_per_m",
            "kxy_N_per_m",
            "kyx_N_per_m",
            "kyy_N_per_m",
            "cxx_Ns_per_m",
            "cxy_Ns_per_m",
            "cyx_Ns_per_m",
            "cyy_Ns_per_m",
        }
    )
    assert doc["leakage_kg_per_s"] > 0
    assert doc["whirl_frequency_hz"] == pytest.approx(8000 / 60)
    r2 = invoke("seal", LAB_FILE, "--speed", "8000", "--frequency", "50", "--format", "json")
    assert json.loads(r2.stdout)["whirl_frequency_hz"] == pytest.approx(50.0)


def test_table_and_plots(tmp_path):
    r = invoke("seal", EXAMPLES / "hole_pattern.toml", "--speed", "5000", "--plot", tmp_path / "p")
    assert r.exit_code == 0, r.output
    assert "leakage" in r.stdout and "kxx N/m" in r.stdout
    for name in (
        "distribution.png",
        "coefficients_vs_speed.png",
        "coefficients_vs_frequency.png",
        "seal.json",
    ):
        assert (tmp_path / "p" / name).stat().st_size > 0


def _one_line(r, *needles):
    assert r.exit_code == 2, (r.exit_code, r.output)
    assert r.stderr.startswith("error: ") and len(r.stderr.strip().splitlines()) == 1, r.stderr
    for n in needles:
        assert n in r.stderr, (n, r.stderr)


def _toml(doc: dict) -> str:
    lines, tables = [], []
    for k, v in doc.items():
        if isinstance(v, dict):
            tables.append((k, v))
        else:
            lines.append(f"{k} = {json.dumps(v)}")
    for k, v in tables:
        lines.append(f"[{k}]")
        lines += [f"{kk} = {json.dumps(vv)}" for kk, vv in v.items()]
    return "\n".join(lines) + "\n"


@pytest.mark.parametrize(
    ("change", "needles"),
    [
        ({"radial_clearance": "-0.3 mm"}, ["radial_clearance", "-0.3 mm", "greater than 0"]),
        ({"outlet_pressure": "4 bar"}, ["outlet_pressure", "400000 Pa", "outlet_pressure <"]),
        ({"outlet_pressure": "3.08 bar"}, ["outlet_pressure", "outlet_pressure <"]),
        ({"n_teeth": 0}, ["n_teeth", "0", "greater than or equal to 1"]),
        ({"n_teeth": 2.0}, ["n_teeth", "2.0", "valid integer"]),
        ({"outlet_pressure": 0}, ["outlet_pressure", "greater than 0"]),
        ({"teeth_on": "shaft"}, ["teeth_on", "'shaft'", "stator"]),
        ({"type": "brush"}, ["type", "'brush'", "labyrinth | liquid_annular"]),
        ({"tooth_width": "4 mm"}, ["tooth_width", "tooth_width < pitch"]),
        ({"pich": "3 mm"}, ["unknown key 'pich'", "did you mean 'pitch'"]),
        ({"inlet_temperature": "-5 K"}, ["inlet_temperature", "greater than 0"]),
        ({"gas": {"gamma": 1.4}}, ["gas", "molar_mass", "viscosity"]),
        ({"gas": {"gamma": 0.9, "molar_mass": 29, "viscosity": 1e-5}}, ["gas.gamma", "0.9"]),
    ],
)
def test_bad_inputs_are_one_line(tmp_path, change, needles):
    bad = tmp_path / "bad_seal.toml"
    bad.write_text(_toml({**LAB_DOC, **change}))
    r = invoke("seal", bad, "--speed", "8000")
    _one_line(r, str(bad), *needles)


def test_annular_seal_choking_is_an_input_error(tmp_path):
    text = (EXAMPLES / "hole_pattern.toml").read_text()
    bad = tmp_path / "choked.toml"
    bad.write_text(
        text.replace('length = "76.2 mm"', 'length = "10 mm"').replace(
            'outlet_pressure = "0.8235 MPa"', 'outlet_pressure = "0.3 MPa"'
        )
    )
    _one_line(invoke("seal", bad, "--speed", "5000"), "outlet_pressure", "chokes at the seal exit")


def test_missing_file_and_rotor_model(tmp_path):
    _one_line(invoke("seal", tmp_path / "nope.toml", "--speed", "100"), "nope.toml", "not found")
    _one_line(
        invoke("seal", ROOT / "examples" / "unity_gearbox.toml", "--speed", "100"),
        "rotor model file, not a seal file",
    )
    r = invoke("seal", LAB_FILE, "--speed", "-5")
    assert r.exit_code == 2 and "--speed" in r.stderr


def test_composition_without_coolprop_is_one_line(monkeypatch):
    import sys

    monkeypatch.setitem(sys.modules, "CoolProp", None)
    monkeypatch.setitem(sys.modules, "CoolProp.CoolProp", None)
    doc = {**LAB_DOC, "gas": {"composition": {"Nitrogen": 0.79, "Oxygen": 0.21}}}
    with pytest.raises(ModelError, match=r"gas.composition.*CoolProp.*gearrotor\[seals\]"):
        parse_seal(doc, "x.toml")


def test_composition_through_coolprop():
    pytest.importorskip("CoolProp")
    doc = {
        **LAB_DOC,
        "gas": {"composition": {"Nitrogen": 0.7812, "Oxygen": 0.2096, "Argon": 0.0092}},
    }
    seal = parse_seal(doc)
    # air at 3 bar and 10 °C: Z = 0.999, γ = 1.40, μ = 1.77e-5 Pa s
    assert seal.fluid.gamma == pytest.approx(1.40, abs=0.01)
    assert float(seal.fluid.viscosity(3e5)) == pytest.approx(1.77e-5, rel=0.02)
    with pytest.raises(ModelError, match="unknown fluid"):
        parse_seal({**LAB_DOC, "gas": {"composition": {"Unobtainium": 1.0}}}, "x.toml")


def test_docs_commands_run(tmp_path):
    """Every ``gearrotor`` command of docs/seals.md runs as printed (from the repository root;
    output directories moved to a temporary folder)."""
    cmds = doc_commands(ROOT / "docs" / "seals.md")
    assert len(cmds) >= 4
    for args, _ in cmds:
        files = [ROOT / a for a in args if a.endswith(".toml")]
        args = [str(tmp_path / a) if a.startswith("out/") else a for a in args]
        args = [str(ROOT / a) if a.startswith("examples/") else a for a in args]
        real_gas = any("composition" in f.read_text() for f in files if f.exists())
        if real_gas and not coolprop_available():
            continue
        r = invoke(*args)
        assert r.exit_code == 0, (args, r.output)
    shutil.rmtree(tmp_path, ignore_errors=True)


def test_speed_is_required():
    r = invoke("seal", LAB_FILE)
    assert r.exit_code == 2 and "--speed" in r.output


def test_zero_speed_gives_zero_cross_coupling_without_preswirl():
    seal = parse_seal({**LAB_DOC, "preswirl": 0.0})
    from gearrotor.seals import seal_coefficients

    r = seal_coefficients(seal, 0.0, whirl=2 * math.pi * 50)
    assert r.kxy == 0.0 or abs(r.kxy) < 1e-9 * abs(r.kxx)
