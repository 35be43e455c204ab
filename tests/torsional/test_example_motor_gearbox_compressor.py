"""The motor - gearbox - compressor example: loads, runs the lateral analyses, passes the
torsional separation margins at 1800 rpm, and its start-up synchronises with the expected
torque levels (representative data; the numbers are the model's, checked for consistency)."""

from __future__ import annotations

import json

import numpy as np
import pytest

from gearrotor.analyses import modal
from gearrotor.analyses.torsional import (
    SNCurve,
    fatigue,
    interference,
    torsional_model,
    torsional_transient,
)
from gearrotor.io import load_model
from gearrotor.io.model_file import model_from_dict

RPM = np.pi / 30


@pytest.fixture(scope="module")
def train(examples):
    return load_model(examples / "motor_gearbox_compressor.toml")


def test_example_loads_and_runs_the_lateral_modal(train):
    res = modal(train, max_frequency=20000 * RPM, n_modes=12)
    assert res.stable and len(res) > 3
    assert abs(train.shaft_speeds()[2]) == pytest.approx(1800 * 131 / 22 * RPM)


def test_model_json_round_trip_keeps_the_torsional_table(train, examples):
    data = json.loads(train.model_dump_json())
    assert data["torsional"]["drives"][0]["type"] == "synchronous_motor"
    again = model_from_dict(data)
    assert again.torsional == train.torsional
    # a model without [torsional] serialises as before the field existed
    plain = load_model(examples / "unity_gearbox.toml")
    assert "torsional" not in json.loads(plain.model_dump_json())


def test_example_passes_the_api_separation_margins(train):
    res = interference(train, speed_range=(1800 * RPM, 1800 * RPM))
    assert res.passes
    labels = {c.line for c in res.crossings}
    assert {"line 60 Hz", "2x line 120 Hz"} <= labels
    first = res.modes.frequency_hz[1]
    assert 20 < first < 35  # the motor against the gear and compressor, below 1x motor


@pytest.mark.slow
def test_example_start_up_and_fatigue(train):
    tm = torsional_model(train)
    res = torsional_transient(tm, t_end=16.0)
    assert 10 < res.pull_in_time[0] < 15
    assert res.energy_error < 1e-6
    sections = res.section_table()
    ls = [s for s in sections if s["shaft"] == "bull_gear" and s["section"] == 0][0]
    assert 1.5 < ls["peak_over_rated"] < 4  # synchronous start-ups: 2-6x rated (Wachel 1993)
    f = fatigue(
        res, SNCurve.from_point(m=8.0, stress="200 MPa", cycles=1e4, endurance_limit="60 MPa")
    )
    assert f.allowable_starts == pytest.approx(1 / f.damage.max())
    assert np.isfinite(f.allowable_starts)


def test_three_phase_short_circuit_from_steady_running(train):
    """At rated speed the synchronous motor starts in step at the load angle that carries the
    load (static initial twist): nothing moves until the fault at 0.1 s; then the fault's
    line-frequency torque (representative: 5 p.u. decaying in 0.15 s) loads the train."""
    data = json.loads(train.model_dump_json())
    data["torsional"]["drives"][0]["short_circuit"] = {
        "type": "three_phase",
        "time": "0.1 s",
        "clear_time": "0.4 s",
        "a0": 0.5,
        "tau0": "0.1 s",
        "a1": 5.0,
        "tau1": "0.15 s",
    }
    data["torsional"]["loads"][0]["steps"] = []
    sc = model_from_dict(data)
    res = torsional_transient(sc, t_end=0.6, initial_speed=1800 * RPM)
    before = res.time < 0.1
    ls = 9  # motor[8]: the LS coupling stub, on the load path
    t0 = res.element_torque[0, ls]
    np.testing.assert_allclose(res.element_torque[before, ls], t0, rtol=1e-6)
    np.testing.assert_allclose(res.speed[before, 0], 1800 * RPM, rtol=1e-9)
    assert abs(t0) == pytest.approx(abs(res.rated_element_torque[ls]), rel=1e-6)
    assert res.peak_element_torque[ls] > 1.5 * abs(t0)  # 2.2x here: the rotor takes most
    assert np.all(res.law_torque[res.time >= 0.4, 0] == 0.0)  # cleared: disconnected
