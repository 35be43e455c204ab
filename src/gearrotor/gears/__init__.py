"""Gear meshes from the tooth geometry (issue 27): involute geometry of external spur and
helical pairs (:mod:`.geometry`), tooth compliance by the potential-energy method with the
fillet-foundation and Hertzian terms (:mod:`.tooth`), load sharing over the mesh cycle by
slices along the face with tooth modifications, and the loaded static transmission error and
time-varying mesh stiffness under the operating torque (:mod:`.loaded`); gear-pair files
(:mod:`.io`) and plots (:mod:`.plots`, matplotlib imported when used).

A gear pair is a :class:`gearrotor.model.gear_pair.GearPair`; :func:`mesh_curves` returns the
loaded mesh over one cycle (:class:`MeshCurves`), whose harmonics drive the rotor model's mesh.
"""

from .geometry import PairGeometry, ToothGeometry, pair_geometry
from .io import load_gear_pair, merge_gear_pair, parse_gear_pair
from .loaded import MeshCurves, mesh_curves
from .tooth import hertz_compliance, tooth_compliance, tooth_profile

__all__ = [
    "MeshCurves",
    "PairGeometry",
    "ToothGeometry",
    "hertz_compliance",
    "load_gear_pair",
    "merge_gear_pair",
    "mesh_curves",
    "pair_geometry",
    "parse_gear_pair",
    "tooth_compliance",
    "tooth_profile",
]
