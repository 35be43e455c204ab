"""Gas labyrinth seals: leakage, cavity pressures and swirl, rotordynamic coefficients.

The model is the one-control-volume bulk-flow model of Childs & Scharrer (1986, "An
Iwatsubo-based solution for labyrinth seals: comparison to experimental results", ASME J. Eng.
Gas Turbines Power 108:325-331; Childs, *Turbomachinery Rotordynamics*, 1993, §5.7), after
Iwatsubo (1980):

* **Leakage** (per unit circumference, tooth ``i`` from cavity pressure ``P[i-1]`` to ``P[i]``):
  Neumann's equation ``ṁ = μ1 μ2 H sqrt((P[i-1]² − P[i]²)/(Z R T))`` with Neumann's flow
  coefficient ``μ1 = π/(π + 2 − 5s + 2s²)``, ``s = (P[i-1]/P[i])^((γ−1)/γ) − 1`` (μ1 → π/(π+2),
  Kirchhoff's contraction of a 2-D slot, for a small drop) and **Vermes' kinetic-energy
  carry-over** ``μ2 = 1/sqrt(1 − α)``, ``α = 8.52/((pitch − tooth_width)/H + 7.23)`` on every
  tooth but the first (whose upstream gas is at rest); interlocking teeth deflect the jet and
  carry nothing over (μ2 = 1). Isothermal flow at the inlet temperature (an ideal gas expands
  isenthalpically; the kinetic energy is dissipated in each cavity); Z R T = P/ρ of the fluid.
* **Choked last tooth**: the last tooth passes at most Fliegner's choked flux
  ``ṁ = C_F μ2 H P/sqrt(Z R T)`` with ``C_F = 0.510`` for γ = 1.4 (scaled with the isentropic
  critical flux function for other γ); the leakage is then independent of the outlet pressure.
  Only the last tooth chokes in this model: an outlet pressure so low that an upstream tooth would
  have to choke too cannot occur (the Neumann flux of an upstream tooth at its largest exceeds
  Fliegner's flux of the cavity behind it).
* **Swirl** in each cavity from the circumferential momentum balance
  ``ṁ (V[i] − V[i−1]) = pitch (a_r τ_r − a_s τ_s)`` with Blasius wall shear
  ``τ = ½ ρ u² n (|u| D_h ρ/μ)^m`` (n = 0.079, m = −0.25), ``D_h = 2 (H + B) L/(H + B + L)``,
  the wetted-length ratios ``a = (2B + L)/L`` of the toothed wall (``(B + L)/L`` on both walls of
  an interlocking seal) and 1 of the smooth one; ``V[0] = preswirl · R ω``.
* **Coefficients** from the first-order (perturbed) continuity and circumferential momentum
  equations of every cavity for a circular whirl of frequency Ω (``+Ω`` forward, ``−Ω``
  backward) with the tooth-clearance perturbation, the leakage derivatives holding μ1 fixed as
  Childs & Scharrer do. The pressure force gives the impedances ``H(±Ω)`` and

      K = Re(H(Ω) + H(−Ω))/2,   c = Re(H(Ω) − H(−Ω))/(2Ω),
      k = −Im(H(Ω) + H(−Ω))/2,  C = Im(H(Ω) − H(−Ω))/(2Ω),

  with ``kxx = kyy = K``, ``kxy = −kyx = k``, ``cxx = cyy = C``, ``cxy = −cyx = c`` (forces
  ``f = −K u − C u̇``; a positive kxy feeds forward whirl). The coefficients depend on the whirl
  frequency; synchronous whirl (Ω = ω) is the usual report.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy.optimize import brentq, minimize_scalar

from ..errors import SolverError
from .fluids import Fluid

__all__ = [
    "LabyrinthSeal",
    "LabyrinthFlow",
    "labyrinth_flow",
    "labyrinth_impedance",
    "neumann_mu1",
    "vermes_carry_over",
    "fliegner_coefficient",
]

BLASIUS_N = 0.079
BLASIUS_M = -0.25
#: Fliegner's choked-flow coefficient for air (γ = 1.4), as Childs & Scharrer use it.
FLIEGNER_AIR = 0.510


def neumann_mu1(r, gamma: float):
    """Neumann's flow coefficient at the pressure ratio r = P_downstream/P_upstream."""
    r = np.asarray(r, float)
    s = r ** (-(gamma - 1.0) / gamma) - 1.0
    return np.pi / (np.pi + 2.0 - 5.0 * s + 2.0 * s * s)


