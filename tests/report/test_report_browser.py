"""The HTML report in a real headless browser (Chromium driven by Playwright).

Checks that the page loads from disk with no console error, no page error and no network request
(everything is inline), that every plot renders (an SVG with drawn traces; WebGL canvases for the
3-D figures with the shafts' colours actually painted), and that the mode dropdown and the phase
slider of the 3-D mode shapes work when clicked.

Needs the Python package ``playwright`` and a Chromium binary (Debian: ``apt-get install
chromium``); ``playwright install`` is NOT needed: the test drives the system browser found on
PATH (``chromium``, ``chromium-browser``) or named by ``GEARROTOR_CHROMIUM``. Without either the
tests skip and say why. Set ``GEARROTOR_SCREENSHOT_DIR`` to keep the screenshots.
"""

from __future__ import annotations

import io
import os
import shutil
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("plotly", reason="the HTML report needs plotly (gearrotor[report])")
pytest.importorskip("matplotlib", reason="the report's PNG figures need matplotlib")
pytest.importorskip("xarray", reason="the transient section needs xarray (gearrotor[results])")
pytest.importorskip(
    "playwright.sync_api",
    reason="the browser test needs the 'playwright' Python package (pip install playwright; "
    "no 'playwright install': it drives the system Chromium)",
)


def _chromium() -> str | None:
    env = os.environ.get("GEARROTOR_CHROMIUM")
    if env:
        return env if Path(env).exists() else None
    for name in ("chromium", "chromium-browser"):
        path = shutil.which(name)
        if path:
            return path
    return None


CHROMIUM = _chromium()
pytestmark = pytest.mark.skipif(
    CHROMIUM is None,
    reason="no Chromium binary (apt-get install chromium, or set GEARROTOR_CHROMIUM)",
)

FLAGS = [
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--disable-quic",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
]
RPM = np.pi / 30
FIGURES = (
    "fig-model",
    "fig-modes",
    "fig-campbell",
    "fig-bode",
    "fig-orbits",
    "fig-spectra",
    "fig-waterfall",
    "fig-whirl-power",
    "fig-waterfall-speed",
)
GL_FIGURES = ("fig-model", "fig-modes", "fig-waterfall")
SHAFT_COLORS = ((0x1F, 0x77, 0xB4), (0xD6, 0x27, 0x28))  # shaft1, shaft2 in the 3-D modes


@pytest.fixture(scope="module")
def report(tmp_path_factory, examples, runup_result):
    """The unity gearbox's report with a saved run-up (tests/report/conftest.py), so that the
    transient section has the waterfall against speed too."""
    from gearrotor.io import load_model
    from gearrotor.plots.report import make_report

    train = load_model(examples / "unity_gearbox.toml")
    return make_report(
        train,
        tmp_path_factory.mktemp("browser") / "unity",
        max_frequency=32500 * RPM,
        transient=runup_result[1],
        n_campbell=8,
        n_unbalance=150,
    )


@pytest.fixture(scope="module")
def browser(tmp_path_factory):
    from playwright.sync_api import sync_playwright

    with sync_playwright() as p:
        ctx = p.chromium.launch_persistent_context(
            str(tmp_path_factory.mktemp("chromium-profile")),
            executable_path=CHROMIUM,
            headless=True,
            args=FLAGS,
            viewport={"width": 1400, "height": 900},
        )
        try:
            yield ctx
        finally:
            ctx.close()


class Page:
    """A page with its console/page errors and every request it made recorded."""

    def __init__(self, ctx, url: str):
        self.page = ctx.new_page()
        self.errors: list[str] = []
        self.requests: list[str] = []
        self.page.on(
            "console",
            lambda m: (
                self.errors.append(f"console {m.type}: {m.text}")
                if m.type in ("error", "assert")
                else None
            ),
        )
        self.page.on("pageerror", lambda e: self.errors.append(f"page error: {e}"))
        self.page.on("requestfailed", lambda r: self.errors.append(f"request failed: {r.url}"))
        self.page.on("request", lambda r: self.requests.append(r.url))
        self.page.goto(url, wait_until="load")
        self.page.wait_for_function(
            "() => { const d = document.querySelectorAll('.js-plotly-plot');"
            " return d.length > 0 && Array.from(d).every(g => g._fullLayout); }",
            timeout=90_000,
        )


