"""Gear tooth forces in closed form (SPEC 7, "Operating point first").

For a torque T on a gear of pitch radius r, normal pressure angle αn and helix angle β:
tangential ``Ft = T / r``, separating ``Fr = Ft tan αt`` with ``tan αt = tan αn / cos β`` and
axial ``Fa = Ft tan β``; the normal tooth force is ``Fn = Ft / (cos αn cos β)``. The two halves
of a double-helical (herringbone) gear have opposite β, so their axial forces cancel.

The static solver does not use these formulas (it finds the mesh forces from the stiffness of
the whole train); they are the closed forms its results are checked against.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["ToothForces", "tooth_forces"]


@dataclass(frozen=True)
class ToothForces:
    """Tooth forces of one mesh (N): tangential, separating (radial), axial (signed with β)
    and the normal force along the line of action."""

    tangential: float
    separating: float
    axial: float
    normal: float


def tooth_forces(
    torque: float, pitch_radius: float, pressure_angle: float, helix_angle: float = 0.0
) -> ToothForces:
    """Closed-form tooth forces for a torque (N·m) on a gear of pitch radius (m), normal
    pressure angle αn (rad) and helix angle β (rad, signed)."""
    ft = abs(torque) / pitch_radius
    tan_at = np.tan(pressure_angle) / np.cos(helix_angle)
    return ToothForces(
        tangential=float(ft),
        separating=float(ft * tan_at),
        axial=float(ft * np.tan(helix_angle)),
        normal=float(ft / (np.cos(pressure_angle) * np.cos(helix_angle))),
    )
