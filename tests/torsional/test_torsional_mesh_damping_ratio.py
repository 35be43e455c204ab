"""What a mesh ``damping_ratio`` means in the torsional analyses, and where each mode's damping
comes from (issue 22: the example's mesh ``damping_ratio = 0.02`` was read off ζ 0.71 at 673 Hz
and ζ 0.20 at 741 Hz, which are the couplings' dampers on the coupling-hub modes).

Definition (docs/torsional.md, SPEC 2.2 "mesh damping (coefficient or target damping ratio)"):
the ratio is the mesh damper's share of critical damping on the *mesh mode*, the mode with the
largest share of its strain energy in the mesh: ``c = 2 ζ ω_i / (w·φ_i)²`` adds exactly 2 ζ ω_i
to that mode's modal damping. Checks: the mesh damper's modal damping ratio on that mode is ζ
(to round-off); with no other damping the complex eigenvalue of that mode has ζ to within the
non-proportional coupling of the mesh damper to the neighbouring modes (second order in the
off-diagonal modal damping; 1 % leaves room); and a mode's ``damping_sources`` name the damper
that gives it its damping.
"""

from __future__ import annotations

import json

import numpy as np
import pytest
from typer.testing import CliRunner

from gearrotor.analyses.torsional import torsional_modes
from gearrotor.cli import app
from gearrotor.io import load_model, parse_overrides

EXAMPLE = "examples/motor_gearbox_compressor.toml"


@pytest.fixture(scope="module")
def modes(examples):
    return torsional_modes(load_model(examples / "motor_gearbox_compressor.toml"))


def test_mesh_mode_gets_the_ratio_asked_for(modes):
    (mm,) = modes.mesh_modes
    assert mm["mesh"] == "gear mesh" and mm["damping_ratio"] == 0.02
    assert mm["mesh_damping_ratio_of_mode"] == pytest.approx(0.02, rel=1e-9)
    # the mode with the largest mesh strain-energy share of this train: 67 %, 1330 Hz
    assert mm["mesh_strain_energy_fraction"] == pytest.approx(0.674, abs=0.005)
    assert mm["frequency_hz"] == pytest.approx(1330.5, abs=0.5)
    assert mm["listed"]  # all modes by default in Python (the command keeps 12: its note)


def test_only_the_mesh_damper_gives_the_mesh_mode_its_ratio(examples):
    """Without the couplings' dampers the complex eigenvalue of the mesh mode has ζ = 0.02."""
    train = load_model(
        examples / "motor_gearbox_compressor.toml",
        parse_overrides(["couplings[0].ctz=0", "couplings[1].ctz=0"]),
    )
    res = torsional_modes(train, n_modes=20)
    (mm,) = res.mesh_modes
    assert mm["listed"]
    assert res.damping_ratio[mm["index"]] == pytest.approx(0.02, rel=0.01)


def test_the_heavily_damped_hub_modes_are_the_couplings(modes):
    """ζ 0.71 at 673 Hz and 0.20 at 741 Hz: the low- and high-speed couplings' ctz on their
    hubs; the mesh damper gives them ~1e-6 and ~1e-3."""
    d = modes.to_dict()["modes"]
    f = np.array([m["frequency_hz"] for m in d])
    i9, i10 = int(np.argmin(abs(f - 673.06))), int(np.argmin(abs(f - 741.30)))
    assert d[i9]["damping_ratio"] == pytest.approx(0.71, abs=0.01)
    assert next(iter(d[i9]["damping_sources"])) == "coupling LS coupling"
    assert d[i10]["damping_ratio"] == pytest.approx(0.20, abs=0.01)
    assert next(iter(d[i10]["damping_sources"])) == "coupling HS coupling"
    assert d[i9]["damping_sources"]["mesh gear mesh"] < 1e-5
    assert d[i10]["damping_sources"]["mesh gear mesh"] < 2e-3
    # light damping: the sources add up to the complex eigenvalue's ζ (mode 1: 2.4 %)
    assert sum(d[1]["damping_sources"].values()) == pytest.approx(d[1]["damping_ratio"], rel=0.02)


def test_cli_says_which_mode_the_ratio_refers_to(examples):
    model = str(examples / "motor_gearbox_compressor.toml")
    r = CliRunner().invoke(app, ["torsional", "modes", model])
    assert r.exit_code == 0, r.output
    assert "damping_ratio 0.02 is the mesh damper's ζ on its mesh mode, mode 17" in r.output
    assert "not listed: --n-modes 18" in r.output
    r = CliRunner().invoke(
        app,
        ["torsional", "modes", model, "--format", "json"],
    )
    d = json.loads(r.output)
    assert d["mesh_damping"][0]["index"] == 17
    assert d["mesh_damping"][0]["damping_N_s_per_m"] == pytest.approx(3.19e4, rel=0.01)