def vermes_carry_over(pitch: float, tooth_width: float, clearance: float) -> float:
    """Vermes' (1961) kinetic-energy carry-over factor α (dimensionless, 0 < α < 1)."""
    return 8.52 / ((pitch - tooth_width) / clearance + 7.23)


def _critical_flux(gamma: float) -> float:
    """Isentropic choked flux function sqrt(γ) (2/(γ+1))^((γ+1)/(2(γ−1)))."""
    return math.sqrt(gamma) * (2.0 / (gamma + 1.0)) ** ((gamma + 1.0) / (2.0 * (gamma - 1.0)))


def fliegner_coefficient(gamma: float) -> float:
    """Fliegner's coefficient C_F of the choked last tooth: 0.510 at γ = 1.4, scaled with the
    isentropic critical flux function for other γ."""
    return FLIEGNER_AIR * _critical_flux(gamma) / _critical_flux(1.4)


@dataclass(frozen=True)
class LabyrinthSeal:
    """A gas labyrinth seal (SI units; see the module docstring for the model).

    shaft_diameter : diameter of the rotor surface at the tooth clearance, m
    radial_clearance : tooth-tip radial clearance H, m
    n_teeth : number of teeth (throttlings), ≥ 1 (cavities: n_teeth − 1)
    pitch : axial tooth pitch L, m; tooth_height B, m; tooth_width (tip), m
    teeth_on : "stator", "rotor" or "interlocking"
    inlet_pressure, outlet_pressure : Pa (outlet < inlet); inlet_temperature : K
    preswirl : inlet swirl velocity / rotor surface speed
    fluid : the gas (:class:`~.fluids.IdealGas` or :class:`~.fluids.RealGas`)
    """

    shaft_diameter: float
    radial_clearance: float
    n_teeth: int
    pitch: float
    tooth_height: float
    tooth_width: float
    teeth_on: str
    inlet_pressure: float
    outlet_pressure: float
    inlet_temperature: float
    preswirl: float
    fluid: Fluid
    name: str = "labyrinth"
    kind = "labyrinth"

    @property
    def radius(self) -> float:
        return self.shaft_diameter / 2.0

    @property
    def circumference(self) -> float:
        """Mean circumference of the clearance annulus π(D + H), m (leakage per unit
        circumference times this is the leakage)."""
        return math.pi * (self.shaft_diameter + self.radial_clearance)

    @property
    def length(self) -> float:
        return self.n_teeth * self.pitch

    def carry_over(self) -> NDArray:
        """μ2 of each tooth (first tooth 1; interlocking teeth 1)."""
        mu2 = np.ones(self.n_teeth)
        if self.teeth_on != "interlocking" and self.n_teeth > 1:
            a = vermes_carry_over(self.pitch, self.tooth_width, self.radial_clearance)
            mu2[1:] = 1.0 / math.sqrt(1.0 - a)
        return mu2

    def wetted_ratios(self) -> tuple[float, float]:
        """(a_r, a_s): wetted rotor and stator length of a cavity per pitch."""
        L, B = self.pitch, self.tooth_height
        toothed = (2 * B + L) / L
        if self.teeth_on == "stator":
            return 1.0, toothed
        if self.teeth_on == "rotor":
            return toothed, 1.0
        both = (B + L) / L
        return both, both


@dataclass(frozen=True)
class LabyrinthFlow:
    """The leakage solution (independent of speed): cavity pressures and tooth derivatives.

    pressure : (n_teeth + 1,) inlet, cavities, outlet, Pa
    mdot : leakage per unit circumference, kg/(s m)
    choked : the last tooth passes Fliegner's choked flux
    dmdot : (n_teeth, 3) ∂ṁ/∂P_up, ∂ṁ/∂P_down, ∂ṁ/∂H of each tooth
    """

    pressure: NDArray
    mdot: float
    choked: bool
    dmdot: NDArray


def _tooth_flux(seal: LabyrinthSeal, mu2: float, p_up: float, r):
    """Neumann flux per unit circumference through a tooth at pressure ratio r."""
    g = seal.fluid.gamma
    return (
        neumann_mu1(r, g)
        * mu2
        * seal.radial_clearance
        * p_up
        * np.sqrt(np.maximum(1.0 - r * r, 0.0) / seal.fluid.pv(p_up))
    )


