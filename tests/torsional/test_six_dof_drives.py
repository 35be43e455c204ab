"""The ``[torsional]`` drives and loads in the coupled 6-DOF transient (issue 12 item 4).

Both transients evaluate the same compiled laws (:mod:`gearrotor.analyses.torsional.drive_laws`),
so they must agree:

* on a single shaft (no mesh, no gyroscopic or unbalance term reaching θz) the 6-DOF model's θz
  equations *are* the torsional model's: a synchronous-motor start-up (pulsating torque at
  2 s f_line sweeping through the shaft mode, pull-in) agrees to the integrators' error (the
  modal RK4 against the trapezoidal rule; both converge, the torsional step here is 20 per period
  of the 52 Hz mode, so ~0.3 % phase error accumulates over 20 cycles);
* on the example train the 6-DOF model adds the lateral flexibility of the shafts, bearings and
  mesh, which the torsional model leaves out: the peak torque of the most loaded section (the
  LS coupling) and the speeds still agree (1 % and 5e-4 of the nominal speed; the coupled modes
  shift by a few per cent, so histories drift in phase while peaks and speeds stay close;
  measured: 0.8 % and 1.1e-4).
"""

from __future__ import annotations

import json

import numpy as np
import pytest

from gearrotor.analyses.torsional import torsional_model, torsional_transient
from gearrotor.analyses.transient import ModalRK4, Save, transient
from gearrotor.io import load_model
from gearrotor.io.model_file import model_from_dict
from torsional_helpers import disk, geared_train, shaft

RPM = np.pi / 30


def _single_shaft():
    """Motor disk 0.05 kg·m², load disk 0.03 kg·m² on 2 kN·m/rad (mode at 52 Hz); a 10 kW,
    4-pole, 60 Hz synchronous motor; a quadratic load of 30 N·m at 1800 rpm."""
    return geared_train(
        [shaft("a", 2000.0, [disk(0, 0.05), disk(1, 0.03)])],
        speed="1800 rpm",
        torsional={
            "drives": [
                {
                    "type": "synchronous_motor",
                    "shaft": "a",
                    "node": 0,
                    "rated_power": "10 kW",
                    "poles": 4,
                    "line_frequency": "60 Hz",
                    "pull_in_slip": 0.05,
                    "pull_out_torque": 1.8,
                    "start": {
                        "slip": [1.0, 0.5, 0.05, 0.0],
                        "average": [1.0, 0.8, 1.5, 0.0],
                        "pulsating": [0.6, 0.4, 0.2, 0.1],
                    },
                }
            ],
            "loads": [
                {"type": "quadratic", "shaft": "a", "node": 1, "torque": 30.0, "speed": "1800 rpm"}
            ],
        },
    )


def _twist(res, train, a, b):
    """θz(b) − θz(a) and its rate from a 6-DOF result (node refs (shaft, node))."""
    from gearrotor.assembly import assemble

    asm = assemble(train)

    def col(ref):
        g = asm.node_offset[ref[0]][ref[1]] + 5
        return int(np.flatnonzero(res.recorded_dofs == g)[0])

    i, j = col(a), col(b)
    return res.q[:, j] - res.q[:, i], res.qdot[:, j] - res.qdot[:, i]


def test_single_shaft_synchronous_start_up_matches_the_torsional_transient():
    train = _single_shaft()
    t_end = 0.6
    tors = torsional_transient(train, t_end=t_end, dt=2e-5, save_dt=1e-3)
    six = transient(train, t_end=t_end, initial="rest", save=Save(dt=1e-3))
    assert 0.2 < tors.pull_in_time[0] < 0.5  # the run covers the sweep and the pull-in
    t = six.time
    speed_t = np.interp(t, tors.time, tors.speed[:, 0])
    sync = 1800 * RPM
    np.testing.assert_allclose(six.shaft_speed[:, 0], speed_t, atol=5e-4 * sync)
    # the motor pulled in: the 6-DOF run ends at synchronous speed too
    assert six.shaft_speed[-1, 0] == pytest.approx(sync, rel=2e-3)
    tm = torsional_model(train)
    twist, _ = _twist(six, train, (0, 0), (0, 1))
    torque6 = tm.el_stiffness[0] * twist  # GJ/L (θ1 − θ0), the torsional model's sign
    torque_t = np.interp(t, tors.time, tors.element_torque[:, 0])
    peak = np.abs(torque_t).max()
    assert np.abs(torque6).max() == pytest.approx(peak, rel=0.01)
    assert np.abs(torque6 - torque_t).max() < 0.03 * peak


def test_without_drives_the_six_dof_transient_is_unchanged(examples):
    """A model without [torsional] packs an empty law set: same result as before the drives
    existed (the unity gearbox at constant speed settles to its static mesh load)."""
    train = load_model(examples / "unity_gearbox.toml")
    assert train.torsional is None
    res = transient(train, t_end=0.01, integrator=ModalRK4())
    assert np.all(np.isfinite(res.mesh_force))


