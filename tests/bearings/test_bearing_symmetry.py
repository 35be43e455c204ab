"""Symmetry, reciprocity and self-consistency of equilibrium and coefficients."""

import math
from dataclasses import replace

import numpy as np
import pytest

from gearrotor.bearings import (
    FixedBearing,
    Grid,
    Pocket,
    SolverOptions,
    coefficients,
    equilibrium,
    multilobe,
    plain,
    tilting_pad,
)

OPTS = SolverOptions(grid=Grid(36, 8))
DEG = math.pi / 180


def _rot(a):
    return np.array([[math.cos(a), -math.sin(a)], [math.sin(a), math.cos(a)]])


def _dam_bearing():
    pk = Pocket(0.0, 60 * DEG, 0.090, 0.22e-3)
    return multilobe(0.140, 0.130, 152.4e-6, 0.0152, [52.5 * DEG, 172.5 * DEG, 292.5 * DEG],
                     97 * DEG, 0.33, 0.5, {1: pk, 2: pk}, name="3-lobe dam")


def _mirror_y(bearing: FixedBearing) -> FixedBearing:
    """Mirror image about the y axis (θ → π − θ): pads, offsets and pockets reflected."""
    pads = []
    for p in bearing.pads:
        pocket = p.pocket
        if pocket is not None:
            pocket = replace(pocket, start=p.arc - pocket.start - pocket.arc)
        pads.append(replace(p, start=math.pi - p.start - p.arc, offset=1.0 - p.offset,
                            pocket=pocket))
    return replace(bearing, pads=tuple(pads))


def test_plain_bearing_rotated_load_gives_rotated_coefficients():
    b = plain(0.1, 0.05, 1e-4, 0.02)
    w, omega = 2000.0, 300.0
    base = coefficients(b, (0.0, -w), omega, options=OPTS)
    for a in (37 * DEG, 160 * DEG):
        load = _rot(a) @ np.array([0.0, -w])
        co = coefficients(b, tuple(load), omega, options=OPTS)
        q = _rot(a)
        np.testing.assert_allclose(co.K, q @ base.K @ q.T, rtol=0, atol=1e-2 * abs(base.K).max())
        np.testing.assert_allclose(co.C, q @ base.C @ q.T, rtol=0, atol=1e-2 * abs(base.C).max())
        assert co.equilibrium.eccentricity_ratio == pytest.approx(
            base.equilibrium.eccentricity_ratio, abs=2e-4)


def test_plain_bearing_damping_symmetric_and_reversed_rotation_mirrors():
    b = plain(0.1, 0.05, 1e-4, 0.02)
    w, omega = 2000.0, 300.0
    fwd = coefficients(b, (0.0, -w), omega, options=OPTS)
    rev = coefficients(b, (0.0, -w), -omega, options=OPTS)
    # Cxy = Cyx (the damping of a plain bearing is symmetric; [LT], Someya databook)
    assert fwd.C[0, 1] == pytest.approx(fwd.C[1, 0], rel=1e-3)
    s = np.diag([-1.0, 1.0])
    np.testing.assert_allclose(rev.K, s @ fwd.K @ s, rtol=1e-6, atol=1e-6 * abs(fwd.K).max())
    np.testing.assert_allclose(rev.C, s @ fwd.C @ s, rtol=1e-6, atol=1e-6 * abs(fwd.C).max())
    assert rev.equilibrium.x == pytest.approx(-fwd.equilibrium.x, rel=1e-6)
    assert rev.equilibrium.attitude_angle == pytest.approx(fwd.equilibrium.attitude_angle,
                                                           rel=1e-6)
    assert fwd.equilibrium.attitude_angle > 0


def test_pressure_dam_mirror_geometry_with_reversed_rotation():
    """A non-symmetric bearing (3-lobe with dams) and its mirror image turning the other way
    under the mirrored load have mirrored equilibria and coefficients."""
    b = _dam_bearing()
    bm = _mirror_y(b)
    omega = 10800 * math.pi / 30
    load = (4978.0, 11352.0)
    co = coefficients(b, load, omega, options=OPTS)
    cm = coefficients(bm, (-load[0], load[1]), -omega, options=OPTS)
    s = np.diag([-1.0, 1.0])
    np.testing.assert_allclose(cm.K, s @ co.K @ s, rtol=0, atol=1e-6 * abs(co.K).max())
    np.testing.assert_allclose(cm.C, s @ co.C @ s, rtol=0, atol=1e-6 * abs(co.C).max())
    assert cm.equilibrium.x == pytest.approx(-co.equilibrium.x, rel=1e-6)
    # and the dam matters: running the unmirrored bearing backwards is a different bearing
    back = coefficients(b, load, -omega, options=OPTS)
    assert abs(back.K[1, 1] / co.K[1, 1] - 1) > 0.05


