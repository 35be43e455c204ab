"""One static solver in the package: the transient's static initial state (torques through
the meshes) and the static analysis at the same torques give the same deflection (both call
``analyses/static/solver.solve_static``; they build K and the loads separately, so agreement
to round-off checks the two assemblies of the problem)."""

import math

import numpy as np
import pytest
from test_static_gears import gear_pair

from gearrotor.analyses.static import static
from gearrotor.analyses.transient.equations import build_system, static_state
from gearrotor.model import OperatingPoint


@pytest.mark.parametrize("sense", [1.0, -1.0])
@pytest.mark.parametrize("helix", [0.0, math.radians(20.0)])
def test_transient_static_state_equals_static_analysis(helix, sense):
    """Either flank loaded (the back flank along the mirrored line of action, the physical
    one, which the static analysis always uses)."""
    t = gear_pair(helix)
    data = t.model_dump()
    data["torques"] = [
        {"shaft": "p", "node": 0, "value": sense * 100.0},
        {"shaft": "g", "node": 8, "value": sense * 300.0},
    ]
    t = type(t).model_validate(data)
    system = build_system(t, back_flank="mirrored")
    q_tr, alpha = static_state(system)
    # balanced torques: no rigid acceleration (round-off of a multiplier of order T/J ~ 1e4)
    assert alpha == pytest.approx(0.0, abs=1e-6)
    op = OperatingPoint(
        name="T",
        torque=sense * 100.0,
        gravity=False,
        drive={"shaft": "p", "node": 0},
        load={"shaft": "g", "node": 8},
    )
    res = static(t, op)
    q_st = res.q[system.active]
    scale = np.max(np.abs(q_st))
    assert np.max(np.abs(q_tr - q_st)) < 1e-9 * scale
