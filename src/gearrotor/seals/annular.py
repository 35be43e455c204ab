"""Annular seals by bulk flow: liquid annular seals and gas damper (hole-pattern, honeycomb)
seals.

One axial bulk-flow model serves both (Childs 1983, "Finite-length solutions for rotordynamic
coefficients of turbulent annular seals", ASME J. Lubr. Technol. 105:437-444, for liquids;
Nelson 1985 and Kleynhans & Childs 1997, ISOTSEAL, for gas seals, with the damper's cells as
storage):

* Zeroth order along z (axial velocity W, circumferential velocity U, pressure P; per unit
  circumference ṁ = ρ W H):
  ``ṁ dW/dz = −H dP/dz − τ_z``, ``ṁ dU/dz = −τ_θ``, with Hirs' (1973) turbulent-lubrication shear
  on stator and rotor, ``τ = ½ ρ f u (W, U − Rω)`` with u the bulk speed relative to each wall
  and ``f = n Re^m`` (Hirs; Blasius n = 0.079, m = −0.25; Black–Jenssen's smooth annulus
  n = 0.066, m = −0.25) or Moody's ``f = 0.001375 [1 + (2·10⁴ e/D_h + 10⁶/Re)^(1/3)]``,
  ``Re = ρ u D_h/μ``, ``D_h = 2H``. Entrance loss ``P_in − P(0) = (1 + ξ) ½ ρ W(0)²``, inlet
  swirl ``U(0) = preswirl · Rω``, exit ``P(L) = P_out``. A gas is isothermal (ideal or real);
  an exit Mach number reaching 1 (choked annular seal) is an input error of this model.
* First order: the perturbed continuity (with the cell volume per unit wall area
  ``γ_d h_d`` as storage, compressed isentropically) and axial and circumferential momentum for
  a circular whirl of frequency Ω, solved on the axial grid by a centred box scheme (second
  order, convergence checked in the tests). The pressure integral gives the impedance H(Ω) and
  the frequency-dependent coefficients as for the labyrinth (see ``labyrinth.py``).
* Liquid seals also get Childs' constant-coefficient model ``K − MΩ² + iCΩ`` (x excitation),
  ``k − mΩ² + icΩ`` (cross) fitted over whirl frequencies 0.25ω … 2ω: the added mass M, m.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import lru_cache

import numpy as np
from numpy.typing import NDArray
from scipy.optimize import brentq, minimize_scalar

from ..errors import ModelError, SolverError
from .fluids import Fluid

__all__ = ["Friction", "AnnularSeal", "AnnularFlow", "annular_flow", "annular_impedance"]


@dataclass(frozen=True)
class Friction:
    """Fanning friction factor of one wall: ``law = "hirs"`` f = n Re^m, or ``"moody"`` with
    absolute roughness ``roughness`` (m)."""

    law: str = "hirs"
    n: float = 0.079
    m: float = -0.25
    roughness: float = 0.0

    def scalar(self, re: float, dh: float) -> float:
        """:meth:`factor` of one Reynolds number (floats, for the marching loop)."""
        re = max(re, 1e-12)
        if self.law == "moody":
            return 0.001375 * (1.0 + (2e4 * self.roughness / dh + 1e6 / re) ** (1.0 / 3.0))
        return self.n * re**self.m

    def factor(self, re, dh):
        re = np.maximum(re, 1e-12)
        if self.law == "moody":
            return 0.001375 * (1.0 + (2e4 * self.roughness / dh + 1e6 / re) ** (1.0 / 3.0))
        return self.n * re**self.m


@dataclass(frozen=True)
class AnnularSeal:
    """A liquid annular seal (``fluid`` a :class:`~.fluids.Liquid`) or a gas damper seal
    (hole-pattern or honeycomb stator: ``cell_depth`` h_d, m, and ``hole_area_ratio`` γ_d, the
    share of the stator surface that is cells; a smooth gas annular seal has cell_depth 0).

    shaft_diameter, radial_clearance, length : m; inlet/outlet pressure: Pa; preswirl: inlet
    swirl velocity / surface speed; entrance_loss ξ; stator and rotor :class:`Friction`;
    n_points : axial grid intervals.
    """

    kind: str  # "liquid_annular", "hole_pattern", "honeycomb"
    shaft_diameter: float
    radial_clearance: float
    length: float
    inlet_pressure: float
    outlet_pressure: float
    preswirl: float
    fluid: Fluid
    entrance_loss: float = 0.1
    stator: Friction = field(default_factory=Friction)
    rotor: Friction = field(default_factory=Friction)
    cell_depth: float = 0.0
    hole_area_ratio: float = 0.0
    inlet_temperature: float = 293.15
    n_points: int = 40
    name: str = "annular seal"

    @property
    def radius(self) -> float:
        return self.shaft_diameter / 2.0

    @property
    def circumference(self) -> float:
        return math.pi * (self.shaft_diameter + self.radial_clearance)


@dataclass(frozen=True)
class AnnularFlow:
    """Zeroth-order solution on the axial grid ``z`` (m): pressure (Pa), W and U (m/s), leakage
    per unit circumference ``mdot`` (kg/(s m)), at rotor speed ``speed`` (rad/s)."""

    z: NDArray
    pressure: NDArray
    W: NDArray
    U: NDArray
    mdot: float
    speed: float


def _shears(seal: AnnularSeal, rho, W, U, H, mu, rw):
    """(τ_z, τ_θ) summed over stator and rotor, N/m²."""
    dh = 2.0 * H
    us = np.sqrt(W * W + U * U)
    ur = np.sqrt(W * W + (U - rw) ** 2)
    fs = seal.stator.factor(rho * us * dh / mu, dh)
    fr = seal.rotor.factor(rho * ur * dh / mu, dh)
    ks, kr = 0.5 * rho * fs * us, 0.5 * rho * fr * ur
    return (ks + kr) * W, ks * U + kr * (U - rw)


def _integrate(seal: AnnularSeal, mdot: float, speed: float):
    """March the zeroth-order equations for a given leakage; returns (P, W, U) on the grid or
    None when the flow chokes (isothermal Mach 1) or the pressure falls to zero."""
    fl = seal.fluid
    H, L, N = seal.radial_clearance, seal.length, seal.n_points
    rw = seal.radius * speed
    pin = seal.inlet_pressure
    xi = 1.0 + seal.entrance_loss
    # entrance: P(0) = P_in − (1+ξ) ṁ²/(2 ρ(P0) H²)
    if not fl.compressible:
        rho0 = float(fl.density(pin))
        p0 = pin - xi * mdot**2 / (2 * rho0 * H * H)
    else:

        def ent(p):
            return pin - xi * mdot**2 / (2 * float(fl.density(p)) * H * H) - p

        # ent has a maximum (the entrance chokes beyond it): the subsonic root lies above it
        top = minimize_scalar(
            lambda p: -ent(p),
            bounds=(1e-6 * pin, pin),
            method="bounded",
            options={"xatol": 1e-9 * pin},
        ).x
        if ent(top) < 0:
            return None
        p0 = brentq(ent, top, pin, xtol=1e-12 * pin)
    if p0 <= 0:
        return None
    dz = L / N
    P = np.empty(N + 1)
    U = np.empty(N + 1)
    P[0], U[0] = p0, seal.preswirl * rw

    dh = 2.0 * H
    fs, fr = seal.stator.scalar, seal.rotor.scalar

    def rhs(p, u):
        """(dP/dz, a, U_eq) with dU/dz = −a (U − U_eq): the swirl relaxes to U_eq over 1/a."""
        rho, beta, mu = fl.props(p)
        w = mdot / (rho * H)
        us = math.sqrt(w * w + u * u)
        ur = math.sqrt(w * w + (u - rw) ** 2)
        ks = 0.5 * rho * fs(rho * us * dh / mu, dh) * us
        kr = 0.5 * rho * fr(rho * ur * dh / mu, dh) * ur
        den = 1.0 - w * w * beta
        if den <= 0.02:  # isothermal Mach number ~ 1: choked
            return None
        a = (ks + kr) / mdot
        return -(ks + kr) * w / (H * den), a, kr * rw / (ks + kr) if ks + kr > 0 else u

    def du(f, u):
        return -f[1] * (u - f[2])

    def step(p, u, h, k1):
        """One step of length h from (p, u): RK4, or, when the swirl relaxes within the step
        (a h > 0.5: a slow leak, a viscous liquid), Heun's step with the relaxation integrated
        exactly (RK4 would lose accuracy and then stability)."""
        if k1[1] * h > 0.5:
            pp, up = p + h * k1[0], k1[2] + (u - k1[2]) * math.exp(-k1[1] * h)
            k2 = rhs(pp, up) if pp > 0 else None
            if k2 is None:
                return None
            a, ueq = 0.5 * (k1[1] + k2[1]), 0.5 * (k1[2] + k2[2])
            return p + 0.5 * h * (k1[0] + k2[0]), ueq + (u - ueq) * math.exp(-a * h)
        u1 = u + 0.5 * h * du(k1, u)
        q = p + 0.5 * h * k1[0]
        k2 = rhs(q, u1) if q > 0 else None
        if k2 is None:
            return None
        u2 = u + 0.5 * h * du(k2, u1)
        q = p + 0.5 * h * k2[0]
        k3 = rhs(q, u2) if q > 0 else None
        if k3 is None:
            return None
        u3 = u + h * du(k3, u2)
        q = p + h * k3[0]
        k4 = rhs(q, u3) if q > 0 else None
        if k4 is None:
            return None
        return (
            p + h / 6 * (k1[0] + 2 * k2[0] + 2 * k3[0] + k4[0]),
            u + h / 6 * (du(k1, u) + 2 * du(k2, u1) + 2 * du(k3, u2) + du(k4, u3)),
        )

    for k in range(N):
        p, u = P[k], U[k]
        k1 = rhs(p, u)
        if k1 is None:
            return None
        # substeps where the swirl relaxes faster than the grid resolves (a dz > 0.5)
        n_sub = min(64, max(1, math.ceil(k1[1] * dz / 0.5)))
        h = dz / n_sub
        for j in range(n_sub):
            if j:
                k1 = rhs(p, u)
                if k1 is None:
                    return None
            nxt = step(p, u, h, k1)
            if nxt is None or nxt[0] <= 0:
                return None
            p, u = nxt
        P[k + 1], U[k + 1] = p, u
        if P[k + 1] <= 0:
            return None
    W = mdot / (fl.density(P) * H)
    return P, W, U


def annular_flow(seal: AnnularSeal, speed: float) -> AnnularFlow:
    """Leakage and the axial distributions at rotor speed ``speed`` (rad/s)."""
    return _annular_flow(seal, float(speed))


@lru_cache(maxsize=64)
def _annular_flow(seal: AnnularSeal, speed: float) -> AnnularFlow:
    fl = seal.fluid
    H = seal.radial_clearance
    dp = seal.inlet_pressure - seal.outlet_pressure
    rho_in = float(fl.density(seal.inlet_pressure))
    # no more than the entrance loss alone would pass
    hi = rho_in * H * math.sqrt(2 * dp / ((1 + seal.entrance_loss) * rho_in))

    def g(mdot):
        sol = _integrate(seal, mdot, speed)
        if sol is None:
            return -seal.inlet_pressure
        return sol[0][-1] - seal.outlet_pressure

    if g(hi) > 0:  # cannot happen with friction > 0; guards a zero-friction input
        raise ModelError(
            "no leakage solution: the seal has no friction",
            field="stator_friction",
            expected="friction factors > 0",
        )
    lo = hi
    for _ in range(60):  # halve down to a leakage the seal passes with pressure to spare
        lo *= 0.5
        if g(lo) > 0:
            break
    else:
        raise SolverError("annular seal: no leakage bracket found")
    mdot = brentq(g, lo, 2 * lo, xtol=1e-13 * hi, rtol=1e-12)
    sol = _integrate(seal, mdot, speed)
    if sol is None or abs(sol[0][-1] - seal.outlet_pressure) > 1e-6 * dp:
        raise ModelError(
            "the flow chokes at the seal exit (Mach 1): this isothermal bulk-flow model is for "
            "unchoked annular seals",
            field="outlet_pressure",
            value=f"{seal.outlet_pressure:.6g} Pa ({seal.outlet_pressure / seal.inlet_pressure:.4g}"
            " of the inlet)",
            expected="a higher outlet pressure (a smaller pressure ratio across the seal)",
        )
    P, W, U = sol
    z = np.linspace(0.0, seal.length, seal.n_points + 1)
    return AnnularFlow(z, P, W, U, float(mdot), float(speed))


def annular_impedance(seal: AnnularSeal, flow: AnnularFlow, whirl: float) -> complex:
    """Impedance H(Ω) = −(Fx + i Fy)/(x + i y) (N/m) for a circular whirl at ``whirl`` rad/s
    (negative: backward)."""
    A0, A1, b0, b1, weights = _perturbation_system(seal, flow)
    try:
        y = np.linalg.solve(A0 + whirl * A1, b0 + whirl * b1)
    except np.linalg.LinAlgError:
        raise SolverError(
            f"annular seal perturbation system is singular at {flow.speed * 30 / np.pi:.6g} rpm"
        ) from None
    # ĥ = −1: the force of a unit displacement
    return complex(np.pi * seal.radius * (weights @ y[2::3]))


def _perturbation_system(seal: AnnularSeal, flow: AnnularFlow):
    """The first-order system (A0 + Ω A1) y = b0 + Ω b1 on the grid, y = (ŵ, û, p̂) per node,
    for the clearance perturbation ĥ = −1, and the trapezoid weights of ∫ p̂ dz."""
    key = id(flow)
    hit = _SYSTEMS.get(key)
    if hit is not None and hit[0] is flow:
        return hit[1]
    fl = seal.fluid
    R, H = seal.radius, seal.radial_clearance
    rw = seal.radius * flow.speed
    z, P, W, U = flow.z, flow.pressure, flow.W, flow.U
    N = len(z) - 1
    dz = np.diff(z)
    rho, beta = fl.density(P), fl.drho_dp(P)
    beta_s = fl.drho_dp_isentropic(P)
    mu = fl.viscosity(P)
    vc = seal.hole_area_ratio * seal.cell_depth
    hh = -1.0
    rm, bm, bsm, Wm, Um, mum = (0.5 * (a[1:] + a[:-1]) for a in (rho, beta, beta_s, W, U, mu))
    dW, dU, dP = np.diff(W) / dz, np.diff(U) / dz, np.diff(P) / dz
    # shear derivatives at the midpoints by central differences in (ρ, W, U, H)
    base = (rm, Wm, Um, np.full_like(rm, H))
    floor = (0.0, 0.0, np.abs(Wm), 0.0)  # U may cross zero: step on the scale of W
    dz_ = []
    dt_ = []
    for q in range(4):
        h = 1e-6 * (np.abs(base[q]) + floor[q])
        up = list(base)
        dn = list(base)
        up[q] = base[q] + h
        dn[q] = base[q] - h
        tzu, ttu = _shears(seal, *up, mum, rw)
        tzd, ttd = _shears(seal, *dn, mum, rw)
        dz_.append((tzu - tzd) / (2 * h))
        dt_.append((ttu - ttd) / (2 * h))
    tz_r, tz_w, tz_u, tz_h = dz_
    tt_r, tt_w, tt_u, tt_h = dt_
    n = 3 * (N + 1)
    A0 = np.zeros((n, n), complex)
    A1 = np.zeros((n, n), complex)
    b0 = np.zeros(n, complex)
    b1 = np.zeros(n, complex)
    k = np.arange(N)
    e_c, e_a, e_t = 3 * k, 3 * k + 1, 3 * k + 2  # continuity, axial, circumferential rows
    c0, c1 = 3 * k, 3 * k + 3  # first unknown (ŵ) of the interval's two nodes
    W_, U_, P_ = 0, 1, 2
    conv0 = -1j * Um / R  # ∂t + (U/R)∂θ = iΩ + conv0
    rH, rHw = rm * H, rm * H * Wm

    def put(M, rows, cols, vals):
        M[rows, cols] += vals

    for c, sgn in ((c0, -1.0), (c1, 1.0)):
        # continuity: iΩ[(Hβ + V_c β_s) p̂ + ρ ĥ] − (i/R)[ρH û + UHβ p̂ + ρU ĥ] + d/dz[ρHŵ + WHβp̂]
        put(A1, e_c, c + P_, 0.5 * 1j * (H * bm + vc * bsm))
        put(A0, e_c, c + P_, 0.5 * (-1j / R * Um * H * bm))
        put(A0, e_c, c + U_, 0.5 * (-1j / R * rm * H))
        node = k + (1 if sgn > 0 else 0)
        put(A0, e_c, c + W_, sgn * rho[node] * H / dz)
        put(A0, e_c, c + P_, sgn * W[node] * H * beta[node] / dz)
        # axial: ρH[(iΩ + conv0 + W') ŵ + W ŵ'] + (βHp̂ + ρĥ) W W' = −H p̂' − ĥ P' − τ̂_z
        put(A1, e_a, c + W_, 0.5 * 1j * rH)
        put(A0, e_a, c + W_, 0.5 * (rH * (conv0 + dW) + tz_w) + sgn * rHw / dz)
        put(A0, e_a, c + P_, 0.5 * (bm * H * Wm * dW + tz_r * bm) + sgn * H / dz)
        put(A0, e_a, c + U_, 0.5 * tz_u)
        # circumferential: ρH[(iΩ + conv0) û + W û' + U' ŵ] + (βHp̂ + ρĥ) W U' = (iH/R) p̂ − τ̂_θ
        put(A1, e_t, c + U_, 0.5 * 1j * rH)
        put(A0, e_t, c + U_, 0.5 * (rH * conv0 + tt_u) + sgn * rHw / dz)
        put(A0, e_t, c + W_, 0.5 * (rH * dU + tt_w))
        put(A0, e_t, c + P_, 0.5 * (bm * H * Wm * dU - 1j * H / R + tt_r * bm))
    b1[e_c] = -1j * rm * hh
    b0[e_c] = 1j / R * rm * Um * hh
    b0[e_a] = -(rm * Wm * dW + dP + tz_h) * hh
    b0[e_t] = -(rm * Wm * dU + tt_h) * hh
    # boundary conditions: inlet loss, unperturbed inlet swirl, exit pressure
    xi = 1.0 + seal.entrance_loss
    e = 3 * N
    A0[e, P_] = 1.0 + xi * 0.5 * beta[0] * W[0] ** 2
    A0[e, W_] = xi * rho[0] * W[0]
    A0[e + 1, U_] = 1.0
    A0[e + 2, 3 * N + P_] = 1.0
    weights = np.zeros(N + 1)
    weights[:-1] += 0.5 * dz
    weights[1:] += 0.5 * dz
    out = (A0, A1, b0, b1, weights)
    _SYSTEMS.clear()
    _SYSTEMS[key] = (flow, out)
    return out


#: The last flow's first-order system (its matrices are linear in Ω; the frequencies of one
#: speed reuse them).
_SYSTEMS: dict = {}
