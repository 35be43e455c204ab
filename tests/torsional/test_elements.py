"""Torsional springs and dampers to ground, and shaft sections whose torsional rod is given by
its stiffness, inertia and damping directly (issue 22), against closed forms.

Closed forms (lumped torsional systems; Thomson & Dahleh, *Theory of Vibration with
Applications*, 5th ed. 1998, §2.6 and §5.3):

* one inertia J on a spring k0 and a damper c0 to ground: ω_n² = k0 / J,
  ζ = c0 / (2 √(k0 J)), ω_d = ω_n √(1 − ζ²); forced by T cos ωt: |θ| = T / |k0 − ω² J + iωc0|;
* two inertias J1 -k- J2 with J1 on a spring k0 to ground:
  J1 J2 ω⁴ − [J2 (k0 + k) + J1 k] ω² + k0 k = 0;
* a section of n elements of stiffness k each in series: the section's stiffness k / n, so a
  section given as ``torsional_stiffness = K`` over any number of elements is K;
  its polar inertia J_s as consistent rod mass, 2 nodes: M = J_s/6 [[2, 1], [1, 2]].

The "massless" helper material (tests/torsional_helpers.py: rod inertia ~1e-9 of the disks) lets
the lumped forms hold to ~1e-9; tolerances of 1e-7 leave room for that and the eigensolver.
"""

from __future__ import annotations

import numpy as np
import pytest

from gearrotor.analyses import modal
from gearrotor.analyses.torsional import (
    HarmonicTorque,
    torsional_model,
    torsional_modes,
    torsional_response,
    torsional_transient,
)
from gearrotor.assembly import assemble
from gearrotor.errors import ModelError
from torsional_helpers import disk, geared_train, shaft

J, J1, J2 = 2.0, 3.0, 0.8
K0, K = 4.0e5, 1.5e5


def _lumped(k_section: float, supports, *, elements: int = 1, polar=None, damping=None):
    """One shaft of one section whose torsional rod is given directly (stiffness
    ``k_section``), J1 at node 0 and J2 at the last node, ``supports`` at nodes."""
    sh = shaft("s", None, [disk(0, J1), disk(elements, J2)], elements=elements)
    sec = sh["sections"][0]
    sec["torsional_stiffness"] = k_section
    if polar is not None:
        sec["polar_inertia"] = polar
    if damping is not None:
        sec["torsional_damping"] = damping
    return geared_train([sh], torsional_supports=supports)


def test_two_inertias_with_a_grounded_spring_closed_form():
    """J1 on k0 to ground, J1 -k- J2: the quartic's two roots; no rigid-body mode (the spring
    holds the train)."""
    tr = _lumped(K, [{"shaft": "s", "node": 0, "k": K0}])
    res = torsional_modes(tr)
    a, b, c = J1 * J2, -(J2 * (K0 + K) + J1 * K), K0 * K
    w2 = np.sort(np.roots([a, b, c]).real)
    assert not res.rigid_body.any()
    assert res.natural_frequency[:2] == pytest.approx(np.sqrt(w2), rel=1e-7)


@pytest.mark.parametrize("elements", [1, 3, 7])
def test_section_stiffness_is_the_whole_section_whatever_the_elements(elements):
    """Held at node 0, a torque T at the far end twists a section given as K by T / K over 1,
    3 or 7 elements (springs in series of n K each; a linear solve, exact to round-off); free,
    J1 -K- J2 has ω² = K (J1 + J2) / (J1 J2) (one element: the eigensolver's round-off on the
    massless inner nodes of more elements would show at ~1e-6)."""
    tr = _lumped(K, [], elements=elements)
    tm = torsional_model(tr, fixed=[{"shaft": "s", "node": 0}])
    f = np.zeros(tm.n_full)
    f[tm.dof(0, elements)] = 1234.0
    theta, _ = tm.static_twist(f)
    assert theta[tm.dof(0, elements)] == pytest.approx(1234.0 / K, rel=1e-12)
    assert tm.element_torque(theta) == pytest.approx(np.full(elements, 1234.0), rel=1e-12)
    assert tm.el_stiffness == pytest.approx(np.full(elements, K * elements))
    if elements == 1:
        res = torsional_modes(tr)
        assert res.rigid_body[0]
        w = np.sqrt(K * (J1 + J2) / (J1 * J2))
        assert res.natural_frequency[~res.rigid_body][0] == pytest.approx(w, rel=1e-7)


