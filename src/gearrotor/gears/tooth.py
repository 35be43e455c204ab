"""Tooth compliance by the potential-energy method (per unit face width, transverse plane).

The tooth is a cantilever of variable section along its centre line, clamped at the root
circle, loaded at the contact point by the force F along the line of action. Its profile is
the rack-generated one: the involute from the form circle to the tip, and below it the fillet
traced by the rack's tip radius (the envelope of the rack tip circle as the rack rolls on the
reference circle; :func:`tooth_profile`). With the centre line as the y axis, the half
thickness h(y), the contact point (x_c, y_c) and the load angle α₁ between the force and the
x axis (α₁ = tan α_c − ψ_b for a contact at pressure angle α_c), the strain energies of
bending, shear and axial compression give (Yang & Lin 1987; Tian 2004; in Cartesian form as in
Chaari, Fakhfakh & Haddar 2009 and Ma et al. 2014)

    1/k_b = ∫ [(y_c − y) cos α₁ − x_c sin α₁]² / (E I_y) dy,     I_y = (2h)³/12,
    1/k_s = ∫ 1.2 cos² α₁ / (G A_y) dy,                          A_y = 2h,
    1/k_a = ∫ sin² α₁ / (E A_y) dy,

over the tooth from the root circle to y_c (plane stress, per metre of face width). The gear
body's deflection under the tooth is Sainsot, Velex & Duverger's (2004) fillet-foundation term

    1/k_f = cos² α₁ / E · [L* (u_f/S_f)² + M* (u_f/S_f) + P* (1 + Q* tan² α₁)],

u_f the distance from the root circle to the point where the line of action crosses the centre
line, S_f = 2 r_f θ_f the root-circle thickness, and L*, M*, P*, Q* their polynomial fits in
θ_f (the half angle of the tooth at the root circle) and h_f = r_f / r_int (r_int the body's
bore radius). The Hertzian contact of the pair is Yang & Lin's load-independent
k_h = π E* / 2 per unit contact length, 1/E* = (1 − ν₁²)/E₁ + (1 − ν₂²)/E₂ (for equal
materials k_h = π E L / (4 (1 − ν²))).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from ..errors import ModelError
from .geometry import ToothGeometry

__all__ = [
    "ToothProfile",
    "tooth_profile",
    "ToothCompliance",
    "tooth_compliance",
    "sainsot_coefficients",
    "hertz_compliance",
    "SAINSOT_RANGE",
]

# Sainsot, Velex & Duverger (2004), Table 1: X*(h_f, θ_f) = A/θ_f² + B h_f² + C h_f/θ_f
# + D/θ_f + E h_f + F for X* = L*, M*, P*, Q*
_SAINSOT = np.array(
    [
        [-5.574e-5, -1.9986e-3, -2.3015e-4, 4.7702e-3, 0.0271, 6.8045],
        [60.111e-5, 28.100e-3, -83.431e-4, -9.9256e-3, 0.1624, 0.9086],
        [-50.952e-5, 185.50e-3, 0.0538e-4, 53.300e-3, 0.2895, 0.9236],
        [-6.2042e-5, 9.0889e-3, -4.0964e-4, 7.8297e-3, -0.1472, 0.6904],
    ]
)
#: h_f = r_f / r_int covered by the fit: the coefficient values of Sainsot et al.'s fit
#: (L* 6.82–6.94, M* 1.08–3.29, P* 2.56–13.47, Q* 0.141–0.62, the ranges ROSS 3.1 checks)
#: are reached for h_f from about 2 to 7 at usual θ_f (0.04–0.08 rad). Their finite-element
#: bodies were clamped at the bore, so h_f grows with the body's depth and so does its
#: compliance. A gear without a given bore is taken clamped close under its root (h_f at the
#: lower end): the shaft it sits on, or a pinion's own shaft, is in the rotor model.
SAINSOT_RANGE = (2.0, 7.0)


def sainsot_coefficients(h_f: float, theta_f: float) -> NDArray:
    """(L*, M*, P*, Q*) of the fillet-foundation formula."""
    v = np.array([1 / theta_f**2, h_f**2, h_f / theta_f, 1 / theta_f, h_f, 1.0])
    return _SAINSOT @ v


def hertz_compliance(E1: float, nu1: float, E2: float, nu2: float) -> float:
    """Yang & Lin's Hertzian contact compliance per unit contact length (m²/N... i.e. the
    compliance of a contact of length L is this / L): 2 (1/E*) / π."""
    return 2.0 / np.pi * ((1 - nu1**2) / E1 + (1 - nu2**2) / E2)


@dataclass(frozen=True)
class ToothProfile:
    """One flank of a tooth in the tooth frame (y along the centre line from the gear's
    centre, x the half thickness), from the root circle to the tip.

    y, h : (n,) m, increasing y; y_form : where the involute starts; theta_f : half angle of
    the tooth at the root circle (rad); fillet : (m, 2) the fillet points (x, y) in order.
    """

    y: NDArray
    h: NDArray
    y_form: float
    theta_f: float
    r_f: float
    fillet: NDArray


def _rot(a: NDArray, x: NDArray, y: NDArray) -> tuple[NDArray, NDArray]:
    c, s = np.cos(a), np.sin(a)
    return c * x - s * y, s * x + c * y


def tooth_profile(t: ToothGeometry, n_fillet: int = 400, n_involute: int = 400) -> ToothProfile:
    """The rack-generated tooth profile (see the module docstring).

    Generation (transverse plane): the gear turns clockwise by φ while the rack's rolling line
    (the reference line, at r from the centre) rolls on the reference circle, i.e. the rack
    moves by s = r φ. The tip circle of the rack (radius ρ, centre C) cuts the fillet: the
    cutting point is where the normal passes through the pitch point I = (0, r), i.e.
    ``P = C + ρ (C − I)/|C − I|``, between the tip line and the straight flank. Rotating back
    by φ and by π/z (the tooth centre line) gives the fillet in the tooth frame.
    """
    r, rho, a = t.r, t.rho, t.alpha_t
    mt = t.transverse_module
    y_datum = r + t.shift * t.module
    y_c = t.r_f + rho
    u_c = np.pi * mt / 4 + (y_c - y_datum) * np.tan(a) - rho / np.cos(a)
    s0, s1 = -u_c, (r - y_c) / np.tan(a) - u_c
    # cluster the parameter at the root, where the fillet turns fastest
    q = np.linspace(0.0, 1.0, n_fillet)
    s = s0 + (s1 - s0) * (1 - np.cos(np.pi * q / 2))
    cx, cy = u_c + s, np.full_like(s, y_c)
    dx, dy = cx, cy - r
    d = np.hypot(dx, dy)
    d[d == 0] = 1.0
    if rho > 0:
        px, py = cx + rho * dx / d, cy + rho * dy / d
    else:
        px, py = cx, cy
    px, py = _rot(s / r + np.pi / t.teeth, px, py)
    fillet = np.column_stack([-px, py])  # half thickness, centre-line coordinate
    theta_f = float(np.arctan2(fillet[0, 0], fillet[0, 1]))
    # involute from the form circle to the tip
    rr = np.linspace(t.r_form, t.r_a, n_involute)
    psi = t.psi(rr)
    inv_xy = np.column_stack([rr * np.sin(psi), rr * np.cos(psi)])
    pts = np.vstack([fillet, inv_xy[1:]])
    order = np.argsort(pts[:, 1], kind="stable")
    pts = pts[order]
    keep = np.concatenate([[True], np.diff(pts[:, 1]) > 1e-12 * r])
    pts = pts[keep]
    if np.any(pts[:, 0] <= 0):
        raise ModelError(
            "the tooth profile has no thickness left below the tip",
            field="teeth",
            value=t.teeth,
            expected="a tooth whose flanks do not cross (smaller profile shift or addendum)",
        )
    return ToothProfile(
        y=pts[:, 1],
        h=pts[:, 0],
        y_form=float(inv_xy[0, 1]),
        theta_f=theta_f,
        r_f=t.r_f,
        fillet=fillet,
    )


@dataclass(frozen=True)
class ToothCompliance:
    """Compliances (m/N per metre of face width, i.e. m²/N... multiply by 1/b for a face b) of
    one tooth at contact radii ``radius``: bending, shear, axial, fillet foundation."""

    radius: NDArray
    bending: NDArray
    shear: NDArray
    axial: NDArray
    foundation: NDArray
    load_angle: NDArray

    @property
    def total(self) -> NDArray:
        return self.bending + self.shear + self.axial + self.foundation


def _cumtrapz(f: NDArray, x: NDArray) -> NDArray:
    out = np.zeros_like(f)
    out[1:] = np.cumsum(0.5 * (f[1:] + f[:-1]) * np.diff(x))
    return out


def tooth_compliance(
    t: ToothGeometry,
    radius: NDArray,
    E: float,
    poisson: float,
    bore_diameter: float | None = None,
    profile: ToothProfile | None = None,
) -> ToothCompliance:
    """Compliance of one tooth loaded at the involute radii ``radius`` (m), per unit face width."""
    p = tooth_profile(t) if profile is None else profile
    G = E / (2 * (1 + poisson))
    radius = np.atleast_1d(np.asarray(radius, float))
    alpha_c = np.arccos(np.clip(t.r_b / radius, -1.0, 1.0))
    psi = t.psi(radius)
    x_c, y_c = radius * np.sin(psi), radius * np.cos(psi)
    a1 = np.tan(alpha_c) - t.psi_b  # load angle
    # cumulative section integrals from the root, in η = y − y_root (no cancellation)
    eta = p.y - p.y[0]
    inv_i = 12.0 / (2 * p.h) ** 3
    inv_a = 1.0 / (2 * p.h)
    J0 = _cumtrapz(inv_i, eta)
    J1 = _cumtrapz(inv_i * eta, eta)
    J2 = _cumtrapz(inv_i * eta**2, eta)
    A0 = _cumtrapz(inv_a, eta)
    e_c = y_c - p.y[0]
    j0, j1, j2, a0 = (np.interp(e_c, eta, J) for J in (J0, J1, J2, A0))
    # ∫ [(e_c − η) cos α₁ − x_c sin α₁]² / I dη
    ca, sa = np.cos(a1), np.sin(a1)
    moment2 = ca**2 * (e_c**2 * j0 - 2 * e_c * j1 + j2)
    moment2 -= 2 * ca * sa * x_c * (e_c * j0 - j1)
    moment2 += sa**2 * x_c**2 * j0
    bending = moment2 / E
    shear = 1.2 * ca**2 * a0 / G
    axial = sa**2 * a0 / E
    # fillet foundation (Sainsot et al. 2004)
    r_int = None if bore_diameter is None else bore_diameter / 2
    h_f = SAINSOT_RANGE[0] if r_int is None else t.r_f / r_int
    if not SAINSOT_RANGE[0] - 1e-9 <= h_f <= SAINSOT_RANGE[1] + 1e-9:
        raise ModelError(
            f"the bore makes r_f/r_int = {h_f:.3g}, outside the range of Sainsot et al.'s "
            "fillet-foundation fit",
            field="bore_diameter",
            value=bore_diameter,
            expected=f"a bore diameter between {2 * t.r_f / SAINSOT_RANGE[1]:.4g} and "
            f"{2 * t.r_f / SAINSOT_RANGE[0]:.4g} m for this gear, or none (solid body)",
        )
    L, M, P, Q = sainsot_coefficients(h_f, p.theta_f)
    u_f = y_c - x_c * np.tan(a1) - p.r_f
    S_f = 2 * p.r_f * p.theta_f
    foundation = ca**2 / E * (L * (u_f / S_f) ** 2 + M * u_f / S_f + P * (1 + Q * np.tan(a1) ** 2))
    return ToothCompliance(radius, bending, shear, axial, foundation, a1)
