"""The report's operating-points section (issue 11): the numbers in report.json are those of
the static analysis and of modal at the operating point; figures written; --operating-point
puts the report's analyses at the point (a note says so)."""

import json

import numpy as np
import pytest

import gearrotor as gr
from gearrotor.analyses.static import static
from gearrotor.errors import ModelError
from gearrotor.plots.report import make_report


@pytest.fixture(scope="module")
def steam(examples):
    return gr.load_model(examples / "steam_turbine_gearbox.toml")


def test_operating_points_section(steam, tmp_path):
    rep = make_report(
        steam,
        tmp_path / "r",
        analyses="modal",
        operating_points=["LC1", "LC10"],
        operating_point="LC10",
        max_frequency=30000 * np.pi / 30,
    )
    d = json.loads(rep.json.read_text())
    ops = d["operating_points"]
    assert [o["operating_point"] for o in ops] == ["LC1", "LC10"]
    st = static(steam, "LC10")
    assert ops[1]["bearings"][0]["force_N"] == pytest.approx(list(st.bearings[0].force))
    md = gr.modal(steam, operating_point="LC10", max_frequency=30000 * np.pi / 30)
    # the modes with lateral motion, as the stability section judges them
    el = [i for i in range(len(md)) if not md.overdamped[i] and "L" in md.mode_type[i]]
    assert ops[1]["least_stable_log_dec"] == pytest.approx(min(md.log_dec[el]), rel=1e-9)
    # the modes section ran at LC10 too: same least-stable mode
    assert d["stability"]["modal"]["lowest_log_dec"]["log_dec"] == pytest.approx(
        ops[1]["least_stable_log_dec"], rel=1e-9
    )
    for name in ("op_bearing_loads.png", "op_eccentricity_locus.png", "op_log_dec.png"):
        assert (tmp_path / "r" / name).stat().st_size > 0
    html = rep.html.read_text()
    assert "Operating points" in html and "Operating point LC10" in html


def test_unknown_operating_point(steam, tmp_path):
    with pytest.raises(ModelError) as e:
        make_report(steam, tmp_path / "r", analyses="modal", operating_point="LC99")
    assert e.value.field == "--operating-point"
    assert not (tmp_path / "r").exists()
