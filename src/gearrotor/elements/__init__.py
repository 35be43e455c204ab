"""Finite elements: small frozen types with pure matrix methods in the global DOF order."""

from .bearing import CoefficientTable, CrossCoupling, RadialBearing, ThrustBearing
from .coupling import CouplingElement
from .disk import DiskElement
from .mesh import MeshGeometry, buckingham_stiffness, iso6336_stiffness
from .pad_bearing import PadBearing, PadTable, condense
from .rational_fit import RationalImpedance, fit_impedance, fit_row
from .shaft import ShaftElement, shear_coefficient
from .torsional_support import TorsionalSupportElement
from .whirl_bearing import FIT_TOLERANCE, WhirlBearing, WhirlRow, fit_rows

__all__ = [
    "FIT_TOLERANCE",
    "CoefficientTable",
    "CouplingElement",
    "CrossCoupling",
    "DiskElement",
    "MeshGeometry",
    "PadBearing",
    "PadTable",
    "RadialBearing",
    "RationalImpedance",
    "ShaftElement",
    "ThrustBearing",
    "TorsionalSupportElement",
    "WhirlBearing",
    "WhirlRow",
    "buckingham_stiffness",
    "condense",
    "fit_impedance",
    "fit_row",
    "fit_rows",
    "iso6336_stiffness",
    "shear_coefficient",
]
