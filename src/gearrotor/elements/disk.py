"""Rigid disk: lumped mass and inertia at one node (6 DOFs)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

__all__ = ["DiskElement"]


@dataclass(frozen=True)
class DiskElement:
    """Rigid disk at a node.

    mass : kg;  polar : kg·m², polar moment Ip about the spin axis;
    transverse : kg·m², diametral moment It.
    The gyroscopic matrix (per unit spin speed) couples the tilts: the equations read
    ``It θ̈x + Ip Ω θ̇y = Mx`` and ``It θ̈y − Ip Ω θ̇x = My``.
    """

    mass: float
    polar: float
    transverse: float

    def M(self) -> NDArray:
        return np.diag(
            [self.mass, self.mass, self.mass, self.transverse, self.transverse, self.polar]
        )

    def K(self) -> NDArray:
        return np.zeros((6, 6))

    def G(self) -> NDArray:
        g = np.zeros((6, 6))
        g[3, 4] = self.polar
        g[4, 3] = -self.polar
        return g
