"""The HTML report without a browser: self-contained page, expected sections, numbers that agree
with the analyses, the 3-D mode-shape geometry, atomic writing and clear input errors.

The browser test (rendering, console errors) is ``test_report_browser.py``.
"""

from __future__ import annotations

import json
import re

import numpy as np
import pytest

pytest.importorskip("plotly", reason="the HTML report needs plotly (gearrotor[report])")
pytest.importorskip("matplotlib", reason="the report's PNG figures need matplotlib")

from typer.testing import CliRunner  # noqa: E402

from gearrotor.cli.report import report_command  # noqa: E402
from gearrotor.errors import ModelError  # noqa: E402
from gearrotor.io import load_model  # noqa: E402
from gearrotor.plots.report import make_report, parse_analyses  # noqa: E402
from gearrotor.plots.report.sections.modes import mode_shape_figure  # noqa: E402

RPM = np.pi / 30
PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


@pytest.fixture(scope="module")
def train(examples):
    return load_model(examples / "unity_gearbox.toml")


@pytest.fixture(scope="module")
def single(examples):
    """A small model (one shaft) for the tests that only need a report to be written."""
    return load_model(examples / "unity_gearbox_single_shaft.toml")


@pytest.fixture(scope="module")
def transient_file(tmp_path_factory, train):
    pytest.importorskip("xarray", reason="transient results need xarray (gearrotor[results])")
    pytest.importorskip("h5netcdf", reason="transient results need h5netcdf (gearrotor[results])")
    from gearrotor.analyses.transient import ModalRK4, transient

    res = transient(train, t_end=0.1, integrator=ModalRK4())
    return res.save(tmp_path_factory.mktemp("transient") / "run.nc")


@pytest.fixture(scope="module")
def report(tmp_path_factory, train, transient_file):
    out = tmp_path_factory.mktemp("rep") / "unity"
    return make_report(
        train,
        out,
        analyses="modal,campbell,unbalance",
        max_frequency=32500 * RPM,
        transient=transient_file,
        n_campbell=8,
        n_unbalance=150,
        source="examples/unity_gearbox.toml",
    )


@pytest.fixture(scope="module")
def page(report) -> str:
    return report.html.read_text(encoding="utf-8")


# ---- self-contained page ------------------------------------------------------------------------
def test_page_is_self_contained(page):
    from plotly.offline import get_plotlyjs

    # no external script, stylesheet, image or frame: nothing the browser must fetch
    assert not re.search(r"<script[^>]*\bsrc\s*=", page, re.I)
    assert not re.search(r"<link[^>]*\bhref\s*=\s*['\"]?(https?:)?//", page, re.I)
    assert not re.search(r"<(img|iframe)[^>]*\bsrc\s*=\s*['\"]?(https?:)?//", page, re.I)
    # the plotly.js bundle is inline, once
    js = get_plotlyjs()
    assert page.count(js[:400]) == 1
    # and every figure is drawn by it (the model's 3-D view, modes, Campbell, Bode, orbits,
    # spectra, waterfall, whirl power)
    assert page.count('class="plotly-graph-div"') == 8


def test_page_has_the_sections(page, report):
    for sid in (
        "summary",
        "model",
        "modes",
        "stability",
        "campbell",
        "unbalance",
        "api684",
        "transient",
        "files",
    ):
        assert f"<section id='{sid}'>" in page, sid
    for div in (
        "fig-modes",
        "fig-campbell",
        "fig-bode",
        "fig-orbits",
        "fig-spectra",
        "fig-waterfall",
        "fig-whirl-power",
    ):
        assert f'id="{div}"' in page, div
    assert "Crossing speeds" in page
    assert "separation margin" in page
    # a 0.1 s coast-down changes the speed by ~0.1 %: no waterfall against speed
    assert 'id="fig-waterfall-speed"' not in page


def test_png_figures_and_json_are_written(report):
    names = {p.name for p in report.figures}
    assert {
        "modes_1.png",
        "campbell.png",
        "bode.png",
        "orbits_operating.png",
        "transient_spectra.png",
        "transient_whirl_power.png",
        "transient_waterfall.png",
    } <= names
    for p in report.figures:
        assert p.read_bytes()[:8] == PNG_MAGIC, p
    data = json.loads(report.json.read_text())
    assert data["train"] == "Unity-ratio spur gearbox (SPEC 6.1)"
    assert {"modal", "stability", "campbell", "api684", "transient", "verdicts"} <= set(data)
    # no temporary directory is left next to the report
    assert not list(report.directory.parent.glob(".unity.tmp-*"))


