"""Drive and load laws, and their input validation.

* Induction motor: the Thevenin-form torque of the Steinmetz equivalent circuit against a
  direct phasor solution of the same circuit (air-gap power 3 |I2|² R2/s over Ω_s); and
  Chapman, *Electric Machinery Fundamentals*, 4th ed. 2005, Example 7-5 (460 V, 4-pole, 60 Hz,
  R1 0.641, R2 0.332, X1 1.106, X2 0.464, XM 26.3 Ω): T_max 229 N·m at s = 0.198, T_start
  104 N·m. The book approximates the Thevenin impedance (X_TH ≈ X1, R_TH ≈ R1 (XM/(X1+XM))²);
  the exact one used here gives 0.8 % more pull-out torque and 2.6 % more starting torque.
* Synchronous start-up: the pulsating torque T_p sin 2δ, δ = ω_e t − p/2 θ, at constant slip
  s is T_p sin(2 s ω_e t) (frequency 2 s f_line).
* Short circuit: the module's form, T_r [a0 e^(−τ/τ0) + a1 e^(−τ/τ1) sin ωτ − a2 e^(−τ/τ2)
  sin 2ωτ], zero after clearing.
"""

from __future__ import annotations

import numpy as np
import pytest

from gearrotor.analyses.torsional import pack_laws, torsional_transient
from gearrotor.analyses.torsional.drive_laws import advance_states, evaluate
from gearrotor.errors import ModelError
from gearrotor.io.model_file import model_from_dict
from torsional_helpers import disk, geared_train, shaft

CHAPMAN = {"r1": 0.641, "x1": 1.106, "r2": 0.332, "x2": 0.464, "xm": 26.3, "voltage": "460 V"}
START = {
    "slip": [1.0, 0.5, 0.05, 0.0],
    "average": [1.0, 0.8, 1.5, 0.0],
    "pulsating": [0.6, 0.4, 0.2, 0.1],
}


def _train(drive=None, loads=None, **extra):
    drive = drive or {"type": "induction_motor", "circuit": CHAPMAN}
    base = {
        "shaft": "a",
        "node": 0,
        "rated_power": "18.65 kW",
        "poles": 4,
        "line_frequency": "60 Hz",
    }
    if drive.get("type") == "torque":
        base = {"shaft": "a", "node": 0, "rated_power": "10 kW", "rated_speed": "1500 rpm"}
    tors = {
        "drives": [{**base, **drive}],
        "loads": loads
        if loads is not None
        else [
            {"type": "quadratic", "shaft": "a", "node": 1, "torque": "100 N*m", "speed": "1800 rpm"}
        ],
    }
    return geared_train(
        [shaft("a", 1e5, [disk(0, 2.0), disk(1, 1.0)])], speed="1800 rpm", torsional=tors, **extra
    )


def _direct_circuit_torque(s):
    """Air-gap torque of the Chapman circuit solved as a network (no Thevenin step)."""
    c = CHAPMAN
    v = 460 / np.sqrt(3)
    z2 = c["r2"] / s + 1j * c["x2"]
    zm = 1j * c["xm"]
    z = c["r1"] + 1j * c["x1"] + zm * z2 / (zm + z2)
    i1 = v / z
    i2 = i1 * zm / (zm + z2)
    ws = 2 * np.pi * 60 / 2
    return 3 * abs(i2) ** 2 * c["r2"] / s / ws


def test_induction_circuit_torque_is_the_circuit_air_gap_power():
    laws = pack_laws(_train())
    ws = 2 * np.pi * 60 / 2
    slips = np.array([1.0, 0.6, 0.198, 0.05, 0.01, -0.02])
    got = evaluate(laws, 0, 0.0, 0.0, (1 - slips) * ws)
    np.testing.assert_allclose(got, [_direct_circuit_torque(s) for s in slips], rtol=1e-12)


def test_induction_motor_against_chapman_example_7_5():
    laws = pack_laws(_train())
    ws = 2 * np.pi * 60 / 2
    om = np.linspace(0, ws, 200001)
    T = evaluate(laws, 0, 0.0, 0.0, om)
    k = int(np.argmax(T))
    assert T[k] == pytest.approx(229, rel=0.012)  # exact Thevenin: +0.8 %
    assert 1 - om[k] / ws == pytest.approx(0.198, rel=0.03)
    assert T[0] == pytest.approx(104, rel=0.03)  # exact Thevenin: +2.6 %


