"""Bad input gets a clear error naming file, field, value and expectation; nothing half-runs."""

import json
import subprocess
import sys
import tomllib

import numpy as np
import pytest

from gearrotor.analyses import modal
from gearrotor.errors import ModelError
from gearrotor.io import load_model, model_from_dict
from gearrotor.model import Train


@pytest.fixture()
def base(examples):
    return tomllib.loads((examples / "unity_gearbox.toml").read_text())


def _error(data, file="model.toml") -> str:
    with pytest.raises(ModelError) as exc:
        model_from_dict(data, file=file)
    return str(exc.value)


def test_unknown_key(base):
    base["shafts"][0]["sections"][0]["lenght"] = 1.0
    msg = _error(base)
    assert "model.toml" in msg and "shafts[0].sections[0].lenght" in msg
    assert "unknown key" in msg


def test_wrong_units(base):
    base["shafts"][0]["sections"][0]["length"] = "1.02 kg"
    msg = _error(base)
    assert "shafts[0].sections[0].length" in msg and "1.02 kg" in msg
    assert "expected a length" in msg


def test_unreadable_unit(base):
    base["meshes"][0]["stiffness"] = "3e7 N/zork"
    msg = _error(base)
    assert "meshes[0].stiffness" in msg and "3e7 N/zork" in msg


def test_gear_node_not_on_shaft(base):
    base["meshes"][0]["gear"]["node"] = 25
    msg = _error(base)
    assert "meshes[0].gear.node" in msg and "25" in msg and "0..20" in msg


def test_node_by_position(base):
    base["meshes"][0]["gear"] = {"shaft": "shaft1", "at": "0.51 m", "teeth": 30, "radius": "0.11 m"}
    t = model_from_dict(base)
    assert t.node_index(t.meshes[0].gear, "g") == (0, 10)
    base["meshes"][0]["gear"]["at"] = "0.5 m"
    msg = _error(base)
    assert "meshes[0].gear.at" in msg and "nearest nodes" in msg


def test_inconsistent_speed_set(base):
    base["shafts"][1]["speed"] = "6500 rpm"  # must be −6500 rpm for external gears
    msg = _error(base)
    assert "shafts[1].speed" in msg and "6500 rpm" in msg and "-6500 rpm" in msg


def test_unknown_shaft_and_disconnected_train(base):
    bad = json.loads(json.dumps(base))
    bad["bearings"][0]["shaft"] = "shaft9"
    assert "bearings[0].shaft" in _error(bad) and "shaft9" in _error(bad)
    base["meshes"] = []
    base["shafts"][1].pop("speed")
    msg = _error(base)
    assert "disconnected" in msg and "shaft2" in msg


def test_mesh_geometry_checks(base):
    bad = json.loads(json.dumps(base))
    bad["meshes"][0]["mate"]["radius"] = "0.2 m"  # radii no longer match the tooth ratio
    assert "pitch radii do not match" in _error(bad)
    bad = json.loads(json.dumps(base))
    bad["shafts"][1]["position"] = ["0.3 m", "0 m"]  # centre distance must be r1 + r2
    msg = _error(bad)
    assert "shafts[1].position" in msg and "0.22" in msg


def test_singular_mass_matrix_is_an_input_error():
    """A massless shaft with mass only at some nodes cannot be put in first-order form."""
    t = Train.model_validate(
        {
            "materials": {"m": {"E": 2e11, "density": 7800, "poisson": 0.3}},
            "shafts": [
                {
                    "name": "s",
                    "material": "m",
                    "sections": [
                        {
                            "length": 1.0,
                            "outer_diameter": 0.05,
                            "elements": 2,
                            "mass_outer_diameter": 0.01,
                            "mass_inner_diameter": 0.01,
                        }
                    ],
                    "disks": [{"node": 1, "mass": 10, "polar": 0.1, "transverse": 0.05}],
                }
            ],
            "bearings": [{"shaft": "s", "node": 0, "k": 1e7}, {"shaft": "s", "node": 2, "k": 1e7}],
        }
    )
    with pytest.raises(ModelError, match="singular model"):
        modal(t)