# ---- the numbers are the analyses' numbers -------------------------------------------------------
def test_mode_table_matches_the_modal_result(page, report):
    res = report.modal
    assert len(res) > 0
    for i in range(len(res)):
        assert f"<td>{res.frequency_rpm[i]:.1f}</td>" in page
        assert f"<td>{res.log_dec[i]:.4g}</td>" in page
    # every listed mode carries its status; this model is stable at 6500 rpm (up to
    # 32,500 cpm every elastic mode has lateral motion and log dec above 0.1)
    n_elastic = int(np.sum(~res.overdamped))
    modes = page.split("<section id='modes'>")[1].split("</section>")[0]
    assert modes.count("<td class='l'>stable</td>") == n_elastic
    assert report.summary["stability"]["modal"]["stable"] is True


def test_api_checks_match_the_unbalance_result(report):
    unb = report.unbalance
    rows = report.summary["api684"]["criticals"]
    crit = [(p.name, c) for p in unb.probes for c in p.criticals]
    assert len(rows) == len(crit) > 0
    for row, (name, c) in zip(rows, crit, strict=True):
        assert row["probe"] == name
        assert row["speed_rpm"] == pytest.approx(c.speed / RPM)
        assert row["amplification_factor"] == c.amplification_factor
        assert row["separation_margin_pct"] == c.separation_margin
        assert row["required_margin_pct"] == c.required_margin
        assert row["result"] == {True: "pass", False: "fail", None: "not determined"}[c.ok]
    # SPEC 6.1 runs next to its first bending critical: margins fail, and the page says so
    assert report.summary["api684"]["ok"] is False


# ---- 3-D mode shapes: geometry and controls -----------------------------------------------------
def test_mode_shape_traces_are_the_deflected_shafts(report):
    res = report.modal
    modes = [i for i in range(len(res)) if not res.overdamped[i]][:4]
    fig = mode_shape_figure(res, modes=modes, n_phase=8)
    asm = res.assembly
    shafts = asm.train.layout().shafts
    ns = len(shafts)
    scale = fig.layout.meta["scale_m"]
    n_static = len(fig.data) - len(modes) * 8 * ns
    assert n_static == ns + 2  # centre lines, bearings, gears
    # trace (mode m, phase p, shaft k) draws x = x_k + scale·Re(X e^{ip}) along the nodes
    for mi, m in enumerate(modes):
        for p in (0, 3):
            for k, s in enumerate(shafts):
                tr = fig.data[n_static + (mi * 8 + p) * ns + k]
                n = len(s.z)
                offs = asm.node_offset[k]
                rot = np.exp(2j * np.pi * p / 8)
                x_ref = s.position[0] + scale * np.real(res.mode_shapes[m][offs] * rot)
                y_ref = s.position[1] + scale * np.real(res.mode_shapes[m][offs + 1] * rot)
                np.testing.assert_allclose(np.array(tr.x[:n], float), x_ref, atol=1e-12)
                np.testing.assert_allclose(np.array(tr.y[:n], float), y_ref, atol=1e-12)
                np.testing.assert_allclose(np.array(tr.z[:n], float), s.z)
    # the dropdown shows one mode at phase 0 and installs that mode's phase slider
    menu = fig.layout.updatemenus[0]
    assert len(menu.buttons) == len(modes)
    vis = menu.buttons[1].args[0]["visible"]
    shown = [i for i, v in enumerate(vis) if v]
    assert shown == list(range(n_static)) + [n_static + 8 * ns + k for k in range(ns)]
    slider = menu.buttons[1].args[1]["sliders"][0]
    assert len(slider["steps"]) == 8
    step = slider["steps"][3]
    ids = step["args"][1]
    assert ids == list(range(n_static + 8 * ns, n_static + 16 * ns))
    assert [ids[j] for j, v in enumerate(step["args"][0]["visible"]) if v] == [
        n_static + (8 + 3) * ns + k for k in range(ns)
    ]


def test_mode_shape_figure_is_valid_plotly(report):
    """The 3-D mode figure is built without plotly's per-property validation (speed): every
    trace and the layout must still pass it (a misspelt property would be dropped silently
    by plotly.js)."""
    import plotly.graph_objects as go

    res = report.modal
    fig = mode_shape_figure(res, modes=[0, 1], n_phase=2)
    spec = fig.to_dict()
    checked = go.Figure(spec)  # validates; raises ValueError on an unknown property
    assert len(checked.data) == len(fig.data)
    assert checked.layout.scene.xaxis.title.text == "x (m)"