def test_section_polar_inertia_is_consistent_rod_mass():
    """A section with J_s and no disks: M = J_s/6 [[2, 1], [1, 2]] plus the disks' inertias;
    free-free: ω² = K (m11 + m22 + 2 m12) / det M, from det(K − ω² M) = 0 with K = k[[1, −1],
    [−1, 1]]."""
    js = 0.9
    tm = torsional_model(_lumped(K, [], polar=js))
    m = np.array([[J1 + js / 3, js / 6], [js / 6, J2 + js / 3]])
    assert tm.M == pytest.approx(m, rel=1e-9, abs=1e-6)  # the helper material adds ~1e-9
    w2 = K * (m[0, 0] + m[1, 1] + 2 * m[0, 1]) / np.linalg.det(m)
    res = torsional_modes(tm)
    assert res.natural_frequency[1] == pytest.approx(np.sqrt(w2), rel=1e-7)


def test_grounded_spring_and_damper_single_inertia_damped_closed_form():
    """J (both disks on one node: J1 + J2 on a 1-node-free shaft held rigidly between them by a
    very stiff section) on k0, c0 to ground: ω_d and ζ of the complex eigenvalue."""
    c0 = 600.0
    tr = _lumped(1e12, [{"shaft": "s", "node": 0, "k": K0, "c": c0}])
    res = torsional_modes(tr, n_modes=1)
    jt = J1 + J2
    wn = np.sqrt(K0 / jt)
    zeta = c0 / (2 * np.sqrt(K0 * jt))
    # the 1e12 N·m/rad section shifts ω_n by ~K0 / 1e12 relative
    assert res.natural_frequency[0] == pytest.approx(wn, rel=1e-6)
    assert res.damping_ratio[0] == pytest.approx(zeta, rel=1e-6)
    assert res.damped_frequency[0] == pytest.approx(wn * np.sqrt(1 - zeta**2), rel=1e-6)
    src = res.to_dict()["modes"][0]["damping_sources"]
    assert list(src) == ["support torsional_supports[0]"]
    assert src["support torsional_supports[0]"] == pytest.approx(zeta, rel=1e-6)


def test_propeller_damping_forced_response_closed_form():
    """Free train J1 -K- J2 with a damper c to ground at J2 (propeller damping) forced at J1
    by T cos ωt: the complex 2-DOF solution, and the undamped rigid rotation stays a
    rigid-body mode (a damper does not hold the train)."""
    c = 250.0
    tr = _lumped(K, [{"shaft": "s", "node": 1, "c": c, "name": "propeller"}])
    modes = torsional_modes(tr)
    assert modes.rigid_body[0] and modes.rigid_body.sum() == 1
    w = 2 * np.pi * np.array([5.0, 20.0, 60.0])
    amp = 1000.0
    res = torsional_response(
        tr,
        excitations=[HarmonicTorque(shaft="s", node=0, amplitude=amp, frequency=w[0])],
        speeds=np.array([100.0]),
    )
    for wk in w:
        res = torsional_response(
            tr,
            excitations=[HarmonicTorque(shaft="s", node=0, amplitude=amp, frequency=wk)],
            speeds=np.array([100.0]),
        )
        Z = np.array([[K - wk**2 * J1, -K], [-K, K - wk**2 * J2 + 1j * wk * c]])
        th = np.linalg.solve(Z, [amp, 0.0])
        assert res.element_torque[0, 0] == pytest.approx(K * abs(th[1] - th[0]), rel=1e-7)


