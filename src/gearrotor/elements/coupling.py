"""Flexible coupling: diagonal stiffness and damping between two nodes, all 6 directions."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

__all__ = ["CouplingElement"]


@dataclass(frozen=True)
class CouplingElement:
    """Node-to-node coupling, uncoupled between directions.

    stiffness : 6 values for x, y, z (N/m), θx, θy, θz (N·m/rad);
    damping : 6 values (N·s/m, N·m·s/rad). Matrices are 12×12 on (node i, node j).
    """

    stiffness: tuple[float, float, float, float, float, float]
    damping: tuple[float, float, float, float, float, float] = (0.0,) * 6

    @staticmethod
    def _pair(d: NDArray) -> NDArray:
        dm = np.diag(d)
        return np.block([[dm, -dm], [-dm, dm]])

    def K(self) -> NDArray:
        return self._pair(np.asarray(self.stiffness, float))

    def C(self) -> NDArray:
        return self._pair(np.asarray(self.damping, float))