@pytest.fixture(scope="module")
def loaded(browser, report):
    """The report loaded once, for the tests that only look at it (loading and painting the
    page takes most of each test's 6-9 s); a test that clicks opens its own page."""
    pg = Page(browser, report.html.as_uri())
    pg.page.wait_for_timeout(1500)  # let WebGL paint
    yield pg
    pg.page.close()


def _save_shot(png: bytes, name: str, tmp_path: Path) -> Path:
    path = tmp_path / name
    path.write_bytes(png)
    keep = os.environ.get("GEARROTOR_SCREENSHOT_DIR")
    if keep:
        Path(keep).mkdir(parents=True, exist_ok=True)
        shutil.copy(path, Path(keep) / name)
    return path


def _color_pixels(png: bytes, rgb, tol: int = 40) -> int:
    from matplotlib.image import imread

    img = (imread(io.BytesIO(png), format="png")[..., :3] * 255).astype(int)
    return int(np.sum(np.all(np.abs(img - np.array(rgb)) <= tol, axis=-1)))


def test_page_loads_offline_and_every_plot_renders(loaded, tmp_path):
    pg = loaded
    page = pg.page
    assert pg.errors == []
    external = [u for u in pg.requests if not u.startswith(("file:", "data:", "blob:"))]
    assert external == [], "the report must not fetch anything"

    state = page.evaluate(
        """() => Array.from(document.querySelectorAll('.js-plotly-plot')).map(g => ({
            id: g.id,
            svg: g.querySelectorAll('svg.main-svg').length,
            traces: g.querySelectorAll('.scatterlayer .trace, .barlayer .trace').length,
            canvases: Array.from(g.querySelectorAll('.gl-container canvas'))
                .filter(c => c.width > 0 && c.height > 0).length,
            data: g._fullData.length,
        }))"""
    )
    by_id = {s["id"]: s for s in state}
    assert sorted(by_id) == sorted(FIGURES)
    for fid, s in by_id.items():
        assert s["svg"] > 0 and s["data"] > 0, (fid, s)
        if fid in GL_FIGURES:
            assert s["canvases"] > 0, (fid, s)
        else:
            assert s["traces"] > 0, (fid, s)

    shot = _save_shot(page.screenshot(full_page=True), "report.png", tmp_path)
    assert shot.stat().st_size > 50_000
    # the WebGL figure really painted both shafts (not a blank canvas)
    modes = page.locator("#fig-modes")
    modes.scroll_into_view_if_needed()
    png = modes.screenshot()
    _save_shot(png, "modes.png", tmp_path)
    for rgb in SHAFT_COLORS:
        assert _color_pixels(png, rgb) > 200, rgb


def test_waterfall_against_speed_renders(loaded, report, tmp_path):
    """Every window's spectrum and the order lines are drawn (one SVG path per trace), the
    spectra in their colour and the 1x line in its own, with the speed axis labelled."""
    from gearrotor.plots.waterfall import speed_waterfall

    wf = speed_waterfall(report.transient)
    pg = loaded
    page = pg.page
    fig = page.locator("#fig-waterfall-speed")
    fig.scroll_into_view_if_needed()
    page.wait_for_timeout(500)
    st = page.evaluate(
        """() => { const g = document.querySelector('#fig-waterfall-speed');
            const n = t => g.querySelectorAll(t).length;
            return { data: g._fullData.length,
                     traces: n('.scatterlayer .trace'),
                     lines: Array.from(g.querySelectorAll('.scatterlayer .trace path.js-line'))
                        .filter(p => (p.getAttribute('d') || '').length > 20).length,
                     fills: n('.scatterlayer .trace path.js-fill'),
                     ytitle: g._fullLayout.yaxis.title.text,
                     legend: Array.from(g.querySelectorAll('.legend .legendtext'))
                        .map(e => e.textContent) }; }"""
    )
    n_spectra = 2 * len(wf.time)  # two panels
    assert st["traces"] == st["data"] and st["data"] >= n_spectra + 3, st
    assert st["lines"] == st["data"], st  # every trace drew its line
    assert st["fills"] == n_spectra, st  # and every spectrum its hiding fill
    assert st["ytitle"] == "speed of shaft1 (rpm)"
    assert any(t.startswith("1x") for t in st["legend"]), st["legend"]
    assert any(t.startswith("mesh (") for t in st["legend"]), st["legend"]
    png = fig.screenshot()
    _save_shot(png, "waterfall_speed.png", tmp_path)
    assert _color_pixels(png, (0x1F, 0x77, 0xB4)) > 2000  # spectra (COLORS[0])
    assert _color_pixels(png, (0xD6, 0x27, 0x28), tol=30) > 50  # 1x order line (COLORS[1])
    assert pg.errors == []


