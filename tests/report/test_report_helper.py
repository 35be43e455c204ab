"""Issue 28: the report's second process (plots/report/helper.py). With a second core free the
Campbell sweep runs in a forked helper while the report's process runs the other analyses and
draws the model, and the PNG files are drawn by both; the report must be the same file for
file. A job that fails in the helper is run again in the report's process, so its error is the
one it raises without the helper."""

from __future__ import annotations

import os
import re

import numpy as np
import pytest

pytest.importorskip("plotly", reason="the HTML report needs plotly (gearrotor[report])")
pytest.importorskip("matplotlib", reason="the report's PNG figures need matplotlib")
if not hasattr(os, "fork"):
    pytest.skip("the helper process needs os.fork", allow_module_level=True)

from gearrotor.errors import ModelError  # noqa: E402
from gearrotor.io import load_model  # noqa: E402
from gearrotor.plots.report import build, make_report  # noqa: E402
from gearrotor.plots.report.helper import Helper  # noqa: E402

RPM = np.pi / 30


def _report(train, out, monkeypatch, processes: int):
    monkeypatch.setattr(build, "processes", lambda: processes)
    return make_report(
        train,
        out,
        analyses="modal,campbell,unbalance",
        max_frequency=120000 * RPM,  # 2 pages of mode shapes: the helper draws one of them
        n_campbell=8,
        n_unbalance=60,
    )


def test_report_with_the_helper_is_the_same(examples, tmp_path, monkeypatch):
    """Every file byte for byte (the page's time stamp aside): the same code on the same data in
    both processes, one BLAS thread in each."""
    train = load_model(examples / "unity_gearbox.toml")
    one = _report(train, tmp_path / "one", monkeypatch, 1)
    two = _report(train, tmp_path / "two", monkeypatch, 2)
    names = sorted(p.name for p in one.directory.iterdir())
    assert names == sorted(p.name for p in two.directory.iterdir())
    assert {"modes_1.png", "modes_2.png", "campbell.png", "model.png"} <= set(names)
    assert [p.name for p in one.figures] == [p.name for p in two.figures]
    stamp = re.compile(rb"\d{4}-\d\d-\d\d \d\d:\d\d UTC")
    for name in names:
        a = (one.directory / name).read_bytes()
        b = (two.directory / name).read_bytes()
        if name == "report.html":
            a, b = stamp.sub(b"", a), stamp.sub(b"", b)
        assert a == b, name
    np.testing.assert_array_equal(one.campbell.damped_frequency, two.campbell.damped_frequency)
    assert not any(p.name.startswith(".") for p in tmp_path.iterdir())  # no temporaries left


def test_helper_runs_jobs_and_returns_their_values():
    helper = Helper(True)
    assert helper.enabled
    helper.submit("a", lambda: np.arange(3) * 2)
    helper.submit("b", lambda: {"x": 1.5})
    helper.submit("c", lambda: os.getpid())
    np.testing.assert_array_equal(helper.result("a"), [0, 2, 4])
    helper.finish()
    assert helper.result("b") == {"x": 1.5}
    assert isinstance(helper.result("c"), int)


def test_a_job_that_fails_in_the_helper_runs_again_here():
    """An error raised in the helper comes back as the job's own error, raised here; a value
    that does not pickle (a lambda) is computed here; a helper killed by a signal too."""
    parent = os.getpid()
    helper = Helper(True)

    def fails():
        raise ModelError("bad field", field="f", value=1, expected="2")

    helper.submit("error", fails)
    with pytest.raises(ModelError, match="bad field"):
        helper.result("error")
    helper.submit("unpicklable", lambda: lambda: os.getpid())
    assert helper.result("unpicklable")() == parent

    def killed():
        if os.getpid() != parent:
            os.kill(os.getpid(), 9)
        return "here"

    helper.submit("killed", killed)
    assert helper.result("killed") == "here"
    helper.finish()


