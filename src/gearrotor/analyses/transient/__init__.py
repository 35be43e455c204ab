"""Nonlinear transient analysis of geared trains (SPEC 2.4–2.6, 3.3).

``transient(train, t_end=..., integrator=RK4(dt=...))`` integrates the equations of
:mod:`.equations` with the mesh law of :mod:`.mesh`, using the compiled kernels of
:mod:`.kernels`, and returns a :class:`TransientResult`.
"""

from .equations import TransientSystem, build_system, mesh_damping_from_ratio, static_state
from .integrators import RK4, Checkpoint, ModalRK4, Save, rk4_max_step, transient
from .mesh import MeshLaw, backlash_h, fourier_coefficients, stiffness
from .results import (
    SolverStats,
    TransientResult,
    amplitude_at,
    load_result,
    order_amplitudes,
    spectrum,
)

__all__ = [
    "RK4",
    "Checkpoint",
    "MeshLaw",
    "ModalRK4",
    "Save",
    "SolverStats",
    "TransientResult",
    "TransientSystem",
    "amplitude_at",
    "backlash_h",
    "build_system",
    "fourier_coefficients",
    "load_result",
    "mesh_damping_from_ratio",
    "order_amplitudes",
    "rk4_max_step",
    "spectrum",
    "static_state",
    "stiffness",
    "transient",
]