@pytest.mark.slow
def test_example_start_up_six_dof_agrees_with_the_torsional_model(examples):
    train = load_model(examples / "motor_gearbox_compressor.toml")
    data = json.loads(train.model_dump_json())
    data["unbalances"] = []
    # no backlash: tooth rattle at the first impacts is sensitive to the mesh's lateral
    # compliance, which only the 6-DOF model has (its speeds differ by ~2e-3 there)
    data["meshes"][0]["backlash"]["value"] = 0.0
    train = model_from_dict(data)
    t_end = 0.1  # the first impacts, the 120 Hz pulsation through the 26 and 72 Hz modes
    tors = torsional_transient(train, t_end=t_end, save_dt=1e-4)
    six = transient(train, t_end=t_end, initial="rest", save=Save(dt=2e-4))
    nominal = np.abs(train.shaft_speeds())
    speed_t = np.array([np.interp(six.time, tors.time, tors.speed[:, s]) for s in range(4)]).T
    dev = np.abs(np.abs(six.shaft_speed) - speed_t).max(axis=0)
    np.testing.assert_array_less(dev, 5e-4 * nominal)
    tm = tors.model
    cp = train.couplings[0]  # LS coupling: the most loaded section
    twist, rate = _twist(
        six, train, train.node_index(cp.node_i, ""), train.node_index(cp.node_j, "")
    )
    ls6 = tm.cp_stiffness[0] * twist + tm.cp_damping[0] * rate
    peak_t = max(abs(tors.coupling_torque_max[0]), abs(tors.coupling_torque_min[0]))
    assert np.abs(ls6).max() == pytest.approx(peak_t, rel=0.01)


def test_checkpoint_resumed_after_pull_in_keeps_the_motor_in_step(tmp_path, monkeypatch):
    """A start-up stopped after the pull-in (0.33 s) resumes from its last checkpoint with the
    motor still in step at its captured load angle: bit-identical to a run that was not
    stopped (the state is part of the checkpoint; re-synchronising at the resumed angle would
    change the torque from there on)."""
    from gearrotor.analyses.transient import Checkpoint, driver

    train = _single_shaft()
    kw = dict(t_end=0.6, initial="rest", save=Save(dt=1e-3))
    reference = transient(train, checkpoint=Checkpoint(tmp_path / "ref.npz"), **kw)
    real = driver.kn.rk4_modal

    def dies_at_70_percent(t0, dt, nst, *args):
        if t0 + nst * dt > 0.42:
            raise KeyboardInterrupt
        return real(t0, dt, nst, *args)

    ck = Checkpoint(tmp_path / "run.npz", every=1e9)
    monkeypatch.setattr(driver.kn, "rk4_modal", dies_at_70_percent)
    with pytest.raises(KeyboardInterrupt):
        transient(_single_shaft(), checkpoint=ck, **kw)
    monkeypatch.setattr(driver.kn, "rk4_modal", real)
    saved = np.load(ck.path)
    assert saved["drive_state"][0, 0] == 1.0  # stopped after the pull-in
    res = transient(_single_shaft(), checkpoint=ck, **kw)
    assert res.stats.steps > res.stats.rhs_evaluations // 4  # it did resume
    np.testing.assert_array_equal(res.shaft_speed, reference.shaft_speed)
    np.testing.assert_array_equal(res.final_q, reference.final_q)


def test_torque_histories_act_in_the_six_dof_transient():
    """A torque history drive (a ramp, 0 → 6 N·m over 0.2 s, then held) against a braking
    load history on the single shaft: the 6-DOF run's speed is the torsional run's (one
    compiled law for both; the inertia-weighted speed is ∫T dt / J exactly in both, the
    shaft's twist oscillation differs by the integrators' error)."""
    data = json.loads(_single_shaft().model_dump_json())
    data["torsional"] = {
        "drives": [
            {
                "type": "torque",
                "name": "ramp",
                "shaft": "a",
                "node": 0,
                "rated_power": "1 kW",
                "rated_speed": "1800 rpm",
                "history": {"time": [0.0, 0.2], "torque": [0.0, 6.0]},
            }
        ],
        "loads": [
            {
                "type": "history",
                "name": "brake",
                "shaft": "a",
                "node": 1,
                "history": {"time": [0.0, 0.3], "torque": [1.0, 1.0]},
            }
        ],
    }
    train = model_from_dict(data)
    t_end = 0.3
    tors = torsional_transient(train, t_end=t_end, dt=1e-4, save_dt=1e-3)
    six = transient(train, t_end=t_end, initial="rest", save=Save(dt=1e-3))
    tm = torsional_model(train)
    jt = tm.M.sum()
    # ∫(T_drive − T_load) dt = 6·0.2/2 + 6·0.1 − 1·0.3 = 0.9 N·m·s
    assert tors.speed[-1, 0] == pytest.approx(0.9 / jt, rel=1e-6)
    # the 6-DOF run's inertia-weighted speed of the two nodes (its shaft_speed is a node's,
    # which carries the 52 Hz twist oscillation the load step excites, ~1 %)
    from gearrotor.assembly import assemble

    asm = assemble(train)
    cols = [int(np.flatnonzero(six.recorded_dofs == asm.node_offset[0][n] + 5)[0]) for n in (0, 1)]
    w = tm.M.sum(axis=1)
    speed6 = six.qdot[-1, cols] @ w / w.sum()
    t = six.time[-1]  # the record's last sample (≤ t_end: its steps need not end on it)
    assert 0.2 < t <= t_end
    impulse = 6.0 * 0.2 / 2 + 6.0 * (t - 0.2) - 1.0 * t
    # RK4 integrates the piecewise-linear torque exactly but for the kinks inside a step (at
    # 0.2 s): measured 5e-6
    assert speed6 == pytest.approx(impulse / jt, rel=2e-5)
