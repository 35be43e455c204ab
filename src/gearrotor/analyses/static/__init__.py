"""Static analysis at operating points: deflection, bearing loads, tooth forces (issue 11).

``static(train, operating_point)`` solves the whole train (weight, gear forces from the
transmitted torque, static forces; fluid-film journals iterated to equilibrium with the shaft);
``at_operating_point(train, point)`` gives the train whose fluid-film bearings carry their
coefficients at the static loads, which every linear analysis then uses.
"""

from .analysis import journal_equilibrium, resolve_operating_point, static, static_sweep
from .loads import ToothForces, tooth_forces
from .operating_point import at_operating_point
from .results import BearingLoad, MeshLoad, ShaftStatics, StaticResult, StaticSweep
from .solver import Contact, LinearStatic, rigid_modes, solve_static

__all__ = [
    "at_operating_point",
    "BearingLoad",
    "Contact",
    "LinearStatic",
    "MeshLoad",
    "ShaftStatics",
    "StaticResult",
    "StaticSweep",
    "ToothForces",
    "journal_equilibrium",
    "resolve_operating_point",
    "rigid_modes",
    "solve_static",
    "static",
    "static_sweep",
    "tooth_forces",
]
