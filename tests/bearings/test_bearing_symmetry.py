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
    return multilobe(
        0.140,
        0.130,
        152.4e-6,
        0.0152,
        [52.5 * DEG, 172.5 * DEG, 292.5 * DEG],
        97 * DEG,
        0.33,
        0.5,
        {1: pk, 2: pk},
        name="3-lobe dam",
    )


def _mirror_y(bearing: FixedBearing) -> FixedBearing:
    """Mirror image about the y axis (θ → π − θ): pads, offsets and pockets reflected."""
    pads = []
    for p in bearing.pads:
        pocket = p.pocket
        if pocket is not None:
            pocket = replace(pocket, start=p.arc - pocket.start - pocket.arc)
        pads.append(
            replace(p, start=math.pi - p.start - p.arc, offset=1.0 - p.offset, pocket=pocket)
        )
    return replace(bearing, pads=tuple(pads))


def test_plain_bearing_rotated_load_gives_rotated_coefficients():
    """Exact in the continuum; on a grid fixed to the bearing the cavitation boundary falls
    differently between nodes, so the agreement is a discretisation measure: on 72×8 (144
    nodes round) within 1 % of max|K| (measured 0.3 %; on 36×8 kxy differs by ~3 %)."""
    b = plain(0.1, 0.05, 1e-4, 0.02)
    w, omega = 2000.0, 300.0
    opts = SolverOptions(grid=Grid(72, 8))
    base = coefficients(b, (0.0, -w), omega, options=opts)
    for a in (37 * DEG, 160 * DEG):
        load = _rot(a) @ np.array([0.0, -w])
        co = coefficients(b, tuple(load), omega, options=opts)
        q = _rot(a)
        np.testing.assert_allclose(co.K, q @ base.K @ q.T, rtol=0, atol=1e-2 * abs(base.K).max())
        np.testing.assert_allclose(co.C, q @ base.C @ q.T, rtol=0, atol=1e-2 * abs(base.C).max())
        assert co.equilibrium.eccentricity_ratio == pytest.approx(
            base.equilibrium.eccentricity_ratio, abs=2e-4
        )


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
    assert rev.equilibrium.attitude_angle == pytest.approx(fwd.equilibrium.attitude_angle, rel=1e-6)
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
    (central differences of two more equilibria per load component). Agreement 1 % of
    max|K|."""
    if which == "plain":
        b, load, omega = plain(0.1, 0.05, 1e-4, 0.02), (300.0, -2000.0), 300.0
    else:
        b, load, omega = _dam_bearing(), (4978.0, 11352.0), 10800 * math.pi / 30
    opts = replace(OPTS, tol=1e-12)
    co = coefficients(b, load, omega, options=opts)
    # a load step moving the journal by about the coefficient perturbation (1 % of c)
    dw = 2e-2 * math.hypot(*load)
    compliance = np.zeros((2, 2))
    for j in range(2):
        e = np.zeros(2)
        e[j] = dw
        p = equilibrium(b, tuple(np.array(load) + e), omega, options=opts)
        m = equilibrium(b, tuple(np.array(load) - e), omega, options=opts)
        compliance[:, j] = [(p.x - m.x) / (2 * dw), (p.y - m.y) / (2 * dw)]
    # equilibrium F(x) + W = 0 → dx/dW = K⁻¹
    np.testing.assert_allclose(np.linalg.inv(compliance), co.K, rtol=0, atol=1e-2 * abs(co.K).max())


def test_tilting_pad_reduced_coefficients_properties():
    """Moment-free pivots: each pad's force passes (nearly) through its pivot, so for 4 pads
    at 45° with the load between pads kxx = kyy and kxy ≈ 0 (Lund 1964; the usual reason
    tilting pads are chosen)."""
    b = tilting_pad(
        0.1,
        0.07,
        78.44e-6,
        0.0277,
        [45 * DEG, 135 * DEG, 225 * DEG, 315 * DEG],
        75 * DEG,
        0.47,
        0.5,
        inertia=2e-4,
        thickness=0.02,
    )
    omega = 4000 * math.pi / 30
    co = coefficients(b, (0.0, -10000.0), omega, options=SolverOptions(grid=Grid(24, 6)))
    eq = co.equilibrium
    assert abs(eq.x) < 1e-6 * b.clearance
    assert eq.attitude_angle == pytest.approx(0.0, abs=1e-6)
    for m in (co.K, co.C):
        # pad forces pass through the journal centre and the pivot: their direction deviates
        # from the pivot radius by O(e/R) ~ 1e-3, the size of the measured cross terms (0.3 %)
        assert abs(m[0, 1]) < 1e-2 * m[0, 0] and abs(m[1, 0]) < 1e-2 * m[0, 0]
        assert m[0, 0] == pytest.approx(m[1, 1], rel=1e-2)
    # full coefficients reduce at other whirl frequencies too, and pad inertia matters there
    k_half, c_half = co.reduced(0.5 * omega)
    assert k_half[1, 1] > 0 and c_half[1, 1] > 0
    assert co.K_full.shape == (6, 6) and co.dofs[2:] == ("tilt_1", "tilt_2", "tilt_3", "tilt_4")
    # a flexible pivot adds a series spring: lower stiffness; the pivot springs carry the load
    kp = 5e8
    bf = tilting_pad(
        0.1,
        0.07,
        78.44e-6,
        0.0277,
        [45 * DEG, 135 * DEG, 225 * DEG, 315 * DEG],
        75 * DEG,
        0.47,
        0.5,
        inertia=2e-4,
        mass=0.5,
        thickness=0.02,
        pivot_stiffness=kp,
    )
    cf = coefficients(bf, (0.0, -10000.0), omega, options=SolverOptions(grid=Grid(24, 6)))
    assert cf.K[1, 1] < co.K[1, 1]
    radial = cf.equilibrium.pad_dofs[[1, 3, 5, 7]]
    normals = np.array([[math.cos(p.pivot), math.sin(p.pivot)] for p in bf.pads])
    np.testing.assert_allclose(kp * radial @ normals, [0.0, -10000.0], atol=10.0)


def test_tilting_pad_mirror_with_reversed_rotation():
    """Load on pad, 5 pads, offset 0.6: the mirrored bearing turning backwards mirrors."""
    piv = [270 * DEG + k * 72 * DEG for k in range(5)]
    b = tilting_pad(0.1, 0.05, 80e-6, 0.02, piv, 60 * DEG, 0.3, 0.6, inertia=1e-4)
    mir = tilting_pad(
        0.1, 0.05, 80e-6, 0.02, [math.pi - p for p in piv], 60 * DEG, 0.3, 0.4, inertia=1e-4
    )
    opts = SolverOptions(grid=Grid(20, 5))
    omega = 5000 * math.pi / 30
    co = coefficients(b, (500.0, -3000.0), omega, options=opts)
    cm = coefficients(mir, (-500.0, -3000.0), -omega, options=opts)
    s = np.diag([-1.0, 1.0])
    np.testing.assert_allclose(cm.K, s @ co.K @ s, rtol=0, atol=1e-5 * abs(co.K).max())
    np.testing.assert_allclose(cm.C, s @ co.C @ s, rtol=0, atol=1e-5 * abs(co.C).max())


def test_tilting_pad_reduction_limits():
    """Pads of huge inertia cannot follow the whirl: Z_r → Z_jj, the journal block of the full
    matrices (pads frozen, a fixed-pad bearing). A fixed bearing's reduction is the identity."""
    b = tilting_pad(
        0.1,
        0.05,
        80e-6,
        0.02,
        [45 * DEG, 135 * DEG, 225 * DEG, 315 * DEG],
        70 * DEG,
        0.3,
        0.5,
        inertia=1e4,
        thickness=0.015,
    )
    co = coefficients(b, (0.0, -3000.0), 600.0, options=SolverOptions(grid=Grid(20, 5)))
    np.testing.assert_allclose(co.K, co.K_full[:2, :2], rtol=0, atol=1e-4 * co.K_full[0, 0])
    np.testing.assert_allclose(co.C, co.C_full[:2, :2], rtol=0, atol=1e-4 * co.C_full[0, 0])
    light = replace(b, pads=tuple(replace(p, inertia=0.0) for p in b.pads))
    co = coefficients(light, (0.0, -3000.0), 600.0, options=SolverOptions(grid=Grid(20, 5)))
    # pads frozen are stiffer and more cross-coupled than pads free to tilt
    assert abs(co.K_full[0, 1]) > 10 * abs(co.K[0, 1])
    p = coefficients(plain(0.1, 0.05, 1e-4, 0.02), (0.0, -2000.0), 300.0, options=OPTS)
    np.testing.assert_array_equal(p.reduced(123.0)[0], p.K)


