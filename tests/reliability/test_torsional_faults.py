"""Faults of ``torsional transient`` (issue 23): Ctrl-C is one line and exit 130 (the shared
``cli_errors``), the result file and the figures appear together or not at all
(``files.output_set``), and the temporaries a killed run left (``X.nc.tmp-PID-TOKEN``,
``.json.tmp-…``, a figure's) are removed by the next run that writes there
(``files.check_output``)."""

from __future__ import annotations

import signal
from pathlib import Path

import pytest

from fault_helpers import dead_pid, full_disk_at_fsync, leftovers, run_signalled, skip_without_proc

from .conftest import run
from .test_torsional_inputs import TORSIONAL


@pytest.fixture
def model(tmp_path: Path) -> Path:
    path = tmp_path / "torsional.toml"
    path.write_text(TORSIONAL)
    return path


@pytest.mark.parametrize("suffix", [".nc", ".json"])
def test_next_run_removes_a_killed_runs_temporaries(model, tmp_path, suffix):
    out = tmp_path / "out"
    plots = out / "plots"
    plots.mkdir(parents=True)
    pid = dead_pid()
    stale = [
        out / f"x{suffix}.tmp-{pid}-a1b2c3",
        plots / f"torsional_transient.png.tmp-{pid}-d4e5f6",
    ]
    for p in stale:
        p.write_bytes(b"\0" * 1000)
    r, _ = run(
        "torsional",
        "transient",
        model,
        "--t-end",
        "0.05",
        "--output",
        out / f"x{suffix}",
        "--plot",
        plots,
    )
    assert r.exit_code == 0, (r.output, r.exception)
    assert leftovers(out) == []
    assert (out / f"x{suffix}").exists() and (plots / "torsional_transient.png").exists()


def test_full_disk_writes_nothing(model, tmp_path, monkeypatch):
    """No space for the second file: neither the result nor any figure appears."""
    r, _ = run("torsional", "transient", model, "--t-end", "0.05")  # compiled before the
    assert r.exit_code == 0, r.output  # fault: numba's cache writes are not the outputs'
    full_disk_at_fsync(monkeypatch, after=1)
    out = tmp_path / "out"
    out.mkdir()
    r, _ = run(
        "torsional",
        "transient",
        model,
        "--t-end",
        "0.05",
        "--output",
        out / "x.nc",
        "--plot",
        out / "plots",
    )
    assert r.exit_code == 2, (r.output, r.exception)
    assert "no space left" in r.stderr and len(r.stderr.strip().splitlines()) == 1
    assert not (out / "x.nc").exists()
    assert not list(out.rglob("*.png")) and leftovers(out) == []


@pytest.mark.slow
@skip_without_proc
def test_ctrl_c_during_the_run_is_one_line(model, tmp_path):
    """Before: exit 130 with no message."""
    out = tmp_path / "x.nc"
    r = run_signalled(
        "gearrotor.analyses.torsional.transient:_run",
        "SIGINT",
        "torsional",
        "transient",
        model,
        "--t-end",
        "0.05",
        "--output",
        out,
    )
    assert r.returncode == 128 + signal.SIGINT, (r.returncode, r.stderr)
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("interrupted (Ctrl-C)"), r.stderr
    assert not out.exists() and leftovers(tmp_path) == []
