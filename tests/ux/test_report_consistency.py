"""Issue 14 items 6 and 7: one mode numbering in the report's checks, the orbit at the
operating speed, pk-pk beside pk-pk, no Python booleans in tables, and a default frequency
range that holds the coupled modes and is stated."""

from __future__ import annotations

import json
import re
import subprocess
import sys

import numpy as np
import pytest

from gearrotor import load_model
from gearrotor.analyses import unbalance_response

pytest.importorskip("plotly")
pytest.importorskip("matplotlib")
RPM = np.pi / 30


@pytest.fixture(scope="module")
def report(examples, tmp_path_factory):
    from gearrotor.plots.report import make_report

    out = tmp_path_factory.mktemp("rep") / "r"
    make_report(
        load_model(examples / "unity_gearbox.toml"),
        out,
        analyses=("modal", "campbell"),
        n_campbell=3,
    )
    return json.loads((out / "report.json").read_text()), (out / "report.html").read_text()


def test_default_range_holds_the_coupled_modes_and_is_stated(report):
    # the flagship at 6500 rpm: mesh frequency 30 teeth × 6500 = 195,000 cpm; its L-T modes at
    # 57,000 and 71,000 cpm were outside the former default 5 × speed = 32,500 cpm
    summary, html = report
    inputs = summary["inputs"]
    teeth = load_model_teeth()
    assert inputs["max_frequency_rpm"] == pytest.approx(1.1 * teeth * 6500, rel=1e-9)
    assert "mesh frequency" in inputs["max_frequency_basis"]
    assert "Modes and Campbell diagram up to" in html


def load_model_teeth() -> int:
    from pathlib import Path

    train = load_model(Path(__file__).resolve().parents[2] / "examples" / "unity_gearbox.toml")
    return train.meshes[0].gear.teeth


def test_least_stable_mode_has_one_number(report):
    summary, _ = report
    stab = summary["stability"]
    low = stab["modal"]["lowest_log_dec"]
    # every Campbell track named by a mode number is that row of the modal table at the
    # operating speed (same frequency there)
    camp = stab["campbell"]
    named = [d for d in camp["modes"] if d["mode"] is not None]
    assert named, "the operating speed is a Campbell sweep point"
    rows = summary["modal"]["modes"]
    for d in named:  # a track is named by its row of the modal table (an elastic mode)
        assert rows[d["mode"]]["class"] != "over-damped"
    # the modal check and the Campbell check speak of the lowest modal mode by the same number
    verdicts = " ".join(v["detail"] for v in summary["verdicts"])
    nums = {int(n) for n in re.findall(r"mode (\d+)", verdicts)}
    assert low["mode"] in nums
    assert nums <= {r["index"] for r in rows}


def test_unbalance_table_pk_pk_and_words(examples):
    res = unbalance_response(
        load_model(examples / "unity_gearbox.toml"),
        speeds=np.linspace(5000, 7500, 26) * RPM,
        operating_range=(5800 * RPM, 7200 * RPM),
    )
    table = res.table()
    assert "False" not in table and "True" not in table
    p = res.probes[0]
    peak_pp = 2 * p.amplitude.max() * 1e6
    assert f"{peak_pp:.3f}" in table.splitlines()[1]  # pk-pk beside the pk-pk limit
    assert "µm pk-pk" in table.splitlines()[0] and "0-pk" not in table.splitlines()[0]


def test_cli_orbits_at_the_end_of_the_operating_range(examples):
    p = subprocess.run(
        [
            sys.executable,
            "-m",
            "gearrotor",
            "unbalance",
            str(examples / "unity_gearbox.toml"),
            "--operating-range",
            "5800,7200",
            "--n-speeds",
            "40",
            "--format",
            "json",
        ],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert p.returncode == 0, p.stderr
    speeds = json.loads(p.stdout)["speeds_rpm"]
    assert any(abs(s - 7200) < 1e-6 for s in speeds) and any(abs(s - 5800) < 1e-6 for s in speeds)
