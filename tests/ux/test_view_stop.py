"""``gearrotor view`` stops with exit status 0 and "view stopped" on Ctrl-C at any moment after
it has printed its address (CI, this stop: a SIGINT sent right after the "serving" line arrived
before the command's own handler was in place and exited 130). The race needs a loaded
machine to show; this guards the behaviour, three times."""

from __future__ import annotations

import signal

import pytest

from helpers import start_view

pytest.importorskip("plotly", reason="the view needs plotly (gearrotor[report])")


@pytest.mark.parametrize("attempt", range(3))
def test_ctrl_c_right_after_the_address(tmp_path, examples, attempt):
    _, proc, line = start_view(tmp_path, examples)
    try:
        assert "http://127.0.0.1:" in line, line
        proc.send_signal(signal.SIGINT)  # at once: the earliest a user could press it
        _, err = proc.communicate(timeout=60)
    finally:
        proc.kill()
    assert proc.returncode == 0 and err.strip() == "view stopped", (proc.returncode, err)
