"""Torsional analysis of whole trains (the torsional audit of API 617 / API RP 684).

* :func:`torsional_model` — the θz model of a train, meshes flexible or rigid;
* :func:`torsional_modes` — natural frequencies, mode shapes, damping, largest-stress element;
* :func:`interference` — interference diagram and separation margins;
* :func:`torsional_response` — steady-state response to harmonic torques over a speed sweep;
* :func:`torsional_transient` — start-ups, short circuits, trips (drives and loads of the
  model's ``[torsional]`` table, speed as a state, mesh backlash);
* :func:`fatigue` — rainflow counting (ASTM E1049-85), S–N curve, Miner's rule.
"""

from .drive_laws import TorqueLaws, pack_laws
from .fatigue import FatigueResult, SNCurve, fatigue, miner_damage, rainflow_cycles
from .interference import ExcitationLine, InterferenceCrossing, InterferenceResult, interference
from .model import MESH_MODELS, TorsionalModel, torsional_model
from .modes import TorsionalModes, torsional_modes
from .response import HarmonicTorque, TorsionalResponse, torsional_response
from .transient import TorsionalTransient, torsional_transient

__all__ = [
    "MESH_MODELS",
    "ExcitationLine",
    "FatigueResult",
    "HarmonicTorque",
    "InterferenceCrossing",
    "InterferenceResult",
    "SNCurve",
    "TorqueLaws",
    "TorsionalModel",
    "TorsionalModes",
    "TorsionalResponse",
    "TorsionalTransient",
    "fatigue",
    "interference",
    "miner_damage",
    "pack_laws",
    "rainflow_cycles",
    "torsional_model",
    "torsional_modes",
    "torsional_response",
    "torsional_transient",
]
