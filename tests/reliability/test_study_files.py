"""Generated corpus of bad study files (issue 17): every row's model is checked before anything
runs, and an error names the study file and the row (exit 2), not the base model alone."""

from __future__ import annotations

from pathlib import Path

import pytest

from .conftest import check_refused, files_in, run

MODEL = (Path(__file__).resolve().parents[2] / "examples" / "unity_gearbox.toml").as_posix()

STUDY = f"""
model = "{MODEL}"
output = "s.study"
[parameters]
unbalance = {{ paths = ["unbalances[0].amount", "unbalances[1].amount"], unit = "g*mm" }}
ka = {{ path = "meshes[0].variation.ka_ratio" }}
[cases]
columns = ["unbalance", "ka"]
rows = [[360, 0.0], [720, 0.2], [1080, 0.1]]
[analysis]
type = "transient"
t_end = "0.1 s"
"""

CASES = [
    (
        "unknown-path",
        STUDY.replace("variation.ka_ratio", "variaton.ka_ratio"),
        ["cases.rows[0]", "meshes[0].variaton", "no such field"],
    ),
    ("unit-typo", STUDY.replace('"g*mm"', '"g*mmm"'), ["cases.rows[0]", "mmm"]),
    ("negative", STUDY.replace("[1080, 0.1]", "[1080, -0.1]"), ["cases.rows[2]", "ka_ratio"]),
    ("nan-cell", STUDY.replace("[1080, 0.1]", "[nan, 0.1]"), ["cases.rows[2]", "finite"]),
    (
        "product",
        STUDY.replace('columns = ["unbalance", "ka"]\n', "").replace(
            "rows = [[360, 0.0], [720, 0.2], [1080, 0.1]]",
            "product = {unbalance = [1], ka = [0.1, -2.0]}",
        ),
        ["cases.product (case 1)", "ka_ratio"],
    ),
    ("empty", "", ["the study file is empty"]),
    ("comment-only", "# nothing here\n", ["the study file is empty"]),
    ("not-utf8", STUDY + "# \xff\n", ["not UTF-8"]),
]


@pytest.mark.parametrize("text, needles", [c[1:] for c in CASES], ids=[c[0] for c in CASES])
def test_bad_study_refused_before_running(tmp_path, text, needles):
    path = tmp_path / "study.toml"
    path.write_bytes(text.encode("latin-1" if "\xff" in text else "utf-8"))
    r, dt = run("study", "run", path, "--no-progress")
    check_refused(r, dt, "study.toml", *needles)
    assert files_in(tmp_path) == {path}  # nothing ran: no study folder
    assert "model" not in r.stderr.split(":")[0]
