"""Progress of long commands (issue 28): the callback protocol (gearrotor.progress), the
terminal reporter (gearrotor.cli.progress) and the commands that use it.

The reporter's terminal mode is checked on a real pseudo-terminal (``pty``), its automatic
silence with stderr redirected on a real pipe, and each long command's lines by forcing it on
(``--progress``) under the test runner.
"""

from __future__ import annotations

import io
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from gearrotor.cli import app
from gearrotor.cli.progress import Reporter, reporting
from gearrotor.progress import part, report, steps

ROOT = Path(__file__).resolve().parents[1]


def test_callbacks_nest_and_clip():
    seen = []

    def cb(f, t):
        seen.append((round(f, 6), t))

    report(cb, 1.5, "over")
    report(None, 0.5, "nothing happens")
    sub = part(cb, 0.5, 0.9, "campbell")
    report(sub, 0.5, "speed 3/6")
    report(part(sub, 0.0, 0.5, "operating point"), 1.0, "")
    assert list(steps(cb, ["a", "b"], "case")) == ["a", "b"]
    assert seen == [
        (1.0, "over"),
        (0.7, "campbell: speed 3/6"),
        (0.7, "campbell: operating point"),
        (0.0, "case 1/2"),
        (0.5, "case 2/2"),
        (1.0, ""),
    ]
    assert part(None, 0, 1) is None


def test_terminal_reporter_draws_in_place_and_erases():
    class Tty(io.StringIO):
        def isatty(self):
            return True

    s = Tty()
    r = Reporter("ucs", s, delay=0.0, interval=0.0)
    assert r.tty
    r(0.25, "stiffness 8/31")
    r(0.5, "stiffness 16/31")
    text = s.getvalue()
    assert text.count("\r\x1b[K") == 2 and "ucs [######" in text and "50 %" in text
    assert "\n" not in text  # one line, redrawn
    r(1.0, "")
    assert s.getvalue().endswith("\r\x1b[K")  # erased when done


def test_plain_lines_when_forced_off_a_terminal():
    s = io.StringIO()
    r = Reporter("static", s, interval=3600.0)
    for i in range(10):
        r(i / 10, f"point {i + 1}/10")
    r(1.0, "")
    lines = s.getvalue().splitlines()
    # the first line, then none within the interval, and the last
    assert len(lines) == 2 and "0 %  point 1/10" in lines[0] and "100 %" in lines[1]


_PTY_SCRIPT = """
import sys, time
from gearrotor.cli import progress
with progress.reporting("demo", {enabled}) as bar:
    if bar is not None:
        bar.delay = bar.interval = 0.0  # draw at once
    for i in range(3):
        if bar is not None:
            bar(i / 3, f"step {{i + 1}}/3")
        time.sleep(0.01)
    print("error: something", file=sys.stderr)
"""


def _on_pty(enabled: str) -> str:
    """Run the script with stderr on a pseudo-terminal; what the terminal received."""
    pty = pytest.importorskip("pty")
    master, slave = pty.openpty()
    env = dict(os.environ, PYTHONPATH=str(ROOT / "src"))
    p = subprocess.Popen(
        [sys.executable, "-c", _PTY_SCRIPT.format(enabled=enabled)],
        stderr=slave,
        stdout=subprocess.DEVNULL,
        env=env,
    )
    os.close(slave)
    chunks = []
    while True:
        try:
            data = os.read(master, 4096)
        except OSError:  # the child closed the terminal
            break
        if not data:
            break
        chunks.append(data)
    p.wait(timeout=60)
    os.close(master)
    return b"".join(chunks).decode()


@pytest.mark.skipif(sys.platform == "win32", reason="pseudo-terminals")
def test_on_a_terminal_by_default_and_errors_start_a_clean_line():
    out = _on_pty("None")
    assert "demo [" in out and "step 3/3" in out
    # the error line erased the bar first: it starts after the erase sequence, not after the bar
    assert "\r\x1b[Kerror: something" in out
    assert "demo [" not in _on_pty("False")  # --no-progress


def test_silent_when_stderr_is_not_a_terminal(examples):
    """A real pipe, no option: nothing but the command's own output."""
    p = subprocess.run(
        [sys.executable, "-m", "gearrotor", "static", str(examples / "steam_turbine_gearbox.toml")],
        capture_output=True,
        text=True,
        env=dict(os.environ, PYTHONPATH=str(ROOT / "src")),
        timeout=600,
    )
    assert p.returncode == 0, p.stderr
    assert p.stderr == ""
    with reporting("x", None) as bar:  # the test runner's stderr is not a terminal either
        assert bar is None


def _lines(result, title):
    return [ln for ln in result.stderr.splitlines() if ln.startswith(f"{title} [")]


@pytest.mark.parametrize(
    "args, title, first",
    [
        (["campbell", "unity_gearbox.toml", "--n-speeds", "5"], "campbell", "speed 1/5"),
        (["static", "steam_turbine_gearbox.toml", "--all"], "static", "operating point LC1"),
        (["ucs", "unity_gearbox.toml", "--n-points", "5"], "ucs", "speed-ratio group 1/"),
    ],
)
def test_long_commands_report_when_forced(examples, args, title, first):
    args = [str(examples / a) if a.endswith(".toml") else a for a in args]
    r = CliRunner().invoke(app, [*args, "--progress"])
    assert r.exit_code == 0, r.output
    lines = _lines(r, title)
    assert first in lines[0] and "100 %" in lines[-1], lines
    fractions = [float(ln.split("]")[1].split("%")[0]) for ln in lines]
    assert fractions == sorted(fractions)
    quiet = CliRunner().invoke(app, args)  # not a terminal: off
    assert quiet.exit_code == 0 and _lines(quiet, title) == []
    off = CliRunner().invoke(app, [*args, "--progress", "--no-progress"])
    assert _lines(off, title) == []


def test_stability_with_operating_point_reports_its_static_solves(examples):
    r = CliRunner().invoke(
        app,
        [
            "stability",
            str(examples / "steam_turbine_gearbox.toml"),
            "--operating-point",
            "LC10",
            "--progress",
        ],
    )
    assert r.exit_code in (0, 1), r.output
    text = "\n".join(_lines(r, "stability"))
    assert "operating point: static solve 1/" in text and "100 %" in text


def test_analyses_accept_a_progress_callback(examples):
    from gearrotor.analyses import campbell
    from gearrotor.io import load_model

    seen = []
    train = load_model(examples / "unity_gearbox.toml")
    campbell(
        train,
        speeds=np.linspace(0, 600, 4),
        max_frequency=5000.0,
        progress=lambda f, t: seen.append((f, t)),
    )
    assert [t for _, t in seen] == ["speed 1/4", "speed 2/4", "speed 3/4", "speed 4/4", ""]
    assert [f for f, _ in seen] == [0, 0.25, 0.5, 0.75, 1.0]
