"""Torsional analysis of whole trains (the torsional audit of API 617 / API RP 684).

* :func:`torsional_model` — the θz model of a train, meshes flexible or rigid;
* :func:`torsional_modes` — natural frequencies, mode shapes, damping, largest-stress element;
"""

from .model import MESH_MODELS, TorsionalModel, torsional_model
from .modes import TorsionalModes, torsional_modes

__all__ = [
    "MESH_MODELS",
    "TorsionalModel",
    "TorsionalModes",
    "torsional_model",
    "torsional_modes",
]
