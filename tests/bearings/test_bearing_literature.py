"""Agreement with published isoviscous bearing tables.

Sources
-------
.. [RB] Raimondi, A. A. & Boyd, J. (1958). A solution for the finite journal bearing and its
   application to analysis and design: III. ASLE Transactions 1(1), 194–209. Full (360°)
   bearing, L/D = 1, Reynolds (Swift–Stieber) boundary condition, oil fed at zero pressure at
   the maximum film (the film starts there). Their table of S and φ vs ε (as reproduced in
   Shigley's Mechanical Engineering Design, chapter 12).
.. [LT] Lund, J. W. & Thomsen, K. K. (1978). A calculation method and data for the dynamic
   coefficients of oil-lubricated journal bearings. In: Topics in Fluid Film Bearing and
   Rotor Bearing System Design and Optimization, ASME, 1–28. Two-axial-groove bearing
   (two 160° pads, 20° grooves at the horizontal split), load downwards between the grooves,
   finite-difference Swift–Stieber solution. (The same rows are used by ROSS's literature
   tests.) Their frame has x along the load (down) and y horizontal in the direction of
   rotation; with our counter-clockwise rotation and load along −y that is x_LT = −y,
   y_LT = x, hence K_LT = [[kyy, −kyx], [−kxy, kxx]] (same for damping), with
   K̄ = K c/W and B̄ = C c ω/W. Their elliptical (lemon) bearing: two 160° lobes centred at
   the top and bottom, preload 0.5, L/D = 1; all their groups there use the PAD clearance
   c_p: S = μNLD/W (R/c_p)², ε = e/c_p, K̄ = K c_p/W, B̄ = C c_p ω/W.
"""

import math

import numpy as np
import pytest

from gearrotor.bearings import (
    FixedBearing,
    Grid,
    Pad,
    SolverOptions,
    axial_groove,
    coefficients,
    elliptical,
    film_state,
)

# (ε, S, φ deg) of [RB], L/D = 1
RAIMONDI_BOYD_LD1 = [
    (0.1, 1.33, 79.5),
    (0.2, 0.631, 74.02),
    (0.4, 0.264, 63.10),
    (0.6, 0.121, 50.58),
    (0.8, 0.0446, 36.24),
    (0.9, 0.0188, 26.45),
]


@pytest.mark.parametrize("eps, s_ref, phi_ref", RAIMONDI_BOYD_LD1)
def test_raimondi_boyd_full_bearing_ld1(eps, s_ref, phi_ref):
    """S within 2 % and φ within 0.6° on a 72×16 grid.

    Measured deviations (S %, φ deg): +0.14/−0.10, +0.29/−0.17, −1.16/−0.51, +0.21/−0.01,
    +0.39/+0.08, +0.97/+0.18. The ε = 0.4 row is the worst on every grid (−1.3 % at 144×24
    too), which points at the three-figure table entry rather than at the discretisation;
    2 % / 0.6° is the accuracy the printed charts/tables support.
    """
    d, c, mu, omega = 0.1, 1e-4, 0.02, 100.0
    r = d / 2
    # the 360° film starts at the maximum film: journal displaced towards θ = 0
    bearing = FixedBearing(d, d, c, mu, (Pad(math.pi, 2 * math.pi),))
    f = film_state(bearing, omega, eps * c, 0.0, options=SolverOptions(grid=Grid(72, 16)))
    w = -f.forces[:2]
    s = mu * omega / (2 * math.pi) * d * d * (r / c) ** 2 / math.hypot(*w)
    phi = -math.degrees(math.atan2(w[1], w[0]))
    assert s == pytest.approx(s_ref, rel=0.02)
    assert phi == pytest.approx(phi_ref, abs=0.6)


def test_plain_periodic_bearing_eccentricity_matches_raimondi_boyd():
    """The ungrooved, periodic plain bearing at equilibrium: ε within 0.01 of [RB] for the
    same S. (Its attitude angle differs by up to ~4° at small ε because the film is not forced
    to start at the maximum film — a real difference of boundary condition, not an error.)"""
    from gearrotor.bearings import equilibrium, plain

    d, c, mu, omega = 0.1, 1e-4, 0.02, 100.0
    b = plain(d, d, c, mu)
    for eps, s_ref, _ in RAIMONDI_BOYD_LD1[2:5]:
        w = mu * omega / (2 * math.pi) * d * d * (d / 2 / c) ** 2 / s_ref
        eq = equilibrium(b, (0.0, -w), omega, options=SolverOptions(grid=Grid(36, 8)))
        assert eq.eccentricity_ratio == pytest.approx(eps, abs=0.01)


