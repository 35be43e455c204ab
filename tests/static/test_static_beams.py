"""Static deflection of single shafts against beam closed forms with shear deformation.

Timoshenko beam results (e.g. Timoshenko & Gere, Mechanics of Materials, and the unit-load
method with the shear term ∫V v/(κGA)): the shaft element's stiffness is exact for a uniform
Timoshenko beam and the weight is its consistent load, so nodal deflections, slopes and the
element end forces are exact; the tolerance 1e-8 allows for round-off only. Supports are
springs k whose settlement enters the closed forms exactly. Every test also checks equilibrium:
the ground reactions balance the applied loads to round-off.
"""

import numpy as np
import pytest

from gearrotor.analyses.static import static
from gearrotor.elements import shear_coefficient
from gearrotor.model import OperatingPoint
from helpers import single_shaft

E, NU, RHO, G0 = 211e9, 0.3, 7850.0, 9.80665
G = E / (2 * (1 + NU))
D = 0.05
A, I = np.pi * D**2 / 4, np.pi * D**4 / 64
KGA = shear_coefficient(0, D, NU) * G * A
KB = 2e9
REL = 1e-8


def _point(node, force):
    return OperatingPoint(
        name="p", gravity=False, forces=[{"shaft": "s", "node": node, "force": force}]
    )


def _equilibrium(res):
    scale = max(np.abs(res.applied).max(), 1.0)
    assert np.abs(res.residual).max() < 1e-9 * scale


def test_simply_supported_point_load():
    """Centre load P: δ = PL³/48EI + PL/4κGA + P/2k, ψ(0) = PL²/16EI, R = P/2, M = PL/4."""
    L, P = 1.0, 1000.0
    t = single_shaft(
        length=L, diameter=D, elements=10, bearings=[{"node": 0, "k": KB}, {"node": 10, "k": KB}]
    )
    res = static(t, _point(5, (0.0, -P, 0.0)))
    s = res.shaft("s")
    expect = P * L**3 / (48 * E * I) + P * L / (4 * KGA) + P / (2 * KB)
    assert -s.deflection[5, 1] == pytest.approx(expect, rel=REL)
    # θx = −dy/dz (conventions.md): the left end turns down the slope towards the load
    assert abs(s.deflection[0, 3]) == pytest.approx(P * L**2 / (16 * E * I), rel=REL)
    for b in res.bearings:
        assert b.force[1] == pytest.approx(-P / 2, rel=REL)
    assert np.max(np.abs(s.moment[:, 0])) == pytest.approx(P * L / 4, rel=REL)
    assert np.max(np.abs(s.shear[:, 1])) == pytest.approx(P / 2, rel=REL)
    assert np.max(s.von_mises) == pytest.approx(P * L / 4 * D / 2 / I, rel=REL)
    _equilibrium(res)


def test_simply_supported_weight():
    """Own weight w = ρAg: δ = 5wL⁴/384EI + wL²/8κGA + wL/2k, R = wL/2, M = wL²/8."""
    L = 1.2
    t = single_shaft(
        length=L,
        diameter=D,
        elements=12,
        density=RHO,
        bearings=[{"node": 0, "k": KB}, {"node": 12, "k": KB}],
    )
    res = static(t)  # weight only
    w = RHO * A * G0
    s = res.shaft("s")
    expect = 5 * w * L**4 / (384 * E * I) + w * L**2 / (8 * KGA) + w * L / (2 * KB)
    assert -s.deflection[6, 1] == pytest.approx(expect, rel=REL)
    for b in res.bearings:
        assert b.force[1] == pytest.approx(-w * L / 2, rel=REL)
    assert np.max(np.abs(s.moment[:, 0])) == pytest.approx(w * L**2 / 8, rel=REL)
    assert res.applied[1] == pytest.approx(-w * L, rel=1e-12)
    _equilibrium(res)