def test_mode_dropdown_and_phase_slider(browser, report, tmp_path):
    pg = Page(browser, report.html.as_uri())
    page = pg.page
    fig = page.locator("#fig-modes")
    fig.scroll_into_view_if_needed()
    res = report.modal
    modes = [i for i in range(len(res)) if not res.overdamped[i]][:16]
    n_static = (
        page.evaluate("() => document.querySelector('#fig-modes')._fullData.length")
        - len(modes) * 12 * 2
    )

    def visible():
        return page.evaluate(
            "() => document.querySelector('#fig-modes')._fullData"
            ".map((t, i) => t.visible === true ? i : null).filter(i => i !== null)"
        )

    assert visible() == list(range(n_static)) + [n_static, n_static + 1]
    # choose the third mode in the dropdown
    fig.locator(".updatemenu-header-group").click()
    fig.locator(".updatemenu-dropdown-button").nth(2).click()
    page.wait_for_timeout(300)
    first = n_static + 2 * 12 * 2
    assert visible() == list(range(n_static)) + [first, first + 1]
    title = page.evaluate("() => document.querySelector('#fig-modes')._fullLayout.title.text")
    assert title.startswith(f"mode {modes[2]}: {res.frequency_rpm[modes[2]]:.1f} cpm")
    # click the slider at 90° (step 3 of 12): that phase's traces of the same mode show
    rail = fig.locator(".slider-rail-touch-rect").bounding_box()
    page.mouse.click(rail["x"] + rail["width"] * 3 / 11, rail["y"] + rail["height"] / 2)
    page.wait_for_timeout(300)
    assert visible() == list(range(n_static)) + [first + 6, first + 7]
    _save_shot(fig.screenshot(), "modes_90deg.png", tmp_path)
    assert pg.errors == []
    page.close()


def test_campbell_legend_hides_no_marker(loaded, tmp_path):
    """Issue 22: the Campbell legend sat on the plot area, over the modes' markers. In the
    browser the legend's box lies outside the plot area's, and it lists the operating speed's
    line, drawn at 6,500 rpm."""
    pg = loaded
    page = pg.page
    fig = page.locator("#fig-campbell")
    fig.scroll_into_view_if_needed()
    page.wait_for_timeout(300)
    st = page.evaluate(
        """() => { const g = document.querySelector('#fig-campbell');
            const box = e => { const r = e.getBoundingClientRect();
                return [r.left, r.top, r.right, r.bottom]; };
            const op = g._fullData.find(t => t.name.startsWith('operating speed'));
            return { legend: box(g.querySelector('.legend')),
                     plot: box(g.querySelector('.draglayer .nsewdrag')),
                     texts: Array.from(g.querySelectorAll('.legend .legendtext'))
                        .map(e => e.textContent),
                     op_x: op ? Array.from(op.x) : null }; }"""
    )
    (l0, t0, r0, b0), (l1, t1, r1, b1) = st["legend"], st["plot"]
    assert not (l0 < r1 and l1 < r0 and t0 < b1 and t1 < b0), st
    assert "operating speed 6,500 rpm" in st["texts"], st["texts"]
    assert st["op_x"] == pytest.approx([6500, 6500])
    _save_shot(fig.screenshot(), "campbell.png", tmp_path)
    assert pg.errors == []
