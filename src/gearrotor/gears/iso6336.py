"""ISO 6336-1:2006 method B internal dynamic factor K_v of a gear pair (clause 6.4), for the
comparison with the dynamic factor of
:func:`gearrotor.analyses.lateral.mesh_response.mesh_response`.

The pair is idealised as two rigid disc gears coupled by the mesh stiffness: the resonance
speed of the pinion is ``n_E1 = 30000/(π z1) √(c_γα / m_red)`` (min⁻¹; c_γα in N/(mm·µm), the
reduced mass per unit face width in kg/mm)

    m_red = π/8 (d_m1/d_b1)² d_m1² / [1/((1 − q1⁴) ρ1) + 1/((1 − q2⁴) ρ2 u²)],

``d_m = (d_a + d_f)/2``, ``q = d_i/d_m`` (bore over mean diameter), u = z2/z1; the resonance
ratio is N = n1/n_E1, and with ``w = F_t/b`` (N/mm; K_A = 1)

    B_p = c' f_pb,eff / w,  B_f = c' f_fα,eff / w,  B_k = |1 − c' C_a / w|,
    subcritical (N ≤ N_S):    K_v = N (C_v1 B_p + C_v2 B_f + C_v3 B_k) + 1,
    main resonance (≤ 1.15):  K_v = C_v1 B_p + C_v2 B_f + C_v4 B_k + 1,
    supercritical (≥ 1.5):    K_v = C_v5 B_p + C_v6 B_f + C_v7,
    intermediate:             linear in N between N = 1.15 and 1.5,

N_S = 0.85 (w ≥ 100 N/mm, else 0.5 + 0.35 √(w/100)), the C_v factors of the standard's
Table 4 as functions of the total contact ratio ε_γ. c' and c_γα are the standard's own
(:func:`gearrotor.elements.mesh.iso6336_stiffness`, with the basic-rack factor
C_B = [1 + 0.5 (1.2 − h_fP/m_n)] [1 − 0.02 (20° − α_Pn)]). The pitch and profile deviations
f_pb, f_fα of real teeth are inputs here (0 for the ideal teeth of the geometry model); the
tip relief C_a is the larger of the pair's tip reliefs.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from ..elements.mesh import iso6336_stiffness
from .loaded import MeshCurves

__all__ = ["IsoDynamicFactor", "dynamic_factor", "cv_factors"]


def cv_factors(eps_gamma: float) -> tuple[float, ...]:
    """(C_v1 … C_v7) of ISO 6336-1:2006 Table 4."""
    eg = eps_gamma
    cv1 = 0.32
    cv2 = 0.34 if eg <= 2 else 0.57 / (eg - 0.3)
    cv3 = 0.23 if eg <= 2 else 0.096 / (eg - 1.56)
    cv4 = 0.90 if eg <= 2 else (0.57 - 0.05 * eg) / (eg - 1.44)
    cv5 = 0.47
    cv6 = 0.47 if eg <= 2 else 0.12 / (eg - 1.74)
    if eg <= 1.5:
        cv7 = 0.75
    elif eg <= 2.5:
        cv7 = 0.125 * np.sin(np.pi * (eg - 2.0)) + 0.875
    else:
        cv7 = 1.0
    return cv1, cv2, cv3, cv4, cv5, cv6, cv7


@dataclass(frozen=True)
class IsoDynamicFactor:
    """K_v against pinion speed; c_prime, c_gamma_alpha in N/(mm·µm), m_red kg/mm,
    resonance_speed the pinion's n_E1 (rad/s)."""

    pinion_speed: NDArray
    kv: NDArray
    resonance_ratio: NDArray
    resonance_speed: float
    c_prime: float
    c_gamma_alpha: float
    m_red: float
    B_k: float


def dynamic_factor(
    curves: MeshCurves,
    pinion_speed: NDArray,
    density: tuple[float, float] = (7850.0, 7850.0),
    bore_diameter: tuple[float, float] | None = None,
    *,
    modulus: tuple[float, float] = (206e9, 206e9),
    f_pb: float = 0.0,
    f_falpha: float = 0.0,
    tip_relief: float = 0.0,
) -> IsoDynamicFactor:
    """ISO 6336-1 method B K_v of the pair of ``curves`` at the pinion speeds (rad/s);
    densities kg/m³, moduli Pa, bores and deviations m."""
    g = curves.geometry
    p, q = g.pinion, g.gear
    b_mm = g.face_width * 1e3
    eps_a = g.contact_ratio
    cb = (1 + 0.5 * (1.2 - p.dedendum)) * (1 - 0.02 * (20 - np.rad2deg(p.pressure_angle)))
    k_norm = iso6336_stiffness(
        p.teeth,
        q.teeth,
        g.face_width,
        eps_a,
        p.helix_angle,
        p.pressure_angle,
        modulus[0],
        modulus[1],
        p.shift,
        q.shift,
        CB=cb,
    )
    c_gamma = k_norm * np.cos(g.beta_b) ** 2 / (g.face_width * 1e9)  # N/(mm·µm)
    c_prime = c_gamma / (0.75 * eps_a + 0.25)
    w = curves.torque / p.r / b_mm  # F_t at the reference circle over b (N/mm), K_A = 1
    # reduced mass per unit face width
    bores = bore_diameter or (0.0, 0.0)
    dm = [(2 * t.r_a + 2 * t.r_f) / 2 * 1e3 for t in (p, q)]  # mm
    qq = [bores[i] * 1e3 / dm[i] for i in range(2)]
    rho = [d * 1e-9 for d in density]  # kg/mm³
    u = q.teeth / p.teeth
    db1 = 2 * p.r_b * 1e3
    m_red = (
        np.pi
        / 8
        * (dm[0] / db1) ** 2
        * dm[0] ** 2
        / (1 / ((1 - qq[0] ** 4) * rho[0]) + 1 / ((1 - qq[1] ** 4) * rho[1] * u**2))
    )
    nE1 = 30000 / (np.pi * p.teeth) * np.sqrt(c_gamma / m_red)  # min⁻¹
    n1 = np.abs(np.asarray(pinion_speed, float)) * 30 / np.pi
    N = n1 / nE1
    NS = 0.85 if w >= 100 else 0.5 + 0.35 * np.sqrt(w / 100)
    Bp = c_prime * f_pb * 1e6 / w
    Bf = c_prime * f_falpha * 1e6 / w
    Bk = abs(1 - c_prime * tip_relief * 1e6 / w)
    cv1, cv2, cv3, cv4, cv5, cv6, cv7 = cv_factors(g.total_contact_ratio)
    sub = N * (cv1 * Bp + cv2 * Bf + cv3 * Bk) + 1
    main = cv1 * Bp + cv2 * Bf + cv4 * Bk + 1
    sup = cv5 * Bp + cv6 * Bf + cv7
    inter = sup + (main - sup) / 0.35 * (1.5 - N)
    kv = np.where(N <= NS, sub, np.where(N <= 1.15, main, np.where(N < 1.5, inter, sup)))
    return IsoDynamicFactor(
        pinion_speed=np.asarray(pinion_speed, float),
        kv=np.maximum(kv, 1.0),
        resonance_ratio=N,
        resonance_speed=float(nE1 * np.pi / 30),
        c_prime=float(c_prime),
        c_gamma_alpha=float(c_gamma),
        m_red=float(m_red),
        B_k=float(Bk),
    )
