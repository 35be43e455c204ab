"""A model's gear mesh from its tooth geometry: the mean stiffness in every linear analysis,
the TVMS and transmission error in the transient's law, the checks between the geometry and
the mesh's kinematics, gear-pair files (relative paths, one-line errors), and
``gearrotor mesh``."""

from __future__ import annotations

import json
import shutil

import numpy as np
import pytest
from typer.testing import CliRunner

from gearrotor import load_model
from gearrotor.assembly import assemble
from gearrotor.cli import app
from gearrotor.errors import ModelError
from gearrotor.gears import load_gear_pair, mesh_curves

RIG = "gears/spur_rig.toml"


def run(*args):
    return CliRunner().invoke(app, [str(a) for a in args])


def test_mean_stiffness_is_the_mesh_stiffness(examples):
    train = load_model(examples / RIG)
    curves = mesh_curves(load_gear_pair(examples / "gears/spur_50_50.toml"))
    asm = assemble(train)
    assert asm.meshes[0].stiffness == pytest.approx(curves.mean_stiffness, rel=1e-12)


def test_transient_law_is_the_loaded_mesh(examples):
    """The transient's stiffness table is the TVMS (20 harmonics), its transmission error
    e = STE − F/k: at the operating force the law's static deflection k⁻¹F + e is the STE."""
    from gearrotor.analyses.transient.equations import build_system
    from gearrotor.analyses.transient.mesh import stiffness

    train = load_model(examples / RIG)
    law = build_system(train).meshes[0]
    c = mesh_curves(load_gear_pair(examples / "gears/spur_50_50.toml"))
    assert law.has_table and law.kg == pytest.approx(c.mean_stiffness, rel=1e-12)
    # the pinion (gear i) turns +: τ = φ/2π
    phi = 2 * np.pi * c.position
    k = stiffness(law, phi)
    s = np.arange(1, len(law.te) + 1)
    e = law.te[:, 0] @ np.cos(np.outer(s, phi)) + law.te[:, 1] @ np.sin(np.outer(s, phi))
    ste = c.force / k + e
    ste_mean_free = c.ste - c.fourier(c.ste - c.force / c.stiffness)[0].real
    # away from the jumps the 20-harmonic law reproduces the loaded STE (less its mean offset)
    assert np.median(np.abs(ste - ste_mean_free)) < 0.02 * np.ptp(c.ste)


def test_geometry_must_match_the_mesh(examples, tmp_path):
    text = (examples / RIG).read_text()
    for old, new, field in (
        ("teeth = 50, radius", "teeth = 52, radius", "teeth"),
        ('pressure_angle = "20 deg"', 'pressure_angle = "22 deg"', "pressure_angle"),
        ('radius = "0.075 m"', 'radius = "0.08 m"', "radius"),
    ):
        src = tmp_path / f"m_{field}.toml"
        shutil.copy(examples / "gears/spur_50_50.toml", tmp_path / "spur_50_50.toml")
        src.write_text(text.replace(old, new, 1 if field == "pressure_angle" else 2))
        with pytest.raises(ModelError) as exc:
            assemble(load_model(src))
        msg = str(exc.value)
        assert "\n" not in msg and field in (exc.value.field or ""), msg


def test_stiffness_and_geometry_exclude_each_other(examples, tmp_path):
    text = (examples / RIG).read_text()
    shutil.copy(examples / "gears/spur_50_50.toml", tmp_path / "spur_50_50.toml")
    cases = {
        "both": ("damping_ratio = 0.03", 'damping_ratio = 0.03\nstiffness = "1e9 N/m"'),
        "ka": ("damping_ratio = 0.03", "damping_ratio = 0.03\nvariation = { ka_ratio = 0.2 }"),
    }
    for name, (old, new) in cases.items():
        src = tmp_path / f"{name}.toml"
        src.write_text(text.replace(old, new))
        with pytest.raises(ModelError) as exc:
            load_model(src)
        assert "\n" not in str(exc.value) and "meshes[0]" in str(exc.value)
    # the square wave stays an option: Kg from the geometry, the Fourier law of `variation`
    src = tmp_path / "sq.toml"
    src.write_text(
        text.replace(
            "damping_ratio = 0.03",
            'damping_ratio = 0.03\nexcitation = "square_wave"\n'
            "variation = { ka_ratio = 0.2, contact_ratio = 1.71, terms = 5 }",
        )
    )
    from gearrotor.analyses.transient.equations import build_system

    law = build_system(load_model(src)).meshes[0]
    assert not law.has_table and law.ka == pytest.approx(0.2 * law.kg)


def test_missing_gear_file_names_the_field(examples, tmp_path):
    src = tmp_path / "m.toml"
    src.write_text((examples / RIG).read_text())
    with pytest.raises(ModelError) as exc:
        load_model(src)
    assert exc.value.field == "meshes[0].geometry.file" and "not found" in str(exc.value)


def test_model_json_without_geometry_unchanged(examples):
    """Meshes without a geometry serialise as before (study keys, checkpoint fingerprints)."""
    train = load_model(examples / "unity_gearbox.toml")
    d = train.model_dump()["meshes"][0]
    assert "geometry" not in d and "excitation" not in d and "stiffness" in d


def test_mesh_command_json_and_plots(examples, tmp_path):
    r = run("mesh", examples / "gears/spur_50_50.toml", "--format", "json", "--torque", "0.2 kN*m")
    assert r.exit_code == 0, r.output
    doc = json.loads(r.output)
    for key in ("mean_stiffness_N_per_m", "max_stiffness_N_per_m", "min_stiffness_N_per_m",
                "contact_ratio", "curves", "ste_harmonics"):  # fmt: skip
        assert key in doc
    assert doc["torque_N_m"] == pytest.approx(200.0)
    assert len(doc["ste_harmonics"]) == 20
    r = run("mesh", examples / "gears/spur_50_50.toml", "--plot", tmp_path / "p")
    assert r.exit_code == 0, r.output
    assert {p.name for p in (tmp_path / "p").iterdir()} == {
        "mesh_cycle.png",
        "harmonics.png",
        "mesh.json",
    }


@pytest.mark.parametrize(
    ("text", "words"),
    [
        ("module = '3 mm'\nteeth = [12, 40]\npressure_angle = '20 deg'\nface_width = '20 mm'\n"
         "E = 2e11\npoisson = 0.3\ntorque = 10", "undercut"),
        ("module = '3 mm'\nteeth = [30, 40]\npressure_angle = '20 deg'\nface_widht = '20 mm'\n",
         "did you mean 'face_width'"),
        ("module = '3 mm'\nteeth = [30, 40]\npressure_angle = '20 deg'\nface_width = '20 mm'\n"
         "E = 2e11\npoisson = 0.3\n", "operating torque"),
        ("module = '-3 mm'\n", "module"),
    ],
)  # fmt: skip
def test_mesh_command_one_line_errors(tmp_path, text, words):
    f = tmp_path / "pair.toml"
    f.write_text(text)
    r = run("mesh", f)
    assert r.exit_code == 2, r.output
    lines = [x for x in r.output.splitlines() if x.strip()]
    assert len(lines) == 1 and str(f) in lines[0] and words in lines[0], r.output
