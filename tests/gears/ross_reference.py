"""Regenerate ross_reference.json: ROSS 3.1's GearElementTVMS on its own test pair
(ross/tests/test_gear_element.py: 62 teeth, module 2 mm, 20 mm face, 35 mm bore, 206 GPa, ν 0.3,
20°). Run with the interpreter that has ROSS (ross-rotordynamics 3.1.0), never in the test
suite (ROSS is not a dependency of gearrotor):

    /work/ross-venv/bin/python tests/gears/ross_reference.py
"""

import json
import warnings
from copy import deepcopy
from pathlib import Path

import numpy as np

warnings.filterwarnings("ignore")

from ross.materials import Material  # noqa: E402
from ross.multi_rotor.gear_element import GearElementTVMS  # noqa: E402
from ross.multi_rotor.mesh import Mesh  # noqa: E402
from ross.units import Q_  # noqa: E402

mat = Material("Gear_steel", rho=Q_(7.81, "g/cm**3"), E=Q_(206, "GPa"), Poisson=0.3)
gear = GearElementTVMS(
    n=0,
    material=mat,
    module=Q_(2, "mm"),
    width=Q_(20, "mm"),
    n_teeth=62,
    bore_diameter=Q_(35, "mm"),
    pr_angle=Q_(20, "deg"),
)
mesh = Mesh(gear, deepcopy(gear))
_, k = mesh.get_stiffness_for_mesh_period(stiffness_type="equivalent", n_points=1000)
angles = np.linspace(gear.pr_angles_dict["start_point"], gear.pr_angles_dict["addendum"], 5)
out = {
    "ross_version": "3.1.0",
    "contact_ratio": mesh.contact_ratio,
    "hertz_N_per_m": mesh.hertzian_stiffness,
    "buckingham_N_per_m": mesh.stiffness,
    "tvms_mean_N_per_m": float(np.mean(k)),
    "tvms_max_N_per_m": float(np.max(k)),
    "tvms_min_N_per_m": float(np.min(k)),
    "double_contact_fraction": float(np.mean(k > 0.5 * (k.max() + k.min()))),
    "tooth_stiffness_form_to_tip_N_per_m": [float(gear._compute_stiffness(a)) for a in angles],
    # one mesh cycle, 100 samples (ROSS's origin: the driving tooth at its involute's start)
    "tvms_curve_N_per_m": [float(x) for x in k[::10]],
}
Path(__file__).with_name("ross_reference.json").write_text(json.dumps(out, indent=1) + "\n")
print(json.dumps(out, indent=1))
