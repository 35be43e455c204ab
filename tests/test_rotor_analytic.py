"""Whole-rotor results against closed forms: Jeffcott critical speed on flexible bearings,
gyroscopic split of an overhung disk, harmonic response of a damped single-DOF rotor."""

import numpy as np
import pytest
import scipy.linalg as la

from gearrotor.analyses import modal, unbalance_response
from gearrotor.analyses.lateral.modal import state_matrices
from gearrotor.elements import DiskElement, ShaftElement, shear_coefficient
from helpers import single_shaft

E, NU = 211e9, 0.3
G = E / (2 * (1 + NU))


def test_jeffcott_critical_speed_with_flexible_bearings():
    """Mid-span disk m on a (nearly) massless shaft with bearings kb at both ends:
    ω² = k_eq/m, 1/k_eq = L³/(48EI) + L/(4κGA) + 1/(2kb)."""
    L, d, m, kb = 0.8, 0.03, 25.0, 2e6
    t = single_shaft(
        length=L,
        diameter=d,
        elements=8,
        E=E,
        density=1.0,
        bearings=[{"node": 0, "k": kb}, {"node": 8, "k": kb}],
        disks=[{"node": 4, "mass": m, "polar": 0.1, "transverse": 0.05}],
    )
    res = modal(t, speed=0.0)
    A, I = np.pi * d**2 / 4, np.pi * d**4 / 64
    kappa = shear_coefficient(0, d, NU)
    flex = L**3 / (48 * E * I) + L / (4 * kappa * G * A) + 1 / (2 * kb)
    m_eff = m + 0.5 * 1.0 * A * L  # shaft (ρ = 1 kg/m³) adds < 1e-5 of m
    expect = np.sqrt(1 / flex / m_eff)
    lat = res.damped_frequency[np.array(res.mode_type) == "L"]
    assert lat[0] == pytest.approx(expect, rel=1e-4)
    assert lat[1] == pytest.approx(expect, rel=1e-4)  # isotropic: x and y planes


def test_overhung_disk_gyroscopic_split():
    """Disk at the free end of a (massless) cantilever: with u = x + iy, ψ = θy − iθx and
    u = U e^{iωt}, (k11 − mω²)(k22 − It ω² + Ip Ω ω) − k12² = 0 (ω > 0 forward, < 0 backward),
    the classic overhung-rotor result (Friswell et al. 2010, sec. 3.5)."""
    L, d = 0.4, 0.04
    m, Ip, It = 10.0, 0.2, 0.11
    el = ShaftElement(L, d, 0.0, E, G, 1e-6)
    disk = DiskElement(m, Ip, It)
    K, M, Gy = el.K(), el.M(), el.G()
    M[6:, 6:] += disk.M()
    Gy[6:, 6:] += disk.G()
    keep = [6, 7, 9, 10]  # tip x, y, θx, θy (root clamped; axial/torsion dropped)
    ix = np.ix_(keep, keep)
    phi = el.phi
    c = E * el.inertia / ((1 + phi) * L**3)
    k11, k12, k22 = 12 * c, -6 * L * c, (4 + phi) * L**2 * c
    for spin in (0.0, 500.0, 3000.0):
        A, B = state_matrices(M[ix], spin * Gy[ix], K[ix])
        lam = la.eigvals(A, B)
        fem = np.sort(lam.imag[lam.imag > 0])
        # closed form: polynomial in ω
        p1 = np.poly1d([-m, 0, k11])
        p2 = np.poly1d([-It, Ip * spin, k22])
        roots = np.roots((p1 * p2 - k12**2).coeffs)
        roots = roots[np.abs(roots.imag) < 1e-6 * np.abs(roots).max()].real
        ref = np.sort(np.abs(roots))
        np.testing.assert_allclose(fem, ref, rtol=1e-6)
        if spin > 0:
            fwd = np.sort(roots[roots > 0])
            bwd = np.sort(-roots[roots < 0])
            assert fwd[1] > bwd[1]  # the conical forward mode stiffens with spin


def test_damped_sdof_harmonic_response():
    """Rigid shaft on isotropic bearings (k, c) with a mid-span unbalance: a damped SDOF in
    each plane, X = m_u e ω² / (K − M ω² + i C ω) along a circular forward orbit."""
    kb, cb, md = 1e6, 300.0, 40.0
    t = single_shaft(
        length=0.6,
        diameter=0.05,
        elements=4,
        E=1e17,
        density=1.0,
        bearings=[{"node": 0, "k": kb, "c": cb}, {"node": 4, "k": kb, "c": cb}],
        disks=[{"node": 2, "mass": md, "polar": 0.4, "transverse": 0.2}],
        unbalances=[{"shaft": "s", "node": 2, "amount": 1e-4, "phase": 0.3}],
        probes=[
            {"name": "px", "shaft": "s", "node": 2, "angle": 0.0},
            {"name": "py", "shaft": "s", "node": 2, "angle": np.pi / 2},
        ],
    )
    mass = md + 1.0 * np.pi * 0.05**2 / 4 * 0.6
    speeds = np.linspace(10, 500, 200)
    res = unbalance_response(t, speeds=speeds)
    ref = 1e-4 * np.exp(0.3j) * speeds**2 / (2 * kb - mass * speeds**2 + 2j * cb * speeds)
    # shaft compliance (E = 1e17: 3e-7 of the bearings'), amplified ~1/(2ζ) near resonance,
    # and the conditioning (~1e10) of the stiff shaft bound the agreement to ~1e-5
    np.testing.assert_allclose(res.probes[0].response, ref, rtol=1e-5)
    np.testing.assert_allclose(res.probes[1].response, -1j * ref, rtol=1e-5)
    # circular forward orbit: minor axis = major axis > 0
    np.testing.assert_allclose(res.probes[0].minor, res.probes[0].major, rtol=1e-6)
    # API 684 half-power AF of an SDOF is 1/(2ζ) to first order in ζ
    wn = np.sqrt(2 * kb / mass)
    zeta = 2 * cb / (2 * np.sqrt(2 * kb * mass))
    crit = res.probes[0].criticals[0]
    assert crit.speed == pytest.approx(wn / np.sqrt(1 - 2 * zeta**2), rel=2e-3)
    assert crit.amplification_factor == pytest.approx(1 / (2 * zeta), rel=0.03)
