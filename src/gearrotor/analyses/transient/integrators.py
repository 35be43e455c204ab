"""The former home of the transient integrators and driver, kept so that existing imports work:
the option objects are in :mod:`.options`, the driver :func:`transient` in :mod:`.driver`, the
RK4 step limits in :mod:`.step_limits` (and the modal reduction, the kernel arrays, the force
packing and the checkpoints in :mod:`.reduction`, :mod:`.prepare`, :mod:`.forces`,
:mod:`.checkpoint`). Import from :mod:`gearrotor.analyses.transient`."""

from .driver import transient
from .options import RK4, Checkpoint, ModalRK4, Save, excitation_frequency
from .step_limits import rk4_max_step

__all__ = [
    "RK4",
    "ModalRK4",
    "Save",
    "Checkpoint",
    "transient",
    "rk4_max_step",
    "excitation_frequency",
]