def test_grounded_spring_is_in_every_analysis():
    """The assembly puts k0 and c0 on the node's θz (so the 6-DOF modal sees it): the 6-DOF
    model's lowest torsional mode with stiff bearings is the lumped one."""
    tr = _lumped(1e12, [{"shaft": "s", "node": 0, "k": K0, "c": 0.0 + 1.0}])
    asm = assemble(tr)
    d = asm.dof(0, 0, 5)
    base = assemble(_lumped(1e12, []))
    assert asm.K0[d, d] - base.K0[d, d] == pytest.approx(K0)
    assert asm.C0[d, d] - base.C0[d, d] == pytest.approx(1.0)
    res = modal(tr, speed=0.0, n_modes=12)
    wn = np.sqrt(K0 / (J1 + J2))
    assert np.min(np.abs(res.natural_frequency - wn)) / wn < 1e-5


def test_transient_refuses_a_spring_to_ground():
    tr = _lumped(
        K,
        [{"shaft": "s", "node": 0, "k": K0}],
    )
    with pytest.raises(ModelError, match=r"torsional_supports\[0\]\.k"):
        torsional_transient(tr, t_end=0.1)


def test_support_needs_k_or_c():
    with pytest.raises(ValueError, match="k > 0 or c > 0"):
        _lumped(K, [{"shaft": "s", "node": 0}])


def test_section_fields_absent_keep_the_model_json():
    """A model without the new fields serialises as before (study keys, fingerprints)."""
    tr = _lumped(K, [])
    text = geared_train([shaft("s", K, [disk(0, J1)])]).model_dump_json()
    assert "torsional_stiffness" not in text and "torsional_supports" not in text
    assert "torsional_stiffness" in tr.model_dump_json()


def _history_train(load_history=None):
    """J1 -K- J2 free, a torque drive with a history (a ramp T = a t) at J1 and a load with a
    history at J2."""
    tr = _lumped(K, [])
    data = tr.model_dump()
    data["torsional"] = {
        "drives": [
            {
                "type": "torque",
                "name": "ramp",
                "shaft": "s",
                "node": 0,
                "rated_power": "10 kW",
                "rated_speed": "1000 rpm",
                "history": {"time": [0.0, 1.0], "torque": [0.0, RAMP]},
            }
        ],
        "loads": [
            {
                "type": "history",
                "name": "record",
                "shaft": "s",
                "node": 1,
                "history": load_history or {"time": [0.0, 1.0], "torque": [0.0, 0.0]},
            }
        ],
    }
    return type(tr).model_validate(data)


RAMP = 60.0  # N·m at 1 s


def test_torque_history_drive_ramp_closed_form():
    """A ramp T = a t on the free train from rest: the inertia-weighted speed is
    a t² / (2 (J1 + J2)) exactly (the trapezoidal rule integrates a linear force exactly; the
    shaft's own rod inertia, ~1e-9 of the disks, is in the sum); the drive's work is the
    kinetic plus strain energy (the energy balance)."""
    tr = _history_train()
    res = torsional_transient(tr, t_end=1.0, dt=1e-3)
    jt = torsional_model(tr).M.sum()
    assert res.speed[-1, 0] == pytest.approx(RAMP / 2 / jt, rel=1e-9)
    assert res.law_torque[-1, 0] == pytest.approx(RAMP, rel=1e-12)
    assert res.energy_error < 1e-9


def test_torque_history_load_against_the_rotation():
    """A load history braking the ramp: T_load = b t, net a − b: speed (a − b) t² / (2 J)."""
    b = 20.0
    tr = _history_train({"time": [0.0, 1.0], "torque": [0.0, b]})
    res = torsional_transient(tr, t_end=1.0, dt=1e-3)
    jt = torsional_model(tr).M.sum()
    assert res.speed[-1, 0] == pytest.approx((RAMP - b) / 2 / jt, rel=1e-9)
    # the linear analyses take a history's last value (held beyond its end)
    assert tr.torsional.loads[0].torque_at(10.0) == b


def test_history_needs_its_table():
    with pytest.raises(ValueError, match="'history' load needs 'history'"):
        _history_train().torsional.loads[0].model_validate(
            {"type": "history", "shaft": "s", "node": 1, "torque": 3.0}
        )
