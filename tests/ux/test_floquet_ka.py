"""Issue 14 item 1: a Ka/Kg that cannot act is refused before anything runs; one that acts says
the law it used; the chart draws the table's neutral band."""

from __future__ import annotations

import subprocess
import sys

import pytest

from gearrotor import load_model
from gearrotor.analyses.lateral.floquet import check_ka_ratio
from gearrotor.analyses.transient import build_system
from gearrotor.errors import ModelError


def test_ka_refused_when_the_law_has_no_terms(examples):
    # the flagship's mesh has variation.terms = 0: Ka 0, 0.25 and 0.5 gave identical tables
    system = build_system(load_model(examples / "unity_gearbox.toml"))
    check_ka_ratio(system, 0.0)  # Ka = 0 is what the law does anyway: allowed
    with pytest.raises(ModelError, match=r"variation\.terms.*terms=5"):
        check_ka_ratio(system, 0.25)


def test_cli_refuses_in_one_line_before_running(examples):
    p = subprocess.run(
        [
            sys.executable,
            "-m",
            "gearrotor",
            "floquet",
            str(examples / "unity_gearbox.toml"),
            "--ka",
            "0,0.25",
        ],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert p.returncode == 2
    assert p.stdout == ""  # nothing ran (the Ka = 0 case is not printed first)
    assert len(p.stderr.strip().splitlines()) == 1
    assert "meshes[0].variation.terms" in p.stderr


def test_law_used_is_reported(examples):
    from gearrotor.analyses.lateral.floquet import floquet

    train = load_model(
        examples / "unity_gearbox.toml",
        {"meshes[0].variation.terms": "3", "meshes[0].variation.contact_ratio": "1.6"},
    )
    res = floquet(build_system(train), ka_ratio=0.25, cutoff=1500.0)
    (law,) = res.to_dict()["mesh_laws"]
    assert law == {
        "mesh": "mesh",
        "law": "fourier",
        "ka_ratio": 0.25,
        "contact_ratio": 1.6,
        "terms": 3,
    }
