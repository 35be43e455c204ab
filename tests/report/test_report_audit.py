"""The report's "API audit" section (plots/report/sections/audit.py) on the Jeffcott rotor of
tests/audit_models.py with an operating range, an MCS, an [api_audit] table, unbalance and a
probe: the section's numbers are those of the commands (same Q_0, Q_A, verdicts), the
response checks use the model's operating range, and bad requests are refused before running.

Oracle for Q_0: the Jeffcott onset q = c ω_n (rel 1e-3, see tests/audit/test_stability.py).
"""

from __future__ import annotations

import json

import pytest

pytest.importorskip("plotly", reason="the HTML report needs plotly (gearrotor[report])")
pytest.importorskip("matplotlib", reason="the report's PNG figures need matplotlib")

from typer.testing import CliRunner  # noqa: E402

from audit_models import Q_ONSET, jeffcott_toml  # noqa: E402
from gearrotor.cli import app  # noqa: E402
from gearrotor.errors import ModelError  # noqa: E402
from gearrotor.io import load_model  # noqa: E402
from gearrotor.plots.report import make_report  # noqa: E402

TOP = 'operating_speed_range = ["2500 rpm", "2865 rpm"]\n'
TABLES = f"""
[[unbalances]]
shaft = "s"
node = 2
amount = "100 g*mm"

[[probes]]
name = "mid"
shaft = "s"
node = 2

[api_audit]
qa = "{Q_ONSET / 1.5} N/m"
at = [{{ shaft = "s", node = "mid_span" }}]
"""


@pytest.fixture(scope="module")
def model(tmp_path_factory):
    p = tmp_path_factory.mktemp("audit") / "jeffcott.toml"
    p.write_text(jeffcott_toml(TABLES, top=TOP))
    return p


@pytest.fixture(scope="module")
def report(model, tmp_path_factory):
    out = tmp_path_factory.mktemp("rep") / "r"
    return make_report(load_model(model), out, analyses="unbalance,audit", n_unbalance=80)


def test_section_numbers_are_the_commands(report, model):
    a = report.summary["api_audit"]
    st = a["stability"]
    assert st["threshold_q_N_per_m"] == pytest.approx(Q_ONSET, rel=1e-3)
    assert st["ratio_q0_qa"] == pytest.approx(1.5, rel=1e-3)
    assert (st["level1_verdict"], st["level2_verdict"], st["verdict"]) == (
        "level II required",
        "pass",
        "pass",
    )
    assert "8th edition" in a["edition"]
    cmd = CliRunner().invoke(app, ["stability", str(model), "--format", "json"])
    assert cmd.exit_code == 0, cmd.output
    d = json.loads(cmd.stdout)
    for k in ("threshold_q_N_per_m", "qa_N_per_m", "ratio_q0_qa", "verdict"):
        assert st[k] == d[k]
    # the response checks over the model's range (min operating speed .. MCS), in the audit
    # and in the unbalance section alike
    assert a["operating_range_rpm"] == pytest.approx([2500, 2865])
    assert report.summary["api684"]["operating_range_rpm"] == pytest.approx([2500, 2865])
    assert a["response"]["criticals"], "the rotor's critical lies in the sweep"
    # issue 22: one line per check; "Level II required" is not a failure, Level II decides
    checks = {v["key"]: v for v in report.summary["verdicts"]}
    assert len(checks) == len(report.summary["verdicts"])
    assert checks["api617_level1"]["result"] == "Level II required"
    assert checks["api617_level1"]["ok"] is None
    assert (checks["api617_level2"]["result"], checks["api617_level2"]["ok"]) == ("pass", True)
    # the separation margins of the unbalance and audit sections are one check (one response)
    margins = [v for v in report.summary["verdicts"] if "separation margin" in v["check"]]
    assert [v["key"] for v in margins] == ["separation_margins"]
    assert "FAIL" not in {v["result"] for v in report.summary["verdicts"] if "617" in v["check"]}
    html = report.html.read_text()
    # the Level I criterion Q_0/Q_A >= 2 is not met: "Level II required" there too, not FAIL
    level1 = html.split("<h3>Level I</h3>")[1].split("<h3>Level II</h3>")[0]
    assert '<span class="na">Level II required</span>' in level1
    assert "FAIL" not in level1 and "Verdict: <b>Level II required</b>" in level1
    assert "API audit" in html and "Undamped critical speed map" in html
    assert f"{st['threshold_q_N_per_m']:.4g}" in html  # the same Q_0 on the page
    for name in ("audit_ucs.png", "audit_level1.png", "audit_screening.png", "audit_level2.png"):
        assert (report.directory / name).read_bytes()[:4] == b"\x89PNG"


def test_audit_is_not_run_by_default(report, model, tmp_path):
    r = make_report(load_model(model), tmp_path / "d", analyses="modal")
    assert "api_audit" not in r.summary


@pytest.mark.parametrize(
    "top, tables, kw, match",
    [
        ("", TABLES, {}, "operating_speed_range"),
        (TOP, TABLES.split("[api_audit]")[0], {}, "api_audit"),
        (TOP, TABLES, {"speed": 300.0}, "--speed"),
    ],
)
def test_bad_requests_are_refused_before_running(tmp_path, top, tables, kw, match):
    p = tmp_path / "m.toml"
    p.write_text(jeffcott_toml(tables, top=top))
    with pytest.raises(ModelError, match=match):
        make_report(load_model(p), tmp_path / "out", analyses="audit", **kw)
    assert not (tmp_path / "out").exists()
