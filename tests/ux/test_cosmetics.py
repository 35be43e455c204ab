"""Issue 14 item 16: names, units and labels as seen."""

from __future__ import annotations

import json
import subprocess
import sys

import numpy as np

from gearrotor import load_model
from gearrotor.analyses import modal

RPM = np.pi / 30


def test_speed_reads_as_given(examples):
    # 6500 rpm → rad/s → rpm printed 6499.999999999999 in the JSON
    d = modal(load_model(examples / "unity_gearbox.toml"), speed=6500 * RPM, n_modes=2).to_dict()
    assert d["speed_rpm"] == 6500.0
    assert set(d["shaft_speeds_rpm"].values()) <= {6500.0, -6500.0}


def test_tables_use_micro_sign_and_explain_their_columns(examples):
    p = subprocess.run(
        [sys.executable, "-m", "gearrotor", "bearing", str(examples / "bearings/plain_ld1.toml")],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert p.returncode == 0, p.stderr
    assert "hmin µm" in p.stdout and " um" not in p.stdout
    assert "m_crit" in p.stdout and "critical journal mass" in p.stdout  # the legend


def test_campbell_order_column_fits_its_header(examples):
    from gearrotor.analyses import campbell

    res = campbell(
        load_model(examples / "unity_gearbox.toml"),
        speeds=np.array([0.0, 4000.0, 8000.0]) * RPM,
        max_frequency=3e4 * RPM,
    )
    lines = res.table().splitlines()
    start = lines[0].index("order")
    end = lines[0].index("speed rpm")
    for row in lines[2:]:
        cell = row[start:end]
        assert cell.endswith(" ") and not row[start - 1].strip()  # the text stays in its column


def test_pressure_colour_bar_has_round_ticks(examples):
    import matplotlib

    matplotlib.use("Agg")
    from gearrotor.bearings import coefficients, load_bearing
    from gearrotor.bearings.plots import plot_pressure

    case = load_bearing(examples / "bearings/tilting_4pad.toml")
    co = coefficients(case.bearing, case.loads[0], case.speed, options=case.options)
    fig = plot_pressure(co.equilibrium, case.bearing)
    cbar = [a for a in fig.axes if a.get_label() == "<colorbar>"][0]
    ticks = [t for t in cbar.get_yticks() if t > 0]
    assert ticks and all(
        abs(t * 4 - round(t * 4)) < 1e-9 or abs(t * 10 - round(t * 10)) < 1e-9 for t in ticks
    )
    json.dumps([float(t) for t in ticks])
