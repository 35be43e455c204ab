"""Finite elements: small frozen types with pure matrix methods in the global DOF order."""

from .bearing import CoefficientTable, CrossCoupling, RadialBearing, ThrustBearing
from .coupling import CouplingElement
from .disk import DiskElement
from .mesh import MeshGeometry, buckingham_stiffness, iso6336_stiffness
from .shaft import ShaftElement, shear_coefficient

__all__ = [
    "CoefficientTable",
    "CouplingElement",
    "CrossCoupling",
    "DiskElement",
    "MeshGeometry",
    "RadialBearing",
    "ShaftElement",
    "ThrustBearing",
    "buckingham_stiffness",
    "iso6336_stiffness",
    "shear_coefficient",
]
