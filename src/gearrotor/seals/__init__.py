"""Annular seals from geometry: gas labyrinth seals, liquid annular seals, gas damper seals
(hole-pattern, honeycomb).

:func:`load_seal` reads a seal file; :func:`seal_coefficients` gives the leakage and the 8
rotordynamic coefficients at a speed and whirl frequency; :func:`seal_table` tabulates the
synchronous coefficients over speed for a rotor model (``[[seals]] file = ...``). The models and
their sources are in the module docstrings of :mod:`.labyrinth` and :mod:`.annular`, and in
``docs/seals.md``.
"""

from .annular import AnnularSeal, Friction
from .coefficients import (
    COEFFICIENT_KEYS,
    SealResult,
    seal_coefficients,
    seal_table,
    seal_whirl_table,
)
from .fluids import IdealGas, Liquid, RealGas, coolprop_available
from .io import SEAL_TYPES, load_seal, parse_seal
from .labyrinth import LabyrinthSeal

__all__ = [
    "AnnularSeal",
    "COEFFICIENT_KEYS",
    "Friction",
    "IdealGas",
    "LabyrinthSeal",
    "Liquid",
    "RealGas",
    "SEAL_TYPES",
    "SealResult",
    "coolprop_available",
    "load_seal",
    "parse_seal",
    "seal_coefficients",
    "seal_table",
    "seal_whirl_table",
]