def test_without_the_helper_jobs_run_at_once():
    helper = Helper(False)
    seen = []
    helper.submit("a", lambda: seen.append(os.getpid()) or 7)
    assert seen == [os.getpid()] and helper.result("a") == 7
    helper.finish()
    helper.close()


def test_an_error_stops_the_helper_and_leaves_no_folder(examples, tmp_path, monkeypatch):
    """An analysis error while the helper runs: the helper is stopped (no process left) and
    the temporary folder removed."""
    train = load_model(examples / "unity_gearbox.toml")
    from gearrotor.plots.report.sections import unbalance

    def broken(*args, **kwargs):
        raise ModelError("the unbalance failed", field="x", value=0, expected="1")

    from gearrotor.plots.report import helper as helper_module

    started = []
    start = helper_module.Helper._start

    def recording(self, key):
        start(self, key)
        started.append(self._running[0])

    monkeypatch.setattr(helper_module.Helper, "_start", recording)
    monkeypatch.setattr(build, "processes", lambda: 2)
    monkeypatch.setattr(unbalance, "_clearances", broken)
    with pytest.raises(ModelError, match="the unbalance failed"):
        make_report(train, tmp_path / "out", analyses="modal,campbell,unbalance", n_campbell=40)
    assert list(tmp_path.iterdir()) == []
    assert started  # the Campbell helper ran (or runs) when the unbalance failed
    for pid in started:  # and has been reaped: no such child any more
        with pytest.raises(ChildProcessError):
            os.waitpid(pid, os.WNOHANG)


def test_a_killed_report_leaves_no_helper_behind(tmp_path):
    """A report killed by SIGKILL (it cannot clean up) leaves no orphan: the helper dies with
    its parent (PR_SET_PDEATHSIG), rather than finishing its job alone."""
    import signal
    import subprocess
    import sys
    import time

    if not sys.platform.startswith("linux"):
        pytest.skip("the parent-death signal is Linux's")
    pidfile = tmp_path / "helper.pid"
    script = f"""
import os, time
from gearrotor.plots.report.helper import Helper

def job():
    with open({str(pidfile)!r}, "w") as f:
        f.write(str(os.getpid()))
    time.sleep(60)

h = Helper(True)
h.submit("slow", job)
time.sleep(60)
"""
    proc = subprocess.Popen([sys.executable, "-c", script])
    try:
        deadline = time.monotonic() + 60
        while not (pidfile.exists() and pidfile.read_text()) and time.monotonic() < deadline:
            time.sleep(0.05)
        helper = int(pidfile.read_text())
    finally:
        proc.send_signal(signal.SIGKILL)
        proc.wait()
    deadline = time.monotonic() + 10
    while time.monotonic() < deadline:
        try:
            os.kill(helper, 0)
        except ProcessLookupError:
            return
        # a zombie is gone as a process (reaped by init): check its state
        try:
            with open(f"/proc/{helper}/stat") as f:
                if f.read().split(")")[-1].split()[0] == "Z":
                    return
        except FileNotFoundError:
            return
        time.sleep(0.05)
    pytest.fail(f"helper {helper} still runs after its parent was killed")


def test_sections_that_inline_a_png_wait_for_its_job(examples, tmp_path, monkeypatch):
    """The torsional, static, audit and mesh-response sections put their PNG into the page as
    a data URI: with the helper they read the file while its job may still be queued or running
    (the steam-turbine audit report failed with 'audit_ucs.png: No such file or directory' on
    two idle cores). Here the helper starts no job on its own, so every job waits until asked
    for: the page must still hold the image."""
    train = load_model(examples / "unity_gearbox.toml")
    monkeypatch.setattr(build, "processes", lambda: 2)
    monkeypatch.setattr(Helper, "_poll", lambda self: None)  # jobs wait in the queue
    rep = make_report(train, tmp_path / "out", analyses="modal,torsional")
    html = rep.html.read_text()
    assert re.search(r'<img src="data:image/png;base64,[A-Za-z0-9+/]{100}', html)
