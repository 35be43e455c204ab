"""Shared helpers of the reliability corpus: run a command in-process and check the contract of
the README's exit-status section (issue 17): exit 2 (input) or 3 (solver), one line on stderr
naming what was wrong, no traceback, no file left behind, within seconds."""

from __future__ import annotations

import time
from pathlib import Path

import pytest
from typer.testing import CliRunner

from fault_helpers import files_in  # noqa: F401  (the corpus's modules import it from here)
from gearrotor.cli import app

#: A small single-shaft model (4 Timoshenko elements on two bearings): every analysis on it
#: takes milliseconds, so each case costs only the time to find the error.
SMALL = """\
name = "small"
speed = "3000 rpm"

[materials.steel]
E = "211 GPa"
poisson = 0.3
density = "7890 kg/m^3"

[[shafts]]
name = "s1"
material = "steel"
sections = [{ length = "0.8 m", outer_diameter = "0.05 m", elements = 4 }]

[[bearings]]
name = "B1"
shaft = "s1"
node = 0
k = "1e7 N/m"
c = "1e3 N*s/m"

[[bearings]]
name = "B2"
shaft = "s1"
node = 4
k = "1e7 N/m"
c = "1e3 N*s/m"

[[unbalances]]
shaft = "s1"
node = 2
amount = "100 g*mm"

[[probes]]
name = "mid_x"
shaft = "s1"
node = 2
"""

#: Seconds one bad input may take to be refused (the slowest, a study, imports xarray).
MAX_SECONDS = 10.0


def run(*args, cwd: Path | None = None):
    """Invoke the CLI in-process; returns (result, seconds)."""
    t0 = time.perf_counter()
    r = CliRunner().invoke(app, [str(a) for a in args])
    return r, time.perf_counter() - t0


def check_refused(r, seconds: float, *needles: str, code: int = 2) -> None:
    """Exit ``code`` with one line on stderr containing every needle, quickly, no traceback."""
    assert r.exit_code == code, (r.exit_code, r.output, r.exception)
    err = r.stderr
    assert "Traceback" not in r.output, r.output
    prefix = "solver error: " if code == 3 else "error: "
    assert err.startswith(prefix), err
    assert len(err.strip().splitlines()) == 1, err
    for n in needles:
        assert n in err, (n, err)
    assert seconds < MAX_SECONDS, seconds


@pytest.fixture
def small(tmp_path: Path) -> Path:
    path = tmp_path / "small.toml"
    path.write_text(SMALL)
    return path
