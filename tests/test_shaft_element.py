"""Timoshenko shaft element against closed-form beam, bar and rod results."""

import numpy as np
import pytest
import scipy.linalg as la

from gearrotor.analyses import modal
from gearrotor.elements import ShaftElement, shear_coefficient
from helpers import single_shaft

E, RHO, NU = 211e9, 7850.0, 0.3
G = E / (2 * (1 + NU))


def timoshenko_simply_supported(n: int, L: float, d: float) -> float:
    """Lower root of the Timoshenko frequency equation of a simply supported solid beam,
    mode n: ρ²I/(κG) ω⁴ − (ρA + ρI k²(1 + E/(κG))) ω² + EI k⁴ = 0, k = nπ/L."""
    A, I = np.pi * d**2 / 4, np.pi * d**4 / 64
    k = n * np.pi / L
    kappa = shear_coefficient(0, d, NU)
    a = RHO * I * RHO / (kappa * G)
    b = -(RHO * A + RHO * I * k**2 * (1 + E / (kappa * G)))
    c = E * I * k**4
    return float(np.sqrt((-b - np.sqrt(b * b - 4 * a * c)) / (2 * a)))


def simply_supported_bending(L: float, d: float, n_el: int, k: float = 1e18) -> np.ndarray:
    """Bending frequencies (rad/s, one per x/y pair, ascending) of a beam on very stiff lateral
    supports at both ends (pinned: the tilts are free)."""
    t = single_shaft(
        length=L,
        diameter=d,
        elements=n_el,
        E=E,
        density=RHO,
        bearings=[{"node": 0, "k": k}, {"node": n_el, "k": k}],
    )
    res = modal(t, speed=0.0)
    return np.sort(res.damped_frequency[np.array(res.mode_type) == "L"])[::2]


def element(L=0.1, d=0.06, di=0.0, **kw):
    return ShaftElement(L, d, di, E, G, RHO, **kw)


def test_matrices_symmetry_and_rigid_body_modes():
    e = element(di=0.02)
    K, M, Gy = e.K(), e.M(), e.G()
    assert np.allclose(K, K.T, atol=1e-6 * abs(K).max())
    assert np.allclose(M, M.T)
    assert np.allclose(Gy, -Gy.T)
    assert la.eigvalsh(M).min() > 0
    # 6 rigid-body motions (3 translations, 3 rotations) carry no strain energy
    w = la.eigvalsh(K)
    assert np.sum(np.abs(w) < 1e-9 * w.max()) == 6
    # total translating mass = ρ A L in x, y and z
    ones = np.zeros(12)
    for d in (0, 1, 2):
        ones[:] = 0
        ones[[d, 6 + d]] = 1
        assert ones @ M @ ones == pytest.approx(RHO * e.area * e.length, rel=1e-12)


def test_stiffness_equals_closed_form_timoshenko():
    """Przemieniecki's closed-form Timoshenko beam stiffness (exact for this interpolation)."""
    e = element(L=0.08)
    L, phi, EI = e.length, e.phi, E * e.inertia
    kc = (
        EI
        / ((1 + phi) * L**3)
        * np.array(
            [
                [12, 6 * L, -12, 6 * L],
                [6 * L, (4 + phi) * L**2, -6 * L, (2 - phi) * L**2],
                [-12, -6 * L, 12, -6 * L],
                [6 * L, (2 - phi) * L**2, -6 * L, (4 + phi) * L**2],
            ]
        )
    )
    K = e.K()
    ix = [0, 4, 6, 10]  # x, θy (θy = +dx/dz)
    np.testing.assert_allclose(K[np.ix_(ix, ix)], kc, rtol=1e-12, atol=1e-6)
    iy = [1, 3, 7, 9]  # y, θx (θx = −dy/dz)
    T = np.diag([1, -1, 1, -1])
    np.testing.assert_allclose(K[np.ix_(iy, iy)], T @ kc @ T, rtol=1e-12, atol=1e-6)


def test_hutchinson_and_cowper_solid_section():
    # closed forms for a solid circle: Hutchinson 6(1+ν)²/(7+12ν+4ν²), Cowper 6(1+ν)/(7+6ν)
    assert shear_coefficient(0, 1, NU) == pytest.approx(6 * 1.3**2 / (7 + 3.6 + 0.36))
    assert shear_coefficient(0, 1, NU, "cowper") == pytest.approx(7.8 / 8.8)
    # thin-walled tube limit of Cowper: 2(1+ν)/(4+3ν)
    assert shear_coefficient(0.9999, 1, NU, "cowper") == pytest.approx(2.6 / 4.9, rel=1e-3)