def test_torsional_spokes_swing_with_torsion(report):
    """The spoke of a node turns by 0.8 rad per unit normalised torsion θz·r (doc of
    mode_shape_figure): check it on the mode with the most torsional energy."""
    res = report.modal
    m = int(np.argmax(res.energy_fractions[:, 2]))
    fig = mode_shape_figure(res, modes=[m], n_phase=4)
    asm = res.assembly
    s = asm.train.layout().shafts[0]
    n_static = len(fig.data) - 4 * len(asm.train.layout().shafts)
    tr = fig.data[n_static]  # phase 0, shaft 0
    n = len(s.z)
    xs = np.array([np.nan if v is None else v for v in tr.x], float)
    ys = np.array([np.nan if v is None else v for v in tr.y], float)
    # after the centre line and a gap: triples (centre, tip, gap) per node
    cx, cy = xs[n + 1 :: 3], ys[n + 1 :: 3]
    tx, ty = xs[n + 2 :: 3], ys[n + 2 :: 3]
    ang = np.arctan2(ty - cy, tx - cx)
    tz = np.real(res.mode_shapes[m][asm.node_offset[0] + 5]) * s.outer_radius
    np.testing.assert_allclose(ang, np.pi / 2 + 0.8 * tz, atol=1e-9)


# ---- tabulated (fluid-film) bearings ------------------------------------------------------------
def test_tabulated_bearings_get_a_section_and_limit_the_sweeps(examples, tmp_path):
    """A bearing table that covers 2000..9000 rpm (no extrapolation): the report plots its
    coefficients and runs the sweeps inside the table, saying so, rather than failing."""
    import tomllib

    from gearrotor.io import model_from_dict

    data = tomllib.loads((examples / "unity_gearbox_single_shaft.toml").read_text())
    b = data["bearings"][0]
    for key in ("k", "c"):
        b.pop(key, None)
    b["table"] = {
        "speed": ["2000 rpm", "9000 rpm"],
        "kxx": ["0.8e7 N/m", "1.2e7 N/m"],
        "kxy": ["0 N/m", "2e6 N/m"],
        "kyx": ["0 N/m", "-2e6 N/m"],
        "kyy": ["0.8e7 N/m", "1.2e7 N/m"],
        "cxx": ["1.75e4 N*s/m", "1.75e4 N*s/m"],
        "cxy": ["0 N*s/m", "0 N*s/m"],
        "cyx": ["0 N*s/m", "0 N*s/m"],
        "cyy": ["1.75e4 N*s/m", "1.75e4 N*s/m"],
    }
    rep = make_report(model_from_dict(data), tmp_path / "out", n_campbell=5, n_unbalance=40)
    page = rep.html.read_text()
    assert "<section id='bearings'>" in page and 'id="fig-bearings"' in page
    assert (tmp_path / "out" / "bearings.png").read_bytes()[:8] == PNG_MAGIC
    assert "Campbell sweep limited to 2000..8125 rpm" in page
    assert "unbalance sweep limited to 2000..9000 rpm" in page
    assert rep.campbell.speeds[0] == pytest.approx(2000 * RPM)
    assert rep.unbalance.speeds[-1] == pytest.approx(9000 * RPM)


# ---- errors -------------------------------------------------------------------------------------
def test_parse_analyses():
    assert parse_analyses("campbell, modal,campbell") == ("campbell", "modal")
    with pytest.raises(ModelError, match="unknown analysis.*'bode'"):
        parse_analyses("modal,bode")
    with pytest.raises(ModelError, match="no analysis"):
        parse_analyses(" , ")


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"analyses": "modal,bode"}, "--analyses: unknown analysis"),
        ({"analyses": "modal,transient"}, "--transient: the transient section needs"),
        ({"speed": -100.0}, "--speed: the report needs a positive operating speed"),
        ({"max_frequency": 0.0}, "--max-frequency"),
        (
            {"analyses": "campbell", "max_frequency": 100 * RPM},
            "--max-frequency: the Campbell diagram cannot be made",
        ),
    ],
)
def test_bad_requests_are_clear_errors(train, tmp_path, kwargs, message):
    with pytest.raises(ModelError) as exc:
        make_report(train, tmp_path / "out", **kwargs)
    assert message in str(exc.value)
    assert not (tmp_path / "out").exists()


def test_unreadable_transient_file_names_the_file(train, tmp_path):
    with pytest.raises(ModelError, match="result file not found"):
        make_report(train, tmp_path / "out", analyses="modal", transient=tmp_path / "none.nc")
    bad = tmp_path / "bad.nc"
    bad.write_text("not a netcdf file")
    with pytest.raises(ModelError) as exc:
        make_report(train, tmp_path / "out", analyses="modal", transient=bad)
    assert str(bad) in str(exc.value)
    assert not (tmp_path / "out").exists()


