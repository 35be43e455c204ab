"""``gearrotor view``: the live model view in a real headless Chromium (Playwright driving the
system browser, as the report's browser tests do; they skip without a Chromium binary).

The command runs as a user runs it (a subprocess on a free port); the test edits the model file
and watches the page follow: a changed diameter redraws the 3-D model, an invalid node shows the
command line's one-line error, the fixed file brings the model back. Also: the server listens
on the loopback interface only and serves nothing from the network (plotly.js is local)."""

from __future__ import annotations

import re
import signal
import socket
import subprocess
import sys

import pytest

pytest.importorskip("plotly", reason="the view needs plotly (gearrotor[report])")
pytest.importorskip("playwright.sync_api", reason="the browser test needs playwright")
from helpers import start_view  # noqa: E402
from report.test_report_browser import CHROMIUM, FLAGS  # noqa: E402

pytestmark = pytest.mark.skipif(CHROMIUM is None, reason="no Chromium binary")


@pytest.fixture
def served(tmp_path, examples):
    model, proc, line = start_view(tmp_path, examples)
    m = re.search(r"http://(127\.0\.0\.1):(\d+)/", line)
    assert m, line
    yield model, f"http://127.0.0.1:{m.group(2)}/", int(m.group(2)), proc
    proc.send_signal(signal.SIGINT)
    out, err = proc.communicate(timeout=30)
    assert proc.returncode == 0 and "view stopped" in err


def _wait_version(page, above: int, timeout=60_000) -> int:
    page.wait_for_function(
        f"() => Number(document.body.dataset.version) > {above}", timeout=timeout
    )
    return int(page.evaluate("() => document.body.dataset.version"))


def test_view_follows_the_file(served):
    from playwright.sync_api import sync_playwright

    model, url, port, _ = served
    with sync_playwright() as pw:
        browser = pw.chromium.launch(executable_path=CHROMIUM, args=FLAGS)
        page = browser.new_page()
        requests = []
        page.on("request", lambda r: requests.append(r.url))
        page.goto(url)
        v = _wait_version(page, 0)
        assert page.evaluate("() => document.body.dataset.state") == "ok"
        page.wait_for_function("() => document.getElementById('figure')._fullData")
        traces = page.evaluate("() => document.getElementById('figure')._fullData.length")
        assert traces > 4
        assert "shaft1" in page.inner_text("#summary")
        hover = page.evaluate(
            "() => document.getElementById('figure').data.map(t => t.hovertext).flat().join(' ')"
        )
        assert "shaft1 node 10" in hover and "shaft2 element 19" in hover

        # a thicker shaft: the page redraws with the new mass in the summary
        before = page.inner_text("#summary")
        model.write_text(
            model.read_text().replace('outer_diameter = "0.06 m"', 'outer_diameter = "0.09 m"')
        )
        v = _wait_version(page, v)
        assert page.evaluate("() => document.body.dataset.state") == "ok"
        assert page.inner_text("#summary") != before
        # an invalid node: the one-line error of the command line, in the page
        model.write_text(model.read_text().replace("node = 20", "node = 99", 1))
        v = _wait_version(page, v)
        assert page.evaluate("() => document.body.dataset.state") == "error"
        err = page.inner_text("#error")
        assert err.startswith(f"error: {model}: bearings[1].node: node is not on shaft")
        assert "\n" not in err.strip()
        # fixed again
        model.write_text(model.read_text().replace("node = 99", "node = 20", 1))
        _wait_version(page, v)
        assert page.evaluate("() => document.body.dataset.state") == "ok"
        browser.close()
    assert all(u.startswith(url) for u in requests), "the page must not fetch from elsewhere"


def test_view_listens_on_loopback_only(served):
    _, _, port, _ = served
    addrs = {a[4][0] for a in socket.getaddrinfo(socket.gethostname(), None, socket.AF_INET)}
    addrs.discard("127.0.0.1")
    for addr in addrs:  # another interface of this machine, if it has one
        with socket.socket() as s:
            s.settimeout(2)
            assert s.connect_ex((addr, port)) != 0, addr
    with socket.create_connection(("127.0.0.1", port), timeout=5):
        pass


def test_view_missing_file_is_one_line(tmp_path):
    r = subprocess.run(
        [sys.executable, "-m", "gearrotor", "view", str(tmp_path / "no.toml")],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert r.returncode == 2 and r.stderr.count("\n") == 1 and "no.toml" in r.stderr