def test_no_equilibrium_raises_solver_error():
    from gearrotor.errors import SolverError

    b = plain(0.1, 0.05, 1e-4, 0.02)
    with pytest.raises(SolverError, match="no equilibrium found"):
        equilibrium(b, (0.0, -1e8), 300.0, options=SolverOptions(grid=Grid(24, 6)))


def test_zero_speed_is_an_input_error():
    from gearrotor.errors import ModelError

    with pytest.raises(ModelError, match="non-zero speed"):
        equilibrium(plain(0.1, 0.05, 1e-4, 0.02), (0.0, -100.0), 0.0)


def test_stability_threshold_half_frequency_whirl():
    """Rigid rotor on plain bearings (Lund's threshold): a lightly loaded plain bearing whirls
    at half speed (measured 0.4998 at ε = 0.004), and the threshold disappears at high
    eccentricity (ε = 0.85 at L/D = 0.5: stable for any mass)."""
    b = plain(0.1, 0.05, 1e-4, 0.02)
    ratio, m_crit = coefficients(b, (0.0, -10.0), 300.0, options=OPTS).stability_threshold()
    assert ratio == pytest.approx(0.5, abs=0.005) and 0 < m_crit < math.inf
    heavy = coefficients(b, (0.0, -20000.0), 300.0, options=OPTS)
    assert heavy.equilibrium.eccentricity_ratio > 0.8
    assert heavy.stability_threshold()[1] == math.inf