def _r_max(gamma: float) -> float:
    """Pressure ratio at which Neumann's flux μ1(r) sqrt(1 − r²) is largest."""
    res = minimize_scalar(
        lambda r: -neumann_mu1(r, gamma) * math.sqrt(1 - r * r),
        bounds=(1e-4, 0.999),
        method="bounded",
        options={"xatol": 1e-10},
    )
    return float(res.x)


def labyrinth_flow(seal: LabyrinthSeal) -> LabyrinthFlow:
    """Leakage and cavity pressures (the last tooth choked when Fliegner's flux caps it)."""
    nt = seal.n_teeth
    p_in, p_out = seal.inlet_pressure, seal.outlet_pressure
    mu2 = seal.carry_over()
    g = seal.fluid.gamma
    r_star = _r_max(g)
    cf = fliegner_coefficient(g)
    H = seal.radial_clearance

    def choke(p):
        return cf * mu2[-1] * H * p / math.sqrt(float(seal.fluid.pv(p)))

    def last(p):  # flux through the last tooth from p to the outlet
        r = max(p_out / p, r_star)
        return min(float(_tooth_flux(seal, mu2[-1], p, r)), choke(p))

    def march(mdot):
        """Cavity pressures passing mdot through teeth 1..nt-1; None when a tooth cannot."""
        p = np.empty(nt + 1)
        p[0] = p_in
        for i in range(1, nt):
            f_max = float(_tooth_flux(seal, mu2[i - 1], p[i - 1], r_star))
            if mdot >= f_max:
                return None
            r = brentq(
                lambda r, i=i: float(_tooth_flux(seal, mu2[i - 1], p[i - 1], r)) - mdot,
                r_star,
                1.0,
                xtol=1e-14,
                rtol=1e-15,
            )
            p[i] = r * p[i - 1]
            if p[i] <= p_out:
                return None
        p[nt] = p_out
        return p

    def residual(mdot):
        p = march(mdot)
        if p is None:
            return -mdot
        return last(p[nt - 1]) - mdot

    hi = float(_tooth_flux(seal, mu2[0], p_in, r_star))
    if nt == 1:
        mdot = last(p_in)
        p = np.array([p_in, p_out])
    else:
        mdot = brentq(residual, 0.0, hi, xtol=1e-15 * hi, rtol=1e-13)
        p = march(mdot)
        if p is None or abs(residual(mdot)) > 1e-8 * mdot:
            raise SolverError(
                f"labyrinth leakage did not converge (outlet/inlet pressure {p_out / p_in:.4g}, "
                f"{nt} teeth)"
            )
    choked = bool(
        choke(p[nt - 1])
        <= float(_tooth_flux(seal, mu2[-1], p[nt - 1], max(p_out / p[nt - 1], r_star)))
    )
    d = np.empty((nt, 3))
    for i in range(1, nt + 1):
        pu, pd = p[i - 1], p[i]
        if i == nt and choked:
            d[i - 1] = (mdot / pu, 0.0, mdot / H)
        else:
            den = pu * pu - pd * pd
            d[i - 1] = (mdot * pu / den, -mdot * pd / den, mdot / H)
    return LabyrinthFlow(p, float(mdot), choked, d)


def _shear(rho, u, dh, mu, n=BLASIUS_N, m=BLASIUS_M):
    """Blasius wall shear ½ ρ u² n (|u| D_h ρ/μ)^m, signed with u."""
    return 0.5 * rho * n * (dh * rho / mu) ** m * abs(u) ** (1.0 + m) * u


def labyrinth_swirl(seal: LabyrinthSeal, flow: LabyrinthFlow, speed: float):
    """Swirl velocity (m/s) of the inlet and every cavity at rotor speed ``speed`` (rad/s)."""
    nc = seal.n_teeth - 1
    v = np.empty(nc + 1)
    rw = seal.radius * speed
    v[0] = seal.preswirl * rw
    ar, as_ = seal.wetted_ratios()
    H, B, L = seal.radial_clearance, seal.tooth_height, seal.pitch
    dh = 2 * (H + B) * L / (H + B + L)
    p = flow.pressure[1 : nc + 1]
    rho = seal.fluid.density(p)
    mu = seal.fluid.viscosity(p)
    for i in range(1, nc + 1):
        r, m_ = float(rho[i - 1]), float(mu[i - 1])

        def f(x, i=i, r=r, m_=m_):
            return flow.mdot * (x - v[i - 1]) - L * (
                ar * _shear(r, rw - x, dh, m_) - as_ * _shear(r, x, dh, m_)
            )

        lo, hi = min(v[i - 1], 0.0, rw), max(v[i - 1], 0.0, rw)
        v[i] = lo if hi == lo else brentq(f, lo, hi, xtol=1e-12 * max(abs(hi), abs(lo)))
    return v