def test_voltage_dip_scales_induction_torque_with_the_voltage_squared():
    drive = {
        "type": "induction_motor",
        "circuit": CHAPMAN,
        "voltage": {"time": [0.0, 1.0, 2.0], "factor": [1.0, 0.7, 0.7]},
    }
    laws = pack_laws(_train(drive))
    om = 0.8 * np.pi * 60
    t0, t1 = evaluate(laws, 0, [0.0, 1.5], 0.0, om)
    assert t1 / t0 == pytest.approx(0.49, rel=1e-12)


def test_synchronous_pulsation_at_twice_slip_frequency_and_pull_in():
    drive = {
        "type": "synchronous_motor",
        "start": START,
        "pull_out_torque": 2.0,
        "pull_in_slip": 0.05,
    }
    laws = pack_laws(_train(drive))
    tr = laws.rated_torque[0]
    ws, we = 2 * np.pi * 60 / 2, 2 * np.pi * 60
    s = 0.3
    om = (1 - s) * ws
    t = np.linspace(0, 0.2, 2001)
    avg = np.interp(s, [0, 0.05, 0.5, 1.0], [0.0, 1.5, 0.8, 1.0])
    puls = np.interp(s, [0, 0.05, 0.5, 1.0], [0.1, 0.2, 0.4, 0.6])
    got = evaluate(laws, 0, t, om * t, om)
    np.testing.assert_allclose(
        got, tr * (avg + puls * np.sin(2 * s * we * t)), rtol=1e-10, atol=1e-10 * tr
    )
    # pull-in at 5 % slip: synchronous torque T_po sin(δ − δ_p) starts at zero
    state = laws.new_state()
    om_in = 0.96 * ws
    th = 1.234
    assert advance_states(0.5, np.array([th]), np.array([om_in]), state, laws.par)
    assert state[0, 0] == 1.0
    at_pull_in = evaluate(laws, 0, 0.5, th, om_in, state)
    assert at_pull_in == pytest.approx(tr * np.interp(0.04, [0, 0.05], [0.0, 1.5]), rel=1e-10)
    later = evaluate(laws, 0, 0.5, th - 0.1, om_in, state)  # rotor behind: δ grows by 0.2
    assert later - at_pull_in == pytest.approx(2.0 * tr * np.sin(0.2), rel=1e-10)


@pytest.mark.parametrize("kind, a2", [("three_phase", 0.0), ("two_phase", 2.5)])
def test_short_circuit_air_gap_torque(kind, a2):
    sc = {
        "type": kind,
        "time": "0.1 s",
        "clear_time": "0.4 s",
        "a0": 0.5,
        "tau0": "0.05 s",
        "a1": 4.0,
        "tau1": "0.12 s",
        "a2": a2,
        "tau2": "0.08 s",
    }
    laws = pack_laws(
        _train(
            {
                "type": "synchronous_motor",
                "start": START,
                "pull_out_torque": 2.0,
                "short_circuit": sc,
            }
        )
    )
    tr = laws.rated_torque[0]
    w = 2 * np.pi * 60
    t = np.linspace(0.1, 0.39, 300)
    tau = t - 0.1
    ref = tr * (
        0.5 * np.exp(-tau / 0.05)
        + 4 * np.exp(-tau / 0.12) * np.sin(w * tau)
        - a2 * np.exp(-tau / 0.08) * np.sin(2 * w * tau)
    )
    np.testing.assert_allclose(
        evaluate(laws, 0, t, 0.0, 0.9 * w / 2), ref, rtol=1e-12, atol=1e-12 * tr
    )
    assert evaluate(laws, 0, 0.41, 0.0, 0.9 * w / 2) == 0.0


def test_trip_and_load_steps():
    laws = pack_laws(
        _train(
            {"type": "torque", "value": "60 N*m", "trip_time": "1 s"},
            loads=[
                {
                    "type": "constant",
                    "shaft": "a",
                    "node": 1,
                    "torque": "40 N*m",
                    "steps": [{"time": "0.5 s", "factor": 0.5}, {"time": "2 s", "factor": 0.0}],
                }
            ],
        )
    )
    np.testing.assert_allclose(evaluate(laws, 0, [0.0, 0.99, 1.0], 0.0, 10.0), [60, 60, 0])
    np.testing.assert_allclose(evaluate(laws, 1, [0.0, 0.5, 1.9, 2.0], 0.0, 10.0), [40, 20, 20, 0])
    assert list(laws.is_drive) == [True, False]


