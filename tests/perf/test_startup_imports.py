"""Start-up (issue 28): an input error is reported before the heavy modules are imported.

Not a timed test (a loaded machine would decide it): the modules a command has imported when it
reports the error are the measure. A missing or unparsable model file is read before anything
else (``gearrotor.cli.common_options``: only the command line, numpy and the file reader are
loaded: measured 1.0–1.4x the time of ``python -c "import numpy, scipy.sparse"``, goal 2.5x); a
bad field is found by the model's validation before the analyses are imported. All commands run
in one fresh interpreter one after the other (a command that imported a heavy module would show
it in every later line, so the first offender is named).
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import typer.main

from gearrotor.cli import app

ROOT = Path(__file__).resolve().parents[2]

#: Modules no input error may pay for: the compiled kernels, dense/sparse solvers, optimisers,
#: the analyses and the plotting libraries.
HEAVY = (
    "numba",
    "scipy.linalg",
    "scipy.sparse.linalg",
    "scipy.optimize",
    "gearrotor.assembly",
    "gearrotor.analyses",
    "matplotlib",
    "plotly",
)
#: What a missing file must not import either: the model's classes and the units (pint).
#: (pydantic itself is loaded by typer 0.29 when it converts the options.)
MODEL = ("gearrotor.model", "gearrotor.io", "pint")

#: Commands that validate the model before importing their analysis (the bad-field check).
BAD_FIELD = ("modal", "campbell", "static", "floquet", "report", "transient")

#: Required options besides the model.
REQUIRED = {
    "report": ["-o", "report_dir"],
    "response": ["--torque", "shaft=motor,node=4,amplitude=5 kN*m,order=2"],
}

_SCRIPT = """
import json, sys
from typer.testing import CliRunner
from gearrotor.cli import app
for args in json.loads(sys.argv[1]):
    r = CliRunner().invoke(app, args)
    names = {name for name in sys.modules}
    print(json.dumps({"args": args, "status": r.exit_code, "output": r.output,
                      "loaded": [m for m in json.loads(sys.argv[2]) if m in names]}))
"""


def _model_commands() -> list[list[str]]:
    """Every command (also in the groups) whose first argument is a model file."""
    out = []

    def walk(group, prefix):
        for name, cmd in sorted(group.commands.items()):
            if hasattr(cmd, "commands"):
                walk(cmd, [*prefix, name])
            elif any(p.name == "model" for p in cmd.params):
                out.append([*prefix, name])

    walk(typer.main.get_command(app), [])
    return out


def _run(cases: list[list[str]], modules: tuple[str, ...]) -> list[dict]:
    p = subprocess.run(
        [sys.executable, "-c", _SCRIPT, json.dumps(cases), json.dumps(modules)],
        capture_output=True,
        text=True,
        cwd=ROOT,
        timeout=600,
    )
    assert p.returncode == 0, p.stderr
    return [json.loads(line) for line in p.stdout.splitlines()]


def test_missing_model_file_before_any_heavy_import(tmp_path):
    commands = _model_commands()
    assert len(commands) >= 14 and ["torsional", "modes"] in commands  # the walk sees them
    missing = str(tmp_path / "no_such_model.toml")
    rows = _run([[*c, missing, *REQUIRED.get(c[-1], [])] for c in commands], HEAVY + MODEL)
    for row in rows:
        assert row["status"] == 2, row
        assert "model file not found" in row["output"] and missing in row["output"], row
        assert row["loaded"] == [], row


def test_bad_field_before_the_analyses(tmp_path, examples):
    text = (examples / "unity_gearbox.toml").read_text()
    bad = tmp_path / "bad.toml"
    # a negative element count: a field error of the model's validation
    bad.write_text(text.replace("elements = ", "elements = -", 1))
    rows = _run([[c, str(bad), *REQUIRED.get(c, [])] for c in BAD_FIELD], HEAVY)
    for row in rows:
        assert row["status"] == 2, row
        assert "elements" in row["output"], row
        assert row["loaded"] == [], row