def labyrinth_impedance(
    seal: LabyrinthSeal, flow: LabyrinthFlow, speed: float, whirl: float, swirl=None
) -> complex:
    """Impedance H(Ω) = −(Fx + i Fy)/(x + i y) (N/m) for a circular whirl x + iy = a e^{iΩt}
    at whirl frequency ``whirl`` (rad/s, negative: backward) and rotor speed ``speed``."""
    nc = seal.n_teeth - 1
    if nc == 0:
        return 0.0 + 0.0j
    v = labyrinth_swirl(seal, flow, speed) if swirl is None else swirl
    R, H, B, L = seal.radius, seal.radial_clearance, seal.tooth_height, seal.pitch
    A = (B + H) * L
    dh = 2 * (H + B) * L / (H + B + L)
    ddh = 2 * L * L / (H + B + L) ** 2  # ∂D_h/∂H
    ar, as_ = seal.wetted_ratios()
    p = flow.pressure[1 : nc + 1]
    rho = seal.fluid.density(p)
    beta = seal.fluid.drho_dp(p)
    mu = seal.fluid.viscosity(p)
    m0 = flow.mdot
    rw = R * speed
    m = BLASIUS_M
    hh = -1.0  # clearance perturbation ĥ for a unit displacement toward θ = 0
    n = 2 * nc
    A_ = np.zeros((n, n), complex)
    b = np.zeros(n, complex)
    d = flow.dmdot
    for j in range(nc):  # cavity i = j + 1: unknowns P̂ (2j), V̂ (2j + 1)
        i = j + 1
        P, V = 2 * j, 2 * j + 1
        r, be, vi, vu = float(rho[j]), float(beta[j]), v[i], v[i - 1]
        u = rw - vi
        ts, tr = _shear(r, vi, dh, mu[j]), _shear(r, u, dh, mu[j])
        c = 0.5 * r * BLASIUS_N * (dh * r / mu[j]) ** m
        ts_v, tr_u = (2 + m) * c * abs(vi) ** (1 + m), (2 + m) * c * abs(u) ** (1 + m)
        ts_rho, tr_rho = (1 + m) * ts / r, (1 + m) * tr / r
        ts_h, tr_h = m * ts / dh * ddh, m * tr / dh * ddh
        # tooth i (into the cavity) and tooth i + 1 (out of it): ṁ̂ = a P̂_up + b P̂_down + g ĥ
        a_in, b_in, g_in = d[i - 1]
        a_out, b_out, g_out = d[i]
        # continuity
        A_[P, P] += 1j * whirl * A * be - 1j / R * A * vi * be - b_in + a_out
        A_[P, V] += -1j / R * r * A
        if j > 0:
            A_[P, P - 2] += -a_in
        if j < nc - 1:
            A_[P, P + 2] += b_out
        b[P] -= (1j * whirl * r * L - 1j / R * r * vi * L + g_out - g_in) * hh
        # circumferential momentum
        dv = vi - vu
        A_[V, V] += r * A * 1j * (whirl - vi / R) + m0 + L * (ar * tr_u + as_ * ts_v)
        A_[V, P] += b_in * dv - 1j * A / R - L * (ar * tr_rho - as_ * ts_rho) * be
        if j > 0:
            A_[V, V - 2] += -m0
            A_[V, P - 2] += a_in * dv
        b[V] -= (g_in * dv - L * (ar * tr_h - as_ * ts_h)) * hh
    try:
        lu = np.linalg.solve(A_, b)
    except np.linalg.LinAlgError:
        raise SolverError(
            "labyrinth perturbation system is singular at "
            f"{speed * 30 / np.pi:.6g} rpm, whirl {whirl / (2 * np.pi):.6g} Hz"
        ) from None
    return complex(np.pi * R * L * lu[0::2].sum() / (-hh))


def coefficients_from_impedance(hf: complex, hb: complex, whirl: float) -> tuple[float, ...]:
    """(K, k, C, c) from the forward and backward impedances at |Ω| = whirl > 0."""
    K = 0.5 * (hf.real + hb.real)
    c = (hf.real - hb.real) / (2.0 * whirl)
    k = -0.5 * (hf.imag + hb.imag)
    C = (hf.imag - hb.imag) / (2.0 * whirl)
    return K, k, C, c
