"""Inputs of pad dynamics (issue 24): one-line errors naming the file, the field, the value and
what was expected, before anything runs (exit status 2)."""

import subprocess
import sys

import pytest
from pad_models import write

from gearrotor.assembly import assemble
from gearrotor.errors import ModelError


@pytest.mark.parametrize(
    "extra, field",
    [
        ('fluid_film.pivot_stiffness = "0 N/m"', "fluid_film.pivot_stiffness"),
        ('fluid_film.pivot_stiffness = "-1e9 N/m"', "fluid_film.pivot_stiffness"),
        ('fluid_film.pad_inertia = "0 kg*m^2"', "fluid_film.pad_inertia"),
        ('fluid_film.pad_mass = "-2 kg"', "fluid_film.pad_mass"),
    ],
)
def test_bad_pad_values_are_one_line_errors(tmp_path, extra, field):
    with pytest.raises(ModelError) as exc:
        write(tmp_path, extra=extra)
    msg = str(exc.value)
    assert "\n" not in msg and field in msg and "greater than 0" in msg


def test_pad_dynamics_needs_pad_inertia(tmp_path):
    train = write(tmp_path, inertia=0.0)
    with pytest.raises(ModelError, match="pad_inertia") as exc:
        assemble(train)
    assert "bearings[0].fluid_film.pad_inertia" in str(exc.value)
    assert "\n" not in str(exc.value)


def test_flexible_pivot_needs_pad_mass(tmp_path):
    train = write(tmp_path, extra='fluid_film.pivot_stiffness = "1e9 N/m"\nfluid_film.pad_mass = 1')
    assert assemble(train).n_dof == 42 + 16  # with a mass it assembles
    train = write(tmp_path, extra='fluid_film.pivot_stiffness = "1e9 N/m"')
    (tmp_path / "pad.toml").write_text(
        (tmp_path / "pad.toml").read_text().replace('pad_mass = "0.4 kg"', "")
    )
    with pytest.raises(ModelError, match="pad_mass"):
        assemble(train)


def test_pad_dynamics_needs_tilting_pads(tmp_path, examples):
    train = write(tmp_path)
    (tmp_path / "pad.toml").write_text((examples / "bearings" / "plain_ld1.toml").read_text())
    with pytest.raises(ModelError, match="pad dynamics needs a tilting-pad bearing"):
        assemble(train)


def test_cli_exit_status_2_on_zero_pivot_stiffness(tmp_path):
    write(tmp_path)
    r = subprocess.run(
        [
            sys.executable,
            "-m",
            "gearrotor",
            "modal",
            str(tmp_path / "m.toml"),
            "--set",
            "bearings[1].fluid_film.pivot_stiffness=0",
        ],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert r.returncode == 2
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1
    assert "m.toml" in lines[0] and "bearings[1].fluid_film.pivot_stiffness" in lines[0]
