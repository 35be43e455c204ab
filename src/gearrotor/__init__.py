"""gearrotor: dynamics of geared rotor-bearing systems.

Finite-element models of machinery trains (Timoshenko shafts, disks, bearings, couplings) joined
by gear meshes that couple lateral, torsional and axial motion; damped eigenvalues, Campbell
diagrams, unbalance response, nonlinear transients and fluid-film bearings.
"""

from .errors import GearrotorError, ModelError, SolverError

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


# imported on first use (PEP 562), so that ``import gearrotor`` and ``gearrotor --help`` stay
# light: the model pulls in pint and its unit registry, the analyses scipy.optimize, and the
# transient solver compiles numba kernels
_LAZY = {
    "Assembly": ".assembly",
    "assemble": ".assembly",
    "ModalResult": ".analyses.lateral.modal",
    "modal": ".analyses.lateral.modal",
    "load_model": ".io",
    "Train": ".model",
    "transient": ".analyses.transient",
}


def __getattr__(name: str):
    if name in _LAZY:
        import importlib

        value = getattr(importlib.import_module(_LAZY[name], __name__), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_LAZY))