@pytest.mark.parametrize("which", ["plain", "dam"])
def test_perturbation_coefficients_match_equilibrium_map(which):
    """K from perturbing the film equals the inverse of ∂(x, y)/∂W of the equilibrium map
    (central differences of two more equilibria per load component). Agreement 0.5 %."""
    if which == "plain":
        b, load, omega = plain(0.1, 0.05, 1e-4, 0.02), (300.0, -2000.0), 300.0
    else:
        b, load, omega = _dam_bearing(), (4978.0, 11352.0), 10800 * math.pi / 30
    opts = replace(OPTS, tol=1e-12)
    co = coefficients(b, load, omega, options=opts)
    dw = 1e-3 * math.hypot(*load)
    compliance = np.zeros((2, 2))
    for j in range(2):
        e = np.zeros(2)
        e[j] = dw
        p = equilibrium(b, tuple(np.array(load) + e), omega, options=opts)
        m = equilibrium(b, tuple(np.array(load) - e), omega, options=opts)
        compliance[:, j] = [(p.x - m.x) / (2 * dw), (p.y - m.y) / (2 * dw)]
    # equilibrium F(x) + W = 0 → dx/dW = K⁻¹
    np.testing.assert_allclose(np.linalg.inv(compliance), co.K, rtol=0,
                               atol=5e-3 * abs(co.K).max())


def test_tilting_pad_reduced_coefficients_properties():
    """Moment-free pivots: each pad's force passes through its pivot, so the reduced
    matrices are symmetric, and for 4 pads at 45° with the load between pads kxx = kyy,
    kxy ≈ 0 (Lund 1964; the usual reason tilting pads are chosen)."""
    b = tilting_pad(0.1, 0.07, 78.44e-6, 0.0277, [45 * DEG, 135 * DEG, 225 * DEG, 315 * DEG],
                    75 * DEG, 0.47, 0.5, inertia=2e-4, thickness=0.02)
    omega = 4000 * math.pi / 30
    co = coefficients(b, (0.0, -10000.0), omega, options=SolverOptions(grid=Grid(24, 6)))
    eq = co.equilibrium
    assert abs(eq.x) < 1e-6 * b.clearance
    assert eq.attitude_angle == pytest.approx(0.0, abs=1e-6)
    for m in (co.K, co.C):
        assert abs(m[0, 1]) < 2e-3 * m[0, 0] and abs(m[1, 0]) < 2e-3 * m[0, 0]
        assert m[0, 0] == pytest.approx(m[1, 1], rel=2e-3)
    # full coefficients reduce at other whirl frequencies too, and pad inertia matters there
    k_half, c_half = co.reduced(0.5 * omega)
    assert k_half[1, 1] > 0 and c_half[1, 1] > 0
    assert co.K_full.shape == (6, 6) and co.dofs[2:] == ("tilt_1", "tilt_2", "tilt_3",
                                                         "tilt_4")
    # a flexible pivot adds a series spring: lower stiffness, pivot deflects by W/(2 k cos45)
    kp = 5e8
    bf = tilting_pad(0.1, 0.07, 78.44e-6, 0.0277, [45 * DEG, 135 * DEG, 225 * DEG, 315 * DEG],
                     75 * DEG, 0.47, 0.5, inertia=2e-4, mass=0.5, thickness=0.02,
                     pivot_stiffness=kp)
    cf = coefficients(bf, (0.0, -10000.0), omega, options=SolverOptions(grid=Grid(24, 6)))
    assert cf.K[1, 1] < co.K[1, 1]
    radial = cf.equilibrium.pad_dofs[[5, 7]]
    np.testing.assert_allclose(radial, 10000.0 / (2 * kp * math.cos(45 * DEG)), rtol=1e-6)


def test_tilting_pad_mirror_with_reversed_rotation():
    """Load on pad, 5 pads, offset 0.6: the mirrored bearing turning backwards mirrors."""
    piv = [270 * DEG + k * 72 * DEG for k in range(5)]
    b = tilting_pad(0.1, 0.05, 80e-6, 0.02, piv, 60 * DEG, 0.3, 0.6, inertia=1e-4)
    mir = tilting_pad(0.1, 0.05, 80e-6, 0.02, [math.pi - p for p in piv], 60 * DEG, 0.3, 0.4,
                      inertia=1e-4)
    opts = SolverOptions(grid=Grid(20, 5))
    omega = 5000 * math.pi / 30
    co = coefficients(b, (500.0, -3000.0), omega, options=opts)
    cm = coefficients(mir, (-500.0, -3000.0), -omega, options=opts)
    s = np.diag([-1.0, 1.0])
    np.testing.assert_allclose(cm.K, s @ co.K @ s, rtol=0, atol=1e-5 * abs(co.K).max())
    np.testing.assert_allclose(cm.C, s @ co.C @ s, rtol=0, atol=1e-5 * abs(co.C).max())
