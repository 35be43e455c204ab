"""The torsional transient: exact rigid acceleration, an independent ODE reference, the energy
balance, convergence under step halving, synchronous pull-in, backlash contact states.

Energy: the trapezoidal rule satisfies the discrete identity
ΔKE + ΔPE + Σ (h/4)(v_n + v_n+1)ᵀ C (v_n + v_n+1) = Σ ½ (f_n + f_n+1)·Δθ for the linear part
(substitute θ_n+1 − θ_n = h/2 (v_n + v_n+1) and M(v_n+1 − v_n) = h/2 (M a_n + M a_n+1)); the
drive work summed that way then balances kinetic energy + strain energy + dissipation to
round-off and the drive-torque iteration tolerance, whatever the step. A backlash contact change
inside a step breaks it by ~½ k (δ_n − b)² per impact (the contact force is applied over the
whole step): small when the step resolves the contact mode, as the default step does.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from gearrotor.analyses.torsional import pack_laws, torsional_model, torsional_transient
from gearrotor.analyses.torsional.drive_laws import evaluate
from gearrotor.errors import ModelError
from gearrotor.io.model_file import model_from_dict
from torsional_helpers import disk, geared_train, shaft

START = {
    "slip": [1.0, 0.6, 0.3, 0.1, 0.05, 0.0],
    "average": [1.0, 0.9, 1.0, 1.3, 1.2, 0.0],
    "pulsating": [0.5, 0.45, 0.4, 0.3, 0.25, 0.2],
}


def _geared(backlash_mm=0.0, load_factor=0.5, damping_ratio=0.03, **drive):
    """Motor (J 20) -shaft- hub | coupling (with damping) | hub -shaft- bull gear | mesh |
    pinion (3x) -shaft- load inertia (J 0.8); modes at ~27, ~90 Hz with a few % damping."""
    motor = {
        "type": "synchronous_motor",
        "name": "motor",
        "shaft": "m",
        "node": 0,
        "rated_power": "200 kW",
        "poles": 4,
        "line_frequency": "60 Hz",
        "start": START,
        "pull_out_torque": 2.0,
        **drive,
    }
    return geared_train(
        [
            shaft("m", 4e5, [disk(0, 20.0), disk(1, 0.5)]),
            shaft("g", 1e6, [disk(0, 0.5), disk(1, 1.5)], start=0.6),
            shaft("p", 6e4, [disk(0, 0.1), disk(1, 0.8)], start=1.1),
        ],
        [
            {
                "gear": ("g", 1, 60, 0.3),
                "mate": ("p", 0, 20, 0.1),
                "k": 1e9,
                "damping_ratio": damping_ratio,
                "driver": "gear",
                "backlash": {"value": f"{backlash_mm} mm", "convention": "total"},
            }
        ],
        couplings=[
            {
                "node_i": {"shaft": "m", "node": 1},
                "node_j": {"shaft": "g", "node": 0},
                "ktz": 8e5,
                "ctz": 2000.0,
                "kx": 1e8,
                "ky": 1e8,
            }
        ],
        speed="1800 rpm",
        torsional={
            "drives": [motor],
            "loads": [
                {
                    "type": "quadratic",
                    "name": "load",
                    "shaft": "p",
                    "node": 1,
                    "torque": f"{300 * load_factor} N*m",
                    "speed": "5400 rpm",
                }
            ],
        },
    )


def test_rigid_acceleration_is_exact():
    """One stiff shaft, constant drive T and load T_L: Ω(t) = (T − T_L) t / J_total (the
    trapezoidal rule integrates a constant acceleration exactly)."""
    t = geared_train(
        [shaft("a", 1e6, [disk(0, 3.0), disk(1, 1.0)])],
        torsional={
            "drives": [
                {
                    "type": "torque",
                    "shaft": "a",
                    "node": 0,
                    "value": 120.0,
                    "rated_power": "20 kW",
                    "rated_speed": "1000 rpm",
                }
            ],
            "loads": [{"type": "constant", "shaft": "a", "node": 1, "torque": 40.0}],
        },
    )
    res = torsional_transient(t, t_end=0.5, dt=1e-3, static_initial=True)
    jt = np.sum(torsional_model(t).M)
    np.testing.assert_allclose(res.speed[:, 0], 80.0 / jt * res.time, rtol=1e-9, atol=1e-12)
    # the static initial twist carries the d'Alembert load: 120 − J_0 α through the shaft
    assert res.element_torque[-1, 0] == pytest.approx(-(120.0 - 3.0 * 80.0 / jt), rel=1e-6)


def test_short_circuit_against_an_independent_ode_solution():
    """Two inertias on a shaft, an induction motor at speed hit by a two-phase short circuit:
    the run (dt 2e-5) against scipy's DOP853 (rtol 1e-10) on the same equations (the same
    compiled drive law, its own integrator); the trapezoidal rule's phase error at this step is
    (ωh)²/12 ~ 1e-6 for the 60/120 Hz content and the 52 Hz mode: 1e-3 of the peak torque."""
    k, j1, j2, ctz = 5e4, 1.0, 0.6, 2.0
    circuit = {"r1": 0.641, "x1": 1.106, "r2": 0.332, "x2": 0.464, "xm": 26.3, "voltage": "460 V"}
    sc = {
        "type": "two_phase",
        "time": "0.02 s",
        "clear_time": "0.15 s",
        "a0": 0.3,
        "tau0": "0.05 s",
        "a1": 5.0,
        "tau1": "0.1 s",
        "a2": 2.0,
        "tau2": "0.06 s",
    }
    t = geared_train(
        [shaft("a", None, [disk(1, j1)]), shaft("b", None, [disk(0, j2)], start=0.6)],
        couplings=[
            {
                "node_i": {"shaft": "a", "node": 1},
                "node_j": {"shaft": "b", "node": 0},
                "ktz": k,
                "ctz": ctz,
            }
        ],
        speed="1750 rpm",
        torsional={
            "drives": [
                {
                    "type": "induction_motor",
                    "shaft": "a",
                    "node": 1,
                    "rated_power": "18.65 kW",
                    "poles": 4,
                    "line_frequency": "60 Hz",
                    "circuit": circuit,
                    "short_circuit": sc,
                }
            ],
            "loads": [
                {
                    "type": "quadratic",
                    "shaft": "b",
                    "node": 0,
                    "torque": "60 N*m",
                    "speed": "1750 rpm",
                }
            ],
        },
    )
    w0 = 1750 * np.pi / 30
    res = torsional_transient(
        t, t_end=0.25, dt=2e-5, save_dt=2e-5, initial_speed=w0, static_initial=False
    )
    laws = pack_laws(t)

    def rhs(time, y):
        th1, th2, v1, v2 = y
        td = evaluate(laws, 0, time, th1, v1)[()]
        tl = evaluate(laws, 1, time, th2, v2)[()]
        tc = k * (th2 - th1) + ctz * (v2 - v1)
        return [v1, v2, (td + tc) / j1, (-tl - tc) / j2]

    ref = solve_ivp(
        rhs,
        (0, 0.25),
        [0, 0, w0, w0],
        method="DOP853",
        rtol=1e-10,
        atol=1e-12,
        t_eval=res.time,
        max_step=1e-4,
    )
    coupling = k * (ref.y[1] - ref.y[0]) + ctz * (ref.y[3] - ref.y[2])
    got = res.coupling_torque[:, 0]
    assert np.max(np.abs(got - coupling)) < 1e-3 * np.max(np.abs(coupling))
    # speeds drift by the rule's accumulated phase error, (ωh)²/12 per cycle: 5e-5 over 0.25 s
    np.testing.assert_allclose(res.speed[:, 1], ref.y[3], rtol=5e-5)
    assert np.max(np.abs(coupling)) > 5 * 60  # the fault dominates: a real test of the law


def test_energy_balance_of_a_synchronous_start_up():
    res = torsional_transient(_geared(), t_end=6.0)
    assert res.pull_in_time[0] < 6.0
    ke = res.kinetic[1] - res.kinetic[0]
    assert ke > 0.5 * 0.5 * 22.5 * (1800 * np.pi / 30) ** 2  # near full speed
    assert abs(res.energy_residual) < 1e-8 * res.law_work[0]
    # and in terms of the parts: drive work = KE + PE + dissipation + load work
    parts = ke + (res.potential[1] - res.potential[0]) + res.dissipated - res.law_work[1]
    assert res.law_work[0] == pytest.approx(parts, rel=1e-8)


def test_energy_balance_with_backlash_impacts():
    """Backlash opens at the start (the teeth start inside the clearance) and on the torque
    reversals of the resonance: with the contact mode resolved (default step) the impacts cost
    the identity ~3e-9 of the work here (1e-7 at 4x the step); bound 1e-6."""
    res = torsional_transient(_geared(backlash_mm=0.3, load_factor=0.05), t_end=3.0)
    assert (res.mesh_state == 0).any() and (res.mesh_state == 1).any()
    assert res.mesh_state[0, 0] == 0  # starts separated
    sep = res.mesh_state[:, 0] == 0
    assert np.all(res.mesh_force[sep, 0] == 0.0)
    assert res.energy_error < 1e-6


def test_peak_shaft_torque_converges_under_step_halving():
    """A start-up through the first torsional resonance (the pulsating torque at 2 s f_line
    crosses the 25.6 Hz mode at ~5 s, before pull-in at 5.9 s), no backlash: the peak shaft
    torque of the motor shaft (≈ 4x rated) changes by less than 1e-3 from dt/2 to dt/4, and its
    changes fall at the rule's second order (ratio ~4; measured 3.5)."""
    train = _geared()
    tm = torsional_model(train)
    peaks = []
    for dt in (4e-4, 2e-4, 1e-4):
        res = torsional_transient(tm, t_end=5.5, dt=dt)
        peaks.append(res.peak_element_torque[0])
    d1, d2 = abs(peaks[0] - peaks[1]), abs(peaks[1] - peaks[2])
    assert d2 < 1e-3 * peaks[2]
    assert d1 / d2 > 2.5
    assert peaks[2] > 3 * abs(res.rated_element_torque[0])  # a real resonance peak


