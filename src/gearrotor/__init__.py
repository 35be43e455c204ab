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
    "__version__",
]
