"""Interference diagram and separation margins (API 617 8th ed. 2014 / API RP 684 2nd ed. 2005:
each torsional natural frequency at least 10 % from every excitation frequency over the
operating speed range).

With an order line f_e = a·Ω the mode f_n is met at Ω_c = f_n / a; over [Ω_min, Ω_max] the
smallest relative separation |f_n − f_e| / f_e is Ω_c/Ω_max − 1 above the range, 1 − Ω_c/Ω_min
below it, and 0 inside it. A fixed line's is |f_n − f_e| / f_e.
"""

from __future__ import annotations

import numpy as np
import pytest

from gearrotor.analyses.torsional import interference, torsional_modes
from gearrotor.errors import ModelError
from torsional_helpers import disk, geared_train, shaft

RPM = np.pi / 30


def _pair(**extra):
    """Two inertias on one shaft: one mode at √(k (J1+J2)/(J1 J2)) = 500 rad/s (79.6 Hz)."""
    j1, j2 = 2.0, 2.0
    k = 500.0**2 * j1 * j2 / (j1 + j2)
    return geared_train([shaft("a", k, [disk(0, j1), disk(1, j2)])], speed="3000 rpm", **extra)


def _crossing(res, line):
    return [c for c in res.crossings if c.line == line]


def test_order_line_margins_above_in_and_below_the_range():
    wn = torsional_modes(_pair()).natural_frequency[1]
    wc = wn / 2.0  # the 2x line meets the mode at 2387 rpm
    for lo, hi, where, sm in [
        (2000, 2100, "above range", wc / (2100 * RPM) - 1),
        (2300, 2500, "in range", 0.0),
        (2700, 3000, "below range", 1 - wc / (2700 * RPM)),
    ]:
        res = interference(_pair(), speed_range=(lo * RPM, hi * RPM), diagram_speed=4000 * RPM)
        (c,) = _crossing(res, "2x a")
        assert c.location == where
        assert c.speed == pytest.approx(wc, rel=1e-12)
        assert c.margin == pytest.approx(sm, rel=1e-12)
        assert c.passes == (sm >= 0.10)
    # 1x meets the mode at 4775 rpm, above the diagram: not listed
    res = interference(_pair(), speed_range=(2000 * RPM, 2100 * RPM))
    assert not _crossing(res, "1x a")


def test_line_frequency_from_the_motor_and_fixed_line_margins():
    motor = {
        "type": "induction_motor",
        "shaft": "a",
        "node": 0,
        "rated_power": "50 kW",
        "poles": 2,
        "line_frequency": "50 Hz",
        "table": {"speed": ["0 rpm", "3000 rpm"], "torque": [300.0, 0.0]},
    }
    load = {"type": "constant", "shaft": "a", "node": 1, "torque": 100.0}
    t = _pair(torsional={"drives": [motor], "loads": [load]})
    res = interference(t, speed_range=(2900 * RPM, 2950 * RPM), margin=0.15)
    fn = res.modes.frequency_hz[1]
    (c50,) = _crossing(res, "line 50 Hz")
    (c100,) = _crossing(res, "2x line 100 Hz")
    assert c50.margin == pytest.approx((fn - 50) / 50, rel=1e-12)
    assert c100.margin == pytest.approx((100 - fn) / 100, rel=1e-12)
    assert c100.passes and c50.passes == (c50.margin >= 0.15)
    d = res.to_dict()
    assert d["required_margin"] == 0.15 and "API 617 8th ed. (2014)" in d["basis"]
    assert d["passes"] == all(c["passes"] for c in d["crossings"])


def test_vfd_harmonics_are_multiples_of_the_stator_frequency():
    motor = {
        "type": "induction_motor",
        "shaft": "a",
        "node": 0,
        "rated_power": "50 kW",
        "poles": 4,
        "line_frequency": "60 Hz",
        "table": {"speed": ["0 rpm", "1800 rpm"], "torque": [300.0, 0.0]},
    }
    load = {"type": "constant", "shaft": "a", "node": 1, "torque": 100.0}
    t = _pair(torsional={"drives": [motor], "loads": [load]})
    res = interference(t, speed_range=(600 * RPM, 1800 * RPM), vfd_harmonics=(6,))
    (line,) = [ln for ln in res.lines if ln.kind == "electrical"]
    # 6 f_e with f_e = (poles/2) × shaft speed: slope 12 on the shaft speed
    assert line.slope(res.modes.model.speed_ratio) == pytest.approx(12.0)
    (c,) = _crossing(res, line.label)
    assert c.speed == pytest.approx(res.modes.natural_frequency[1] / 12, rel=1e-12)


def test_interference_input_errors():
    with pytest.raises(ModelError, match="speed_range"):
        interference(_pair(), speed_range=(3000 * RPM, 2000 * RPM))
    with pytest.raises(ModelError, match="vfd_drive"):
        interference(_pair(), speed_range=(1, 2), vfd_harmonics=(6,))
    with pytest.raises(ModelError, match="margin"):
        interference(_pair(), speed_range=(1, 2), margin=1.5)