def test_tables_hold_their_ends():
    laws = pack_laws(
        _train(
            {"type": "torque", "table": {"speed": ["0 rpm", "1000 rpm"], "torque": [50.0, 80.0]}},
            loads=[
                {
                    "type": "table",
                    "shaft": "a",
                    "node": 1,
                    "table": {"speed": ["0 rpm", "1500 rpm"], "torque": [0.0, 30.0]},
                }
            ],
        )
    )
    w = np.array([0.0, 500, 1000, 2000]) * np.pi / 30
    np.testing.assert_allclose(evaluate(laws, 0, 0.0, 0.0, w), [50, 65, 80, 80])
    np.testing.assert_allclose(evaluate(laws, 1, 0.0, 0.0, w), [0, 10, 20, 30])


# ---- bad input ---------------------------------------------------------------------------
def _error(drive=None, loads=None, **extra) -> str:
    with pytest.raises(ModelError) as exc:
        _train(drive, loads, **extra)
    return str(exc.value)


def test_torque_speed_table_not_monotone_in_speed():
    msg = _error({"type": "torque", "table": {"speed": [0.0, 100.0, 90.0], "torque": [1, 2, 3]}})
    assert "torsional.drives[0].torque.table" in msg
    assert "strictly increasing" in msg and "speed[2] = 90" in msg


def test_load_table_not_monotone_in_speed():
    msg = _error(
        loads=[
            {
                "type": "table",
                "shaft": "a",
                "node": 1,
                "table": {"speed": [0.0, 50.0, 50.0], "torque": [0, 1, 2]},
            }
        ]
    )
    assert "torsional.loads[0].table" in msg and "strictly increasing" in msg


@pytest.mark.parametrize("slip", [[1.2, 0.5, 0.0], [1.0, 0.5, -0.1]])
def test_slip_outside_zero_to_one(slip):
    start = {"slip": slip, "average": [1, 1, 0], "pulsating": [0.5, 0.3, 0.1]}
    msg = _error({"type": "synchronous_motor", "start": start, "pull_out_torque": 2.0})
    assert "torsional.drives[0].synchronous_motor.start" in msg
    assert "outside 0..1" in msg


def test_other_drive_input_errors():
    assert "poles must be even" in _error(
        {"type": "induction_motor", "circuit": CHAPMAN, "poles": 3}
    )
    sc = {"type": "three_phase", "time": 0.1, "a1": 4.0, "tau1": 0.1, "a2": 1.0}
    assert "no twice-line-frequency" in _error(
        {"type": "synchronous_motor", "start": START, "pull_out_torque": 2.0, "short_circuit": sc}
    )
    assert "exactly one of 'circuit'" in _error({"type": "induction_motor"})
    msg = _error({"type": "induction_motor", "circuit": CHAPMAN, "node": 7})
    assert "torsional.drives[0].node" in msg and "0..1" in msg


def test_drive_without_load_path():
    """A motor on a shaft joined to the loaded shaft by a coupling without torsional stiffness
    (and one alone in a train without loads) has nowhere to send its torque."""
    t = geared_train(
        [
            shaft("m", 1e5, [disk(0, 2.0), disk(1, 0.5)]),
            shaft("c", 1e5, [disk(0, 0.5), disk(1, 1.0)], start=0.6),
        ],
        couplings=[
            {
                "node_i": {"shaft": "m", "node": 1},
                "node_j": {"shaft": "c", "node": 0},
                "kx": 1e8,
                "ky": 1e8,
            }
        ],
        torsional={
            "drives": [
                {
                    "type": "torque",
                    "shaft": "m",
                    "node": 0,
                    "value": 100.0,
                    "rated_power": "10 kW",
                    "rated_speed": "1000 rpm",
                }
            ],
            "loads": [{"type": "constant", "shaft": "c", "node": 1, "torque": 50.0}],
        },
    )
    with pytest.raises(ModelError, match=r"torsional.drives\[0\]: no load path"):
        torsional_transient(t, t_end=0.1)
    data = t.model_dump()
    data["torsional"]["loads"] = []
    with pytest.raises(ModelError, match="no load path"):
        torsional_transient(model_from_dict(data), t_end=0.1)


def test_the_documented_schema_validates():
    """docs/torsional.md's [torsional] example is valid input (kept in step with the model)."""
    import re
    import tomllib
    from pathlib import Path

    from gearrotor.model import Torsional

    doc = Path(__file__).resolve().parents[2] / "docs" / "torsional.md"
    (block,) = re.findall(r"```toml\n(.*?)```", doc.read_text(), flags=re.S)
    tors = Torsional.model_validate(tomllib.loads(block)["torsional"])
    assert [d.type for d in tors.drives] == ["synchronous_motor", "induction_motor", "torque"]
    assert tors.drives[0].rated_torque == pytest.approx(10e6 / (1800 * np.pi / 30))
