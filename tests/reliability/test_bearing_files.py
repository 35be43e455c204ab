"""Generated corpus of bad bearing files (issue 17): misspelt keys are named with the likely
intended key, a pivot offset outside 0..1, more than 360 deg of pads and a Reynolds grid too
large for memory are refused before the solver runs (exit 2, one line naming file and field)."""

from __future__ import annotations

from pathlib import Path

import pytest

from .conftest import check_refused, files_in, run

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
TILTING = (EXAMPLES / "bearings" / "tilting_4pad.toml").read_text()

CASES = [
    (
        "misspelt",
        TILTING.replace("clearance =", "clearence ="),
        ["bearing.clearence", "did you mean 'clearance'"],
    ),
    ("offset-2", TILTING.replace("offset = 0.5", "offset = 2.0"), ["bearing.offset", "2.0"]),
    ("offset-nan", TILTING.replace("offset = 0.5", "offset = nan"), ["bearing.offset", "finite"]),
    (
        "arc-480",
        TILTING.replace('arc = "75 deg"', 'arc = "120 deg"'),
        ["bearing.arc", "480 deg", "360 deg"],
    ),
    (
        "grid-memory",
        TILTING.replace("n_theta = 24", "n_theta = 5000").replace("n_z = 6", "n_z = 2000"),
        ["bearing.grid", "GB", "nodes"],
    ),
    ("grid-huge", TILTING.replace("n_theta = 24", "n_theta = 20000"), ["grid.n_theta", "20000"]),
    ("grid-float", TILTING.replace("n_theta = 24", "n_theta = 24.0"), ["grid.n_theta", "24.0"]),
    ("viscosity-inf", TILTING.replace('"0.0277 Pa*s"', "inf"), ["bearing.viscosity", "finite"]),
    (
        "rotor-model",
        (EXAMPLES / "unity_gearbox.toml").read_text(),
        ["rotor model file, not a bearing file"],
    ),
    ("latin1", TILTING + "# caf\xe9\n", ["not UTF-8"]),
]


@pytest.mark.parametrize("text, needles", [c[1:] for c in CASES], ids=[c[0] for c in CASES])
def test_bad_bearing_file_refused(tmp_path, text, needles):
    path = tmp_path / "b.toml"
    path.write_bytes(text.encode("latin-1" if "caf\xe9" in text else "utf-8"))
    r, dt = run("bearing", path)
    check_refused(r, dt, "b.toml", *needles)
    assert files_in(tmp_path) == {path}
