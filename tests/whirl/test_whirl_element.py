"""The element of a speed × whirl table (issue 24): what it answers on and off the whirl axis.

Oracles: the definitions in ``gearrotor/elements/whirl_bearing.py`` checked by hand: linear
interpolation in whirl within a row, then in speed; the synchronous coefficients each row's at
its own speed, linear in speed; off the axis the rows' fitted impedances blended linearly in
speed, for every s (a convex combination of two rational functions is one, realised by the
union of their states).
"""

import numpy as np
import pytest

from gearrotor.elements import WhirlBearing, fit_rows
from gearrotor.errors import ModelError


def _row(speed, scale):
    """A Maxwell-type row: Z = k1 + k2 c s / (k2 + c s), scaled (exactly rational, one pole)."""
    whirl = np.linspace(0.0, 2000.0, 9)
    k1, k2, c = 2e7 * scale, 3e7 * scale, 2e4

    def z(s):
        return k1 + k2 * c * s / (k2 + c * s)

    vals = np.zeros((9, 8))
    for j, w in enumerate(whirl):
        zz = z(1j * max(w, 1e-9))
        vals[j, [0, 3]] = zz.real
        vals[j, [4, 7]] = zz.imag / max(w, 1e-9)
        vals[j, 1], vals[j, 2] = 1e6 * scale, -1e6 * scale  # cross-coupled, whirl-independent
    return (speed, whirl, vals), z


@pytest.fixture(scope="module")
def element():
    (r1, z1), (r2, z2) = _row(500.0, 1.0), _row(1500.0, 1.5)
    rows = fit_rows([r1, r2], 1e-10, field="test")
    return WhirlBearing(rows), (r1, r2), (z1, z2)


def test_coefficients_on_the_whirl_axis(element):
    el, (r1, r2), _ = element
    # at a row's speed and a tabulated whirl frequency: the table
    np.testing.assert_array_equal(el.coefficients(500.0, whirl=r1[1][3]), r1[2][3])
    # bilinear: linear in whirl inside each row, then in speed
    w = 0.5 * (r1[1][3] + r1[1][4])
    a = 0.5 * (r1[2][3] + r1[2][4])
    b = 0.5 * (r2[2][3] + r2[2][4])
    np.testing.assert_allclose(el.coefficients(750.0, whirl=w), 0.75 * a + 0.25 * b, rtol=1e-14)
    # synchronous: each row at its own speed, linear in speed between them
    s1 = np.array([np.interp(500.0, r1[1], r1[2][:, j]) for j in range(8)])
    s2 = np.array([np.interp(1500.0, r2[1], r2[2][:, j]) for j in range(8)])
    np.testing.assert_allclose(el.coefficients(1000.0), 0.5 * (s1 + s2), rtol=1e-14)
    np.testing.assert_array_equal(el.K(1000.0), el.coefficients(1000.0)[:4].reshape(2, 2))


def test_off_the_axis_the_rows_are_blended_for_every_s(element):
    el, _, (z1, z2) = element
    for s in (-200 + 700j, -900 + 30j, 50j):
        ref = np.array([[0.25 * z1(s) + 0.75 * z2(s), 0.0], [0.0, 0.0]])
        ref[1, 1] = ref[0, 0]
        ref[0, 1], ref[1, 0] = 0.25 * 1e6 + 0.75 * 1.5e6, -(0.25 * 1e6 + 0.75 * 1.5e6)
        np.testing.assert_allclose(el.impedance(1250.0, s), ref, rtol=1e-10)
    # between two rows both rows' states; at a row's speed its own only
    assert el.realization(1250.0).n_states == 4
    assert el.realization(500.0).n_states == 2


def test_outside_the_speeds(element):
    el, *_ = element
    with pytest.raises(ModelError, match="outside the bearing coefficient table"):
        el.coefficients(2000.0)
    with pytest.raises(ModelError, match="outside the bearing coefficient table"):
        el.realization(100.0)
    held = WhirlBearing(el.rows, "hold")
    np.testing.assert_array_equal(held.coefficients(2000.0), held.coefficients(1500.0))
    assert held.realization(100.0).n_states == 2
