"""Nonlinear transient analysis of geared trains (SPEC 2.4–2.6, 3.3).

``transient(train, t_end=..., integrator=RK4(dt=...))`` integrates the equations of
:mod:`.equations` with the mesh law of :mod:`.mesh`, using the compiled kernels of
:mod:`.kernels`, and returns a :class:`TransientResult`.

One call, in reading order: :func:`.driver.transient` builds the system
(:func:`.equations.build_system`: matrices, DOF maps, the mesh laws of :mod:`.mesh`), picks the
recorded DOFs (:mod:`.forces`), prepares the compiled kernel's arrays for the integrator chosen
in :mod:`.options` (:mod:`.prepare`: the full model for RK4, the modal reduction of
:mod:`.reduction` for ModalRK4, both checked against :mod:`.step_limits`), integrates in chunks
(:mod:`.kernels`; checkpoints: :mod:`.checkpoint`) and builds the :class:`TransientResult`
(:mod:`.results`, which recomputes the mesh forces with the packing of :mod:`.forces`).
Figures of a result: :mod:`.plots`; spectra and order amplitudes: :mod:`gearrotor.signals`.
"""

from ...signals import amplitude_at, order_amplitudes, spectrum
from .driver import transient, transient_at_operating_point
from .equations import TransientSystem, build_system, mesh_damping_from_ratio, static_state
from .mesh import MeshLaw, backlash_h, fourier_coefficients, stiffness
from .options import RK4, Checkpoint, ModalRK4, Save
from .results import SolverStats, TransientResult, load_result
from .step_limits import rk4_max_step

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
    "transient_at_operating_point",
]
