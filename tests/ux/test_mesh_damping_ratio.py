"""Issue 14 item 9: a mesh damping_ratio acts in every analysis, by one conversion (assembly)."""

from __future__ import annotations

import numpy as np
import pytest

from gearrotor import load_model
from gearrotor.analyses import campbell, modal, unbalance_response
from gearrotor.assembly import assemble
from gearrotor.model import Train

RPM = np.pi / 30


def _geared_pair(**mesh) -> Train:
    # two rigid gears on a mesh spring, bearings 1e14 N/m: the one elastic mode is the mesh
    # torsional mode ω² = k cos²α (r1²/j1 + r2²/j2) (tests/test_mesh_element.py)
    shafts, bearings = [], []
    for name, J in (("p", 0.4), ("g", 3.1)):
        shafts.append(
            {
                "name": name,
                "material": "m",
                "sections": [{"length": 0.01, "outer_diameter": 0.05, "elements": 1}],
                "disks": [{"node": 0, "mass": 1.0, "polar": J, "transverse": 0.5}],
            }
        )
        bearings += [{"shaft": name, "node": node, "k": 1e14} for node in (0, 1)]
    return Train.model_validate(
        {
            "materials": {"m": {"E": 2e11, "density": 7800, "poisson": 0.3}},
            "shafts": shafts,
            "bearings": bearings,
            "speed": 0.0,
            "thrust_bearings": [{"shaft": s, "node": 0, "kzz": 1e14} for s in ("p", "g")],
            "meshes": [
                {
                    "gear": {"shaft": "p", "node": 0, "teeth": 20, "radius": 0.1},
                    "mate": {"shaft": "g", "node": 0, "teeth": 50, "radius": 0.25},
                    "pressure_angle": 0.349,
                    "stiffness": 2e8,
                    **mesh,
                }
            ],
        }
    )


def test_damping_ratio_gives_the_mesh_mode_its_damping_ratio():
    # the mesh mode is a single-DOF oscillator in modal coordinates (the bearings are 1e6 times
    # stiffer): its damping ratio must be the given ζ (to the lateral compliance, ~1e-6)
    res = modal(_geared_pair(damping_ratio=0.05))
    tors = np.array(res.mode_type) == "T"
    assert res.damping_ratio[tors][0] == pytest.approx(0.05, rel=1e-4)
    assert modal(_geared_pair()).damping_ratio[tors][0] == 0.0  # no damping without it


def test_damping_ratio_acts_in_modal_campbell_unbalance_as_the_equivalent_damper(examples):
    # the flagship with ζ = 0.05 on its mesh: every linear analysis must equal the same model
    # with the equivalent damper c given directly (one conversion, in the assembly)
    base = load_model(examples / "unity_gearbox.toml")
    spec = base.model_dump()
    spec["meshes"][0]["damping"] = 0.0
    spec["meshes"][0]["damping_ratio"] = 0.05
    with_ratio = Train.model_validate(spec)
    c = assemble(with_ratio).meshes[0].damping
    assert c > 0
    spec["meshes"][0]["damping_ratio"] = None
    spec["meshes"][0]["damping"] = c
    with_c = Train.model_validate(spec)
    spec["meshes"][0]["damping"] = 0.0
    undamped = Train.model_validate(spec)
    kw = dict(speed=6500 * RPM, max_frequency=8e4 * RPM)
    a, b, u = (modal(t, **kw) for t in (with_ratio, with_c, undamped))
    np.testing.assert_allclose(a.eigenvalues, b.eigenvalues, rtol=1e-10)
    coupled = int(np.argmin(abs(a.frequency_rpm - 57010)))
    assert a.log_dec[coupled] > u.log_dec[coupled] + 0.05  # the mesh damper acts
    sweep = dict(speeds=np.array([3000.0, 6500.0]) * RPM, max_frequency=8e4 * RPM)
    ca, cb = (campbell(t, **sweep) for t in (with_ratio, with_c))
    np.testing.assert_allclose(ca.log_dec, cb.log_dec, rtol=1e-8)
    speeds = np.array([5000.0, 7000.0]) * RPM
    ua, ub = (unbalance_response(t, speeds=speeds) for t in (with_ratio, with_c))
    np.testing.assert_allclose(ua.response, ub.response, rtol=1e-8)
