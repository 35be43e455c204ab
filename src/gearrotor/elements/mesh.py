"""Gear mesh element derived from contact-point kinematics (SPEC 2.3).

Direction cosines of the tooth normal force resolved at the pitch point:
``cx = cos β cos αn`` (tangential), ``cy = sin αn`` (radial), ``cz = sin β cos αn`` (axial).
With ``e = (cos ϕ, sin ϕ, 0)`` the unit vector along the line of centres from gear i to gear j,
the unit normal is ``n = (sin ϕ cx + cos ϕ cy, sin ϕ cy − cos ϕ cx, cz)``. The pitch point is
``p_i = r_i e`` from gear i's centre and ``p_j = −r_j e`` from gear j's centre, so the relative
approach of the two tooth surfaces along n is

    δ = n·(u_i + θ_i × p_i) − n·(u_j + θ_j × p_j) = w · [q_i, q_j],

with ``n·(θ × p) = θ·(p × n)``:  ``w_i = [n, p_i × n] = [n, r_i (e × n)]`` and
``w_j = −[n, p_j × n] = [−n, r_j (e × n)]``. The element is the rank-one ``K = k w wᵀ`` (and
``C = c w wᵀ``) on the 12 DOFs ``(x, y, z, θx, θy, θz)`` of gear i then gear j.

Since ``(e × n)_z = −cx``, gears turning at ``r_i θz_i = −r_j θz_j`` (external gears, opposite
senses) give δ = 0, and a static mesh force F produces torques in the ratio r_j / r_i.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

__all__ = [
    "MeshGeometry",
    "buckingham_stiffness",
    "iso6336_stiffness",
    "transverse_pressure_angle",
    "base_helix_angle",
]


def transverse_pressure_angle(normal_pressure_angle: float, helix_angle: float) -> float:
    """αt from tan αt = tan αn / cos β (rad)."""
    return float(np.arctan(np.tan(normal_pressure_angle) / np.cos(helix_angle)))


def base_helix_angle(normal_pressure_angle: float, helix_angle: float) -> float:
    """βb from sin βb = sin β cos αn (rad)."""
    return float(np.arcsin(np.sin(helix_angle) * np.cos(normal_pressure_angle)))


@dataclass(frozen=True)
class MeshGeometry:
    """Kinematics of one gear mesh.

    radius_i, radius_j : m, pitch radii; pressure_angle : rad, normal αn; helix_angle : rad,
    signed β (the hand); orientation : rad, angle ϕ of the line of centres from gear i to gear j;
    flank : +1 for the tooth flank of SPEC 2.3 (a contact force puts +z torque on both gears),
    −1 for the opposite flank (tangential and axial cosines reversed, radial kept: the contact
    force still separates the gears).
    """

    radius_i: float
    radius_j: float
    pressure_angle: float
    helix_angle: float = 0.0
    orientation: float = 0.0
    flank: int = 1

    @property
    def direction_cosines(self) -> tuple[float, float, float]:
        a, b, f = self.pressure_angle, self.helix_angle, self.flank
        return f * np.cos(b) * np.cos(a), np.sin(a), f * np.sin(b) * np.cos(a)

    @property
    def e(self) -> NDArray:
        return np.array([np.cos(self.orientation), np.sin(self.orientation), 0.0])

    @property
    def n(self) -> NDArray:
        cx, cy, cz = self.direction_cosines
        s, c = np.sin(self.orientation), np.cos(self.orientation)
        return np.array([s * cx + c * cy, s * cy - c * cx, cz])

    def w(self) -> NDArray:
        """Kinematic vector (12,): δ = w · [q_i, q_j]."""
        n, e = self.n, self.e
        exn = np.cross(e, n)
        return np.concatenate([n, self.radius_i * exn, -n, self.radius_j * exn])

    def K(self, stiffness: float) -> NDArray:
        """Mesh stiffness matrix k w wᵀ (12×12) for a stiffness k (N/m) along the normal."""
        w = self.w()
        return stiffness * np.outer(w, w)

    def C(self, damping: float) -> NDArray:
        w = self.w()
        return damping * np.outer(w, w)

    @property
    def torque_arm_i(self) -> float:
        """|dδ/dθz_i| = r_i cos β cos αn (m): torque per unit normal force on gear i."""
        return abs(self.radius_i * self.direction_cosines[0])

    @property
    def torque_arm_j(self) -> float:
        return abs(self.radius_j * self.direction_cosines[0])


def buckingham_stiffness(contact_ratio: float, face_width: float, E_i: float, E_j: float) -> float:
    """Buckingham's average mesh stiffness ``Kg = c·w·E1E2 / (9(E1+E2))`` (N/m).

    contact_ratio : c (–); face_width : w (m); E_i, E_j : Young's moduli (Pa).
    """
    return contact_ratio * face_width * E_i * E_j / (9.0 * (E_i + E_j))


# ISO 6336-1:2019, method B, eq. (B.? ) coefficients C1..C9 of the flexibility q' (mm·µm/N)
_ISO_C = (0.04723, 0.15551, 0.25791, -0.00635, -0.11654, -0.00193, -0.24188, 0.00529, 0.00182)


def iso6336_stiffness(
    teeth_i: int,
    teeth_j: int,
    face_width: float,
    contact_ratio: float,
    helix_angle: float = 0.0,
    pressure_angle: float = np.deg2rad(20.0),
    E_i: float = 206e9,
    E_j: float = 206e9,
    shift_i: float = 0.0,
    shift_j: float = 0.0,
    CM: float = 0.8,
    CR: float = 1.0,
    CB: float = 1.0,
) -> float:
    """Average mesh stiffness along the normal line of action from ISO 6336-1 (N/m).

    Single-pair stiffness ``c'_th = 1/q'`` with ``q' = C1 + C2/zn1 + C3/zn2 + C4 x1 + C5 x1/zn1
    + C6 x2 + C7 x2/zn2 + C8 x1² + C9 x2²`` (virtual tooth counts ``zn = z/cos³β``, profile shifts
    x), ``c' = c'_th CM CR CB cos β`` for solid steel gears scaled by E/206 GPa, mesh stiffness
    ``cγα = c'(0.75 εα + 0.25)`` per unit face width (N/(mm·µm)) in the transverse plane.
    The returned normal-direction stiffness is ``cγα·b / cos² βb``.
    """
    b = abs(helix_angle)
    zn1 = teeth_i / np.cos(b) ** 3
    zn2 = teeth_j / np.cos(b) ** 3
    C1, C2, C3, C4, C5, C6, C7, C8, C9 = _ISO_C
    q = (
        C1
        + C2 / zn1
        + C3 / zn2
        + C4 * shift_i
        + C5 * shift_i / zn1
        + C6 * shift_j
        + C7 * shift_j / zn2
        + C8 * shift_i**2
        + C9 * shift_j**2
    )
    e_eq = 2 * E_i * E_j / (E_i + E_j)
    c_single = (1.0 / q) * CM * CR * CB * np.cos(b) * e_eq / 206e9
    c_gamma = c_single * (0.75 * contact_ratio + 0.25)  # N/(mm·µm) = 1e9 N/m²
    beta_b = base_helix_angle(pressure_angle, b)
    return c_gamma * 1e9 * face_width / np.cos(beta_b) ** 2
