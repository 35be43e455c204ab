"""Torsional spring and damper from a node's θz to ground (1 DOF)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

__all__ = ["TorsionalSupportElement"]


@dataclass(frozen=True)
class TorsionalSupportElement:
    """Spring ``k`` (N·m/rad) and damper ``c`` (N·m·s/rad) between a node's θz and ground.

    Matrices are 1×1 on the node's θz: the restoring torque is ``−k θz − c θ̇z``.
    """

    k: float
    c: float = 0.0

    def K(self) -> NDArray:
        return np.array([[float(self.k)]])

    def C(self) -> NDArray:
        return np.array([[float(self.c)]])