def test_unbalance_without_probes_is_an_error(examples, tmp_path):
    import tomllib

    from gearrotor.io import model_from_dict

    data = tomllib.loads((examples / "unity_gearbox.toml").read_text())
    data.pop("probes")
    with pytest.raises(ModelError, match="probes: the unbalance analysis needs probes"):
        make_report(model_from_dict(data), tmp_path / "out", analyses="unbalance")


def test_output_that_is_a_file_is_an_error(train, tmp_path):
    f = tmp_path / "file"
    f.write_text("x")
    with pytest.raises(ModelError, match="not a directory"):
        make_report(train, f, analyses="modal")


def test_failed_write_leaves_nothing_behind(single, tmp_path, monkeypatch):
    import gearrotor.plots.report.build as rp

    def boom(*args, **kwargs):
        raise RuntimeError("disk full")

    monkeypatch.setattr(rp, "_page", boom)
    with pytest.raises(RuntimeError, match="disk full"):
        make_report(single, tmp_path / "out", analyses="modal")
    assert list(tmp_path.iterdir()) == []


def test_existing_directory_is_replaced_as_a_whole(single, tmp_path):
    """Issue 23: an earlier report's folder is replaced as a whole (no file of the earlier
    report survives into the new one); a folder holding other files is refused, so that they
    do not go with it."""
    out = tmp_path / "out"
    out.mkdir()
    rep = make_report(single, out, analyses="modal")  # an empty folder is fine
    (out / "stale.png").write_text("a figure the next report does not make")
    rep = make_report(single, out, analyses="modal")
    assert rep.html.exists() and (out / "modes_1.png").exists()
    assert not (out / "stale.png").exists()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out"]
    mine = tmp_path / "mine"
    mine.mkdir()
    (mine / "notes.txt").write_text("mine")
    with pytest.raises(ModelError, match="not a gearrotor report"):
        make_report(single, mine, analyses="modal")
    assert (mine / "notes.txt").read_text() == "mine"


# ---- the command --------------------------------------------------------------------------------
def _app():
    import typer

    app = typer.Typer(add_completion=False, pretty_exceptions_enable=False)
    app.command("report")(report_command)

    @app.command("other")
    def other() -> None:  # a second command keeps 'report' a sub-command, as in gearrotor.cli
        pass

    return app


def test_cli_writes_the_report(examples, tmp_path):
    out = tmp_path / "rep"
    r = CliRunner().invoke(
        _app(),
        [
            "report",
            str(examples / "unity_gearbox_single_shaft.toml"),
            "--analyses",
            "modal",
            "--speed",
            "6000",
            "--max-frequency",
            "30000",
            "--set",
            "bearings[0].k=2e7 N/m",
            "--output",
            str(out),
        ],
    )
    assert r.exit_code == 0, r.output
    assert "report written to" in r.output
    data = json.loads((out / "report.json").read_text())
    assert data["inputs"]["speed_rpm"] == pytest.approx(6000)
    assert data["modal"]["speed_rpm"] == pytest.approx(6000)
    assert max(m["frequency_rpm"] for m in data["modal"]["modes"]) <= 30000
    # the --set override reached the model: same modes as the Python API with it
    from gearrotor.analyses import modal

    ref = modal(
        load_model(examples / "unity_gearbox_single_shaft.toml", {"bearings[0].k": "2e7 N/m"}),
        speed=6000 * RPM,
        max_frequency=30000 * RPM,
    )
    got = [m["frequency_rpm"] for m in data["modal"]["modes"]]
    np.testing.assert_allclose(got, ref.frequency_rpm, rtol=1e-9)


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--analyses", "modal,bogus"], "unknown analysis"),
        (["--analyses", "transient"], "needs a saved transient result"),
        (["--speed", "0"], "positive operating speed"),
        (["--set", "meshes[0].stiffness"], "--set option needs PATH=VALUE"),
    ],
)
def test_cli_bad_input_exits_2(examples, tmp_path, args, message):
    r = CliRunner().invoke(
        _app(),
        ["report", str(examples / "unity_gearbox.toml"), "--output", str(tmp_path / "o"), *args],
    )
    assert r.exit_code == 2
    assert message in r.stderr
    assert "Traceback" not in r.output
    assert not (tmp_path / "o").exists()


def test_cli_missing_model_exits_2(tmp_path):
    r = CliRunner().invoke(
        _app(), ["report", str(tmp_path / "nope.toml"), "--output", str(tmp_path / "o")]
    )
    assert r.exit_code == 2
    assert "nope.toml" in r.stderr
