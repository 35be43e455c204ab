"""Rainflow counting, S–N curve and Miner's rule.

* ASTM E1049-85 (reapproved 2017), "Standard Practices for Cycle Counting in Fatigue Analysis",
  §5.4.4 rainflow counting, Fig. 6: the history −2, 1, −3, 5, −1, 3, −4, 4, −2 counts
  range 3: 0.5, 4: 1.5, 6: 0.5, 8: 1.0, 9: 0.5 cycles (the standard's Fig. 6(c) table).
* Miner's rule on a constant-amplitude history of N full cycles from peak to peak: every
  reversal pair is one half cycle of range 2A, so D = N / N_f(A) exactly.
"""

from __future__ import annotations

import numpy as np
import pytest

from gearrotor.analyses.torsional import SNCurve, miner_damage, rainflow_cycles
from gearrotor.analyses.torsional.fatigue import turning_points
from gearrotor.errors import ModelError

ASTM = [-2, 1, -3, 5, -1, 3, -4, 4, -2]
ASTM_COUNTS = {3.0: 0.5, 4.0: 1.5, 6.0: 0.5, 8.0: 1.0, 9.0: 0.5}


def _histogram(ranges, counts):
    out = {}
    for r, c in zip(ranges, counts, strict=True):
        out[float(r)] = out.get(float(r), 0.0) + float(c)
    return out


def test_rainflow_reproduces_astm_e1049_fig6():
    rng, mean, cnt = rainflow_cycles(ASTM)
    assert _histogram(rng, cnt) == ASTM_COUNTS
    assert cnt.sum() == pytest.approx(4.0)  # 8 half cycles


def test_turning_points_do_not_change_the_count():
    """Sampling the ASTM history finely (linear ramps, plateaus) leaves the same reversals."""
    fine = np.concatenate(
        [np.linspace(a, b, 7)[:-1] for a, b in zip(ASTM, ASTM[1:], strict=False)]
        + [[ASTM[-1], ASTM[-1]]]
    )
    np.testing.assert_array_equal(turning_points(fine), ASTM)
    rng, _, cnt = rainflow_cycles(fine)
    assert _histogram(rng, cnt) == ASTM_COUNTS


@pytest.mark.parametrize("n_cycles", [1, 7, 250])
def test_miner_sum_of_a_constant_amplitude_history(n_cycles):
    amp = 80e6
    sn = SNCurve.from_point(m=6.0, stress="200 MPa", cycles=1e5)
    t = np.linspace(0, n_cycles, 40 * n_cycles + 1)
    history = 30e6 + amp * np.cos(2 * np.pi * t)  # a mean does nothing without Goodman
    d, cycles, amax = miner_damage(history, sn)
    nf = 1e5 * (200e6 / amp) ** 6
    assert d == pytest.approx(n_cycles / nf, rel=1e-9)
    assert cycles == pytest.approx(n_cycles)
    assert amax == pytest.approx(amp, rel=1e-12)


def test_endurance_limit_range_measure_and_goodman():
    sn = SNCurve.from_point(m=5.0, stress="100 MPa", cycles=1e6, endurance_limit="50 MPa")
    below = 40e6 * np.cos(np.linspace(0, 20 * np.pi, 401))
    assert miner_damage(below, sn)[0] == 0.0
    # the same curve written for ranges: S_range = 2 S_a, C scaled by 2^m
    sn_r = SNCurve(m=5.0, C=sn.C * 2**5, measure="range")
    h = 90e6 * np.cos(np.linspace(0, 6 * np.pi, 301))
    assert miner_damage(h, sn_r)[0] == pytest.approx(miner_damage(h, SNCurve(5.0, sn.C))[0])
    # Goodman: S_eq = S_a / (1 - S_m / S_u)
    mean, su = 200e6, 800e6
    d_g = miner_damage(mean + h, SNCurve(5.0, sn.C), ultimate_strength=su)[0]
    assert d_g == pytest.approx(3 / sn.cycles_to_failure(90e6 / (1 - mean / su)), rel=1e-9)


@pytest.mark.parametrize("m", [0.0, -3.0, float("nan")])
def test_non_positive_sn_exponent_is_an_error(m):
    with pytest.raises(ModelError, match=r"sn_curve.m.*expected m > 0"):
        SNCurve(m=m, C=1e30)
    with pytest.raises(ModelError, match="sn_curve.m"):
        SNCurve.from_point(m=m, stress="100 MPa", cycles=1e6)


def test_bad_sn_constant_and_measure():
    with pytest.raises(ModelError, match="sn_curve.C"):
        SNCurve(m=3.0, C=-1.0)
    with pytest.raises(ModelError, match="sn_curve.measure"):
        SNCurve(m=3.0, C=1.0, measure="peak")
