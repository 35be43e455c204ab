"""Seals against closed forms, limits and symmetries.

* A tooth at a small pressure drop is a 2-D sharp-edged slot: Neumann's flow coefficient tends
  to Kirchhoff's free-streamline contraction π/(π+2) = 0.611 and the flow to the incompressible
  orifice μ H sqrt(2ρΔP) (Neumann 1964; Childs 1993 eq. 5.xx).
* n teeth at small drops in series pass ṁ = μ1 H sqrt((P0² − Pn²)/(RT Σ 1/μ2_i²)) (sum of
  Neumann's equation over the teeth, μ1 the same for all).
* A choked last tooth passes Fliegner's flux, independent of the outlet pressure.
* With no swirl anywhere (rotor at rest, no preswirl) the seal is symmetric under θ → −θ: the
  cross-coupled stiffness and damping vanish.
* The liquid annular seal in the short-seal limit (no circumferential flow, constant friction
  factor, rotor at rest) has a closed-form first-order solution, derived in
  :func:`short_seal_impedance`: it holds Lomakin's direct stiffness, the squeeze-film damping and
  the fluid inertia (added mass).
* The annular solver's box scheme converges at second order on its axial grid.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest
from seal_cases import AIR, HOLE_PATTERN, LAB, RPM, kanki_long

from gearrotor.seals import AnnularSeal, Friction, Liquid, seal_coefficients
from gearrotor.seals.annular import annular_flow, annular_impedance
from gearrotor.seals.labyrinth import (
    fliegner_coefficient,
    labyrinth_flow,
    neumann_mu1,
    vermes_carry_over,
)

RT = AIR.R * AIR.temperature


def test_neumann_coefficient_limits():
    """μ1 → π/(π+2) (Kirchhoff's 2-D slot contraction) as the drop vanishes; it rises with the
    pressure ratio (a compressible jet contracts less), and at the critical ratio of air it
    equals the contraction implied by Fliegner's choked coefficient, 0.510 over the isentropic
    critical flux function 0.6847 (two independent fits of slot flow agree to 0.2 %)."""
    assert neumann_mu1(1.0, 1.4) == pytest.approx(math.pi / (math.pi + 2), rel=1e-15)
    mu = neumann_mu1(np.array([0.99, 0.9, 0.7, 0.5]), 1.4)
    assert np.all(np.diff(mu) > 0)
    r_crit = (2 / 2.4) ** (1.4 / 0.4)
    psi = math.sqrt(1.4) * (2 / 2.4) ** (2.4 / 0.8)
    assert neumann_mu1(r_crit, 1.4) == pytest.approx(0.510 / psi, rel=2e-3)


def test_single_tooth_small_drop_is_an_incompressible_slot():
    p0, dp = 3e5, 30.0  # ΔP/P = 1e-4
    seal = replace(LAB, n_teeth=1, inlet_pressure=p0, outlet_pressure=p0 - dp)
    res = seal_coefficients(seal, 0.0)
    rho = p0 / RT
    slot = math.pi / (math.pi + 2) * seal.radial_clearance * math.sqrt(2 * rho * dp)
    assert res.leakage == pytest.approx(slot * math.pi * (0.145 + 0.3e-3), rel=2e-4)
    assert res.coefficients == (0.0,) * 8  # no cavity, no force


def test_teeth_in_series_small_drops():
    """Summing Neumann's equation over n teeth; carry-over on teeth 2..n (Vermes)."""
    p0, pn, n = 3.0e5, 2.97e5, 12
    for teeth_on in ("stator", "interlocking"):
        seal = replace(LAB, n_teeth=n, inlet_pressure=p0, outlet_pressure=pn, teeth_on=teeth_on)
        flow = labyrinth_flow(seal)
        mu2 = np.ones(n)
        if teeth_on == "stator":
            a = vermes_carry_over(seal.pitch, seal.tooth_width, seal.radial_clearance)
            mu2[1:] = 1 / math.sqrt(1 - a)
        mdot = (
            math.pi
            / (math.pi + 2)
            * seal.radial_clearance
            * math.sqrt((p0**2 - pn**2) / (RT * np.sum(1 / mu2**2)))
        )
        # μ1 at a 0.1 % drop per tooth differs from π/(π+2) by 4e-4
        assert flow.mdot == pytest.approx(mdot, rel=1e-3)
        assert not flow.choked


def test_choked_last_tooth_passes_fliegner_flux():
    """Three interlocking teeth from 10 bar: the last tooth chokes; the leakage is Fliegner's
    flux of the last cavity and does not change when the outlet pressure falls further."""
    seal = replace(LAB, inlet_pressure=1.0e6, n_teeth=3)
    a = labyrinth_flow(seal)
    b = labyrinth_flow(replace(seal, outlet_pressure=0.6 * seal.outlet_pressure))
    assert a.choked and b.choked
    cf = fliegner_coefficient(AIR.gamma)
    assert a.mdot == pytest.approx(cf * seal.radial_clearance * a.pressure[-2] / math.sqrt(RT))
    assert b.mdot == pytest.approx(a.mdot, rel=1e-9)
    assert fliegner_coefficient(1.4) == pytest.approx(0.510, rel=1e-12)


def test_unchoked_leakage_grows_as_outlet_pressure_falls():
    ps = [2.5e5, 2.0e5, 1.5e5, 1.0e5]
    m = [labyrinth_flow(replace(LAB, outlet_pressure=p)).mdot for p in ps]
    assert np.all(np.diff(m) > 0)


@pytest.mark.parametrize("teeth_on", ["stator", "rotor", "interlocking"])
def test_no_swirl_no_cross_coupling(teeth_on):
    seal = replace(LAB, teeth_on=teeth_on, preswirl=0.0)
    r = seal_coefficients(seal, 0.0, whirl=2 * math.pi * 100)
    K, k, _, _, C, c, _, _ = r.coefficients
    assert abs(k) <= 1e-9 * abs(K)
    assert abs(c) <= 1e-9 * abs(C)
    assert C > 0


def test_isotropic_skew_symmetric_coefficients():
    r = seal_coefficients(LAB, 8000 * RPM)
    kxx, kxy, kyx, kyy, cxx, cxy, cyx, cyy = r.coefficients
    assert (kxx, cxx) == (kyy, cyy)
    assert (kxy, cxy) == (-kyx, -cyx)


def test_cross_coupling_follows_the_inlet_swirl():
    """kxy is driven by the circumferential velocity: it grows with the preswirl and turns
    negative when the gas enters against the rotation (Benckert & Wachter 1980)."""
    k = [seal_coefficients(replace(LAB, preswirl=p), 8000 * RPM).kxy for p in (-0.5, 0.0, 0.5, 1.0)]
    assert k[0] < 0 < k[2] < k[3]
    assert np.all(np.diff(k) > 0)


def short_seal_impedance(seal: AnnularSeal, whirl: float) -> complex:
    """H(Ω) of an incompressible annular seal in the short-seal limit: no circumferential flow,
    rotor at rest, constant Fanning factor f on both walls (λ = 2f), ĥ = −1 uniform.

    Continuity: ŵ' = iΩ/H → ŵ = ŵ0 + iΩz/H. Axial momentum (dP0/dz = −ρλW²/(2H)):
    p̂' = −(iΩρ + ρλW/H) ŵ − iΩρW/H − ρλW²/(2H²). Entrance p̂(0) = −(1+ξ)ρWŵ0, exit p̂(L) = 0
    fix ŵ0; H(Ω) = πR ∫ p̂ dz."""
    H, L, xi = seal.radial_clearance, seal.length, 1.0 + seal.entrance_loss
    rho = seal.fluid.rho
    lam = 2 * seal.stator.n
    dp = seal.inlet_pressure - seal.outlet_pressure
    W = math.sqrt(2 * dp / (rho * (xi + lam * L / H)))
    a = 1j * whirl * rho + rho * lam * W / H
    s = 1j * whirl * rho * W / H + rho * lam * W**2 / (2 * H * H)
    # 0 = p̂(L) = p̂(0) − a (ŵ0 L + iΩL²/(2H)) − s L
    w0 = -(a * 1j * whirl * L * L / (2 * H) + s * L) / (xi * rho * W + a * L)
    p0 = -xi * rho * W * w0
    # ∫0^L p̂ dz with p̂(z) = p0 − a (ŵ0 z + iΩz²/(2H)) − s z
    integral = p0 * L - a * (w0 * L**2 / 2 + 1j * whirl * L**3 / (6 * H)) - s * L**2 / 2
    return math.pi * seal.shaft_diameter / 2 * integral


@pytest.mark.parametrize("hz", [0.5, 20.0, 80.0])
def test_short_liquid_seal_matches_closed_form(hz):
    """Lomakin stiffness, squeeze damping and inertia of a short seal: radius 100 m so that the
    circumferential flow (relative effect ~ (L/R)²) is negligible; 200 grid intervals (the box
    scheme's error ~ 1e-5)."""
    seal = AnnularSeal(
        "liquid_annular",
        shaft_diameter=200.0,
        radial_clearance=0.3e-3,
        length=0.04,
        inlet_pressure=2.0e6,
        outlet_pressure=0.2e6,
        preswirl=0.0,
        fluid=Liquid(998.0, 1.0e-3),
        entrance_loss=0.3,
        stator=Friction("hirs", 0.005, 0.0),
        rotor=Friction("hirs", 0.005, 0.0),
        n_points=200,
    )
    om = 2 * math.pi * hz
    flow = annular_flow(seal, 0.0)
    for w in (om, -om):
        assert annular_impedance(seal, flow, w) == pytest.approx(
            short_seal_impedance(seal, w), rel=1e-4
        )


def test_liquid_leakage_closed_form():
    """At rest with a constant friction factor: ΔP = (1 + ξ + λL/H) ½ρW² (Childs 1993 eq. 4.xx)."""
    seal = replace(
        kanki_long(),
        stator=Friction("hirs", 0.004, 0.0),
        rotor=Friction("hirs", 0.004, 0.0),
    )
    r = seal_coefficients(seal, 0.0)
    rho, H, L = seal.fluid.rho, seal.radial_clearance, seal.length
    W = math.sqrt(2 * 0.98e6 / (rho * (1.2 + 0.008 * L / H)))
    assert r.leakage == pytest.approx(rho * W * H * seal.circumference, rel=1e-9)


@pytest.mark.parametrize("seal", [kanki_long(), HOLE_PATTERN], ids=["liquid", "hole_pattern"])
def test_annular_grid_convergence_second_order(seal):
    """Coefficients on 20, 40, 80 intervals: the differences shrink by 4 (order 2 ± 0.3)."""
    vals = []
    for n in (20, 40, 80):
        r = seal_coefficients(replace(seal, n_points=n), 3000 * RPM)
        vals.append(np.array(r.coefficients)[[0, 1, 4, 5]])
    d1, d2 = vals[1] - vals[0], vals[2] - vals[1]
    big = np.abs(vals[2]) > 1e-3 * np.abs(vals[2]).max()
    order = np.log2(np.abs(d1[big]) / np.abs(d2[big]))
    assert np.all((order > 1.7) & (order < 2.3)), order


def test_damper_seal_frequency_dependence():
    """A hole-pattern seal's direct stiffness rises and its direct damping falls with the whirl
    frequency (the cells' gas is a spring in series; Childs & Wade 2004); a smooth gas seal
    (no cells) shows much less of it."""

    def sweep(seal):
        rs = [seal_coefficients(seal, 5000 * RPM, 2 * math.pi * f) for f in (20, 100, 200)]
        return [r.kxx for r in rs], [r.cxx for r in rs]

    K, C = sweep(HOLE_PATTERN)
    assert K[0] < K[1] < K[2] and C[0] > C[1] > C[2]
    Ks, _ = sweep(replace(HOLE_PATTERN, cell_depth=0.0))
    assert (K[2] - K[0]) > 3 * abs(Ks[2] - Ks[0])


def test_squeeze_film_inertia_of_an_open_ended_short_gap():
    """Without through-flow or friction the seal is an open-ended short squeeze film, whose
    fluid inertia is M = π ρ R L³/(12 c) (Reinhardt & Lund 1975; San Andrés, Squeeze Film
    Dampers notes): ΔP = 1 mPa, friction factor 1e-9, no entrance loss; K(Ω) = −MΩ². The
    formula is the short-film limit: R = 10 m (at R = 0.1 m, L/R = 0.3, the circumferential
    flow lowers M by 0.9 %)."""
    seal = AnnularSeal(
        "liquid_annular",
        shaft_diameter=20.0,
        radial_clearance=0.4e-3,
        length=0.03,
        inlet_pressure=1.0e5 + 1e-3,
        outlet_pressure=1.0e5,
        preswirl=0.0,
        fluid=Liquid(850.0, 0.02),
        entrance_loss=0.0,
        stator=Friction("hirs", 1e-9, 0.0),
        rotor=Friction("hirs", 1e-9, 0.0),
        n_points=100,
    )
    M = math.pi * 850.0 * 10.0 * 0.03**3 / (12 * 0.4e-3)
    for hz in (10.0, 100.0):
        r = seal_coefficients(seal, 0.0, 2 * math.pi * hz)
        assert r.kxx == pytest.approx(-M * (2 * math.pi * hz) ** 2, rel=2e-3)