def test_overhung_point_load():
    """Span a, overhang b, tip load P (unit-load method): δ = Pb²(a+b)/3EI + Pb(1 + b/a)/κGA
    + P[(b/a)² + ((a+b)/a)²]/k; reactions −Pb/a and P(a+b)/a."""
    a, b, P = 0.8, 0.3, 500.0
    n = 22  # 0.05 m elements: bearings at nodes 0 and 16, tip at node 22
    t = single_shaft(
        length=a + b, diameter=D, elements=n, bearings=[{"node": 0, "k": KB}, {"node": 16, "k": KB}]
    )
    res = static(t, _point(n, (0.0, -P, 0.0)))
    s = res.shaft("s")
    expect = (
        P * b**2 * (a + b) / (3 * E * I)
        + P * b * (1 + b / a) / KGA
        + P * ((b / a) ** 2 + ((a + b) / a) ** 2) / KB
    )
    assert -s.deflection[n, 1] == pytest.approx(expect, rel=REL)
    assert res.bearings[0].force[1] == pytest.approx(P * b / a, rel=REL)
    assert res.bearings[1].force[1] == pytest.approx(-P * (a + b) / a, rel=REL)
    assert np.max(np.abs(s.moment[:, 0])) == pytest.approx(P * b, rel=REL)
    _equilibrium(res)


def test_overhung_weight():
    """Own weight on span a with overhang b: reactions from statics, R2 = w(a+b)²/2a,
    R1 = w(a+b) − R2, and the bending moment wb²/2 over the support at the overhang."""
    a, b = 0.8, 0.3
    t = single_shaft(
        length=a + b,
        diameter=D,
        elements=22,
        density=RHO,
        bearings=[{"node": 0, "k": KB}, {"node": 16, "k": KB}],
    )
    res = static(t)
    w = RHO * A * G0
    r2 = w * (a + b) ** 2 / (2 * a)
    assert res.bearings[1].force[1] == pytest.approx(-r2, rel=REL)
    assert res.bearings[0].force[1] == pytest.approx(-(w * (a + b) - r2), rel=REL)
    s = res.shaft("s")
    at_support = np.isclose(s.z_section, a)
    assert np.abs(s.moment[at_support, 0]) == pytest.approx(w * b**2 / 2, rel=REL)
    _equilibrium(res)


def test_three_bearing_continuous_beam():
    """Two equal spans L on three spring supports under own weight (statically indeterminate):
    the centre reaction from compatibility of a 2L simply supported beam,
    R_m = (δ_w + wL/k) / (f_R + 1.5/k), δ_w = 5w(2L)⁴/384EI + w(2L)²/8κGA,
    f_R = (2L)³/48EI + 2L/4κGA; Euler–Bernoulli on rigid supports gives 5wL/4 (the classic
    continuous-beam result), which it approaches for a slender shaft."""
    L = 0.6
    t = single_shaft(
        length=2 * L,
        diameter=D,
        elements=12,
        density=RHO,
        bearings=[{"node": 0, "k": KB}, {"node": 6, "k": KB}, {"node": 12, "k": KB}],
    )
    res = static(t)
    w = RHO * A * G0
    dw = 5 * w * (2 * L) ** 4 / (384 * E * I) + w * (2 * L) ** 2 / (8 * KGA)
    fr = (2 * L) ** 3 / (48 * E * I) + 2 * L / (4 * KGA)
    rm = (dw + w * L / KB) / (fr + 1.5 / KB)
    assert -res.bearings[1].force[1] == pytest.approx(rm, rel=REL)
    assert -res.bearings[0].force[1] == pytest.approx((2 * w * L - rm) / 2, rel=REL)
    assert rm == pytest.approx(5 * w * L / 4, rel=2e-3)  # slender: near the classic value
    _equilibrium(res)


def test_gravity_direction_and_static_moment():
    """Gravity along +x loads the bearings along +x; a static moment M at mid-span of a simply
    supported shaft gives reactions ±M/L."""
    L = 1.0
    t = single_shaft(
        length=L,
        diameter=D,
        elements=10,
        density=RHO,
        bearings=[{"node": 0, "k": KB}, {"node": 10, "k": KB}],
    )
    res = static(t, OperatingPoint(name="x", gravity_direction=(2.0, 0.0, 0.0)))
    w = RHO * A * G0
    assert [b.force[0] for b in res.bearings] == pytest.approx([w * L / 2] * 2, rel=REL)
    op = OperatingPoint(
        name="m", gravity=False, forces=[{"shaft": "s", "node": 5, "moment": (0.0, 100.0, 0)}]
    )
    res = static(t, op)
    fx = [b.force[0] for b in res.bearings]
    assert fx[0] == pytest.approx(-fx[1], rel=REL)
    assert abs(fx[0]) == pytest.approx(100.0 / L, rel=REL)
    _equilibrium(res)
