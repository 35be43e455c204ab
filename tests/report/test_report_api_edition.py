"""``gearrotor report --api --edition``: the report's API 617 unbalance, close-clearance check and
audit follow the edition (issue 22 follow-up): ``--edition``, else the model's ``[api_audit]
edition``, else the 8th; the sections and report.json say which. The 9th edition's close
clearances default to the model's ``[api_audit] clearances``, else twice the radial clearance
of each fluid-film journal bearing's file.

Oracles: the library's own 9th-edition functions (``mode_unbalances``, ``clearance_check``,
checked against ROSS 3.1's implementation in tests/audit/test_api617_9th.py), called directly
with the report's speeds: the same numbers (rel 1e-12, the same computation); the 8th edition's
4 × 6350 W/N g·mm (tests/report/test_report_api.py); the bearing files' clearance values.
"""

from __future__ import annotations

import json
import tomllib
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("plotly", reason="the HTML report needs plotly (gearrotor[report])")
pytest.importorskip("matplotlib", reason="the report's PNG figures need matplotlib")

from gearrotor.analyses.audit.api_unbalance import (  # noqa: E402
    CloseClearance,
    bearing_clearances,
    clearance_check,
    close_clearances,
    mode_unbalances,
)
from gearrotor.errors import ModelError  # noqa: E402
from gearrotor.io import load_model  # noqa: E402
from gearrotor.plots.report import make_report  # noqa: E402

RPM = np.pi / 30
NINTH = "API 617 9th edition (2022)"
EIGHTH = "API 617 8th edition (2014)"


@pytest.fixture(scope="module")
def model_file(tmp_path_factory):
    """ROSS's rotor_example with an [api_audit] table: 9th edition, two close clearances."""
    import sys

    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "audit"))
    from test_api617_9th import AUDIT_TABLE, ROTOR_TOML

    p = tmp_path_factory.mktemp("ed") / "rotor.toml"
    p.write_text(ROTOR_TOML + AUDIT_TABLE)
    return p


def _report(model_file, tmp_path, **kw):
    kw.setdefault("analyses", "unbalance")
    return make_report(load_model(model_file), tmp_path / "r", n_unbalance=40, **kw)


def test_ninth_edition_from_the_model_table(model_file, tmp_path):
    rep = _report(model_file, tmp_path, api=True)
    s = rep.summary
    used = s["api684"]["unbalance"]
    assert used["edition"] == NINTH and s["inputs"]["api617_edition"] == NINTH
    # the unbalance placed from the mode shape: the library's numbers
    placed = mode_unbalances(load_model(model_file), max_continuous_speed=9000 * RPM)
    lib = placed.to_dict()["unbalances"]
    assert [p["node"] for p in used["planes"]] == [u["node"] for u in lib]
    for p, u in zip(used["planes"], lib, strict=True):
        assert p["amount_g_mm"] == pytest.approx(u["amount_g_mm"], rel=1e-12)
        assert p["basis"] == u["basis"]
    # the close-clearance check at the table's clearances, as the library computes it
    cc = s["api684"]["close_clearance"]
    direct = clearance_check(
        rep.unbalance.assembly,
        [CloseClearance("s", 3, 0.5e-3, "eye"), CloseClearance("s", 0, 200e-6, "DE")],
        speeds=rep.unbalance.speeds,
        operating_range=rep.unbalance.operating_range,
        unbalance=placed,
    ).to_dict()
    assert [c["name"] for c in cc["locations"]] == ["eye", "DE"]
    for a, b in zip(cc["locations"], direct["locations"], strict=True):
        assert a["scaled_response_pp_um"] == pytest.approx(b["scaled_response_pp_um"], rel=1e-12)
    line = next(v for v in s["verdicts"] if v["key"] == "close_clearances")
    assert line["check"].startswith(NINTH) and line["ok"] == (direct["verdict"] == "pass")
    assert NINTH in next(v for v in s["verdicts"] if v["key"] == "vibration_limit")["detail"]
    html = rep.html.read_text()
    assert f"Close clearances ({NINTH}" in html and f"{NINTH} unbalance" in html


def test_edition_option_overrides_the_table(model_file, tmp_path):
    rep = _report(model_file, tmp_path, api=True, edition="8th")
    used = rep.summary["api684"]["unbalance"]
    assert used["edition"] == EIGHTH
    assert rep.summary["api684"]["close_clearance"] is None  # the 9th edition's check only
    assert [p["node"] for p in used["planes"]] == [2]  # the model's plane, 4 × U_r
    assert "close_clearances" not in {v["key"] for v in rep.summary["verdicts"]}
    with pytest.raises(ModelError) as e:  # the edition without --api or the audit: refused
        _report(model_file, tmp_path, edition="9th")
    assert e.value.field == "--edition"


@pytest.mark.slow
def test_audit_section_follows_the_edition(model_file, tmp_path):
    # the audit section's Level I/II run with the report's edition and say so
    rep = _report(model_file, tmp_path, analyses="audit", edition="8th")
    assert rep.summary["api_audit"]["edition"] == EIGHTH
    assert EIGHTH in rep.html.read_text()


def test_close_clearances_from_the_bearing_files(examples, tmp_path):
    # the steam turbine's pinion journals are fluid-film bearing files (152.4 µm radial
    # clearance, examples/bearings): diametral 0.3048 mm at their nodes, the values
    # docs/stability.md gave by hand; the bull gear's bearings are tables (no clearance)
    train = load_model(examples / "steam_turbine_gearbox.toml")
    files = [(b, b.fluid_film.file) for b in train.bearings if b.fluid_film is not None]
    assert len(files) == 2
    got = close_clearances(train)
    assert got == bearing_clearances(train)
    for (b, f), c in zip(files, got, strict=True):
        doc = tomllib.loads(Path(f).read_text(encoding="utf-8"))["bearing"]
        assert doc["clearance"] == "152.4 um"
        assert c.diametral == pytest.approx(2 * 152.4e-6, rel=1e-12)
        assert (c.shaft, c.node, c.name) == (b.shaft, b.node, b.name)
    assert [c.node for c in got] == [4, 15]
    # an [api_audit] clearances list takes precedence
    text = (examples / "steam_turbine_gearbox.toml").read_text()
    text = text.replace(
        '[api_audit]\n', '[api_audit]\nclearances = [{ shaft = "pinion", node = 8, '
        'diametral = "0.2 mm", name = "seal" }]\n', 1
    )  # fmt: skip
    p = tmp_path / "st.toml"
    p.write_text(text.replace('"bearings/', f'"{examples}/bearings/'))
    assert close_clearances(load_model(p)) == [CloseClearance("pinion", 8, 0.2e-3, "seal")]


def test_unbalance_command_takes_the_bearing_clearances(examples):
    # `gearrotor unbalance --api --edition 9th` without --clearance: the check runs at the
    # bearings' clearances (it ran at none before)
    from typer.testing import CliRunner

    from gearrotor.cli import app

    r = CliRunner().invoke(
        app,
        [
            "unbalance",
            str(examples / "steam_turbine_gearbox.toml"),
            *("--api", "--edition", "9th", "--min-speed", "8000", "--max-speed", "13000"),
            *("--n-speeds", "30", "--format", "json"),
        ],
    )
    assert r.exit_code == 0, r.output
    locs = json.loads(r.stdout)["close_clearance_check"]["locations"]
    assert [(c["node"], round(c["diametral_clearance_um"], 6)) for c in locs] == [
        (4, 304.8),
        (15, 304.8),
    ]