def test_tilting_pad_static_stiffness_matches_equilibrium_map():
    """The equilibrium map of a tilting-pad bearing (pads re-settling at every load) has the
    derivative K_jj − K_jp K_pp⁻¹ K_pj: the full matrices condensed at zero whirl frequency.
    Checks the pad rows/columns of the full matrices. Measured 0.015 % of max|K| (tolerance
    1 %); the synchronous value differs from it by 0.76 %."""
    piv = [270 * DEG + k * 72 * DEG for k in range(5)]
    b = tilting_pad(0.1, 0.05, 80e-6, 0.02, piv, 60 * DEG, 0.3, 0.6, inertia=1e-4)
    opts = SolverOptions(grid=Grid(20, 5), tol=1e-12)
    omega, load = 5000 * math.pi / 30, np.array([500.0, -3000.0])
    co = coefficients(b, tuple(load), omega, options=opts)
    dw = 2e-2 * np.hypot(*load)
    compliance = np.zeros((2, 2))
    for j in range(2):
        e = np.zeros(2)
        e[j] = dw
        p = equilibrium(b, tuple(load + e), omega, options=opts)
        m = equilibrium(b, tuple(load - e), omega, options=opts)
        compliance[:, j] = [(p.x - m.x) / (2 * dw), (p.y - m.y) / (2 * dw)]
    k_static = co.reduced(1e-6)[0]
    np.testing.assert_allclose(
        np.linalg.inv(compliance), k_static, rtol=0, atol=1e-2 * abs(k_static).max()
    )
    # and it differs from the synchronous value (pad damping matters at whirl = speed)
    assert abs(co.K - k_static).max() > 1e-3 * abs(k_static).max()