def _free_free_beam(n_el, slender=True):
    L, d = (2.0, 0.02) if slender else (0.5, 0.1)
    t = single_shaft(length=L, diameter=d, elements=n_el, E=E, density=RHO)
    return t, L, d


def test_euler_bernoulli_limit_free_free():
    """Slender free-free beam: ω = (βL)² √(EI/(ρA L⁴)), βL = 4.7300, 7.8532, 10.9956."""
    t, L, d = _free_free_beam(40)
    res = modal(t, speed=0.0)
    A, I = np.pi * d**2 / 4, np.pi * d**4 / 64
    bl = np.array([4.730040745, 7.853204624, 10.99560784])
    exact = bl**2 * np.sqrt(E * I / (RHO * A * L**4))
    lat = np.sort(res.damped_frequency[np.array(res.mode_type) == "L"])
    # each bending frequency appears twice (x-z and y-z planes)
    got = lat[::2][:3]
    # L/d = 100: shear and rotary inertia change ω by < (π d/L)² ~ 1e-3; 40 cubic elements
    # resolve the third mode to < 1e-5
    np.testing.assert_allclose(got, exact, rtol=2e-3)


def test_pinned_pinned_and_mesh_convergence_order():
    """Simply supported Euler–Bernoulli-like beam: ω_n = (nπ/L)² √(EI/ρA); cubic elements
    converge as h⁴."""
    L, d = 2.0, 0.02

    def first(n_el):
        return simply_supported_bending(L, d, n_el, k=1e16)[2]  # 3rd bending mode

    exact = timoshenko_simply_supported(3, L, d)
    errs = [abs(first(n) - exact) / exact for n in (6, 12, 24)]
    order = np.log2(errs[0] / errs[1]), np.log2(errs[1] / errs[2])
    assert errs[-1] < 3e-5, errs
    assert min(order) > 3.5, order  # h⁴ convergence of the cubic Hermite-type element


def test_timoshenko_shear_effect_thick_beam():
    """Thick simply supported beam (L/d = 5): Timoshenko closed form (shear + rotary inertia)
    vs FE; Euler–Bernoulli overestimates by ~10 % here, so a 0.2 % match shows the shear terms."""
    L, d = 0.5, 0.1
    A, I = np.pi * d**2 / 4, np.pi * d**4 / 64
    lat = simply_supported_bending(L, d, 40)
    for n, got in zip((1, 2), lat[:2], strict=True):
        k = n * np.pi / L
        timo = timoshenko_simply_supported(n, L, d)
        eb = k**2 * np.sqrt(E * I / (RHO * A))
        assert got == pytest.approx(timo, rel=2e-3)
        assert eb / timo > 1.04  # the shear effect is real at this slenderness (4.5 %, 15 %)


def test_axial_and_torsional_rod_free_free():
    """Free-free bar ω_n = nπ/L √(E/ρ); rod ω_n = nπ/L √(G/ρ) (consistent mass converges h²)."""
    L = 1.0
    t = single_shaft(length=L, diameter=0.05, elements=80, E=E, density=RHO)
    res = modal(t, speed=0.0)
    types = np.array(res.mode_type)
    ax = np.sort(res.damped_frequency[types == "A"])[:2]
    tor = np.sort(res.damped_frequency[types == "T"])[:2]
    n = np.array([1, 2])
    np.testing.assert_allclose(ax, n * np.pi / L * np.sqrt(E / RHO), rtol=1e-3)
    np.testing.assert_allclose(tor, n * np.pi / L * np.sqrt(G / RHO), rtol=1e-3)


def test_convergence_rate_depends_on_element_slenderness():
    """Slender elements (Φ ≪ 1): O(h⁴); elements shorter than the diameter (Φ ≳ 1): O(h²)."""

    def rate(L, d, n0):
        ex = timoshenko_simply_supported(2, L, d)
        errs = []
        for n in (n0, 2 * n0):
            lat = simply_supported_bending(L, d, n)
            errs.append(abs(lat[1] - ex) / ex)
        return np.log2(errs[0] / errs[1])

    assert rate(2.0, 0.02, 8) > 3.6  # Φ ~ 1e-3 (pre-asymptotic at 8 elements: 3.7)
    assert 1.8 < rate(0.5, 0.1, 16) < 2.3  # Φ ~ 10