def test_synchronous_motor_pulls_into_step():
    """Pull-in when the slip first reaches 5 %; then the speed locks to synchronous speed (the
    hunting oscillation decays) and the motor carries the load: 150 N·m × 3 at the motor."""
    res = torsional_transient(_geared(), t_end=12.0)
    ws = 1800 * np.pi / 30
    first = res.time[np.argmax(res.speed[:, 0] >= 0.95 * ws)]
    assert res.pull_in_time[0] == pytest.approx(first, abs=2 * res.dt + 1e-3)
    late = res.time > 10.0
    assert np.mean(res.speed[late, 0]) == pytest.approx(ws, rel=2e-4)
    assert np.max(np.abs(res.speed[late, 0] - ws)) < 2e-3 * ws
    assert np.mean(res.law_torque[late, 0]) == pytest.approx(450.0, rel=1e-2)


def test_rigid_and_flexible_meshes_give_the_same_start():
    """A stiff mesh (mesh mode ~1.8 kHz) against the rigid constraint: the same speeds, and
    the rigid constraint force equals the flexible mesh force at its largest."""
    train = _geared()
    a = torsional_transient(train, t_end=2.0, mesh="flexible", dt=1e-4)
    b = torsional_transient(train, t_end=2.0, mesh="rigid", dt=1e-4)
    np.testing.assert_allclose(a.speed[-1], b.speed[-1], rtol=1e-3)
    k = np.argmax(np.abs(a.mesh_force[:, 0]))
    assert b.mesh_force[k, 0] == pytest.approx(a.mesh_force[k, 0], rel=1e-2)


def test_transient_input_errors():
    with pytest.raises(ModelError, match="rigid meshes have no backlash"):
        torsional_transient(_geared(backlash_mm=0.2), t_end=0.1, mesh="rigid")
    tm = torsional_model(_geared(), fixed=[{"shaft": "m", "node": 0}])
    with pytest.raises(ModelError, match="fixed nodes are not allowed"):
        torsional_transient(tm, t_end=0.1)
    data = _geared().model_dump()
    data["meshes"][0]["mate"]["radius"] = 0.1005
    with pytest.raises(ModelError, match=r"meshes\[0\].*exactly in the tooth ratio"):
        torsional_transient(model_from_dict(data), t_end=0.1)
    data = _geared().model_dump()
    data.pop("torsional")
    with pytest.raises(ModelError, match="needs drives or loads"):
        torsional_transient(model_from_dict(data), t_end=0.1)
