"""Finite elements: small frozen types with pure matrix methods in the global DOF order."""

from .bearing import CoefficientTable, CrossCoupling, RadialBearing, ThrustBearing
from .coupling import CouplingElement
from .disk import DiskElement
from .mesh import MeshGeometry, buckingham_stiffness, iso6336_stiffness
from .pad_bearing import PadBearing, PadTable, condense
from .shaft import ShaftElement, shear_coefficient
from .torsional_support import TorsionalSupportElement

__all__ = [
    "CoefficientTable",
    "CouplingElement",
    "CrossCoupling",
    "DiskElement",
    "MeshGeometry",
    "PadBearing",
    "PadTable",
    "RadialBearing",
    "ShaftElement",
    "ThrustBearing",
    "TorsionalSupportElement",
    "buckingham_stiffness",
    "condense",
    "iso6336_stiffness",
    "shear_coefficient",
]
