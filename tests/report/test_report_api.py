"""``gearrotor report --api``: the unbalance section with the API 617 unbalance.

Oracles: API 617's U = 4 × 6350 W/N g·mm per plane with W from the closed-form shaft mass of
the SPEC 6.1 gearbox (solid steel shaft ρ π r² L = 7890 × π × 0.03² × 1.02 = 22.755 kg, one
plane per shaft) and N = 6500 rpm: U = 88.92 g·mm; and linearity: the response to it is the
response to the model's 720 g·mm scaled by U/720 (both planes scale alike).
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

pytest.importorskip("plotly", reason="the HTML report needs plotly (gearrotor[report])")
pytest.importorskip("matplotlib", reason="the report's PNG figures need matplotlib")

from typer.testing import CliRunner  # noqa: E402

from gearrotor.cli import app  # noqa: E402
from gearrotor.io import load_model  # noqa: E402
from gearrotor.plots.report import make_report  # noqa: E402

RPM = np.pi / 30
W_SHAFT = 7890 * math.pi * 0.03**2 * 1.02  # kg
U_API = 4 * 6350 * W_SHAFT / 6500  # g·mm = 88.92


@pytest.fixture(scope="module")
def train(examples):
    return load_model(examples / "unity_gearbox.toml")


@pytest.fixture(scope="module")
def reports(tmp_path_factory, train):
    out = tmp_path_factory.mktemp("api")
    kw = dict(analyses="unbalance", n_unbalance=60)
    return (
        make_report(train, out / "model", **kw),
        make_report(train, out / "api", api=True, **kw),
    )


def test_api617_amounts(reports):
    _, api = reports
    used = api.summary["api684"]["unbalance"]
    assert used["basis"] == "api617"
    assert api.summary["unbalance"]["basis"] == "api617"
    assert api.summary["inputs"]["unbalance"] == "api617"
    assert [p["shaft"] for p in used["planes"]] == ["shaft1", "shaft2"]
    for p in used["planes"]:
        assert p["journal_mass_kg"] == pytest.approx(W_SHAFT, rel=1e-9)
        assert p["max_continuous_speed_rpm"] == pytest.approx(6500)
        assert p["amount_g_mm"] == pytest.approx(U_API, rel=1e-9)
        assert p["node"] == 10 and p["phase_deg"] == 0.0
    assert U_API == pytest.approx(88.92, abs=0.01)


def test_response_scales_with_the_unbalance(reports):
    model, api = reports
    assert model.summary["api684"]["unbalance"]["basis"] == "model"
    ratio = U_API / 720.0
    for pm, pa in zip(model.unbalance.probes, api.unbalance.probes, strict=True):
        np.testing.assert_allclose(pa.amplitude, ratio * pm.amplitude, rtol=1e-9)
    # so the critical speeds and AF are the same, the amplitudes in the checks scale
    cm, ca = model.summary["api684"]["criticals"], api.summary["api684"]["criticals"]
    assert len(ca) == len(cm) > 0
    for a, m in zip(ca, cm, strict=True):
        assert a["speed_rpm"] == pytest.approx(m["speed_rpm"], rel=1e-9)  # peak interpolation
        assert a["amplification_factor"] == pytest.approx(m["amplification_factor"], rel=1e-9)
        assert a["amplitude_um"] == pytest.approx(ratio * m["amplitude_um"], rel=1e-9)


def test_the_checks_table_states_the_unbalance(reports):
    model, api = reports
    page = api.html.read_text(encoding="utf-8")
    sec = page[page.index("<section id='api684'>") :]
    sec = sec[: sec.index("</section>")]
    # the edition: the model's [api_audit] edition, none here: the 8th
    ed = "API 617 8th edition (2014)"
    assert f"Unbalance used for these checks: {ed} unbalance: 4 × 6350 W/N g·mm" in sec
    assert f"{U_API:.1f} g·mm on shaft1 node 10" in sec and "N = 6500 rpm" in sec
    assert f"W = {W_SHAFT:.2f} kg" in sec
    unb = page[page.index("<section id='unbalance'>") :]
    assert f"with {ed} unbalance" in unb[: unb.index("</section>")]
    verdict = [v for v in api.summary["verdicts"] if "vibration limit" in v["check"]][0]
    assert verdict["detail"].endswith(f"(with the {ed} unbalance)")
    page = model.html.read_text(encoding="utf-8")
    sec = page[page.index("<section id='api684'>") :]
    assert "Unbalance used for these checks: the model's unbalance" in sec
    assert "720.0 g·mm on shaft1 node 10" in page


def test_cli_report_api_matches_unbalance_api(examples, tmp_path):
    """`gearrotor report --api` and `gearrotor unbalance --api` use the same amounts."""
    model = str(examples / "unity_gearbox.toml")
    r = CliRunner().invoke(
        app,
        ["report", model, "--api", "--analyses", "unbalance", "-o", str(tmp_path / "r")],
    )
    assert r.exit_code == 0, r.output
    rep = json.loads((tmp_path / "r" / "report.json").read_text())
    u = CliRunner().invoke(
        app, ["unbalance", model, "--api", "--n-speeds", "20", "--format", "json"]
    )
    assert u.exit_code == 0, u.output
    amounts = [x["amount_g_mm"] for x in json.loads(u.stdout)["unbalances"]]
    assert [p["amount_g_mm"] for p in rep["api684"]["unbalance"]["planes"]] == amounts
    assert amounts == pytest.approx([U_API, U_API], rel=1e-9)