def test_overrides(examples):
    t = load_model(
        examples / "unity_gearbox.toml",
        {
            "meshes[0].stiffness": "6e7 N/m",
            "speed": "3000 rpm",
            "shafts.0.speed": "3000 rpm",
            "shafts.1.speed": "-3000 rpm",
        },
    )
    assert t.meshes[0].stiffness == 6e7
    assert t.speed == pytest.approx(3000 * np.pi / 30)
    with pytest.raises(
        ModelError, match=r"override index out of range .*0\.\.0 \(the model has 1\)"
    ):
        load_model(examples / "unity_gearbox.toml", {"meshes[3].stiffness": "1"})


def test_toml_syntax_error(tmp_path):
    p = tmp_path / "bad.toml"
    p.write_text("name = \n")
    with pytest.raises(ModelError, match="bad.toml: invalid TOML"):
        load_model(p)
    with pytest.raises(ModelError, match="model file not found"):
        load_model(tmp_path / "nope.toml")


def _cli(*args):
    return subprocess.run(
        [sys.executable, "-m", "gearrotor", *args], capture_output=True, text=True, timeout=120
    )


def test_cli_modal_json(examples):
    r = _cli(
        "modal",
        str(examples / "unity_gearbox.toml"),
        "--speed",
        "6500",
        "--max-frequency",
        "80000",
        "--format",
        "json",
    )
    assert r.returncode == 0, r.stderr
    d = json.loads(r.stdout)
    modes = d["modes"]
    f = [m["frequency_rpm"] for m in modes]
    assert f == sorted(f) and all(x > 0 for x in f) and max(f) <= 80000
    for m in modes:
        for key in (
            "index",
            "frequency_rpm",
            "frequency_hz",
            "log_dec",
            "damping_ratio",
            "whirl",
            "type",
        ):
            assert key in m
        assert m["frequency_hz"] == pytest.approx(m["frequency_rpm"] / 60)
    assert sum(m["overdamped"] for m in modes) == 7


def test_cli_bad_input_is_one_clear_line(tmp_path, examples):
    text = (
        (examples / "unity_gearbox.toml")
        .read_text()
        .replace("node = 10, teeth = 30", "node = 99, teeth = 30", 1)
    )
    p = tmp_path / "m.toml"
    p.write_text(text)
    r = _cli("modal", str(p), "--speed", "6500")
    assert r.returncode == 2
    assert "Traceback" not in r.stderr
    assert str(p) in r.stderr and "meshes[0].gear.node" in r.stderr and "99" in r.stderr
    assert r.stdout == ""  # nothing half-ran


def test_cli_modal_json_with_shapes(examples):
    r = _cli(
        "modal",
        str(examples / "unity_gearbox_single_shaft.toml"),
        "--max-frequency",
        "10000",
        "--format",
        "json",
        "--shapes",
    )
    assert r.returncode == 0, r.stderr
    m = [m for m in json.loads(r.stdout)["modes"] if not m["overdamped"]][0]
    shape = m["shape"]["shaft1"]
    x = np.array(shape["x"]["re"]) + 1j * np.array(shape["x"]["im"])
    y = np.array(shape["y"]["re"]) + 1j * np.array(shape["y"]["im"])
    # first bending mode of a symmetric shaft: largest at mid-span (node 10), normalised to 1
    assert np.argmax(np.abs(x) + np.abs(y)) == 10
    assert max(np.abs(x).max(), np.abs(y).max()) == pytest.approx(1.0)


def test_failed_layout_check_raises_every_time(base):
    """A model whose node check failed must not return a cached, unchecked layout later."""
    base["meshes"][0]["gear"]["node"] = 25
    t = Train.model_validate(base)
    for _ in range(2):
        with pytest.raises(ModelError, match="meshes\\[0\\].gear.node"):
            t.layout()
