"""gearrotor: dynamics of geared rotor-bearing systems.

Finite-element models of machinery trains (Timoshenko shafts, disks, bearings, couplings) joined
by gear meshes that couple lateral, torsional and axial motion; damped eigenvalues, Campbell
diagrams, unbalance response, nonlinear transients and fluid-film bearings.
"""

from .analyses import ModalResult, modal
from .assembly import Assembly, assemble
from .errors import GearrotorError, ModelError, SolverError
from .io import load_model
from .model import Train

__version__ = "0.1.0"

__all__ = [
    "Assembly",
    "GearrotorError",
    "ModalResult",
    "ModelError",
    "SolverError",
    "Train",
    "assemble",
    "load_model",
    "modal",
    "transient",
    "__version__",
]


def __getattr__(name: str):
    # the transient solver compiles numba kernels: import it only when it is used
    if name == "transient":
        from .analyses.transient import transient

        return transient
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