# [LT] rows: (S, ε, φ, Kxx, Kxy, Kyx, Kyy, Bxx, Bxy, Byy)
LT_TWO_AXIAL_GROOVE = {
    0.5: [
        (1.656, 0.244, 65.85, 1.69, 5.06, -2.20, 1.95, 9.93, 2.15, 4.80),
        (0.917, 0.372, 57.45, 2.12, 4.01, -1.30, 1.85, 7.70, 2.06, 3.23),
        (0.580, 0.477, 51.01, 2.67, 3.70, -0.78, 1.75, 6.96, 1.94, 2.40),
        (0.379, 0.570, 45.43, 3.33, 3.64, -0.43, 1.68, 6.76, 1.87, 1.89),
        (0.244, 0.655, 40.25, 4.21, 3.74, -0.13, 1.64, 6.87, 1.82, 1.54),
    ],
    1.0: [
        (0.991, 0.150, 70.58, 1.56, 7.29, -2.16, 1.52, 14.66, 1.58, 4.49),
        (0.635, 0.224, 63.54, 1.62, 5.33, -1.57, 1.56, 10.80, 1.70, 3.41),
        (0.235, 0.460, 49.27, 2.19, 3.57, -0.80, 1.55, 7.36, 1.89, 2.19),
        (0.159, 0.559, 44.33, 2.73, 3.36, -0.48, 1.48, 6.94, 1.78, 1.74),
        (0.108, 0.650, 39.72, 3.45, 3.34, -0.23, 1.44, 6.89, 1.72, 1.43),
    ],
}
_LT_CASES = [(ld, row) for ld, rows in LT_TWO_AXIAL_GROOVE.items() for row in rows]


@pytest.mark.parametrize("ld, row", _LT_CASES, ids=[f"LD{ld}-S{row[0]}" for ld, row in _LT_CASES])
def test_lund_thomsen_two_axial_groove(ld, row):
    """ε within 0.005, φ within 0.3°, each dimensionless coefficient within 0.05 + 3 %.

    Measured on the default 36×8 grid: ε ≤ 0.002, φ ≤ 0.11°, coefficients ≤ 0.11 absolute
    (Byy at S = 0.917 / L/D = 0.5: 3.34 vs 3.23, the worst; most within 0.03). The tables
    print two decimals and come from a coarser 1978 finite-difference grid, so a few
    hundredths plus a few percent is what they support.
    """
    s, eps, phi, *ref = row
    d, c, mu, rpm = 0.1, 100e-6, 0.02, 3000.0
    omega = rpm * math.pi / 30
    length = ld * d
    w = mu * rpm / 60 * length * d * (d / 2 / c) ** 2 / s
    b = axial_groove(d, length, c, mu, n_grooves=2, groove_arc=math.radians(20.0))
    co = coefficients(b, (0.0, -w), omega, options=SolverOptions(grid=Grid(36, 8)))
    assert co.sommerfeld == pytest.approx(s, rel=1e-12)
    assert co.equilibrium.eccentricity_ratio == pytest.approx(eps, abs=0.005)
    assert math.degrees(co.equilibrium.attitude_angle) == pytest.approx(phi, abs=0.3)
    k, b_ = co.dimensionless(c)
    ours = [k[1, 1], -k[1, 0], -k[0, 1], k[0, 0], b_[1, 1], -b_[1, 0], b_[0, 0]]
    np.testing.assert_allclose(ours, ref, rtol=0.03, atol=0.05)


# [LT] elliptical bearing rows: (S, ε, φ, Kxx, Kxy, Kyx, Kyy, Bxx, Bxy, Byy), pad clearance
LT_ELLIPTICAL = [
    (0.211, 0.260, 87.79, 6.65, 4.36, -3.21, 0.86, 13.09, -2.23, 3.70),
    (0.161, 0.304, 83.29, 5.63, 3.84, -2.32, 1.01, 10.75, -1.02, 3.07),
    (0.120, 0.350, 81.80, 4.99, 3.54, -1.52, 1.14, 9.04, -0.01, 2.49),
    (0.097, 0.381, 78.65, 4.82, 3.46, -1.01, 1.21, 8.26, 0.56, 2.10),
]


@pytest.mark.parametrize("row", LT_ELLIPTICAL, ids=[f"S{r[0]}" for r in LT_ELLIPTICAL])
def test_lund_thomsen_elliptical_preload(row):
    """Preloaded lobes (m = 0.5) on a 72×16 grid: ε within 0.005, coefficients within
    0.05 + 3 % (measured ≤ 0.03 except Bxy 0.53 vs 0.56), φ within 0.3° — except the
    S = 0.161 row, printed 83.29° where we get 85.28° on every grid: the neighbouring rows
    agree within 0.07°, and 85.3° lies on their smooth trend (87.8, 85.3, 81.8, 78.6), so the
    printed value looks like a typo (ROSS's test makes the same observation)."""
    s, eps, phi, *ref = row
    d, mu, rpm, cp, m = 0.1, 0.02, 3000.0, 200e-6, 0.5
    c = cp * (1 - m)
    w = mu * rpm / 60 * d * d * (d / 2 / cp) ** 2 / s
    b = elliptical(d, d, c, mu, preload=m, groove_arc=math.radians(20.0))
    co = coefficients(b, (0.0, -w), rpm * math.pi / 30, options=SolverOptions(grid=Grid(72, 16)))
    assert co.equilibrium.eccentricity_ratio * c / cp == pytest.approx(eps, abs=0.005)
    att = math.degrees(co.equilibrium.attitude_angle)
    assert att == pytest.approx(85.3 if s == 0.161 else phi, abs=0.3)
    k, b_ = co.dimensionless(cp)
    ours = [k[1, 1], -k[1, 0], -k[0, 1], k[0, 0], b_[1, 1], -b_[1, 0], b_[0, 0]]
    np.testing.assert_allclose(ours, ref, rtol=0.03, atol=0.05)
