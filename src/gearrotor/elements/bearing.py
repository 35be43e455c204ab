"""Bearing-type elements: radial bearings/seals, thrust bearings, cross-coupled stiffness.

All act on the lateral (x, y) or axial (z) DOFs of a node, either to ground or to a second node
(a support/pedestal); forces are ``f = −K u − C u̇`` with u the relative motion.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

__all__ = ["RadialBearing", "ThrustBearing", "CrossCoupling", "CoefficientTable"]

_NAMES = ("kxx", "kxy", "kyx", "kyy", "cxx", "cxy", "cyx", "cyy")


@dataclass(frozen=True)
class CoefficientTable:
    """Eight bearing coefficients tabulated against speed.

    speed : rad/s, strictly increasing (absolute shaft speed); values : shape (n, 8) in the order
    kxx kxy kyx kyy (N/m) cxx cxy cyx cyy (N·s/m). Between points the coefficients are linearly
    interpolated; outside the table :meth:`at` raises unless ``extrapolate="hold"`` holds the
    end values.
    """

    speed: NDArray
    values: NDArray
    extrapolate: str = "error"

    def at(self, speed: float) -> NDArray:
        w = abs(speed)
        s = self.speed
        if self.extrapolate != "hold" and not (s[0] - 1e-9 <= w <= s[-1] + 1e-9) and len(s) > 1:
            from ..errors import ModelError

            raise ModelError(
                "speed outside the bearing coefficient table",
                value=f"{w * 30 / np.pi:.6g} rpm",
                expected=f"a speed within {s[0] * 30 / np.pi:.6g}..{s[-1] * 30 / np.pi:.6g} rpm "
                '(extend the table or set extrapolate = "hold")',
            )
        return np.array([np.interp(w, s, self.values[:, j]) for j in range(8)])


@dataclass(frozen=True)
class RadialBearing:
    """Eight-coefficient radial bearing or seal (constant, or tabulated vs speed)."""

    kxx: float = 0.0
    kxy: float = 0.0
    kyx: float = 0.0
    kyy: float = 0.0
    cxx: float = 0.0
    cxy: float = 0.0
    cyx: float = 0.0
    cyy: float = 0.0
    table: CoefficientTable | None = field(default=None, compare=False)

    def coefficients(self, speed: float = 0.0) -> NDArray:
        """The 8 coefficients at a shaft speed (rad/s)."""
        if self.table is not None:
            return self.table.at(speed)
        return np.array([getattr(self, n) for n in _NAMES])

    def K(self, speed: float = 0.0) -> NDArray:
        c = self.coefficients(speed)
        return np.array([[c[0], c[1]], [c[2], c[3]]])

    def C(self, speed: float = 0.0) -> NDArray:
        c = self.coefficients(speed)
        return np.array([[c[4], c[5]], [c[6], c[7]]])

    @property
    def speed_dependent(self) -> bool:
        return self.table is not None


@dataclass(frozen=True)
class ThrustBearing:
    """Axial stiffness kzz (N/m) and damping czz (N·s/m)."""

    kzz: float = 0.0
    czz: float = 0.0

    def K(self) -> NDArray:
        return np.array([[self.kzz]])

    def C(self) -> NDArray:
        return np.array([[self.czz]])


@dataclass(frozen=True)
class CrossCoupling:
    """Destabilising cross-coupled stiffness at a node: kxy = −kyx = q (N/m).

    With ``f = −K u`` a positive q feeds forward whirl about +z (the force is along the whirl
    velocity), as aerodynamic cross-coupling or seal forces do.
    """

    q: float

    def K(self) -> NDArray:
        return np.array([[0.0, self.q], [-self.q, 0.0]])
