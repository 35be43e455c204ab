"""Liquid annular seals against measurements: Kanki & Kawakami (1984), "Experimental study on
the dynamic characteristics of pump annular seals", IMechE Conf. Vibrations in Rotating
Machinery, C297/84, pp. 159-166; water seals of radius 100 mm and clearance 0.5 mm at 2000 rpm
with 0.98 MPa across them.

Measured: the long seal (L = 200 mm, no inlet swirl) leaks 4634 cm³/s with K = 3.59 MN/m,
k = 10.8 MN/m, C = 147 kN·s/m, c = 55.3 kN·s/m, M = 221.5 kg; the short seal (L = 40 mm,
inlet swirl 0.2) leaks 9047 cm³/s with K = 3.96/4.01 MN/m, k = 0.664/0.337 MN/m (the two
directions measured). Tolerances: bulk-flow theory predicts the leakage of plain liquid seals
within about 10 %, the direct damping within 20 % and the stiffness and added mass within
about 40-50 % of such tests (Childs 1993, Turbomachinery Rotordynamics, §4.6, and the theory-
test comparisons cited there); each bound below is that spread, not a fit to our numbers.

Not tested: the short seal's measured direct damping (24.6 kN·s/m) is about twice what
bulk-flow theory gives (12.0 kN·s/m here, ~15 kN·s/m from Childs' short-seal formula); see
docs/seals.md.
"""

from __future__ import annotations

import pytest
from seal_cases import RPM, kanki_long, kanki_short

from gearrotor.seals import seal_coefficients


def test_kanki_kawakami_long_seal():
    seal = kanki_long()
    r = seal_coefficients(seal, 2000 * RPM)
    q = r.leakage / seal.fluid.rho * 1e6  # cm³/s
    K, k, C, c, M, _ = r.constant
    assert q == pytest.approx(4634.0, rel=0.12)
    assert C == pytest.approx(147e3, rel=0.20)
    assert c == pytest.approx(55.3e3, rel=0.20)
    assert K == pytest.approx(3.59e6, rel=0.40)
    assert M == pytest.approx(221.5, rel=0.45)
    assert k == pytest.approx(10.8e6, rel=0.50)


def test_kanki_kawakami_short_seal():
    seal = kanki_short()
    r = seal_coefficients(seal, 2000 * RPM)
    q = r.leakage / seal.fluid.rho * 1e6
    K, k, *_ = r.constant
    assert q == pytest.approx(9047.0, rel=0.10)
    assert K == pytest.approx(0.5 * (3.96e6 + 4.01e6), rel=0.20)
    assert k == pytest.approx(0.5 * (0.664e6 + 0.337e6), rel=0.30)


def test_liquid_seal_frequency_dependent_coefficients_hold_the_added_mass():
    """The coefficients at a whirl frequency Ω are the constant model's K − MΩ², k − mΩ², C, c
    (Childs' fit over 0.25ω-2ω reproduces the frequency-dependent ones)."""
    seal = kanki_long()
    w = 2000 * RPM
    K, k, C, c, M, m = seal_coefficients(seal, w).constant
    for ratio in (0.5, 1.5):
        om = ratio * w
        r = seal_coefficients(seal, w, om)
        assert r.kxx == pytest.approx(K - M * om**2, rel=0.02)
        assert r.cxx == pytest.approx(C, rel=0.02)
        assert r.kxy == pytest.approx(k - m * om**2, rel=0.02)


def test_interlock_versus_tooth_on_stator_trends():
    """Childs, Elrod & Hale (1988, ASME GT1988 V005T14A003), air tests of an interlock and a
    tooth-on-stator labyrinth to 16,000 cpm and 7.5 bar: "the interlock seal leaks substantially
    less than labyrinth seals" and "destabilizing forces are lower for the interlock seal". The
    same geometry with its teeth interlocking or on the stator, at preswirl 0.98 and 8000/16000
    rpm, shows both."""
    from dataclasses import replace

    from seal_cases import LAB

    for rpm in (8000, 16000):
        inter = seal_coefficients(replace(LAB, teeth_on="interlocking"), rpm * RPM)
        stator = seal_coefficients(replace(LAB, teeth_on="stator"), rpm * RPM)
        assert inter.leakage < 0.85 * stator.leakage
        assert 0 < inter.kxy < stator.kxy
