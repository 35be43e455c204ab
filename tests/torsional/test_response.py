"""Steady-state torsional forced response against closed forms.

Two inertias J1, J2 joined by a spring k with a damper c (a coupling), harmonic torque
T0 e^{iωt} on J1 (e.g. Thomson & Dahleh, *Theory of Vibration with Applications*, 5th ed. 1998,
§5.? forced two-DOF systems, solved by hand): with z = k + iωc,

    Θ1 − Θ2 = T0 J2 / (z (J1 + J2) − ω² J1 J2),   coupling torque = |z (Θ1 − Θ2)|.

A rigid gear pair with the inertia J_b on the pinion: the mesh force turns the pinion side, so
|F| r_b cos αn = J_b ω² |Θ_b| (its constraint reaction must say so).
"""

from __future__ import annotations

import numpy as np
import pytest

from gearrotor.analyses.torsional import torsional_response
from gearrotor.errors import ModelError
from torsional_helpers import disk, geared_train, shaft

J1, J2, K, C = 2.0, 5.0, 3e5, 120.0


def _pair():
    return geared_train(
        [shaft("a", None, [disk(1, J1)]), shaft("b", None, [disk(0, J2)], start=0.6)],
        couplings=[
            {
                "node_i": {"shaft": "a", "node": 1},
                "node_j": {"shaft": "b", "node": 0},
                "ktz": K,
                "ctz": C,
            }
        ],
    )


def test_two_inertia_forced_response_matches_the_closed_form():
    speeds = np.linspace(50, 800, 301)  # order 1.5: ω = 75 .. 1200 rad/s, resonance at 458
    res = torsional_response(
        _pair(),
        excitations=[{"shaft": "a", "node": 1, "amplitude": "100 N*m", "order": 1.5}],
        speeds=speeds,
    )
    w = 1.5 * speeds
    z = K + 1j * w * C
    ref = np.abs(z * 100 * J2 / (z * (J1 + J2) - w**2 * J1 * J2))
    # lumped closed form vs the model with its 1e-9 rod inertia: 1e-6
    np.testing.assert_allclose(res.coupling_torque[:, 0], ref, rtol=1e-6)
    k = np.argmax(ref)
    assert ref[k] > 4 * 100 * J2 / (J1 + J2)  # crosses the resonance (ζ 0.09: AF ~5.5)


def test_fixed_frequency_and_phase_sum():
    """Two torques at the same fixed frequency add with their phases: in anti-phase on the two
    ends of the same node they cancel; different frequencies add amplitudes."""
    speeds = np.array([100.0, 200.0])
    exc = [
        {"shaft": "a", "node": 1, "amplitude": 50.0, "frequency": "30 Hz"},
        {"shaft": "a", "node": 1, "amplitude": 50.0, "frequency": "30 Hz", "phase": "180 deg"},
    ]
    res = torsional_response(_pair(), excitations=exc, speeds=speeds)
    assert np.all(res.coupling_torque < 1e-9)
    exc2 = [
        {"shaft": "a", "node": 1, "amplitude": 50.0, "frequency": "30 Hz"},
        {"shaft": "a", "node": 1, "amplitude": 50.0, "frequency": "31 Hz"},
    ]
    both = torsional_response(_pair(), excitations=exc2, speeds=speeds).coupling_torque
    one = [
        torsional_response(_pair(), excitations=[e], speeds=speeds).coupling_torque for e in exc2
    ]
    np.testing.assert_allclose(both, one[0] + one[1], rtol=1e-12)


def _geared(mesh_k):
    return geared_train(
        [
            shaft("g", 2e5, [disk(0, 3.0), disk(1, 0.6)]),
            shaft("p", None, [disk(0, 0.4)], start=0.5),
        ],
        [{"gear": ("g", 1, 50, 0.25), "mate": ("p", 0, 20, 0.1), "k": mesh_k, "driver": "gear"}],
        speed="1500 rpm",
    )


def test_rigid_mesh_force_is_the_constraint_reaction():
    speeds = np.linspace(100, 400, 61)
    exc = [{"shaft": "g", "node": 0, "amplitude": 200.0, "order": 2.0}]
    rigid = torsional_response(_geared(1e9), excitations=exc, speeds=speeds, mesh="rigid")
    flex = torsional_response(_geared(1e13), excitations=exc, speeds=speeds, mesh="flexible")
    # a 1e13 N/m mesh is rigid to ~1e-6 of this train's stiffness; the undamped resonance in
    # the sweep amplifies that frequency shift to ~2e-5 next to it
    np.testing.assert_allclose(rigid.mesh_force[:, 0], flex.mesh_force[:, 0], rtol=1e-4)
    # the pinion's inertia is accelerated by the mesh alone: F · r_b = J_b ω² |Θ_b|
    tm = rigid.model
    w = 2.0 * speeds
    arm_p = tm.torque_arm[0, 1]
    theta_p = rigid.mesh_force[:, 0] * arm_p / (0.4 * w**2)
    pinion_torque = rigid.mesh_torque[:, 0, 1]
    np.testing.assert_allclose(pinion_torque, 0.4 * w**2 * theta_p, rtol=1e-12)
    assert arm_p == pytest.approx(0.1 * np.cos(np.deg2rad(20)), rel=1e-12)


def test_contact_loss_where_the_dynamic_load_exceeds_the_mean():
    """Rated 300 N·m through the gear: mean normal force 300 / (r_g cos αn). Near the
    resonance the dynamic force exceeds it (tooth separation); far from it, not."""
    speeds = np.linspace(100, 600, 201)
    exc = [{"shaft": "g", "node": 0, "amplitude": 40.0, "order": 1.0}]
    rated = [
        {"shaft": "g", "node": 0, "value": 300.0},
        {"shaft": "p", "node": 0, "value": 300.0 * 20 / 50},
    ]  # both ends turn the same way
    res = torsional_response(_geared(1e9), excitations=exc, speeds=speeds, rated_load=rated)
    assert abs(res.mean_mesh_force[0]) == pytest.approx(
        300 / (0.25 * np.cos(np.deg2rad(20))), rel=1e-6
    )
    lost = res.contact_loss[:, 0]
    assert lost.any() and not lost.all()
    np.testing.assert_array_equal(lost, res.mesh_force[:, 0] > abs(res.mean_mesh_force[0]))
    peak = np.argmax(res.mesh_force[:, 0])
    assert lost[peak]
    d = res.to_dict()
    assert d["meshes"][0]["contact_loss_speeds_rpm"]
    assert "CONTACT LOSS" in res.table()


def test_unbalanced_rated_load_is_an_error():
    with pytest.raises(ModelError, match="do not balance"):
        torsional_response(
            _geared(1e9),
            excitations=[{"shaft": "g", "node": 0, "amplitude": 40.0, "order": 1.0}],
            speeds=[100.0],
            rated_load=[{"shaft": "g", "node": 0, "value": 300.0}],
        )


def test_excitation_needs_order_or_frequency():
    with pytest.raises(ValueError, match="exactly one of 'order' or 'frequency'"):
        torsional_response(
            _pair(), excitations=[{"shaft": "a", "node": 1, "amplitude": 1.0}], speeds=[100.0]
        )
